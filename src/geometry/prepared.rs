//! A shape prepared once for many ray tests ([`Prepared`]): what [`Shape::intersect`] would
//! recompute per ray (a quad's edges, cross product and margin scale) is stored, and the
//! distance is found apart from the normal, which only the closest hit needs.
//!
//! [`Prepared::t`] is the `t` of [`Shape::intersect`] bit for bit: the same functions in the same
//! order on the same values (the ray's shear for the watertight test is computed once per ray
//! and only if some flat shape survives its rejection, [`ShearedRay::t`] is exactly
//! `triangle_t`, and a quad's [`ShearedRay::t_quad`] is `t` of its two triangles, the shared
//! corners sheared once). [`Prepared::normal`] is its normal for that `t`. The tests are in
//! `src/scene/accel/tests.rs`, against [`Shape::intersect`] (whose quad test still calls `t`
//! twice).

use super::Shape;
use super::intersect::{accept, box_normal, nearest_crossing, slab_interval, sphere_roots};
use super::reject::{QuadFrame, plane_out_of_range};
use crate::math::Ray;
use crate::mesh::triangle::ShearedRay;
use glam::DVec3;

/// The watertight test's per-ray shear, computed at the first flat shape that needs it.
///
/// A plain flag and value behind `&mut` rather than a `OnceCell` behind `&`: the cell's
/// outlined, re-entrancy-checked initialisation (`OnceCell::try_init`) cost 3.6% of a render
/// of `benches/mitsuba-scenes/glass-emitters.json` (perf, self time), where this is one
/// inlined branch. The same `ShearedRay::new(ray)`, so the same bits.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Shear {
    done: bool,
    ray: Option<ShearedRay>,
}

impl Shear {
    /// A shear not yet computed (one for each ray).
    #[inline(always)]
    #[must_use]
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// `ShearedRay::new(ray)`, computed on the first call.
    #[inline(always)]
    pub(crate) fn get(&mut self, ray: &Ray) -> Option<&ShearedRay> {
        if !self.done {
            self.ray = ShearedRay::new(ray);
            self.done = true;
        }
        self.ray.as_ref()
    }
}

/// A non-mesh shape with its per-shape precomputation; meshes keep their own BVH and are
/// tested by the caller.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Prepared {
    /// [`Shape::Sphere`].
    Sphere { center: DVec3, radius: f64 },
    /// [`Shape::Plane`].
    Plane { point: DVec3, normal: DVec3 },
    /// [`Shape::Triangle`].
    Triangle { vertices: [DVec3; 3], normal: DVec3 },
    /// [`Shape::Quad`] with its rejection frame.
    Quad {
        vertices: [DVec3; 4],
        normal: DVec3,
        frame: QuadFrame,
    },
    /// [`Shape::Box`].
    Box { min: DVec3, max: DVec3 },
    /// [`Shape::Mesh`]: tested by the caller.
    Mesh,
}

impl Prepared {
    /// Prepare `shape`.
    #[must_use]
    pub(crate) fn new(shape: &Shape) -> Self {
        match *shape {
            Shape::Sphere { center, radius } => Prepared::Sphere { center, radius },
            Shape::Plane { point, normal } => Prepared::Plane { point, normal },
            Shape::Triangle { vertices, normal } => Prepared::Triangle { vertices, normal },
            Shape::Quad { vertices, normal } => Prepared::Quad {
                vertices,
                normal,
                frame: QuadFrame::new(&vertices),
            },
            Shape::Box { min, max } => Prepared::Box { min, max },
            Shape::Mesh(_) => Prepared::Mesh,
        }
    }

    /// The `t` of [`Shape::intersect`] (`None` where it misses); `sheared` holds
    /// `ShearedRay::new(ray)` once a flat shape has needed it (a fresh one for each ray).
    /// Meshes: `None` (the caller's).
    #[inline]
    #[must_use]
    pub(crate) fn t(&self, ray: &Ray, sheared: &mut Shear, t_max: f64) -> Option<f64> {
        self.t_inline(ray, sheared, t_max)
    }

    /// [`Prepared::t`], always inlined (for the scan of a scene of planes and spheres).
    #[inline(always)]
    #[must_use]
    pub(crate) fn t_inline(&self, ray: &Ray, sheared: &mut Shear, t_max: f64) -> Option<f64> {
        let t = match *self {
            Prepared::Sphere { center, radius } => {
                return nearest_crossing(sphere_roots(center, radius, ray)?, ray, t_max);
            }
            Prepared::Plane { point, normal } => {
                let denom = normal.dot(ray.direction);
                if denom == 0.0 {
                    return None;
                }
                (point - ray.origin).dot(normal) / denom
            }
            Prepared::Triangle { vertices, normal } => {
                if plane_out_of_range(vertices[0], normal, ray, t_max) {
                    return None;
                }
                sheared.get(ray)?.t(&vertices)?
            }
            Prepared::Quad {
                ref vertices,
                normal,
                ref frame,
            } => {
                if frame.surely_missed(vertices[0], normal, ray, t_max) {
                    return None;
                }
                // `t` of the triangles v0 v1 v2, then v0 v2 v3, bit for bit.
                sheared.get(ray)?.t_quad(vertices)?
            }
            Prepared::Box { min, max } => {
                return nearest_crossing(slab_interval(min, max, ray)?, ray, t_max);
            }
            Prepared::Mesh => return None,
        };
        accept(t, ray.t_min, t_max).then_some(t)
    }

    /// The outward normal [`Shape::intersect`] reports with its hit at `t` (meshes: the
    /// caller's, from the triangle; this returns zero).
    #[must_use]
    pub(crate) fn normal(&self, ray: &Ray, t: f64) -> DVec3 {
        match *self {
            Prepared::Sphere { center, radius } => ((ray.at(t) - center) / radius).normalize(),
            Prepared::Plane { normal, .. }
            | Prepared::Triangle { normal, .. }
            | Prepared::Quad { normal, .. } => normal,
            Prepared::Box { min, max } => box_normal(min, max, ray.at(t)),
            Prepared::Mesh => DVec3::ZERO,
        }
    }
}
