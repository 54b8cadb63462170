//! A dielectric coating over a Lambertian base: Mitsuba 3's `plastic` (smooth) and
//! `roughplastic` (rough) BSDFs, the model of Weidlich and Wilkie 2007 ("Arbitrarily layered
//! micro-facet surfaces") as Mitsuba writes it (`src/bsdfs/plastic.cpp`, `roughplastic.cpp`).
//!
//! With `wo`, `wi` above the surface, `F` the dielectric Fresnel of the coating (index `eta`
//! over the outside), `rho` the base albedo and `s` the coating's tint:
//!
//! - the coating reflects `s F(wo.m)` (a mirror when smooth, Walter et al. 2007's microfacet
//!   reflection `s F D G / (4 cos_o cos_i)` when rough);
//! - the base is seen through it: `f_d = rho / (1 - F_dr,int) * t(cos_i) t(cos_o) / (eta^2 pi)`.
//!   `t(mu)` is the coating's transmittance from the outside (`1 - F(mu)` when smooth; the
//!   rough dielectric's transmitted fraction, tabulated, when rough) and `F_dr,int` the
//!   coating's hemispherical reflectance seen from inside (the diffuse light the coating sends
//!   back to the base). Dividing by `1 - F_dr,int` sums the inter-reflections between base and
//!   coating as if the base were white (Mitsuba's default `nonlinear = false`); `1 / eta^2` is
//!   the radiance compression of refraction into the coating.
//!
//! For a white base and a white smooth coating the directional albedo is exactly
//! `F(cos_o) + (1 - F(cos_o)) = 1` (because `(1 - F_dr,ext) = eta^2 (1 - F_dr,int)`), and for
//! a base of albedo `rho` it is `s F(cos_o) + (1 - F(cos_o)) rho`: the tests pin both.
//!
//! `F_dr` here is computed by quadrature of the exact Fresnel, not by Mitsuba's polynomial fit
//! of d'Eon and Irving (which is within 1e-3 of it for `eta` 1.5; see the tests).
//!
//! The lobe is sampled as Mitsuba does: the coating with probability
//! `(1 - t(cos_o)) w / ((1 - t(cos_o)) w + t(cos_o) (1 - w))`, `w = mean(s) / (mean(s) +
//! mean(rho))`, else the base by the cosine-weighted hemisphere.

use super::microfacet::{Distribution, Microfacet};
use crate::math::Rgb;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock, PoisonError};

/// Points of the rough transmittance table, `mu = k / (RES - 1)` (Mitsuba's
/// `MI_ROUGH_TRANSMITTANCE_RES`).
pub const RES: usize = 64;

/// Quadrature nodes per axis of the visible-normal square when tabulating.
const NODES: usize = 64;

/// A coating's transmittance from the outside, `t(mu)` at `RES` cosines, linearly
/// interpolated; and its hemispherical internal reflectance.
#[derive(Debug, PartialEq)]
pub struct Transmittance {
    values: [f64; RES],
    /// `F_dr,int`: `2 int_0^1 R_int(mu) mu dmu` of the rough interface seen from inside.
    pub internal: f64,
}

impl Transmittance {
    /// `t(mu)`, `mu` clamped to `[0, 1]`.
    #[must_use]
    pub fn at(&self, mu: f64) -> f64 {
        let x = mu.clamp(0.0, 1.0) * (RES - 1) as f64;
        let i = (x as usize).min(RES - 2);
        let f = x - i as f64;
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }
}

/// A dielectric coating: its index and, when rough, the tabulated transmittance of its
/// microfacet interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coating {
    /// Index of the coating over the outside medium (> 0, not 1).
    pub eta: f64,
    /// `F_dr,int`, the hemispherical reflectance of the coating from inside.
    pub internal: f64,
    /// The rough interface's transmittance table (`None`: smooth).
    pub rough: Option<&'static Transmittance>,
    /// Whether the inter-reflections between base and coating are tinted by the base
    /// (Mitsuba's `nonlinear`): see [`Coating::effective`].
    pub nonlinear: bool,
}

impl Coating {
    /// A smooth coating of index `eta`.
    #[must_use]
    pub fn smooth(eta: f64) -> Self {
        Self {
            eta,
            internal: diffuse_fresnel(1.0 / eta),
            rough: None,
            nonlinear: false,
        }
    }

    /// A coating of index `eta` with microfacets `dist` (smooth below
    /// [`super::SMOOTH_ALPHA`]).
    #[must_use]
    pub fn new(eta: f64, dist: Option<Microfacet>) -> Self {
        match dist {
            None => Self::smooth(eta),
            Some(d) => {
                let t = table(eta, d);
                Self {
                    eta,
                    internal: t.internal,
                    rough: Some(t),
                    nonlinear: false,
                }
            }
        }
    }

    /// `t(mu)`, the coating's transmittance at cosine `mu` (> 0) from the outside.
    #[must_use]
    #[inline]
    pub fn transmittance(&self, mu: f64) -> f64 {
        match self.rough {
            None => 1.0 - super::fr_dielectric(mu, self.eta),
            Some(t) => t.at(mu),
        }
    }

    /// The factor on the base's `rho / pi`: `t(cos_i) t(cos_o) / (eta^2 (1 - F_dr,int))` for
    /// cosines on the outside (0 otherwise).
    #[must_use]
    #[inline]
    pub fn base_factor(&self, cos_i: f64, cos_o: f64) -> f64 {
        if cos_i <= 0.0 || cos_o <= 0.0 {
            return 0.0;
        }
        self.transmittance(cos_i) * self.transmittance(cos_o) * self.base_scale()
    }

