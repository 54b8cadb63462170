//! BSDFs for Monte Carlo: a [`Bsdf`] is a set of [`Lobe`]s in a local shading frame with
//! `eval`, `sample` and `pdf`; non-delta lobes are combined (one-sample MIS over lobes, pbrt-v3
//! `BSDF::Sample_f`, Mitsuba 3 `BlendBSDF`), a lobe is chosen in proportion to the luminance of
//! its weight. Built from a scene [`Material`] as the Whitted tracer reads it: the diffuse albedo
//! is a Lambert lobe, `reflectivity` a mirror (constant weight, no Fresnel) or, with a
//! `conductor`, a metal (conductor Fresnel per channel), `transmissivity` a dielectric interface
//! with exact Fresnel; a `roughness` above [`SMOOTH_ALPHA`] makes the latter two microfacet
//! lobes (GGX or Beckmann, isotropic or anisotropic). See `docs/monte-carlo.md` and
//! `docs/materials.md`.

mod coated;
mod conductor;
mod frame;
mod lobe;
mod material;
mod microfacet;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_chi2;
#[cfg(test)]
mod tests_coated;
#[cfg(test)]
mod tests_conductor;
#[cfg(test)]
mod tests_reset;

pub use coated::{Coating, Transmittance, diffuse_fresnel};
pub use conductor::{ComplexIor, METALS, fr_complex};
pub use frame::Frame;
pub use lobe::{Lobe, fr_dielectric, thin_reflectance};
pub use microfacet::{Distribution, Microfacet, SMOOTH_ALPHA, roughness_to_alpha};

use crate::math::Rgb;
use glam::{DVec2, DVec3};
use lobe::Draw;
pub use material::{Material, Texture};

/// Most lobes a [`Bsdf`] holds: a material has at most three (diffuse, reflectivity,
/// transmissivity). Three, not four, keeps a `Bsdf` small enough (248 bytes) to be cleared
/// by inline stores.
pub const MAX_LOBES: usize = 3;

/// What kind of event a sample is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LobeKind {
    /// Lambertian reflection.
    Diffuse,
    /// Mirror reflection (delta).
    SpecularReflection,
    /// Refraction through a smooth interface (delta).
    SpecularTransmission,
    /// Rough (GGX) reflection.
    GlossyReflection,
    /// Rough (GGX) refraction.
    GlossyTransmission,
}

impl LobeKind {
    /// The lobe in words ("specular transmission").
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            LobeKind::Diffuse => "diffuse",
            LobeKind::SpecularReflection => "specular reflection",
            LobeKind::SpecularTransmission => "specular transmission",
            LobeKind::GlossyReflection => "glossy reflection",
            LobeKind::GlossyTransmission => "glossy transmission",
        }
    }
}

/// A sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The incident direction (towards the light), unit.
    pub wi: DVec3,
    /// The BSDF value `f(wo, wi)`; for a delta event its coefficient `weight / |cos wi|`.
    pub value: Rgb,
    /// The solid-angle pdf (over all non-delta lobes); for a delta event the probability of
    /// having chosen it.
    pub pdf: f64,
    /// The event.
    pub kind: LobeKind,
    /// Whether `wi` came from a delta lobe (no MIS with light sampling possible).
    pub delta: bool,
}

impl BsdfSample {
    /// The path throughput factor `f |cos wi| / pdf` (0 when the pdf is 0).
    #[must_use]
    pub fn weight(&self, cos_wi: f64) -> Rgb {
        if self.pdf > 0.0 {
            self.value * (cos_wi.abs() / self.pdf)
        } else {
            Rgb::ZERO
        }
    }
}

/// Rec. 709 luminance, the lobe-selection weight.
#[must_use]
pub fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// A BSDF: up to [`MAX_LOBES`] lobes, their selection probabilities and the shading frame.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    frame: Frame,
    lobes: [Lobe; MAX_LOBES],
    probs: [f64; MAX_LOBES],
    len: usize,
}

/// Equal frames and equal lobes with equal probabilities (slots past the lobes, which
/// [`Bsdf::reset_at`] leaves as they were, are not compared).
impl PartialEq for Bsdf {
    fn eq(&self, other: &Self) -> bool {
        self.frame == other.frame
            && self.lobes[..self.len] == other.lobes[..other.len]
            && self.probs[..self.len] == other.probs[..other.len]
    }
}

