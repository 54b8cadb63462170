//! The lobes a material is made of, in the local shading frame (`z` = outward shading normal,
//! `eta = n_inside / n_outside`, so `wo.z < 0` means the ray arrives from inside).
//!
//! Conventions follow pbrt-v4 (`src/pbrt/bxdfs.h`, `bxdfs.cpp`): `eval` is the BSDF value `f`
//! (no cosine), a delta lobe's sample has `f = weight / |cos wi|` and `pdf` = the probability of
//! the event. Transmission carries flux (pbrt-v4's `TransportMode::Importance` form, no
//! `1 / eta^2` radiance scaling), as the Whitted tracer does: it cancels for a closed object with
//! camera and lights outside, and it makes `R + T <= 1` hold per sample.

use super::coated::Coating;
use super::conductor::ComplexIor;
use super::microfacet::{Microfacet, SMOOTH_ALPHA};
use super::{BsdfSample, LobeKind};
use crate::math::{self, Rgb};
use glam::{DVec2, DVec3};
use std::f64::consts::FRAC_1_PI;

/// Smallest `|cos wi|` a delta sample may have (its `f` divides by it).
const MIN_COS: f64 = 1e-12;

/// One lobe and its colour weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    /// Lambertian diffuse `albedo / pi`.
    Lambert {
        /// Albedo.
        albedo: Rgb,
    },
    /// Smooth mirror (delta) of constant reflectance `weight` (the lecture's reflectivity: no
    /// Fresnel, as the Whitted tracer reads it).
    Mirror {
        /// Reflectance.
        weight: Rgb,
    },
    /// Smooth dielectric interface (delta): exact Fresnel `F` reflects, `1 - F` refracts.
    Dielectric {
        /// Overall weight (the lecture's transmissivity).
        weight: Rgb,
        /// `n_inside / n_outside`.
        eta: f64,
    },
    /// A thin dielectric sheet (delta; Mitsuba 3 `thindielectric`): its two faces reflect
    /// `R' = 2R / (1 + R)` of the light in all (the inter-reflections inside summed, `R` the
    /// single face's exact Fresnel at the incident angle) and the rest `1 - R'` passes
    /// straight through, undeviated (the two refractions cancel).
    ThinDielectric {
        /// Overall weight (the material's transmissivity).
        weight: Rgb,
        /// The sheet's index over the medium around it.
        eta: f64,
    },
    /// GGX rough mirror (Fresnel 1 times `weight`; Walter et al. 2007 eq. 20 with `F = 1`).
    RoughMirror {
        /// Reflectance.
        weight: Rgb,
        /// Microfacet distribution.
        dist: Microfacet,
    },
    /// Smooth conductor (delta): a mirror of reflectance `weight * F(cos)` per channel, `F`
    /// the conductor Fresnel of a complex index (pbrt-v4 `ConductorBxDF`, smooth case).
    Conductor {
        /// Tint on the Fresnel reflectance (Mitsuba's `specular_reflectance`).
        weight: Rgb,
        /// Complex index of refraction per channel.
        ior: ComplexIor,
    },
    /// Rough conductor: Walter et al. 2007 eq. 20 with the conductor Fresnel at the microfacet,
    /// `weight F(wo.wm) D G / (4 cos_o cos_i)` (pbrt-v4 `ConductorBxDF`).
    RoughConductor {
        /// Tint on the Fresnel reflectance.
        weight: Rgb,
        /// Complex index of refraction per channel.
        ior: ComplexIor,
        /// Microfacet distribution.
        dist: Microfacet,
    },
    /// A dielectric coating over a Lambertian base (Mitsuba 3 `plastic` / `roughplastic`,
    /// [`super::Coating`]): the coating reflects `specular F` (a delta when smooth, a microfacet
    /// lobe of `dist` when rough), the base is `diffuse t(cos_i) t(cos_o) / (eta^2 (1 -
    /// F_dr,int) pi)`. Two-sided, like [`Lobe::Lambert`].
    Plastic {
        /// The base's albedo `rho` ([`Coating::effective`] of it when the coating is
        /// nonlinear).
        diffuse: Rgb,
        /// The coating's tint `s` (Mitsuba's `specular_reflectance`).
        specular: Rgb,
        /// The coating: index, internal reflectance, rough transmittance.
        coating: Coating,
        /// The coating's microfacets (read only when the coating is rough).
        dist: Microfacet,
    },
    /// GGX rough dielectric (Walter et al. 2007 eq. 20-21, exact Fresnel).
    RoughDielectric {
        /// Overall weight.
        weight: Rgb,
        /// `n_inside / n_outside`.
        eta: f64,
        /// Microfacet distribution.
        dist: Microfacet,
    },
}

