//! Shapes and ray intersection. Closed set: `enum Shape`, matched exhaustively.

use crate::math::Ray;
use crate::mesh::Mesh;
use glam::DVec3;
use std::sync::Arc;

/// A primitive. Every shape has an outward normal; planes bound the half-space behind the normal.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius (> 0).
        radius: f64,
    },
    /// An infinite plane through `point`; its inside is the half-space `(x - point).normal < 0`.
    Plane {
        /// A point on the plane.
        point: DVec3,
        /// Unit outward normal.
        normal: DVec3,
    },
    /// A one-sided-normal triangle; the normal is `(b - a) x (c - a)`, normalized.
    Triangle {
        /// Vertices.
        vertices: [DVec3; 3],
        /// Unit normal.
        normal: DVec3,
    },
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: DVec3,
        /// Upper corner.
        max: DVec3,
    },
    /// A world-space triangle mesh with its own BVH (shared, so cloning a scene is cheap).
    Mesh(Arc<Mesh>),
}

/// The cheap result of a ray-shape test: distance and outward geometric normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Ray parameter of the hit.
    pub t: f64,
    /// Unit outward geometric normal at the hit.
    pub normal: DVec3,
}

impl Shape {
    /// The closest hit with `t` in `(ray.t_min, t_max)`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<ShapeHit> {
        match *self {
            Shape::Sphere { center, radius } => sphere_hit(center, radius, ray, t_max),
            Shape::Plane { point, normal } => {
                let denom = normal.dot(ray.direction);
                if denom == 0.0 {
                    return None;
                }
                let t = (point - ray.origin).dot(normal) / denom;
                accept(t, ray.t_min, t_max).then_some(ShapeHit { t, normal })
            }
            Shape::Triangle { vertices, normal } => {
                let t = triangle_t(&vertices, ray)?;
                accept(t, ray.t_min, t_max).then_some(ShapeHit { t, normal })
            }
            Shape::Box { min, max } => {
                let (t0, t1) = slab_interval(min, max, ray)?;
                let t = if accept(t0, ray.t_min, t_max) {
                    t0
                } else if accept(t1, ray.t_min, t_max) {
                    t1
                } else {
                    return None;
                };
                Some(ShapeHit {
                    t,
                    normal: box_normal(min, max, ray.at(t)),
                })
            }
            Shape::Mesh(ref m) => {
                let (t, i) = m.intersect(ray, t_max, &mut Default::default())?;
                Some(ShapeHit {
                    t,
                    normal: m.geometric_normal(i),
                })
            }
        }
    }

    /// The parameter interval `[t_in, t_out]` where the (infinite) line is inside the solid,
    /// used for Beer's law chords of shadow rays. A triangle has no inside: its interval is the
    /// single crossing `[t, t]`. May extend to +/- infinity (planes).
    #[must_use]
    pub fn inside_interval(&self, ray: &Ray) -> Option<(f64, f64)> {
        let whole = Ray::new(ray.origin, ray.direction, f64::NEG_INFINITY);
        match *self {
            Shape::Sphere { center, radius } => sphere_roots(center, radius, &whole),
            Shape::Plane { point, normal } => {
                let denom = normal.dot(ray.direction);
                let side = (ray.origin - point).dot(normal);
                if denom == 0.0 {
                    return (side < 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
                }
                let t = -side / denom;
                Some(if denom > 0.0 {
                    (f64::NEG_INFINITY, t)
                } else {
                    (t, f64::INFINITY)
                })
            }
            Shape::Triangle { vertices, .. } => triangle_t(&vertices, &whole).map(|t| (t, t)),
            Shape::Box { min, max } => slab_interval(min, max, &whole),
            // The span from the first to the last crossing (exact chords: `Mesh::segment_inside`).
            Shape::Mesh(ref m) => {
                let ts = m.crossings(ray, &mut Default::default());
                Some((*ts.first()?, *ts.last()?))
            }
        }
    }

    /// Axis-aligned bounds, `None` for unbounded shapes (planes).
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match *self {
            Shape::Sphere { center, radius } => Some((center - radius, center + radius)),
            Shape::Plane { .. } => None,
            Shape::Triangle {
                vertices: [a, b, c],
                ..
            } => Some((a.min(b).min(c), a.max(b).max(c))),
            Shape::Box { min, max } => Some((min, max)),
            Shape::Mesh(ref m) => Some((m.bounds().min, m.bounds().max)),
        }
    }
}