    /// The albedo the base factor multiplies: `rho` itself, or, when `nonlinear`, `rho (1 -
    /// F_dr,int) / (1 - rho F_dr,int)` per channel, so that the light going back and forth
    /// between base and coating is absorbed by the base at every bounce (`sum_k (rho
    /// F_dr,int)^k` instead of `sum_k F_dr,int^k`; the two agree for a white base).
    #[must_use]
    #[inline]
    pub fn effective(&self, rho: Rgb) -> Rgb {
        if !self.nonlinear {
            return rho;
        }
        let fi = self.internal;
        let one = |r: f64| r * (1.0 - fi) / (1.0 - r * fi).max(1e-12);
        Rgb::new(one(rho.x), one(rho.y), one(rho.z))
    }

    /// `1 / (eta^2 (1 - F_dr,int))`.
    #[must_use]
    #[inline]
    pub fn base_scale(&self) -> f64 {
        1.0 / (self.eta * self.eta * (1.0 - self.internal).max(1e-6))
    }

    /// The probability of sampling the coating rather than the base at cosine `cos_o`, for
    /// tint `s` and base albedo `rho` (Mitsuba's rule).
    #[must_use]
    #[inline]
    pub fn coat_probability(&self, cos_o: f64, s: Rgb, rho: Rgb) -> f64 {
        let (sm, dm) = (mean(s), mean(rho));
        if sm + dm <= 0.0 {
            return 0.0;
        }
        let w = sm / (sm + dm);
        let t = self.transmittance(cos_o);
        let (ps, pd) = ((1.0 - t) * w, t * (1.0 - w));
        if ps + pd > 0.0 { ps / (ps + pd) } else { 0.0 }
    }
}

fn mean(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// The hemispherical (cosine-weighted) average of the smooth dielectric Fresnel,
/// `F_dr(eta) = 2 int_0^1 F(mu, eta) mu dmu`, by Simpson's rule on the smooth external
/// integrand. From inside (`eta < 1`) it follows exactly from the outside value by the
/// energy balance of the interface, `1 - F_dr(1/eta) = eta^2 (1 - F_dr(eta))`, which sums
/// the total internal reflection below the critical cosine without quadrature across its
/// kink (the tests check it against a direct integration).
#[must_use]
pub fn diffuse_fresnel(eta: f64) -> f64 {
    if eta < 1.0 {
        return 1.0 - eta * eta * (1.0 - diffuse_fresnel(1.0 / eta));
    }
    let n = 4096;
    let h = 1.0 / n as f64;
    let g = |mu: f64| 2.0 * mu * super::fr_dielectric(mu, eta);
    let mut sum = g(0.0) + g(1.0);
    for k in 1..n {
        let w = if k % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * g(k as f64 * h);
    }
    sum * h / 3.0
}

/// The fractions of light from direction cosine `mu` (azimuth 0, upper side) that a rough
/// interface of index `eta` reflects and transmits, single scattering: the expectations over
/// visible normals of `F G1(wr)` and `(1 - F) G1(wt)` (Heitz 2014's masking, the microfacet
/// BSDF's integral), by the midpoint rule on the sample square.
fn rough_fractions(eta: f64, dist: Microfacet, mu: f64) -> (f64, f64) {
    let mu = mu.clamp(1e-6, 1.0);
    let wo = glam::DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let (mut r, mut t) = (0.0, 0.0);
    for a in 0..NODES {
        for b in 0..NODES {
            let u = glam::DVec2::new(
                (a as f64 + 0.5) / NODES as f64,
                (b as f64 + 0.5) / NODES as f64,
            );
            let wm = dist.sample_visible(wo, u);
            let c = wo.dot(wm);
            if c <= 0.0 {
                continue;
            }
            let f = super::fr_dielectric(c, eta);
            let wr = -wo + 2.0 * c * wm;
            if wr.z > 0.0 {
                r += f * dist.g1(wr);
            }
            if let Some(wt) = crate::math::refract(-wo, wm, 1.0 / eta)
                && wt.direction.z < 0.0
            {
                t += (1.0 - f) * dist.g1(wt.direction);
            }
        }
    }
    let n = (NODES * NODES) as f64;
    (r / n, t / n)
}

/// The key of a table: distribution and the bits of alpha and eta.
type Key = (Distribution, u64, u64, u64);

/// The transmittance table of a rough coating, computed once per (distribution, alphas, eta)
/// and kept for the life of the process (a few hundred bytes each), so that a lobe holds a
/// plain reference.
fn table(eta: f64, dist: Microfacet) -> &'static Transmittance {
    static TABLES: OnceLock<Mutex<HashMap<Key, &'static Transmittance>>> = OnceLock::new();
    let key = (
        dist.kind,
        dist.alpha_x.to_bits(),
        dist.alpha_y.to_bits(),
        eta.to_bits(),
    );
    let tables = TABLES.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(t) = tables
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(&key)
    {
        return t;
    }
    let t: &'static Transmittance = Box::leak(Box::new(compute(eta, dist)));
    tables
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .entry(key)
        .or_insert(t)
}

/// Tabulates `t(mu)` from outside and integrates the internal reflectance.
fn compute(eta: f64, dist: Microfacet) -> Transmittance {
    let mut values = [0.0; RES];
    for (k, v) in values.iter_mut().enumerate() {
        *v = rough_fractions(eta, dist, k as f64 / (RES - 1) as f64).1;
    }
    let mut internal = 0.0;
    for k in 0..RES {
        let mu = (k as f64 + 0.5) / RES as f64;
        internal += 2.0 * mu * rough_fractions(1.0 / eta, dist, mu).0;
    }
    Transmittance {
        values,
        internal: internal / RES as f64,
    }
}

#[cfg(test)]
pub(super) fn fractions_for_tests(eta: f64, dist: Microfacet, mu: f64) -> (f64, f64) {
    rough_fractions(eta, dist, mu)
}