/// Unpolarised exact Fresnel reflectance for the signed cosine `cos_i` (positive on the outside)
/// at an interface of relative index `eta = n_inside / n_outside`; 1 under total internal
/// reflection. The Rs, Rp formulas are [`math::fresnel_exact`] (the lecture's).
#[must_use]
pub fn fr_dielectric(cos_i: f64, eta: f64) -> f64 {
    let (mut c, mut e) = (cos_i.clamp(-1.0, 1.0), eta);
    if c < 0.0 {
        e = 1.0 / e;
        c = -c;
    }
    let sin2_t = (1.0 - c * c) / (e * e);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let (rs, rp) = math::fresnel_exact(1.0, e, c, cos_t);
    0.5 * (rs + rp)
}

/// A thin sheet's total reflectance `R' = 2R / (1 + R)` at incident cosine `cos_i` (> 0), `R`
/// the exact Fresnel of one face of index `eta`: the series `R + T^2 R (1 + R^2 + R^4 + ...)`
/// with `T = 1 - R` (Mitsuba 3 `thindielectric`; the same `R` at both faces, whose angles are
/// equal inside the sheet).
#[must_use]
pub fn thin_reflectance(cos_i: f64, eta: f64) -> f64 {
    let r = fr_dielectric(cos_i, eta);
    2.0 * r / (1.0 + r)
}

/// `wo` and `wi` on the same side of the surface.
fn same_side(wo: DVec3, wi: DVec3) -> bool {
    wo.z * wi.z > 0.0
}

/// Mirror `w` about the normal `z`.
fn reflect_z(w: DVec3) -> DVec3 {
    DVec3::new(-w.x, -w.y, w.z)
}

/// What a lobe's `sample` gives: a delta event complete, or a direction whose value and pdf the
/// [`super::Bsdf`] evaluates over all its non-delta lobes.
pub(super) enum Draw {
    /// A delta event.
    Delta(BsdfSample),
    /// A direction from a non-delta lobe.
    Direction(DVec3, LobeKind),
}