fn accept(t: f64, t_min: f64, t_max: f64) -> bool {
    t > t_min && t < t_max
}

/// Both roots of the ray-sphere quadratic, in the numerically stable form of Haines et al.,
/// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7, eq. 10-14):
/// the discriminant is computed from the perpendicular distance, and the second root from
/// `c / q` to avoid cancellation.
fn sphere_roots(center: DVec3, radius: f64, ray: &Ray) -> Option<(f64, f64)> {
    let f = ray.origin - center;
    let d = ray.direction;
    let a = d.dot(d);
    let b = -f.dot(d);
    let perp = f + (b / a) * d;
    let disc = radius * radius - perp.dot(perp);
    if disc < 0.0 {
        return None;
    }
    let c = f.dot(f) - radius * radius;
    let q = b + b.signum_or_one() * (a * disc).sqrt();
    let (r0, r1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    Some((r0.min(r1), r0.max(r1)))
}

trait SignumOrOne {
    fn signum_or_one(self) -> f64;
}

impl SignumOrOne for f64 {
    fn signum_or_one(self) -> f64 {
        if self < 0.0 { -1.0 } else { 1.0 }
    }
}

fn sphere_hit(center: DVec3, radius: f64, ray: &Ray, t_max: f64) -> Option<ShapeHit> {
    let (t0, t1) = sphere_roots(center, radius, ray)?;
    let t = if accept(t0, ray.t_min, t_max) {
        t0
    } else if accept(t1, ray.t_min, t_max) {
        t1
    } else {
        return None;
    };
    let normal = ((ray.at(t) - center) / radius).normalize();
    Some(ShapeHit { t, normal })
}

/// Watertight ray-triangle test (Woop, Benthin, Wald, "Watertight Ray/Triangle Intersection",
/// JCGT 2(1), 2013), two-sided; returns the hit distance.
///
/// The vertices are translated to the ray origin and sheared so the ray runs along +z; the
/// three 2D edge functions are then computed per vertex with the same operations for every
/// triangle, so an edge shared by two triangles gives exactly negated values on both sides and
/// no ray passes between them. Unlike the paper's `f32` kernel no higher-precision fallback is
/// needed for the edge functions: they already are `f64`.
pub(crate) fn triangle_t(v: &[DVec3; 3], ray: &Ray) -> Option<f64> {
    ShearedRay::new(ray)?.t(v)
}

/// The per-ray part of [`triangle_t`] (axis permutation and shear), computed once for testing
/// many triangles; [`ShearedRay::t`] is then exactly `triangle_t`, bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    origin: DVec3,
    /// Axes: sheared x, sheared y, along the ray (the largest direction component).
    pub(crate) k: [usize; 3],
    /// Shear factors `d[kx] / d[kz]`, `d[ky] / d[kz]` and scale `1 / d[kz]`.
    pub(crate) s: [f64; 3],
}

impl ShearedRay {
    /// `None` for a zero or non-finite direction (no triangle is hit).
    pub(crate) fn new(ray: &Ray) -> Option<Self> {
        let d = ray.direction;
        let kz = d.abs().max_position();
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        if !(sx.is_finite() && sy.is_finite() && sz.is_finite()) {
            return None;
        }
        Some(Self {
            origin: ray.origin,
            k: [kx, ky, kz],
            s: [sx, sy, sz],
        })
    }

    /// [`triangle_t`] of `v` for this ray.
    #[inline]
    pub(crate) fn t(&self, v: &[DVec3; 3]) -> Option<f64> {
        let ([kx, ky, kz], [sx, sy, sz]) = (self.k, self.s);
        // Arrays, not `DVec3` indexing (a `match` per component); the same values.
        let [a, b, c] = v.map(|p| (p - self.origin).to_array());
        let shear = |p: [f64; 3]| (p[kx] - sx * p[kz], p[ky] - sy * p[kz]);
        let ((ax, ay), (bx, by), (cx, cy)) = (shear(a), shear(b), shear(c));
        let u = cx * by - cy * bx;
        let w_ = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || w_ < 0.0 || w < 0.0) && (u > 0.0 || w_ > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + w_ + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t_scaled = u * (sz * a[kz]) + w_ * (sz * b[kz]) + w * (sz * c[kz]);
        Some(t_scaled / det)
    }
}

