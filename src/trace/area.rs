//! Area lights in the Whitted local term (issue 14, distribution ray tracing after Cook et al.
//! 1984): every emissive sphere, quad, triangle and mesh ([`crate::Scene::area_light`]) is sampled by
//! `settings.light_samples` shadow rays per diffuse or Blinn-Phong hit, with the Monte Carlo
//! estimator of the direct light
//!
//! `L_direct = (1/N) sum_k f(wi_k) cos(wi_k) L_e(wi_k) V(wi_k) / pdf(wi_k)`
//!
//! (pbrt-v4 section 13.4, Veach 1997 eq. 8.10 for the area-to-solid-angle pdf). The samplers
//! are `crate::lights` (spheres by the cone they subtend, quads, triangles and meshes uniformly by area;
//! emission leaves the outer side only). The 2D samples come from the pixel's sampler, so a
//! re-traced pixel reproduces its value bit for bit. Emission itself is still added only where
//! a camera, mirror or refracted ray hits the emitter (Whitted has no diffuse bounce), so
//! nothing is counted twice.

use super::local::{Cast, cos_to_light, shadow_end};
use super::{RayCounts, Recorder, Tracer};
use crate::geometry::Shape;
use crate::interaction::SurfaceInteraction;
use crate::math::Ray;
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use crate::scene::Scene;
use crate::tree::{AreaSample, EndReason, NodeId, RayKind, RayNode, ShadowInfo};

/// The shadow ray to a sampled point on an emitter (or to where it meets the emitter first)
/// stops this fraction short of it, so it does not find the emitter itself (pbrt-v4's
/// `ShadowEpsilon` in `SpawnRayTo`).
const SHADOW_EPSILON: f64 = 1e-4;

/// A mesh emitter's own hit more than this fraction of the distance (plus twice the shadow
/// ray's origin offset, which shortens the ray to the sampled point's plane) short of its
/// sampled point hides the point. An occluding part of the mesh closer than that to the point
/// is not seen as one (a small error on nearly touching surfaces).
const HIDDEN_BY_ITSELF: f64 = 1e-3;

impl Tracer<'_> {
    /// The direct light at `si` (diffuse albedo `albedo`) from every area light but the surface
    /// itself, `light_samples` recorded shadow rays each (children of `parent`).
    pub(super) fn area_direct<R: Recorder, S: PixelSampler>(
        &self,
        si: &SurfaceInteraction,
        albedo: Rgb,
        (parent, depth): (Option<NodeId>, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let n = self.scene.settings.light_samples.unwrap_or(1).max(1);
        let inv_n = 1.0 / f64::from(n);
        let mut total = Rgb::ZERO;
        for object in 0..self.scene.objects.len() {
            if object == si.object {
                continue;
            }
            let Some((emitter, emission)) = self.scene.area_light(object) else {
                continue;
            };
            for k in 0..n {
                let u = sampler.next_2d();
                let Some(ls) = emitter.sample(si.p, emission, u) else {
                    continue;
                };
                let cos = cos_to_light(si.n, si.ns, ls.direction);
                let value = ls.weight();
                let (brdf, w) = Self::light_weight(
                    self.plan.specular,
                    si.material,
                    albedo,
                    si.ns,
                    (ls.direction, si.wo),
                    cos,
                );
                let weight = w * inv_n;
                let strategy = self.scene.settings.offset.strategy;
                let (ray, seg) =
                    self.shadow_ray(strategy, si.from(), si.p, si.n, ls.direction, ls.distance);
                // The offset origin sees the emitter along a slightly different line: near a
                // sphere's silhouette that line enters it earlier than the sampled point (1.7%
                // of the samples of a 14-degree cone were found blocked by the light itself).
                // The shadow ray stops where it meets the emitter.
                let seg = emitter_shadow_length(self.scene, object, &ray, seg, si.p);
                let id = rec.push(parent, || {
                    let mut node =
                        RayNode::new(RayKind::Shadow, depth, si.p, ray.origin, ray.direction);
                    node.t_min = ray.t_min;
                    node
                });
                let info = |blockers, transmittance| ShadowInfo {
                    light: self.scene.lights.len() + object,
                    light_name: self.scene.objects[object].name.clone(),
                    distance: ls.distance,
                    cos_theta: cos,
                    brdf,
                    irradiance: value,
                    blockers,
                    transmittance,
                    area: Some(AreaSample {
                        object,
                        point: si.p + ls.distance * ls.direction,
                        direction: ls.direction,
                        pdf: ls.pdf,
                        radiance: ls.radiance,
                        sample: k,
                    }),
                };
                if cos <= 0.0 || value == Rgb::ZERO {
                    rec.update(id, |node| {
                        node.weight = weight;
                        node.end = EndReason::LightBehind;
                        node.shadow = Some(info(Vec::new(), Rgb::ZERO));
                    });
                    continue;
                }
                let Cast {
                    transmittance,
                    blockers,
                    cost,
                } = self.cast_shadow(&ray, seg, (si.p, si.from()), id, rec, counts);
                let arriving = value * transmittance;
                rec.update(id, |node| {
                    node.traversal = cost;
                    node.weight = weight;
                    node.radiance = arriving;
                    node.end = shadow_end(transmittance);
                    node.shadow = Some(info(blockers, transmittance));
                });
                if transmittance != Rgb::ZERO {
                    total += weight * arriving;
                }
            }
        }
        total
    }
}

/// The length of the shadow ray `ray` (nominal length `seg`, from the offset origin of shading
/// point `p`) to a point sampled on area light `object`. The offset origin sees the emitter
/// along a slightly different line: near a sphere's silhouette that line enters it earlier than
/// the sampled point (1.7% of the samples of a 14-degree cone were found blocked by the light
/// itself), so the ray stops [`SHADOW_EPSILON`] short of where it first meets the emitter. A
/// non-convex emissive mesh can hide the sampled point behind another of its own triangles:
/// then the ray keeps its full length, and casting it finds the mesh in the way (visibility 0).
pub(crate) fn emitter_shadow_length(
    scene: &Scene,
    object: usize,
    ray: &Ray,
    seg: f64,
    p: glam::DVec3,
) -> f64 {
    // The distance alone (the prepared object's test, without the normal `Shape::intersect`
    // would compute): the same bits.
    let own = scene.object_t(object, ray, seg);
    let hidden = matches!(scene.objects[object].shape, Shape::Mesh(_))
        && own.is_some_and(|t| t < seg * (1.0 - HIDDEN_BY_ITSELF) - 2.0 * ray.origin.distance(p));
    if hidden {
        return seg;
    }
    own.unwrap_or(seg) * (1.0 - SHADOW_EPSILON)
}