impl Lobe {
    /// Whether the lobe is a Dirac delta.
    #[must_use]
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Self::Mirror { .. }
                | Self::Dielectric { .. }
                | Self::ThinDielectric { .. }
                | Self::Conductor { .. }
        )
    }

    /// The colour weight used to choose among lobes.
    #[must_use]
    pub fn weight(&self) -> Rgb {
        match *self {
            Self::Lambert { albedo: w }
            | Self::Mirror { weight: w }
            | Self::Dielectric { weight: w, .. }
            | Self::ThinDielectric { weight: w, .. }
            | Self::RoughMirror { weight: w, .. }
            | Self::Conductor { weight: w, .. }
            | Self::RoughConductor { weight: w, .. }
            | Self::RoughDielectric { weight: w, .. } => w,
            Self::Plastic {
                diffuse, specular, ..
            } => diffuse + specular,
        }
    }

    /// Whether the lobe scatters diffusely: a Lambert lobe, or a plastic with a base.
    #[must_use]
    pub fn is_diffuse(&self) -> bool {
        match self {
            Self::Lambert { .. } => true,
            Self::Plastic { diffuse, .. } => *diffuse != Rgb::ZERO,
            _ => false,
        }
    }

    /// The BSDF value `f(wo, wi)` (0 for delta lobes).
    #[must_use]
    pub fn eval(&self, wo: DVec3, wi: DVec3) -> Rgb {
        match *self {
            Self::Lambert { albedo } if same_side(wo, wi) => albedo * FRAC_1_PI,
            Self::RoughMirror { weight, dist } if same_side(wo, wi) => {
                let wm = (wo + wi).normalize_or_zero();
                let wm = if wm.z < 0.0 { -wm } else { wm };
                let c = (4.0 * wo.z * wi.z).abs();
                weight * (dist.d(wm) * dist.g(wo, wi) / c)
            }
            Self::RoughConductor { weight, ior, dist } if same_side(wo, wi) => {
                rough_conductor_f(weight, ior, dist, wo, wi)
            }
            Self::RoughDielectric { weight, eta, dist } => {
                weight * rough_dielectric_f(dist, eta, wo, wi)
            }
            Self::Plastic { .. } if same_side(wo, wi) => plastic_f(self, wo, wi),
            _ => Rgb::ZERO,
        }
    }

    /// The solid-angle density of `Self::sample`'s direction (0 for delta lobes).
    #[must_use]
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        match *self {
            Self::Lambert { .. } if same_side(wo, wi) => wi.z.abs() * FRAC_1_PI,
            Self::RoughMirror { dist, .. } | Self::RoughConductor { dist, .. }
                if same_side(wo, wi) =>
            {
                let wm = (wo + wi).normalize_or_zero();
                let wm = if wm.z < 0.0 { -wm } else { wm };
                let d = wo.dot(wm).abs();
                if d == 0.0 {
                    0.0
                } else {
                    dist.d_visible(wo, wm) / (4.0 * d)
                }
            }
            Self::RoughDielectric { eta, dist, .. } => rough_dielectric_pdf(dist, eta, wo, wi),
            Self::Plastic { .. } if same_side(wo, wi) => plastic_pdf(self, wo, wi),
            _ => 0.0,
        }
    }

    /// Draw a direction for `wo` from `uc` (event choice) and `u`.
    pub(super) fn sample(&self, wo: DVec3, uc: f64, u: DVec2) -> Option<Draw> {
        let flip = |w: DVec3| if wo.z < 0.0 { -w } else { w };
        match *self {
            Self::Lambert { .. } => {
                let wi = flip(crate::sampling::warp::square_to_cosine_hemisphere(u));
                Some(Draw::Direction(wi, LobeKind::Diffuse))
            }
            Self::Mirror { weight } => {
                delta(reflect_z(wo), weight, 1.0, LobeKind::SpecularReflection)
            }
            Self::Dielectric { weight, eta } => {
                let f = fr_dielectric(wo.z, eta);
                if uc < f {
                    delta(reflect_z(wo), weight * f, f, LobeKind::SpecularReflection)
                } else {
                    let (n, ratio) = if wo.z > 0.0 {
                        (DVec3::Z, 1.0 / eta)
                    } else {
                        (-DVec3::Z, eta)
                    };
                    let t = math::refract(-wo, n, ratio)?;
                    let w = weight * (1.0 - f);
                    delta(t.direction, w, 1.0 - f, LobeKind::SpecularTransmission)
                }
            }
            Self::ThinDielectric { weight, eta } => {
                let r = thin_reflectance(wo.z.abs(), eta);
                if uc < r {
                    delta(reflect_z(wo), weight * r, r, LobeKind::SpecularReflection)
                } else {
                    let w = weight * (1.0 - r);
                    delta(-wo, w, 1.0 - r, LobeKind::SpecularTransmission)
                }
            }
            Self::Conductor { weight, ior } => conductor_sample(weight, ior, wo),
            Self::RoughMirror { dist, .. } | Self::RoughConductor { dist, .. } => {
                let wm = dist.sample_visible(wo, u);
                let wi = -wo + 2.0 * wo.dot(wm) * wm;
                same_side(wo, wi).then_some(Draw::Direction(wi, LobeKind::GlossyReflection))
            }
            Self::Plastic { .. } => plastic_sample(self, wo, uc, u),
            Self::RoughDielectric { eta, dist, .. } => {
                let wm = dist.sample_visible(wo, u);
                let r = fr_dielectric(wo.dot(wm), eta);
                if uc < r {
                    let wi = -wo + 2.0 * wo.dot(wm) * wm;
                    same_side(wo, wi).then_some(Draw::Direction(wi, LobeKind::GlossyReflection))
                } else {
                    let (n, ratio) = if wo.dot(wm) > 0.0 {
                        (wm, 1.0 / eta)
                    } else {
                        (-wm, eta)
                    };
                    let wi = math::refract(-wo, n, ratio)?.direction;
                    (!same_side(wo, wi) && wi.z != 0.0)
                        .then_some(Draw::Direction(wi, LobeKind::GlossyTransmission))
                }
            }
        }
    }
}

