//! Glossy reflection and refraction in the Whitted integrator (issue 14, distribution ray
//! tracing after Cook et al. 1984). A material with `roughness >= SMOOTH_ALPHA` turns its
//! `reflectivity` into a GGX rough mirror and its `transmissivity` into a GGX rough dielectric
//! (Walter et al. 2007, exact Fresnel per microfacet, separable Smith `G1(wo) G1(wi)`), both
//! from [`crate::bsdf`]. Each rough lobe is estimated by `n` rays drawn from it by visible
//! normals (Heitz 2018):
//!
//! `L_lobe = (1/n) sum_k f(wo, wi_k) abs(cos wi_k) L(wi_k) / pdf(wi_k)`
//!
//! with `n = settings.glossy_samples` at the first rough hit of a path and 1 below a sampled
//! ray (splitting once keeps a sample's tree linear in `n`; splitting at every rough hit grows
//! it as `n^k` through `k` rough hits, e.g. 4 interfaces of a frosted ball). For visible-normal
//! sampling a sample's factor `f cos / pdf` is `weight x G1(wi) <= weight` (the rough
//! dielectric's reflection and refraction alike, its Fresnel choice cancelling `F` and `1 -
//! F`), so the automatic min-weight bound (`bound.rs`) holds per sample.
//!
//! The rough dielectric is sampled as a whole (reflection or refraction chosen by the Fresnel
//! of the sampled microfacet, pbrt-v4 `DielectricBxDF::Sample_f`), not split into a reflected
//! and a refracted ray: one ray per sample, and the split's weights come out of the Fresnel
//! choice. A refracted sample enters or leaves the object's medium (the media stack, as the
//! smooth split does); a reflected one stays in the medium it came from. A sample on the wrong
//! side of the geometric surface (possible with a mesh's shading normals) is not traced.
//!
//! Point and directional lights light the rough lobes' reflection through their BSDF value
//! (a glossy highlight; `direct` in `local.rs`). Area lights do not: emitters are seen by the
//! sampled rays instead (their emission is added where a ray hits them, as for mirrors and
//! glass), so light sampling them too would count them twice without multiple importance
//! sampling, which is not done.

use super::{PathState, Secondary, Spawn, Whitted};
use crate::bsdf::{Bsdf, Lobe, LobeKind};
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::SurfaceInteraction;
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use crate::tree::{GlossyLobe, GlossySample, RayKind};
use glam::{DVec2, DVec3};

/// Whether a rough `transmissivity` lobe at `si` refracts (not index-matched), as
/// [`Bsdf::from_material`] decides. Never inlined: `eta` builds a media stack, which would
/// otherwise sit in every recursion level's stack frame.
#[inline(never)]
pub(super) fn refracts(si: &SurfaceInteraction) -> bool {
    (si.eta() - 1.0).abs() > 1e-9
}

/// The rough lobes of `si`'s material (call only when [`crate::scene::Material::is_rough`]).
fn rough_lobes(si: &SurfaceInteraction) -> [Option<(GlossyLobe, Lobe)>; 2] {
    let m = si.material;
    let dist = m.microfacet();
    let mirror = (m.reflectivity != Rgb::ZERO).then(|| {
        let kind = match (m.conductor, m.coating) {
            (Some(_), _) => GlossyLobe::RoughConductor,
            (None, Some(_)) => GlossyLobe::RoughCoating,
            (None, None) => GlossyLobe::RoughMirror,
        };
        (kind, m.reflection_lobe(true))
    });
    let dielectric = (m.is_transmissive() && refracts(si)).then(|| {
        (
            GlossyLobe::RoughDielectric,
            Lobe::RoughDielectric {
                weight: m.transmissivity,
                eta: si.eta(),
                dist,
            },
        )
    });
    [mirror, dielectric]
}

impl Whitted<'_> {
    /// The rough lobes' BSDF value for light arriving from `wi` (world) on the side the ray
    /// came from (reflection only: light through the surface is not sampled, as for smooth
    /// glass). Zero unless the material is rough and the plan has glossy lobes. Never inlined:
    /// its locals would otherwise sit in every recursion level's stack frame.
    #[inline(never)]
    pub(super) fn glossy_brdf(&self, si: &SurfaceInteraction, wi: DVec3) -> Rgb {
        if !(self.core.plan.glossy && si.material.is_rough()) {
            return Rgb::ZERO;
        }
        let frame = si.frame();
        let (wo, wi) = (frame.to_local(si.wo), frame.to_local(wi));
        if wo.z * wi.z <= 0.0 {
            return Rgb::ZERO;
        }
        let f: Rgb = rough_lobes(si)
            .iter()
            .flatten()
            .map(|(_, lobe)| lobe.eval(wo, wi))
            .sum();
        if f.is_finite() { f } else { Rgb::ZERO }
    }

    /// The sampled rays of the rough lobes at `si` (children of `at.parent`), added into `acc`;
    /// `state` is the parent's with the throughput at the hit. Never inlined into `shade`: its
    /// locals (a BSDF, a media stack) would grow every recursion level's stack frame
    /// (`max_depth` 1024 overflowed a worker's stack).
    // The accumulator, the hit, the spawn and path state, plus the sampler, recorder and counts every tracing function threads.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub(super) fn glossy_rays<R: Recorder, S: PixelSampler>(
        &self,
        acc: &mut Secondary,
        si: &SurfaceInteraction,
        at: Spawn,
        state: PathState,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        let m = si.material;
        let count = match state.glossy {
            None => self.core.scene.settings.whitted.glossy_samples.max(1),
            Some(_) => 1,
        };
        let split = state.glossy.unwrap_or(count);
        let inv = 1.0 / f64::from(count);
        let frame = si.frame();
        let wo = frame.to_local(si.wo);
        for (lobe_kind, lobe) in rough_lobes(si).into_iter().flatten() {
            let bsdf = Bsdf::new(frame, &[lobe]);
            for k in 0..count {
                let uc = sampler.next_1d();
                let (u0, u1) = sampler.next_2d();
                let Some(s) = bsdf.sample_local(wo, uc, DVec2::new(u0, u1)) else {
                    continue;
                };
                let transmitted = s.kind == LobeKind::GlossyTransmission;
                let wi = frame.to_world(s.wi);
                let side = if transmitted { -si.n } else { si.n };
                let cos = s.wi.z.abs();
                let weight = s.weight(cos) * inv;
                if wi.dot(side) <= 0.0 || !weight.is_finite() || weight.max_element() <= 0.0 {
                    continue;
                }
                let glossy = GlossySample {
                    lobe: lobe_kind,
                    sample: k,
                    count,
                    pdf: s.pdf,
                    bsdf: s.value,
                    cos,
                    transmitted,
                };
                let spawn = Spawn {
                    kind: if transmitted {
                        RayKind::Refracted
                    } else {
                        RayKind::Reflected
                    },
                    weight,
                    ..at
                };
                let entered;
                let media = if !transmitted {
                    state.media
                } else {
                    entered = if si.entering {
                        let ior = m.ior.unwrap_or(state.media.ior());
                        state.media.entered(si.object, ior)
                    } else {
                        state.media.left(si.object)
                    };
                    &entered
                };
                let state = PathState {
                    media,
                    glossy: Some(split),
                    ..state
                };
                let id = self.secondary(acc, spawn, wi, side, state, sampler, rec, counts);
                rec.update(id, |n| n.glossy = Some(glossy));
            }
        }
    }
}