impl Bsdf {
    /// A BSDF of `lobes` in `frame`. Lobes whose weight has no positive luminance are dropped.
    ///
    /// # Panics
    /// With more than [`MAX_LOBES`] lobes (a programming error).
    #[must_use]
    pub fn new(frame: Frame, lobes: &[Lobe]) -> Self {
        assert!(lobes.len() <= MAX_LOBES, "at most {MAX_LOBES} lobes");
        let mut out = Self::empty(frame);
        let mut total = 0.0;
        for lobe in lobes {
            out.push(*lobe, &mut total);
        }
        out.normalise(total);
        out
    }

    /// No lobe and a zero frame: a value for a loop to [`Bsdf::reset_at`] at each hit, which
    /// sets the frame (a constant of zero bytes, which the compiler clears in place rather than
    /// copying it in).
    pub const EMPTY: Self = Self {
        frame: Frame {
            s: DVec3::ZERO,
            t: DVec3::ZERO,
            n: DVec3::ZERO,
        },
        lobes: [Lobe::Lambert { albedo: Rgb::ZERO }; MAX_LOBES],
        probs: [0.0; MAX_LOBES],
        len: 0,
    };

    /// No lobe yet, in `frame`.
    #[inline(always)]
    pub(crate) fn empty(frame: Frame) -> Self {
        Self {
            frame,
            lobes: [Lobe::Lambert { albedo: Rgb::ZERO }; MAX_LOBES],
            probs: [0.0; MAX_LOBES],
            len: 0,
        }
    }

    /// Adds `lobe` with its luminance as selection weight (added to `total`), unless that
    /// weight is not positive and finite.
    #[inline(always)]
    fn push(&mut self, lobe: Lobe, total: &mut f64) {
        let w = luminance(lobe.weight());
        if w > 0.0 && w.is_finite() {
            self.lobes[self.len] = lobe;
            self.probs[self.len] = w;
            self.len += 1;
            *total += w;
        }
    }

    /// Divides the selection weights by their sum `total`.
    #[inline(always)]
    fn normalise(&mut self, total: f64) {
        if self.len == 1 {
            // w / w is exactly 1 for a positive finite w: no division for the common
            // one-lobe material.
            self.probs[0] = 1.0;
            return;
        }
        for p in &mut self.probs[..self.len] {
            *p /= total;
        }
    }

    /// Makes this the BSDF of material `m` at `p` in `frame` for GGX `roughness` and relative
    /// index `eta`, in place (what [`Bsdf::at`] and [`Bsdf::reset_at`] build from a surface
    /// interaction, `crate::interaction`).
    #[inline(always)]
    pub(crate) fn reset_with(
        &mut self,
        frame: Frame,
        m: &Material,
        p: DVec3,
        roughness: f64,
        eta: f64,
    ) {
        self.frame = frame;
        self.len = 0;
        self.add_material(m, p, roughness, eta);
    }

    /// The BSDF of material `m` at `p` in `frame` for GGX `roughness` and relative index `eta`.
    #[must_use]
    pub fn from_material(m: &Material, p: DVec3, frame: Frame, roughness: f64, eta: f64) -> Self {
        let mut out = Self::empty(frame);
        out.add_material(m, p, roughness, eta);
        out
    }

    /// Adds the lobes of `m` at `p` (see [`Bsdf::from_material`]) to an empty BSDF and
    /// normalises their probabilities.
    #[inline(always)]
    fn add_material(&mut self, m: &Material, p: DVec3, roughness: f64, eta: f64) {
        // `roughness` stands for the material's `roughness` (alpha_u); alpha_v follows it on
        // an isotropic material.
        let roughness_v = if m.is_anisotropic() {
            m.roughness_v
        } else {
            roughness
        };
        let rough = roughness.max(roughness_v) >= SMOOTH_ALPHA;
        let dist = Microfacet::with(m.distribution, roughness, roughness_v);
        let mut total = 0.0;
        if let Some(coating) = m.coating {
            // A coated material is one lobe: the coating over its diffuse base.
            let lobe = Lobe::Plastic {
                diffuse: coating.effective(m.diffuse.at(p)),
                specular: m.reflectivity,
                coating,
                dist,
            };
            self.push(lobe, &mut total);
            self.normalise(total);
            return;
        }
        if !m.diffuse.is_black() {
            let albedo = m.diffuse.at(p);
            self.push(Lobe::Lambert { albedo }, &mut total);
        }
        if m.reflectivity != Rgb::ZERO {
            let mut lobe = m.reflection_lobe(rough);
            if let Lobe::RoughMirror { dist: d, .. } | Lobe::RoughConductor { dist: d, .. } =
                &mut lobe
            {
                *d = dist;
            }
            self.push(lobe, &mut total);
        }
        if m.is_transmissive() {
            let weight = m.transmissivity;
            let lobe = if let Some(eta) = m.thin {
                Lobe::ThinDielectric { weight, eta }
            } else if rough && (eta - 1.0).abs() > 1e-9 {
                Lobe::RoughDielectric { weight, eta, dist }
            } else {
                Lobe::Dielectric { weight, eta }
            };
            self.push(lobe, &mut total);
        }
        self.normalise(total);
    }

