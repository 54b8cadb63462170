//! Error bounds for spawning rays off a surface: [`gamma`], [`Shape::surface_point`] (pbrt-v4's
//! reprojection and conservative bounds) and [`Shape::self_hit_radius`].

use super::Shape;
use glam::DVec3;

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
            Shape::Quad {
                vertices: [a, b, c, d],
                normal,
            } => {
                let q = p - (p - a).dot(normal) * normal;
                (
                    q,
                    gamma(16) * (a.abs() + b.abs() + c.abs() + d.abs() + p.abs()),
                )
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
            Shape::Plane { .. } | Shape::Triangle { .. } | Shape::Quad { .. } => f64::INFINITY,
            Shape::Mesh(ref m) => {
                let b = m.bounds();
                SELF_HIT_FRACTION * (b.max - b.min).max_element()
            }
        }
    }
}

/// Fraction of a curved shape's size below which a re-hit is a self-hit.
pub const SELF_HIT_FRACTION: f64 = 1e-6;
