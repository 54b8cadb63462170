//! Shadow rays: opaque, or translucent by the lecture's attenuation approximation (no caustics).

use crate::bvh::TraversalCost;
use crate::geometry::Shape;
use crate::math::{Ray, Rgb, beer};
use crate::scene::Scene;
use crate::tree::Blocker;

/// Light passing from the ray's origin to distance `dist` (the product of the blockers'
/// factors). When `blockers` is given (recording), every blocker is pushed to it, in object
/// order; the plain render passes `None` and so never allocates. Acceleration-structure work is
/// added to `cost`.
///
/// Opaque mode: the first blocker stops the ray. Translucent mode: each object crossing the
/// segment passes `transmissivity * exp(-absorption * chord)`, where the chord is the part of
/// the segment inside it (lecture slide "Attenuation: Shadows Rays...").
#[inline]
pub(crate) fn transmission(
    scene: &Scene,
    ray: &Ray,
    dist: f64,
    translucent: bool,
    blockers: Option<&mut Vec<Blocker>>,
    cost: &mut TraversalCost,
) -> Rgb {
    if !translucent {
        // Opaque. A recorded tree names the nearest blocker; the render only needs to know
        // there is one (any-hit: BVH traversal stops at the first blocker found).
        return match blockers {
            Some(out) => match scene.intersect_counted(ray, dist, cost) {
                Some(hit) => {
                    out.push(blocker(scene, hit.object, hit.t, 0.0, Rgb::ZERO));
                    Rgb::ZERO
                }
                None => Rgb::ONE,
            },
            None if scene.occluded(ray, dist, cost) => Rgb::ZERO,
            None => Rgb::ONE,
        };
    }
    translucent_transmission(scene, ray, dist, blockers, cost)
}

/// The translucent mode of [`transmission`], out of line so the opaque any-hit test inlines
/// into the shading loop.
#[inline(never)]
fn translucent_transmission(
    scene: &Scene,
    ray: &Ray,
    dist: f64,
    mut blockers: Option<&mut Vec<Blocker>>,
    cost: &mut TraversalCost,
) -> Rgb {
    let mut transmittance = Rgb::ONE;
    // Objects in object order (BVH-culled), so the product is the same as a full scan.
    for i in scene.objects_near(ray, dist, cost) {
        let o = &scene.objects[i];
        let (t0, t1) = match &o.shape {
            // Exact chords through non-convex meshes: (first t, chord) as an interval.
            Shape::Mesh(m) => match m.segment_inside(ray, dist, cost) {
                Some((t, chord)) if chord > 0.0 => (t, t + chord),
                Some((t, _)) => (t, t),
                None => continue,
            },
            s => match s.inside_interval(ray) {
                Some(i) => i,
                None => continue,
            },
        };
        let (a, b) = (t0.max(ray.t_min), t1.min(dist));
        // A crossing counts when some of it lies strictly inside the segment.
        let crosses = if t0 == t1 {
            t0 > ray.t_min && t0 < dist
        } else {
            a < b
        };
        if !crosses {
            continue;
        }
        let m = scene.material_of(i);
        let chord = if t0 == t1 { 0.0 } else { b - a };
        let factor = m.transmissivity * beer(m.absorption, chord);
        transmittance *= factor;
        match blockers.as_deref_mut() {
            Some(out) => out.push(blocker(scene, i, a, chord, factor)),
            None if transmittance == Rgb::ZERO => break,
            None => {}
        }
    }
    transmittance
}

fn blocker(scene: &Scene, object: usize, t: f64, chord: f64, factor: Rgb) -> Blocker {
    Blocker {
        object,
        object_name: scene.objects[object].name.clone(),
        t,
        chord,
        factor,
    }
}