    /// The shading frame.
    #[must_use]
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The lobes and their selection probabilities.
    pub fn lobes(&self) -> impl Iterator<Item = (&Lobe, f64)> {
        self.lobes[..self.len]
            .iter()
            .zip(self.probs[..self.len].iter().copied())
    }

    /// Whether every lobe is a delta (no point in light sampling).
    #[must_use]
    pub fn is_delta(&self) -> bool {
        self.lobes[..self.len].iter().all(Lobe::is_delta)
    }

    /// `f(wo, wi)` summed over the lobes, local frame.
    #[must_use]
    pub fn eval_local(&self, wo: DVec3, wi: DVec3) -> Rgb {
        self.lobes[..self.len].iter().map(|l| l.eval(wo, wi)).sum()
    }

    /// The combined solid-angle pdf `sum_i p_i pdf_i(wo, wi)` of the non-delta lobes, local.
    #[must_use]
    pub fn pdf_local(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.lobes()
            .map(|(l, p)| if l.is_delta() { 0.0 } else { p * l.pdf(wo, wi) })
            .sum()
    }

    /// Sample `wi` for `wo` (local): `uc` chooses the lobe (and, rescaled, the lobe's own
    /// event), `u` the direction. `None` when the sample carries nothing (a reflection below
    /// the horizon, an exactly grazing delta event, an empty BSDF).
    #[must_use]
    pub fn sample_local(&self, wo: DVec3, uc: f64, u: DVec2) -> Option<BsdfSample> {
        let mut lo = 0.0;
        let mut chosen = None;
        for (i, &p) in self.probs[..self.len].iter().enumerate() {
            if uc < lo + p || i + 1 == self.len {
                chosen = Some((i, ((uc - lo) / p).clamp(0.0, 1.0 - f64::EPSILON / 2.0)));
                break;
            }
            lo += p;
        }
        let (i, uc) = chosen?;
        match self.lobes[i].sample(wo, uc, u)? {
            Draw::Delta(mut s) => {
                s.pdf *= self.probs[i];
                Some(s)
            }
            Draw::Direction(wi, kind) => {
                let pdf = self.pdf_local(wo, wi);
                let value = self.eval_local(wo, wi);
                (pdf > 0.0 && pdf.is_finite() && value.is_finite()).then_some(BsdfSample {
                    wi,
                    value,
                    pdf,
                    kind,
                    delta: false,
                })
            }
        }
    }

    /// [`Self::eval_local`] for world directions.
    #[must_use]
    pub fn eval(&self, wo: DVec3, wi: DVec3) -> Rgb {
        self.eval_local(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// [`Self::pdf_local`] for world directions.
    #[must_use]
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.pdf_local(self.frame.to_local(wo), self.frame.to_local(wi))
    }

    /// The reverse density: that of sampling `wo` given `wi`, `pdf(wi, wo)`, the density the
    /// same pair of directions has on a path traced the other way (from the light when this
    /// one is from the camera). Bidirectional estimators need both: a vertex's forward density
    /// is [`Self::pdf`], its reverse one this (Veach 1997, section 10.2; pbrt-v4's
    /// `BSDF::PDF` with the arguments swapped and `TransportMode` reversed). Not `pdf` in
    /// general: a rough dielectric's densities differ by the `eta^2` of its Jacobian, a
    /// cosine-weighted lobe's by the cosines.
    #[must_use]
    pub fn pdf_rev(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.pdf(wi, wo)
    }

    /// [`Self::sample_local`] for a world `wo`; `wi` is returned in world space.
    #[must_use]
    pub fn sample(&self, wo: DVec3, uc: f64, u: DVec2) -> Option<BsdfSample> {
        let s = self.sample_local(self.frame.to_local(wo), uc, u)?;
        Some(BsdfSample {
            wi: self.frame.to_world(s.wi),
            ..s
        })
    }
}