/// The rough conductor's `f` (kept out of [`Lobe::eval`], whose common arms stay small).
#[inline(never)]
fn rough_conductor_f(weight: Rgb, ior: ComplexIor, dist: Microfacet, wo: DVec3, wi: DVec3) -> Rgb {
    let wm = (wo + wi).normalize_or_zero();
    let wm = if wm.z < 0.0 { -wm } else { wm };
    let c = (4.0 * wo.z * wi.z).abs();
    if c == 0.0 {
        return Rgb::ZERO;
    }
    weight * ior.fresnel(wo.dot(wm)) * (dist.d(wm) * dist.g(wo, wi) / c)
}

/// `wo` and `wi` mirrored to the upper side when `wo` is below it (a two-sided lobe).
fn upper(wo: DVec3, wi: DVec3) -> (DVec3, DVec3) {
    if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) }
}

/// The plastic lobe's `f` for `wo`, `wi` on one side (see [`Lobe::Plastic`]).
#[inline(never)]
fn plastic_f(lobe: &Lobe, wo: DVec3, wi: DVec3) -> Rgb {
    let Lobe::Plastic {
        diffuse,
        specular,
        coating,
        dist,
    } = *lobe
    else {
        return Rgb::ZERO;
    };
    let (o, i) = upper(wo, wi);
    let base = diffuse * (coating.base_factor(i.z, o.z) * FRAC_1_PI);
    if coating.rough.is_none() {
        return base;
    }
    let wm = (o + i).normalize_or_zero();
    let c = 4.0 * o.z * i.z;
    if c <= 0.0 || wm.z <= 0.0 {
        return base;
    }
    let f = fr_dielectric(o.dot(wm), coating.eta);
    base + specular * (f * dist.d(wm) * dist.g(o, i) / c)
}

/// The plastic lobe's sampling density: the base's cosine-weighted hemisphere and, when rough,
/// the coating's visible normals, mixed by the coating's probability at `wo`.
#[inline(never)]
fn plastic_pdf(lobe: &Lobe, wo: DVec3, wi: DVec3) -> f64 {
    let Lobe::Plastic {
        diffuse,
        specular,
        coating,
        dist,
    } = *lobe
    else {
        return 0.0;
    };
    let (o, i) = upper(wo, wi);
    let ps = coating.coat_probability(o.z, specular, diffuse);
    let mut pdf = (1.0 - ps) * i.z * FRAC_1_PI;
    if coating.rough.is_some() {
        let wm = (o + i).normalize_or_zero();
        let d = o.dot(wm);
        if d > 0.0 && wm.z > 0.0 {
            pdf += ps * dist.d_visible(o, wm) / (4.0 * d);
        }
    }
    pdf
}

/// Draws the plastic lobe: the coating (a mirror event when smooth, a visible normal when
/// rough) with its probability at `wo`, else the base.
#[inline(never)]
fn plastic_sample(lobe: &Lobe, wo: DVec3, uc: f64, u: DVec2) -> Option<Draw> {
    let Lobe::Plastic {
        diffuse,
        specular,
        coating,
        dist,
    } = *lobe
    else {
        return None;
    };
    let flip = |w: DVec3| if wo.z < 0.0 { -w } else { w };
    let cos_o = wo.z.abs();
    let ps = coating.coat_probability(cos_o, specular, diffuse);
    if uc < ps {
        if coating.rough.is_none() {
            let f = fr_dielectric(cos_o, coating.eta);
            return delta(
                reflect_z(wo),
                specular * f,
                ps,
                LobeKind::SpecularReflection,
            );
        }
        let wm = dist.sample_visible(wo, u);
        let wi = -wo + 2.0 * wo.dot(wm) * wm;
        return same_side(wo, wi).then_some(Draw::Direction(wi, LobeKind::GlossyReflection));
    }
    let wi = flip(crate::sampling::warp::square_to_cosine_hemisphere(u));
    Some(Draw::Direction(wi, LobeKind::Diffuse))
}

