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

use super::lights::Source;
use super::{PathStrategy, PathTracer, Prev};
use crate::bsdf::{Bsdf, Lobe, LobeKind};
use crate::interaction::SurfaceInteraction;
use crate::math::{Rgb, beer};
use crate::sampling::PixelSampler;
use crate::trace::area::emitter_shadow_length;
use crate::trace::local::{Cast, shadow_end};
use crate::trace::{RayCounts, Recorder};
use crate::tree::{
    AreaSample, DeltaTag, EndReason, NodeId, PathInfo, Pdf, RayKind, RayNode, ShadowInfo,
};

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
        if prev.delta || self.strategy == PathStrategy::BsdfOnly || prev.object == object {
            return 1.0;
        }
        let Some((emitter, select)) = self.lights.area(object) else {
            // Not sampled by light sampling (a box or plane emitter): BSDF sampling is the only
            // strategy.
            return 1.0;
        };
        let light_pdf = emitter.pdf(prev.p, dir) * select;
        if light_pdf <= 0.0 {
            return 1.0;
        }
        match self.strategy {
            PathStrategy::LightOnly => 0.0,
            _ => power_heuristic(prev.pdf, light_pdf),
        }
    }

    /// One light sample at `si` (throughput `beta` at the hit), recorded as a shadow child of
    /// `parent`: the contribution to the sample's radiance and the local term it adds (`weight
    /// x radiance`).
    #[allow(clippy::too_many_arguments, clippy::too_many_lines)]
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
        let scene = self.scene();
        if self.lights.is_empty() {
            return (Rgb::ZERO, Rgb::ZERO);
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let (_, source, select) = self.lights.choose(uc);
        let (ls, area, light) = match *source {
            Source::Delta(k) => (Some(scene.lights[k].sample(si.p, u)), None, k),
            Source::Area {
                object,
                ref prepared,
                emission,
                ..
            } => {
                // A surface does not light itself (spheres, quads and triangles are convex; a
                // mesh does not light its own other triangles).
                let ls = (object != si.object)
                    .then(|| prepared.sample(si.p, emission, u))
                    .flatten();
                (ls, Some(object), scene.lights.len() + object)
            }
        };
        let Some(ls) = ls else {
            return (Rgb::ZERO, Rgb::ZERO);
        };
        let wi = ls.direction;
        // The shadow ray leaves on the geometric side of wi; the shading normal must agree.
        let up = wi.dot(si.n) > 0.0;
        let cos_s = wi.dot(si.ns);
        let f = if (cos_s > 0.0) == up && cos_s != 0.0 {
            bsdf.eval(si.wo, wi)
        } else {
            Rgb::ZERO
        };
        let f_cos = f * cos_s.abs();
        let light_pdf = select * ls.pdf;
        let mis = if ls.delta || self.strategy == PathStrategy::LightOnly {
            1.0
        } else {
            power_heuristic(light_pdf, bsdf.pdf(si.wo, wi))
        };
        let weight = if light_pdf > 0.0 {
            f_cos * (mis / light_pdf)
        } else {
            Rgb::ZERO
        };
        let side = if up { si.n } else { -si.n };
        let strategy = scene.settings.offset.strategy;
        let (ray, seg) = self
            .tracer
            .shadow_ray(strategy, si.from(), si.p, side, wi, ls.distance);
        let seg = match area {
            Some(object) => emitter_shadow_length(scene, object, &ray, seg, si.p),
            None => seg,
        };
        let mut event = String::new();
        if R::RECORDS {
            event = format!("{lpe}{}L", lobe_event(bsdf, up == (si.wo.dot(si.n) > 0.0)));
        }
        let id = rec.push(parent, || {
            let mut node = RayNode::new(RayKind::Shadow, depth, si.p, ray.origin, ray.direction);
            node.t_min = ray.t_min;
            node.weight = weight;
            node.path = Some(PathInfo {
                lobe: None,
                pdf: Some(if ls.delta {
                    Pdf::Delta(DeltaTag::Delta)
                } else {
                    Pdf::Density(light_pdf)
                }),
                bsdf_cos_pdf: Some(f_cos),
                mis_weight: Some(mis),
                roulette: None,
                contribution: Rgb::ZERO,
                lpe: event,
            });
            node
        });
        let info = |blockers, transmittance| ShadowInfo {
            light,
            light_name: match area {
                Some(o) => scene.objects[o].name.clone(),
                None => scene.lights[light].name.clone(),
            },
            distance: ls.distance,
            cos_theta: cos_s,
            brdf: f,
            irradiance: ls.value(),
            blockers,
            transmittance,
            area: area.map(|object| AreaSample {
                object,
                point: si.p + ls.distance * wi,
                direction: wi,
                pdf: ls.pdf,
                radiance: ls.radiance,
                sample: 0,
            }),
        };
        if weight == Rgb::ZERO {
            rec.update(id, |node| {
                node.end = EndReason::LightBehind;
                node.shadow = Some(info(Vec::new(), Rgb::ZERO));
            });
            return (Rgb::ZERO, Rgb::ZERO);
        }
        let Cast {
            transmittance,
            blockers,
            cost,
        } = self
            .tracer
            .cast_shadow(&ray, seg, (si.p, si.from()), id, rec, counts);
        // Unblocked, the whole segment lies in the medium around the point: Beer's law on it.
        let medium = si
            .media
            .top()
            .map(|m| scene.material_of(m.object as usize).absorption);
        let absorbed = match medium {
            Some(a) if a != Rgb::ZERO && transmittance != Rgb::ZERO => beer(a, ls.distance),
            _ => Rgb::ONE,
        };
        let radiance = ls.radiance * transmittance * absorbed;
        let local = if transmittance == Rgb::ZERO {
            Rgb::ZERO
        } else {
            weight * radiance
        };
        let c = beta * local;
        if R::PATHS {
            let reflect = up == (si.wo.dot(si.n) > 0.0);
            rec.contribution(lpe, lobe_event(bsdf, reflect), 'L', c);
        }
        rec.update(id, |node| {
            node.traversal = cost;
            node.radiance = radiance;
            node.end = shadow_end(transmittance);
            node.shadow = Some(info(blockers, transmittance));
            if let Some(p) = node.path.as_mut() {
                p.contribution = c;
            }
        });
        (c, local)
    }
}

/// The event of a light sample's scattering: `<RD>` when the BSDF has a Lambert lobe and the
/// light is on the viewer's side, `<RG>`/`<TG>` for a glossy lobe on either side.
fn lobe_event(bsdf: &Bsdf, reflect: bool) -> &'static str {
    let diffuse = bsdf.lobes().any(|(l, _)| matches!(l, Lobe::Lambert { .. }));
    event(match (reflect, diffuse) {
        (true, true) => LobeKind::Diffuse,
        (true, false) => LobeKind::GlossyReflection,
        (false, _) => LobeKind::GlossyTransmission,
    })
}

/// Whether `kind` crosses the surface.
pub(super) fn transmits(kind: LobeKind) -> bool {
    matches!(
        kind,
        LobeKind::SpecularTransmission | LobeKind::GlossyTransmission
    )
}

/// The light path expression event of a sampled lobe (OSL alphabet).
pub(super) fn event(kind: LobeKind) -> &'static str {
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
