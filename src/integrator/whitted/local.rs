//! The lecture's local term at a hit: emitted + ambient + the direct light of every light
//! through its shadow ray, one per point or directional light, and `settings.light_samples` per
//! area light (issue 14, distribution ray tracing after Cook et al. 1984):
//!
//! `L_direct = (1/N) sum_k f(wi_k) cos(wi_k) L_e(wi_k) V(wi_k) / pdf(wi_k)`
//!
//! (pbrt-v4 section 13.4, Veach 1997 eq. 8.10 for the area-to-solid-angle pdf). Every sample
//! goes through the shared estimator (`crate::integrator::direct`); this file gives its
//! Whitted weights ([`WhittedKernel`]): Lambert `albedo / pi` plus the Blinn-Phong highlight
//! (and a rough lobe's glossy highlight for delta lights, `glossy.rs`), times `cos`. The area
//! lights' 2D samples come from the pixel's sampler, so a re-traced pixel reproduces its value
//! bit for bit. Emission itself is added only where a camera, mirror or refracted ray hits the
//! emitter (Whitted has no diffuse bounce), so nothing is counted twice.

use super::Whitted;
use crate::integrator::direct::{DirectKernel, LightEval, LightPick};
use crate::integrator::shading::{DELTA_U, cos_to_light};
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSample};
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use crate::scene::Material;
use crate::tree::NodeId;
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

/// The Whitted weights of a light sample at one hit.
struct WhittedKernel<'t, 'a> {
    tracer: &'t Whitted<'a>,
    /// Diffuse albedo at the hit.
    albedo: Rgb,
    /// `1 / N` for an area light's `N` samples.
    inv_n: f64,
}

impl DirectKernel for WhittedKernel<'_, '_> {
    #[inline(always)]
    fn eval(&self, si: &SurfaceInteraction, light: &Light, ls: &LightSample) -> LightEval {
        let plan = self.tracer.plan();
        let wi = ls.direction;
        let cos = cos_to_light(si.n, si.ns, wi);
        let m = si.material;
        let (mut brdf, mut weight) =
            Whitted::light_weight(plan.specular, m, self.albedo, si.ns, (wi, si.wo), cos);
        let delta = light.is_delta();
        let value = ls.value();
        if delta {
            if plan.glossy && cos > 0.0 && m.is_rough() {
                // The rough lobes' glossy highlight (glossy.rs).
                brdf += self.tracer.glossy_brdf(si, wi);
                weight = brdf * cos;
            }
        } else {
            weight *= self.inv_n;
        }
        LightEval {
            cos,
            brdf,
            weight,
            value,
            mis: 1.0,
            side: si.n,
            behind: cos <= 0.0 || (!delta && value == Rgb::ZERO),
        }
    }

    #[inline(always)]
    fn arriving(
        &self,
        _: &SurfaceInteraction,
        (_, eval): (&LightSample, &LightEval),
        t: Rgb,
    ) -> Rgb {
        eval.value * t
    }
}

impl Whitted<'_> {
    /// Emitted + ambient + the direct light of every light that can light something, with one
    /// shadow ray per delta light in front of the surface and `light_samples` per area light
    /// (recorded as children of `id`).
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
        let ambient = self.scene().ambient * albedo;
        let mut total = emitted + ambient;
        let shaded = !m.diffuse.is_black() || m.specular != Rgb::ZERO;
        let plan = self.plan();
        if shaded || plan.glossy && m.is_rough() {
            let kernel = WhittedKernel {
                tracer: self,
                albedo,
                inv_n: 1.0,
            };
            let lights = self.core.lights.delta_lights();
            for (index, light) in lights.iter().enumerate() {
                if !plan.light_on(index) {
                    continue;
                }
                let pick = LightPick { index, light, k: 0 };
                let d = self
                    .core
                    .direct(si, pick, (DELTA_U, &kernel), (id, depth), rec, counts);
                total += d.map_or(Rgb::ZERO, |d| d.local);
            }
            // Area lights reach rough lobes through their sampled rays instead (glossy.rs).
            if plan.area_lights && shaded {
                total += self.area_direct(si, albedo, (id, depth), sampler, rec, counts);
            }
        }
        Local {
            emitted,
            ambient,
            total,
        }
    }

    /// The direct light at `si` (diffuse albedo `albedo`) from every area light but the surface
    /// itself, `light_samples` recorded shadow rays each (children of `parent`).
    fn area_direct<R: Recorder, S: PixelSampler>(
        &self,
        si: &SurfaceInteraction,
        albedo: Rgb,
        at: (Option<NodeId>, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let n = self
            .scene()
            .settings
            .whitted
            .light_samples
            .unwrap_or(1)
            .max(1);
        let kernel = WhittedKernel {
            tracer: self,
            albedo,
            inv_n: 1.0 / f64::from(n),
        };
        let lights = &self.core.lights;
        let first = lights.delta_lights().len();
        let mut total = Rgb::ZERO;
        for (i, light) in lights.area_lights().iter().enumerate() {
            if light.object() == Some(si.object) {
                continue;
            }
            for k in 0..n {
                let u = sampler.next_2d();
                let pick = LightPick {
                    index: first + i,
                    light,
                    k,
                };
                if let Some(d) = self.core.direct(si, pick, (u, &kernel), at, rec, counts) {
                    total += d.local;
                }
            }
        }
        total
    }

    /// The BRDF (Lambert `albedo / pi`, seen through the coating's transmittance when the
    /// material has one, plus the Blinn-Phong highlight when the plan has one) and the weight
    /// `brdf * max(cos, 0)` of a light at cosine `cos` (both zero behind). `specular` is the
    /// plan's (constant in the direct-only path's loops).
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
            let diffuse = albedo * std::f64::consts::FRAC_1_PI;
            let diffuse = match m.coating {
                None => diffuse,
                Some(c) => {
                    c.effective(albedo)
                        * (std::f64::consts::FRAC_1_PI * c.base_factor(cos, wo.dot(ns).abs()))
                }
            };
            diffuse + highlight
        } else {
            Rgb::ZERO
        };
        (brdf, brdf * cos.max(0.0))
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
