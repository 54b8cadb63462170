//! Next-event estimation and the MIS weights of the path tracer: one light sample per hit,
//! the light chosen in proportion to its power among the scene's point and directional lights
//! and its emissive spheres, quads, triangles and meshes ([`super::lights`]), then a point
//! (direction) on it from the light-sampling kernel
//! ([`crate::scene::Light::sample`], [`crate::scene::AreaEmitter::sample`]).
//!
//! The light sample's estimator is `f |cos| Le V / (p_select p_light)`, weighted by the power
//! heuristic against the BSDF's pdf of the same direction (Veach 1997 eq. 9.13; pbrt-v4
//! `PathIntegrator::SampleLd`); delta lights have weight 1. Emission found by a BSDF-sampled
//! ray is weighted by the power heuristic the other way round ([`PathTracer::emission_weight`]).

use super::{PathStrategy, PathTracer, Prev};
use crate::bsdf::{Bsdf, LobeKind};
use crate::integrator::direct::{DirectKernel, LightEval, LightPick};
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSample};
use crate::math::{Rgb, beer};
use crate::sampling::PixelSampler;
use crate::scene::Scene;
use crate::tree::{DeltaTag, NodeId, PathInfo, Pdf, RayNode};

/// The path tracer's weights of a light sample: `f |cos| mis / (p_select p_light)`.
struct PathKernel<'k> {
    scene: &'k Scene,
    bsdf: &'k Bsdf,
    strategy: PathStrategy,
    /// The probability of having chosen the light.
    select: f64,
    /// The light path expression of the path so far (recording only).
    lpe: &'k str,
}

impl DirectKernel for PathKernel<'_> {
    #[inline(always)]
    fn eval(&self, si: &SurfaceInteraction, _: &Light, ls: &LightSample) -> LightEval {
        let wi = ls.direction;
        // The shadow ray leaves on the geometric side of wi; the shading normal must agree.
        let up = wi.dot(si.n) > 0.0;
        let cos_s = wi.dot(si.ns);
        let f = if (cos_s > 0.0) == up && cos_s != 0.0 {
            self.bsdf.eval(si.wo, wi)
        } else {
            Rgb::ZERO
        };
        let f_cos = f * cos_s.abs();
        let light_pdf = self.select * ls.pdf;
        let mis = if ls.delta || self.strategy == PathStrategy::LightOnly {
            1.0
        } else {
            power_heuristic(light_pdf, self.bsdf.pdf(si.wo, wi))
        };
        let weight = if light_pdf > 0.0 {
            f_cos * (mis / light_pdf)
        } else {
            Rgb::ZERO
        };
        LightEval {
            cos: cos_s,
            brdf: f,
            weight,
            value: ls.radiance,
            mis,
            side: if up { si.n } else { -si.n },
            behind: weight == Rgb::ZERO,
        }
    }

    /// Unblocked, the whole segment lies in the medium around the point: Beer's law on it.
    #[inline(always)]
    fn arriving(
        &self,
        si: &SurfaceInteraction,
        (ls, eval): (&LightSample, &LightEval),
        t: Rgb,
    ) -> Rgb {
        let medium = si
            .media
            .top()
            .map(|m| self.scene.material_of(m.object as usize).absorption);
        let absorbed = match medium {
            Some(a) if a != Rgb::ZERO && t != Rgb::ZERO => beer(a, ls.distance),
            _ => Rgb::ONE,
        };
        eval.value * t * absorbed
    }

    fn annotate(
        &self,
        node: &mut RayNode,
        si: &SurfaceInteraction,
        (ls, eval): (&LightSample, &LightEval),
    ) {
        let reflect = reflects(si, eval.side);
        let light_pdf = self.select * ls.pdf;
        node.path = Some(PathInfo {
            lobe: None,
            pdf: Some(if ls.delta {
                Pdf::Delta(DeltaTag::Delta)
            } else {
                Pdf::Density(light_pdf)
            }),
            bsdf_cos_pdf: Some(eval.brdf * eval.cos.abs()),
            mis_weight: Some(eval.mis),
            roulette: None,
            strategy: None,
            unweighted: None,
            contribution: Rgb::ZERO,
            lpe: format!("{}{}L", self.lpe, lobe_event(self.bsdf, reflect)),
        });
    }
}