/// `gamma(n) = n u / (1 - n u)` with `u` the unit roundoff: the bound on the relative error of
/// `n` chained floating-point operations (Higham; pbrt-v4 `gamma`, PBR 4th ed. section 6.8.1).
#[must_use]
pub fn gamma(n: u32) -> f64 {
    let nu = f64::from(n) * (f64::EPSILON * 0.5);
    nu / (1.0 - nu)
}

impl Shape {
    /// Move a computed hit point `p` onto the surface (up to rounding) and bound the error that
    /// remains, per component: pbrt-v4's reprojection and conservative error bounds
    /// (Pharr, Jakob, Humphreys, PBR 4th ed., section 6.8.5 "Robust spawned ray origins").
    ///
    /// `normal` is the normal at `p` (either orientation). Spheres are reprojected radially (pbrt's
    /// `pHit *= radius / Distance(pHit, 0)`), planes and triangles projected onto their plane
    /// (the triangle bound also covers the rounding of the stored normal over the triangle's
    /// extent), and a box hit snaps the face coordinate exactly onto the face.
    #[must_use]
    pub fn surface_point(&self, p: DVec3, normal: DVec3) -> (DVec3, DVec3) {
        match *self {
            Shape::Sphere { center, radius } => {
                let v = p - center;
                let len = v.length();
                if len == 0.0 || !len.is_finite() {
                    return (p, gamma(8) * (center.abs() + radius));
                }
                let v = v * (radius / len);
                (center + v, gamma(8) * (center.abs() + v.abs()))
            }
            Shape::Plane { point, normal } => {
                let q = p - (p - point).dot(normal) * normal;
                (q, gamma(8) * (p.abs() + point.abs()))
            }
            Shape::Triangle {
                vertices: [a, b, c],
                normal,
            } => {
                let q = p - (p - a).dot(normal) * normal;
                (q, gamma(16) * (a.abs() + b.abs() + c.abs() + p.abs()))
            }
            Shape::Box { min, max } => {
                let mut q = p;
                for i in 0..3 {
                    if normal[i] != 0.0 {
                        let to_max = (max[i] - p[i]).abs() < (p[i] - min[i]).abs();
                        q[i] = if to_max { max[i] } else { min[i] };
                    }
                }
                // The face coordinate is exact; the others do not move the origin off the face.
                (q, gamma(2) * q.abs() * (DVec3::ONE - normal.abs()))
            }
            // Without knowing the triangle: no reprojection, and a bound as for a triangle
            // with the mesh's largest coordinates. The tracer passes the hit triangle instead
            // (`Scene::surface_shape`), which gives the triangle's own, tighter bound.
            Shape::Mesh(ref m) => {
                let b = m.bounds();
                let far = b.min.abs().max(b.max.abs());
                (p, gamma(16) * (3.0 * far + p.abs()))
            }
        }
    }

    /// Distance from its spawn point within which a ray meeting this same shape again counts as
    /// a self-hit: `1e-6` of the radius of a sphere or the thinnest side of a box (a legitimate
    /// re-hit, such as a chord inside a sphere, is that short only at grazing angles or next to
    /// an edge, both of measure ~0), and any
    /// distance for flat shapes, which a straight ray leaving them can never meet again.
    /// For a mesh, `1e-6` of its bounding box's largest side: another triangle that close
    /// (across an edge) is the same surface; the triangle left itself is flat and counts at
    /// any distance (the diagnostics compare triangles).
    #[must_use]
    pub fn self_hit_radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius, .. } => SELF_HIT_FRACTION * radius,
            Shape::Box { min, max } => SELF_HIT_FRACTION * (max - min).min_element(),
            Shape::Plane { .. } | Shape::Triangle { .. } => f64::INFINITY,
            Shape::Mesh(ref m) => {
                let b = m.bounds();
                SELF_HIT_FRACTION * (b.max - b.min).max_element()
            }
        }
    }
}

