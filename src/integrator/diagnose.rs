//! Self-intersection and leak diagnostics for one spawned ray.
//!
//! Definitions (also in `docs/numerics.md`):
//!
//! - **self-hit**: the ray's closest hit (for a shadow ray: the closest object before the light)
//!   is the object it was spawned from, within [`Shape::self_hit_radius`] of the spawn point
//!   (`1e-6` of a sphere's radius or a box's thinnest side; any distance for planes and
//!   triangles, which a straight ray cannot leave and meet again). On a mesh: the triangle it was
//!   spawned from at any distance, or another triangle of the mesh within `1e-6` of the mesh's
//!   size (across an edge). This is the acne of a too-small offset.
//! - **leak**: the offset skipped a surface that a zero offset would have met: some surface
//!   crosses the segment from the true spawn point to the offset origin, or the ray itself at
//!   `t <= t_min`; crossings of the spawning object within its self-hit radius of the spawn
//!   point, or of the spawning mesh triangle, do not count (that is the surface being left).
//!   This is the light leak or detached contact shadow of a too-large offset.
//!
//! Both checks cost extra intersections, so the tracer runs them only for recorders that ask
//! ([`crate::Recorder::DIAGNOSE`]); the no-op recorder of the plain render does not.
//!
//! [`Shape::self_hit_radius`]: crate::geometry::Shape::self_hit_radius

use crate::bvh::TraversalCost;
use crate::geometry::Shape;
use crate::interaction::SurfaceId;
use crate::math::Ray;
use crate::scene::{Hit, Scene};
use crate::tree::Leak;
use glam::DVec3;

/// What the diagnostics found for one ray.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Diagnosis {
    /// The ray re-hit the surface it left.
    pub self_hit: bool,
    /// The closest surface the offset skipped.
    pub leak: Option<Leak>,
}

/// Diagnose `ray`, spawned from `point` on surface `from`, whose closest hit is `hit`.
#[must_use]
pub fn diagnose(
    scene: &Scene,
    ray: &Ray,
    point: DVec3,
    from: SurfaceId,
    hit: Option<Hit>,
) -> Diagnosis {
    let SurfaceId { object, triangle } = from;
    let radius = scene.objects[object].shape.self_hit_radius();
    let self_hit = hit.is_some_and(|h| {
        h.object == object
            && ((triangle.is_some() && h.triangle == triangle)
                || (ray.at(h.t) - point).length() <= radius)
    });
    Diagnosis {
        self_hit,
        leak: skipped(scene, ray, point, from, radius),
    }
}

/// The closest hit of `shape` on `ray` before `t_max`: distance and (meshes) stored triangle.
fn shape_hit(shape: &Shape, ray: &Ray, t_max: f64) -> Option<(f64, Option<u32>)> {
    match shape {
        Shape::Mesh(m) => m
            .intersect(ray, t_max, &mut TraversalCost::default())
            .map(|(t, i)| (t, Some(i as u32))),
        s => s.intersect(ray, t_max).map(|h| (h.t, None)),
    }
}

/// The closest crossing (from `point`) of the skipped region, ignoring the surface being left.
fn skipped(
    scene: &Scene,
    ray: &Ray,
    point: DVec3,
    SurfaceId { object, triangle }: SurfaceId,
    radius: f64,
) -> Option<Leak> {
    let mut best: Option<Leak> = None;
    let mut consider = |seg: Ray, len: f64| {
        if !(len > 0.0 && len.is_finite()) {
            return;
        }
        for (i, o) in scene.objects.iter().enumerate() {
            let mut probe = seg;
            // Re-test beyond the spawning surface's own crossing (at most two crossings matter).
            for _ in 0..3 {
                let Some((t, tri)) = shape_hit(&o.shape, &probe, len) else {
                    break;
                };
                let at = probe.at(t);
                let distance = (at - point).length();
                let same_triangle = triangle.is_some() && tri == triangle;
                if i == object && (distance <= radius || same_triangle) {
                    probe.t_min = t;
                    continue;
                }
                if best.as_ref().is_none_or(|b| distance < b.distance) {
                    best = Some(Leak {
                        object: i,
                        object_name: o.name.clone(),
                        distance,
                    });
                }
                break;
            }
        }
    };
    let off = ray.origin - point;
    let off_len = off.length();
    if off_len > 0.0 {
        consider(Ray::new(point, off / off_len, 0.0), off_len);
    }
    if ray.t_min > 0.0 {
        consider(Ray::new(ray.origin, ray.direction, 0.0), ray.t_min);
    }
    best
}
