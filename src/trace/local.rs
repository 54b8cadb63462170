//! Local shading at a hit, shared by the recursive tracer and the direct-only path: the
//! surface frame (geometric and shading normal) and the lecture's local term, emitted + ambient
//! + the direct light of every light through its shadow ray.

use super::{RayCounts, Recorder, Tracer, offset, shadow};
use crate::bvh::TraversalCost;
use crate::interaction::SurfaceInteraction;
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use crate::mesh::shading;
use crate::sampling::PixelSampler;
use crate::scene::{Hit, Light, Material, OffsetStrategy};
use crate::tree::EndReason;
use crate::tree::{NodeId, RayKind, RayNode, ShadowInfo};
use glam::DVec3;

/// The local term at a hit and its parts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Local {
    /// Emission (seen from outside only).
    pub emitted: Rgb,
    /// Ambient term.
    pub ambient: Rgb,
    /// Emitted + ambient + every light's direct contribution.
    pub total: Rgb,
}

impl Tracer<'_> {
    /// The surface interaction of `hit` for `ray` arriving through `media`.
    #[inline(always)]
    pub(crate) fn surface<'s>(
        &'s self,
        ray: &Ray,
        hit: &Hit,
        media: &'s MediaStack,
    ) -> SurfaceInteraction<'s> {
        let d = ray.direction;
        let p = ray.at(hit.t);
        let entering = d.dot(hit.normal) < 0.0;
        let n = if entering { hit.normal } else { -hit.normal };
        // Built by value where it is returned: an interaction assembled and then moved is a
        // 176-byte `memcpy` per hit (measured: 3% of the classic scene's render time). `smooth`
        // is an argument so that the common case writes a constant `None` (a spilled `None`
        // re-read as 16 bytes stalled store forwarding: 2% of a glass-emitters render, perf).
        let with = |smooth: Option<DVec3>, ns: DVec3, cos_i: f64| SurfaceInteraction {
            p,
            wo: -d,
            entering,
            n,
            ns,
            smooth,
            cos_i,
            object: hit.object,
            triangle: hit.triangle,
            material: self.scene.material_of(hit.object),
            media,
        };
        let cos = |ns: DVec3| (-d.dot(ns)).clamp(0.0, 1.0);
        match hit.triangle.and_then(|_| self.scene.shading_normal(hit, p)) {
            None => with(None, n, cos(n)),
            Some(s) => {
                let ns = shading::shading_normal(d, n, s, entering);
                let ns = self.consistent_shading_normal(&with(Some(s), n, 0.0), ns);
                with(Some(s), ns, cos(ns))
            }
        }
    }

    /// Emitted + ambient + the direct light of every light that can light something, with one
    /// shadow ray per light in front of the surface (recorded as children of `id`).
    #[inline(always)]
    pub(super) fn local<R: Recorder, S: PixelSampler>(
        &self,
        si: &SurfaceInteraction,
        (id, depth): (Option<NodeId>, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Local {
        let m = si.material;
        let albedo = m.diffuse.at(si.p);
        let emitted = if si.entering { m.emission } else { Rgb::ZERO };
        let ambient = self.scene.ambient * albedo;
        let mut total = emitted + ambient;
        let shaded = !m.diffuse.is_black() || m.specular != Rgb::ZERO;
        if shaded || self.plan.glossy && m.is_rough() {
            for (i, light) in self.lights_on() {
                total += self.direct((i, light), (si, albedo), (id, depth), rec, counts);
            }
            // Area lights reach rough lobes through their sampled rays instead (glossy.rs).
            if self.plan.area_lights && shaded {
                total += self.area_direct(si, albedo, (id, depth), sampler, rec, counts);
            }
        }
        Local {
            emitted,
            ambient,
            total,
        }
    }

    /// One light's contribution at `si` (diffuse albedo `albedo`) from its [`crate::trace::LightSample`]:
    /// (diffuse/pi + Blinn-Phong) x value x cos x shadow, recorded as a child of `parent`.
    #[inline(always)]
    pub(super) fn direct<R: Recorder>(
        &self,
        (light, l): (usize, &Light),
        (si, albedo): (&SurfaceInteraction, Rgb),
        (parent, depth): (Option<NodeId>, u32),
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let (ls, cos) = self.sample_light(l, si);
        let (wi, dist, irradiance) = (ls.direction, ls.distance, ls.value());
        let (p, n, from, m) = (si.p, si.n, si.from(), si.material);
        let strategy = self.scene.settings.offset.strategy;
        let (ray, seg) = self.shadow_ray(strategy, from, p, n, wi, dist);
        let id = rec.push(parent, || {
            let mut node = RayNode::new(RayKind::Shadow, depth, p, ray.origin, ray.direction);
            node.t_min = ray.t_min;
            node
        });
        let (mut brdf, mut weight) =
            Self::light_weight(self.plan.specular, m, albedo, si.ns, (wi, si.wo), cos);
        if self.plan.glossy && cos > 0.0 && m.is_rough() {
            // The rough lobes' glossy highlight (glossy.rs).
            brdf += self.glossy_brdf(si, wi);
            weight = brdf * cos;
        }
        if cos <= 0.0 {
            rec.update(id, |node| {
                node.weight = weight;
                node.end = EndReason::LightBehind;
                node.shadow = Some(self.shadow_info(
                    light,
                    dist,
                    cos,
                    brdf,
                    irradiance,
                    Vec::new(),
                    Rgb::ZERO,
                ));
            });
            return Rgb::ZERO;
        }
        let Cast {
            transmittance,
            blockers,
            cost,
        } = self.cast_shadow(&ray, seg, (p, from), id, rec, counts);
        let arriving = irradiance * transmittance;
        rec.update(id, |node| {
            node.traversal = cost;
            node.weight = weight;
            node.radiance = arriving;
            node.end = shadow_end(transmittance);
            node.shadow =
                Some(self.shadow_info(light, dist, cos, brdf, irradiance, blockers, transmittance));
        });
        // A blocked light adds exactly nothing (not `0 * inf` for a light on the surface), as in
        // the direct-only path, which does not evaluate blocked lights at all.
        if transmittance == Rgb::ZERO {
            Rgb::ZERO
        } else {
            weight * arriving
        }
    }

    /// Cast a recorded shadow ray (from `p` on surface `from`): count it, diagnose it when the
    /// recorder does, and find its transmittance; the blockers are collected only when
    /// recording (no `Vec` on the render path). Shared by the point/directional lights' shadow
    /// rays and the area lights' (`area.rs`).
    #[inline(always)]
    pub(super) fn cast_shadow<R: Recorder>(
        &self,
        ray: &Ray,
        seg: f64,
        (p, from): (DVec3, (usize, Option<u32>)),
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Cast {
        counts.add_kind(RayKind::Shadow);
        if R::DIAGNOSE {
            let first = self.scene.intersect(ray, seg);
            self.diagnose(ray, p, from, first, id, rec, counts);
        }
        let mut blockers = R::RECORDS.then(Vec::new);
        let mut cost = TraversalCost::default();
        let transmittance = shadow::transmission(
            self.scene,
            ray,
            seg,
            self.plan.translucent_shadows,
            blockers.as_mut(),
            &mut cost,
        );
        Cast {
            transmittance,
            blockers: blockers.unwrap_or_default(),
            cost,
        }
    }

    /// The BRDF (Lambert `albedo / pi` plus the Blinn-Phong highlight when the plan has one)
    /// and the weight `brdf * max(cos, 0)` of a light at cosine `cos` (both zero behind).
    /// `specular` is the plan's (constant in the direct-only path's loops).
    #[inline(always)]
    pub(super) fn light_weight(
        specular: bool,
        m: &Material,
        albedo: Rgb,
        ns: DVec3,
        (wi, wo): (DVec3, DVec3),
        cos: f64,
    ) -> (Rgb, Rgb) {
        let brdf = if cos > 0.0 {
            let highlight = if specular {
                blinn_phong(m, ns, wi, wo)
            } else {
                Rgb::ZERO
            };
            albedo * std::f64::consts::FRAC_1_PI + highlight
        } else {
            Rgb::ZERO
        };
        (brdf, brdf * cos.max(0.0))
    }

    /// The shadow ray from `p` (on `from`, geometric normal `n` towards the light) to a light
    /// at `dist` along `wi`, offset by `strategy`, and how far it may go: the light's distance
    /// less the offset, so the offset origin does not reach past the light (no square root
    /// except for `robust`). The direct-only path passes a constant `strategy`, so each of its
    /// loops holds one arm.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn shadow_ray(
        &self,
        strategy: OffsetStrategy,
        from: (usize, Option<u32>),
        p: DVec3,
        n: DVec3,
        wi: DVec3,
        dist: f64,
    ) -> (Ray, f64) {
        let eps = self.scene.settings.offset.epsilon;
        match strategy {
            OffsetStrategy::Normal => (Ray::new(p + eps * n, wi, 0.0), (dist - eps).max(0.0)),
            OffsetStrategy::Ray => (Ray::new(p, wi, eps), dist),
            OffsetStrategy::Scaled => {
                let e = offset::scaled_epsilon(eps, p);
                (Ray::new(p + e * n, wi, 0.0), (dist - e).max(0.0))
            }
            OffsetStrategy::Robust => {
                let shape = || self.scene.surface_shape(from.0, from.1);
                let origin = offset::robust_origin(&shape(), p, n);
                let ray = Ray::new(origin, wi, 0.0);
                (ray, (dist - (origin - p).length()).max(0.0))
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn shadow_info(
        &self,
        light: usize,
        distance: f64,
        cos_theta: f64,
        brdf: Rgb,
        irradiance: Rgb,
        blockers: Vec<crate::tree::Blocker>,
        transmittance: Rgb,
    ) -> ShadowInfo {
        ShadowInfo {
            light,
            light_name: self.scene.lights[light].name.clone(),
            distance,
            cos_theta,
            brdf,
            irradiance,
            blockers,
            transmittance,
            area: None,
        }
    }
}

/// What a cast shadow ray found ([`Tracer::cast_shadow`]).
pub(super) struct Cast {
    /// The fraction of the light that arrives (1 unblocked, 0 blocked).
    pub transmittance: Rgb,
    /// The blockers passed or stopped at (empty unless recording).
    pub blockers: Vec<crate::tree::Blocker>,
    /// The traversal work.
    pub cost: TraversalCost,
}

/// A recorded shadow ray's end reason from its transmittance.
pub(super) fn shadow_end(transmittance: Rgb) -> EndReason {
    if transmittance == Rgb::ONE {
        EndReason::Unblocked
    } else if transmittance == Rgb::ZERO {
        EndReason::Blocked
    } else {
        EndReason::Attenuated
    }
}

/// The cosine at which a light in direction `wi` is seen: against the shading normal `ns`,
/// unless the light is behind the geometric normal `n` (the shadow ray leaves on the geometric
/// side, so a light below the geometric surface cannot be reached).
#[inline(always)]
pub(super) fn cos_to_light(n: DVec3, ns: DVec3, wi: DVec3) -> f64 {
    if n.dot(wi) > 0.0 {
        ns.dot(wi)
    } else {
        n.dot(wi)
    }
}

/// Blinn-Phong highlight `specular * (N.H)^shininess` (zero without a specular colour). Inlined
/// always: a call left inside the direct-only light loop makes it spill (docs/cost.md).
#[inline(always)]
fn blinn_phong(m: &Material, n: DVec3, wi: DVec3, wo: DVec3) -> Rgb {
    if m.specular == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let Some(h) = (wi + wo).try_normalize() else {
        return Rgb::ZERO;
    };
    m.specular * n.dot(h).max(0.0).powf(m.shininess)
}