/// Fraction of a curved shape's size below which a re-hit is a self-hit.
pub const SELF_HIT_FRACTION: f64 = 1e-6;

/// Slab test (Kay & Kajiya 1986): the line's parameter interval inside the box.
fn slab_interval(min: DVec3, max: DVec3, ray: &Ray) -> Option<(f64, f64)> {
    let inv = ray.direction.recip();
    let a = (min - ray.origin) * inv;
    let b = (max - ray.origin) * inv;
    // NaN (0 * inf on a face plane) is dropped by f64::min/max, keeping the other axes.
    let t0 = a.x.min(b.x).max(a.y.min(b.y)).max(a.z.min(b.z));
    let t1 = a.x.max(b.x).min(a.y.max(b.y)).min(a.z.max(b.z));
    (t0 <= t1).then_some((t0, t1))
}

/// The outward normal of the box face nearest to `p`.
fn box_normal(min: DVec3, max: DVec3, p: DVec3) -> DVec3 {
    let size = (max - min).max(DVec3::splat(f64::MIN_POSITIVE));
    let lo = (p - min) / size;
    let hi = (max - p) / size;
    let mut best = (lo.x, -DVec3::X);
    for (d, n) in [
        (hi.x, DVec3::X),
        (lo.y, -DVec3::Y),
        (hi.y, DVec3::Y),
        (lo.z, -DVec3::Z),
        (hi.z, DVec3::Z),
    ] {
        if d.abs() < best.0.abs() {
            best = (d, n);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
        Ray::new(DVec3::from(o), DVec3::from(d).normalize(), 0.0)
    }

    #[test]
    fn sphere_front_and_back() {
        let s = Shape::Sphere {
            center: DVec3::ZERO,
            radius: 1.0,
        };
        let h = s
            .intersect(&ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), f64::INFINITY)
            .unwrap();
        assert_eq!(h.t, 4.0);
        assert_eq!(h.normal, -DVec3::Z);
        let h = s
            .intersect(&ray([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), f64::INFINITY)
            .unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(h.normal, DVec3::Z);
        assert!(
            s.intersect(&ray([0.0, 2.0, -5.0], [0.0, 0.0, 1.0]), f64::INFINITY)
                .is_none()
        );
    }

    #[test]
    fn tiny_sphere_far_away_is_precise() {
        let center = DVec3::new(1e5, 0.0, 0.0);
        let s = Shape::Sphere {
            center,
            radius: 1e-3,
        };
        let h = s
            .intersect(&ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
            .unwrap();
        assert!((h.t - (1e5 - 1e-3)).abs() < 1e-9, "{}", h.t);
    }

    #[test]
    fn plane_and_half_space() {
        let p = Shape::Plane {
            point: DVec3::ZERO,
            normal: DVec3::Y,
        };
        let r = ray([0.0, 2.0, 0.0], [0.0, -1.0, 0.0]);
        assert_eq!(p.intersect(&r, f64::INFINITY).unwrap().t, 2.0);
        assert_eq!(p.inside_interval(&r), Some((2.0, f64::INFINITY)));
    }

    #[test]
    fn triangle_hit_and_miss() {
        let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let t = Shape::Triangle {
            vertices: v,
            normal: DVec3::Z,
        };
        assert_eq!(
            t.intersect(&ray([0.2, 0.2, 1.0], [0.0, 0.0, -1.0]), f64::INFINITY)
                .unwrap()
                .t,
            1.0
        );
        assert!(
            t.intersect(&ray([0.8, 0.8, 1.0], [0.0, 0.0, -1.0]), f64::INFINITY)
                .is_none()
        );
    }

    #[test]
    fn box_faces() {
        let b = Shape::Box {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        };
        let h = b
            .intersect(&ray([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]), f64::INFINITY)
            .unwrap();
        assert_eq!((h.t, h.normal), (4.0, DVec3::Y));
        let h = b
            .intersect(&ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
            .unwrap();
        assert_eq!((h.t, h.normal), (1.0, DVec3::X));
        // Axis-parallel ray on no face plane.
        assert!(
            b.intersect(&ray([0.0, 2.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
                .is_none()
        );
    }
}