impl PathTracer<'_> {
    /// The MIS weight of emission from `object` found along `dir` by the ray spawned at `prev`
    /// (`None`: a camera ray, weight 1).
    pub(super) fn emission_weight(
        &self,
        prev: Option<Prev>,
        object: usize,
        dir: glam::DVec3,
    ) -> f64 {
        let Some(prev) = prev else {
            return 1.0;
        };
        if prev.delta || self.strategy == PathStrategy::BsdfOnly || prev.from.object == object {
            return 1.0;
        }
        let Some((light, select)) = self.core.lights.area(object) else {
            // Not sampled by light sampling (a box or plane emitter): BSDF sampling is the only
            // strategy.
            return 1.0;
        };
        let light_pdf = light.pdf_li(prev.p, dir) * select;
        if light_pdf <= 0.0 {
            return 1.0;
        }
        match self.strategy {
            PathStrategy::LightOnly => 0.0,
            _ => power_heuristic(prev.pdf, light_pdf),
        }
    }

    /// One light sample at `si` (throughput `beta` at the hit), recorded as a shadow child of
    /// `parent` by the shared estimator (`crate::integrator::direct`): the contribution to the
    /// sample's radiance and the local term it adds (`weight x radiance`).
    #[allow(clippy::too_many_arguments)] // The hit, its BSDF, the throughput and the path's LPE, plus the estimator's sampler, recorder and counts.
    pub(super) fn nee<R: Recorder, S: PixelSampler>(
        &self,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        beta: Rgb,
        (parent, depth): (Option<NodeId>, u32),
        lpe: &str,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Rgb) {
        let lights = &self.core.lights;
        if lights.is_empty() {
            return (Rgb::ZERO, Rgb::ZERO);
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let (index, light, select) = lights.choose(uc);
        // A surface does not light itself (spheres, quads and triangles are convex; a mesh does
        // not light its own other triangles).
        if light.object() == Some(si.object) {
            return (Rgb::ZERO, Rgb::ZERO);
        }
        let kernel = PathKernel {
            scene: self.scene(),
            bsdf,
            strategy: self.strategy,
            select,
            lpe,
        };
        let pick = LightPick { index, light, k: 0 };
        let at = (parent, depth);
        let Some(d) = self.core.direct(si, pick, (u, &kernel), at, rec, counts) else {
            return (Rgb::ZERO, Rgb::ZERO);
        };
        if !d.cast {
            return (Rgb::ZERO, Rgb::ZERO);
        }
        let c = beta * d.local;
        if R::PATHS {
            let reflect = reflects(si, d.side);
            rec.contribution(lpe, lobe_event(bsdf, reflect), 'L', c);
        }
        rec.update(d.id, |node| {
            if let Some(p) = node.path.as_mut() {
                p.contribution = c;
            }
        });
        (c, d.local)
    }
}

/// Whether a light sample whose shadow ray leaves from the side of normal `side` is on the
/// viewer's side of `si` (a reflection, not a transmission).
fn reflects(si: &SurfaceInteraction, side: glam::DVec3) -> bool {
    (side == si.n) == (si.wo.dot(si.n) > 0.0)
}

/// The event of a light sample's scattering: `<RD>` when the BSDF has a diffuse lobe (Lambert
/// or a plastic's base) and the light is on the viewer's side, `<RG>`/`<TG>` for a glossy lobe on either side.
fn lobe_event(bsdf: &Bsdf, reflect: bool) -> &'static str {
    let diffuse = bsdf.lobes().any(|(l, _)| l.is_diffuse());
    event(match (reflect, diffuse) {
        (true, true) => LobeKind::Diffuse,
        (true, false) => LobeKind::GlossyReflection,
        (false, _) => LobeKind::GlossyTransmission,
    })
}

/// Whether `kind` crosses the surface.
pub(crate) fn transmits(kind: LobeKind) -> bool {
    matches!(
        kind,
        LobeKind::SpecularTransmission | LobeKind::GlossyTransmission
    )
}

/// The light path expression event of a sampled lobe (OSL alphabet).
pub(crate) fn event(kind: LobeKind) -> &'static str {
    match kind {
        LobeKind::Diffuse => "<RD>",
        LobeKind::SpecularReflection => "<RS>",
        LobeKind::SpecularTransmission => "<TS>",
        LobeKind::GlossyReflection => "<RG>",
        LobeKind::GlossyTransmission => "<TG>",
    }
}

/// The power heuristic with beta 2 (Veach 1997, eq. 9.13) for `nf` samples of pdf `f` against
/// one sample of pdf `g`: `f^2 / (f^2 + g^2)`; 1 when `g` is 0, and for an infinite `f`.
#[must_use]
pub(crate) fn power_heuristic(f: f64, g: f64) -> f64 {
    if f.is_infinite() {
        return 1.0;
    }
    let (f2, g2) = (f * f, g * g);
    if f2 + g2 > 0.0 { f2 / (f2 + g2) } else { 0.0 }
}