/// The smooth conductor's mirror event, of weight `weight F(cos)` per channel.
#[inline(never)]
fn conductor_sample(weight: Rgb, ior: ComplexIor, wo: DVec3) -> Option<Draw> {
    let f = weight * ior.fresnel(wo.z);
    delta(reflect_z(wo), f, 1.0, LobeKind::SpecularReflection)
}

/// A delta event, or `None` at exactly grazing `wi` (where `f = weight / |cos|` is unbounded and
/// carries no energy onto the surface).
fn delta(wi: DVec3, weight: Rgb, pdf: f64, kind: LobeKind) -> Option<Draw> {
    if wi.z.abs() < MIN_COS || pdf <= 0.0 {
        return None;
    }
    Some(Draw::Delta(BsdfSample {
        wi,
        value: weight / wi.z.abs(),
        pdf,
        kind,
        delta: true,
    }))
}

/// The generalised half vector of pbrt-v4 `DielectricBxDF` (Walter 2007 eq. 16), facing `+z`,
/// with `etap` (the relative index seen from `wo`'s side) and whether the pair reflects; `None`
/// for degenerate or back-facing configurations (which carry no energy).
fn half_vector(eta: f64, wo: DVec3, wi: DVec3) -> Option<(DVec3, f64, bool)> {
    let (co, ci) = (wo.z, wi.z);
    if co == 0.0 || ci == 0.0 {
        return None;
    }
    let reflect = co * ci > 0.0;
    let etap = if reflect {
        1.0
    } else if co > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    let wm = (wi * etap + wo).try_normalize()?;
    let wm = if wm.z < 0.0 { -wm } else { wm };
    // Discard back-facing microfacets (pbrt-v4).
    if wm.dot(wi) * ci < 0.0 || wm.dot(wo) * co < 0.0 {
        return None;
    }
    Some((wm, etap, reflect))
}

/// The rough dielectric's `f` for unit weight.
fn rough_dielectric_f(dist: Microfacet, eta: f64, wo: DVec3, wi: DVec3) -> f64 {
    if dist.alpha_x.max(dist.alpha_y) < SMOOTH_ALPHA {
        return 0.0;
    }
    let Some((wm, etap, reflect)) = half_vector(eta, wo, wi) else {
        return 0.0;
    };
    let f = fr_dielectric(wo.dot(wm), eta);
    let (co, ci) = (wo.z, wi.z);
    if reflect {
        dist.d(wm) * dist.g(wo, wi) * f / (4.0 * ci * co).abs()
    } else {
        let denom = wi.dot(wm) + wo.dot(wm) / etap;
        let denom = denom * denom * ci * co;
        if denom == 0.0 {
            return 0.0;
        }
        dist.d(wm) * (1.0 - f) * dist.g(wo, wi) * (wi.dot(wm) * wo.dot(wm) / denom).abs()
    }
}

/// The rough dielectric's sampling density: visible normals, the Fresnel choice and the
/// Jacobian of reflection `1 / (4 |wo.wm|)` or refraction `|wi.wm| / (wi.wm + wo.wm / etap)^2`
/// (Walter 2007 eq. 14 and 17).
fn rough_dielectric_pdf(dist: Microfacet, eta: f64, wo: DVec3, wi: DVec3) -> f64 {
    let Some((wm, etap, reflect)) = half_vector(eta, wo, wi) else {
        return 0.0;
    };
    let r = fr_dielectric(wo.dot(wm), eta);
    if reflect {
        let d = wo.dot(wm).abs();
        if d == 0.0 {
            return 0.0;
        }
        dist.d_visible(wo, wm) / (4.0 * d) * r
    } else {
        let denom = wi.dot(wm) + wo.dot(wm) / etap;
        let denom = denom * denom;
        if denom == 0.0 {
            return 0.0;
        }
        dist.d_visible(wo, wm) * wi.dot(wm).abs() / denom * (1.0 - r)
    }
}
