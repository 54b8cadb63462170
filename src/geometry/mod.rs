//! Shapes and ray intersection. Closed set: `enum Shape`, matched exhaustively.
//!
//! The per-shape intersection helpers live in `intersect`, the watertight triangle test in
//! `triangle`, and the error bounds for spawning rays off a surface in `spawn`.

use crate::math::Ray;
use crate::mesh::Mesh;
use glam::DVec3;
use std::sync::Arc;

mod intersect;
mod prepared;
mod reject;
mod spawn;

pub(crate) use crate::mesh::triangle::triangle_t;
use intersect::{accept, box_normal, nearest_crossing, slab_interval, sphere_hit, sphere_roots};
pub(crate) use prepared::{Prepared, Shear};
use reject::{plane_out_of_range, quad_surely_missed};
pub use spawn::{SELF_HIT_FRACTION, gamma};

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
    /// A one-sided-normal parallelogram (`quad` in the scene file): corners `p, p + u,
    /// p + u + v, p + v`; the normal is `u x v`, normalized. Intersected as the two triangles
    /// `(0, 1, 2)` and `(0, 2, 3)` by the watertight test, so no ray slips through the diagonal.
    Quad {
        /// Corners in order.
        vertices: [DVec3; 4],
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
    /// Stored triangle `i` of `mesh` (BVH order) as a stand-alone [`Shape::Triangle`] (outward
    /// normal).
    #[must_use]
    pub fn mesh_triangle(mesh: &Mesh, i: usize) -> Shape {
        Shape::Triangle {
            vertices: mesh.triangle(i),
            normal: mesh.geometric_normal(i),
        }
    }

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
                if plane_out_of_range(vertices[0], normal, ray, t_max) {
                    return None;
                }
                let t = triangle_t(&vertices, ray)?;
                accept(t, ray.t_min, t_max).then_some(ShapeHit { t, normal })
            }
            Shape::Quad { vertices, normal } => {
                if quad_surely_missed(&vertices, normal, ray, t_max) {
                    return None;
                }
                let t = quad_t(&vertices, ray)?;
                accept(t, ray.t_min, t_max).then_some(ShapeHit { t, normal })
            }
            Shape::Box { min, max } => {
                let t = nearest_crossing(slab_interval(min, max, ray)?, ray, t_max)?;
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
            Shape::Quad { vertices, .. } => quad_t(&vertices, &whole).map(|t| (t, t)),
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
            Shape::Quad {
                vertices: [a, b, c, d],
                ..
            } => Some((a.min(b).min(c).min(d), a.max(b).max(c).max(d))),
            Shape::Box { min, max } => Some((min, max)),
            Shape::Mesh(ref m) => Some((m.bounds().min, m.bounds().max)),
        }
    }
}

/// The watertight ray-parallelogram test: the parallelogram's two triangles `(0, 1, 2)` and
/// `(0, 2, 3)` (a plane hit exactly on the shared diagonal is found by at least one).
#[inline]
pub(super) fn quad_t(v: &[DVec3; 4], ray: &Ray) -> Option<f64> {
    // One shear for both triangles: bit for bit two `triangle_t` calls (the shear depends on
    // the ray only), without the second's three divisions.
    let sheared = crate::mesh::triangle::ShearedRay::new(ray)?;
    sheared
        .t(&[v[0], v[1], v[2]])
        .or_else(|| sheared.t(&[v[0], v[2], v[3]]))
}

#[cfg(test)]
mod tests;
