//! Microfacet distributions: GGX (Trowbridge-Reitz) and Beckmann, isotropic or anisotropic,
//! with the Smith masking function and visible-normal sampling.
//!
//! Sources: Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces"
//! (GGX D, G1: eq. 33-34; Beckmann D and Lambda: eq. 25-26); Heitz 2014, "Understanding the
//! Masking-Shadowing Function" (anisotropic Lambda, eq. 72-86: the 1D Lambda at the projected
//! roughness `alpha(phi) = sqrt(cos^2 phi a_x^2 + sin^2 phi a_y^2)`); Heitz 2018, "Sampling the
//! GGX Distribution of Visible Normals" (JCGT 7(4)); pbrt-v4 `TrowbridgeReitzDistribution`
//! (`src/pbrt/util/scattering.h`), whose GGX formulas these are, rewritten without `tan` so
//! that grazing directions give 0 instead of NaN. Beckmann's visible normals are sampled as
//! Heitz & d'Eon 2014 ("Importance Sampling Microfacet-Based BSDFs using the Distribution of
//! Visible Normals") and pbrt-v3 `BeckmannSample` do (stretch, sample the unit-roughness slope
//! distribution seen from the stretched direction, rotate, unstretch); the slope CDF is
//! inverted here by safeguarded Newton iteration in slope space to 1e-13 (pbrt-v3 stops at
//! 1e-5 in erf space). The shadowing-masking term is the separable product `G1(wo) G1(wi)`
//! (Walter et al. 2007 eq. 23; Mitsuba 3's `MicrofacetDistribution::G`).
//!
//! Beckmann's Lambda is the exact `(erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))` (Walter eq.
//! 26), not the rational fit of Walter eq. 27 that PBR 3rd ed. and Mitsuba 3 use (within 0.32%
//! of it in G1, `tests::beckmann_rational_fit_is_close_to_the_exact_lambda`): the visible-normal
//! density must integrate to exactly 1 for the sampler to match its pdf.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Alpha below which a lobe is treated as smooth (a delta lobe; pbrt-v4 `EffectivelySmooth`).
pub const SMOOTH_ALPHA: f64 = 1e-3;

/// `1 / sqrt(pi)`.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// pbrt-v4's `remaproughness true` (the default of its rough materials): the `roughness`
/// parameter is mapped to alpha by `TrowbridgeReitzDistribution::RoughnessToAlpha`,
/// `alpha = sqrt(roughness)` (`src/pbrt/util/scattering.h`). A raytree material's `roughness`
/// *is* alpha, so a pbrt loader applies this when the file does not say `remaproughness false`.
#[must_use]
pub fn roughness_to_alpha(roughness: f64) -> f64 {
    roughness.max(0.0).sqrt()
}

/// Which microfacet normal distribution a rough lobe uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// Trowbridge-Reitz / GGX (pbrt-v4's only one; raytree's default).
    #[default]
    Ggx,
    /// Beckmann-Spizzichino (Mitsuba 3's default for its rough BSDFs).
    Beckmann,
}

impl Distribution {
    /// The name in scene files and reports ("ggx", "beckmann").
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ggx => "ggx",
            Self::Beckmann => "beckmann",
        }
    }
}

/// A microfacet distribution of roughness `alpha_x` along the shading frame's first tangent
/// and `alpha_y` along the second (each > 0; equal for an isotropic one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    /// GGX or Beckmann.
    pub kind: Distribution,
    /// Roughness along local `x` (the frame's `s`).
    pub alpha_x: f64,
    /// Roughness along local `y` (the frame's `t`).
    pub alpha_y: f64,
}

impl Microfacet {
    /// The isotropic GGX distribution of roughness `alpha`, clamped to at least
    /// [`SMOOTH_ALPHA`].
    #[must_use]
    pub fn new(alpha: f64) -> Self {
        Self::with(Distribution::Ggx, alpha, alpha)
    }

    /// A `kind` distribution of roughness `alpha_x`, `alpha_y`, each clamped to at least
    /// [`SMOOTH_ALPHA`].
    #[must_use]
    pub fn with(kind: Distribution, alpha_x: f64, alpha_y: f64) -> Self {
        Self {
            kind,
            alpha_x: alpha_x.max(SMOOTH_ALPHA),
            alpha_y: alpha_y.max(SMOOTH_ALPHA),
        }
    }

    /// Whether `alpha_x == alpha_y`.
    #[must_use]
    #[inline]
    pub fn is_isotropic(&self) -> bool {
        self.alpha_x == self.alpha_y
    }

    /// The normal distribution `D(wm)` for `wm` in the upper hemisphere, else 0.
    /// GGX: `1 / (pi a_x a_y (x^2/a_x^2 + y^2/a_y^2 + z^2)^2)` (Walter 2007 eq. 33 written
    /// without tan; pbrt-v4 `D`). Beckmann: `exp(-(x^2/a_x^2 + y^2/a_y^2) / z^2) / (pi a_x a_y
    /// z^4)` (Walter 2007 eq. 25; PBR 3rd ed. 8.4.2).
    #[must_use]
    #[inline]
    pub fn d(&self, wm: DVec3) -> f64 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let z2 = wm.z * wm.z;
        match self.kind {
            Distribution::Ggx if self.is_isotropic() => {
                let a2 = ax * ax;
                let k = z2 + (wm.x * wm.x + wm.y * wm.y) / a2;
                1.0 / (PI * a2 * k * k)
            }
            Distribution::Ggx => {
                let k = z2 + wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay);
                1.0 / (PI * ax * ay * k * k)
            }
            Distribution::Beckmann => {
                let e = (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / z2;
                (-e).exp() / (PI * ax * ay * z2 * z2)
            }
        }
    }

    /// `sqrt(a_x^2 x^2 + a_y^2 y^2)`: `alpha(phi) sin(theta)` of a unit `w`.
    #[inline]
    fn projected(&self, w: DVec3) -> f64 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        (ax * ax * w.x * w.x + ay * ay * w.y * w.y).sqrt()
    }

    /// GGX's `sqrt(cos^2 + alpha(phi)^2 sin^2)`: the common factor of `Lambda` and `G1`.
    #[inline]
    fn root(&self, w: DVec3) -> f64 {
        if self.is_isotropic() {
            let a2 = self.alpha_x * self.alpha_x;
            (w.z * w.z + a2 * (w.x * w.x + w.y * w.y)).sqrt()
        } else {
            let p = self.projected(w);
            (w.z * w.z + p * p).sqrt()
        }
    }

    /// Beckmann's Smith `Lambda(w)` with `a = cos / (alpha(phi) sin)` (Walter 2007 eq. 26,
    /// Heitz 2014 eq. 80 with the projected roughness); infinite at grazing.
    #[inline(never)]
    fn beckmann_lambda(&self, w: DVec3) -> f64 {
        let (c, p) = (w.z.abs(), self.projected(w));
        if p == 0.0 {
            return 0.0;
        }
        if c == 0.0 {
            return f64::INFINITY;
        }
        let a = c / p;
        (0.5 * ((-a * a).exp() * FRAC_1_SQRT_PI / a - libm::erfc(a))).max(0.0)
    }

    /// Smith masking `G1(w) = 1 / (1 + Lambda(w))`; 0 at grazing. GGX: `2 |cos| / (|cos| +
    /// sqrt(cos^2 + alpha^2 sin^2))` (Walter 2007 eq. 34).
    #[must_use]
    #[inline]
    pub fn g1(&self, w: DVec3) -> f64 {
        match self.kind {
            Distribution::Ggx => {
                let c = w.z.abs();
                let r = self.root(w);
                if r == 0.0 { 0.0 } else { 2.0 * c / (c + r) }
            }
            Distribution::Beckmann => 1.0 / (1.0 + self.beckmann_lambda(w)),
        }
    }

    /// The separable shadowing-masking `G1(wo) G1(wi)`.
    #[must_use]
    #[inline]
    pub fn g(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.g1(wo) * self.g1(wi)
    }

    /// `G1(w) / |cos w|`, finite at grazing for GGX (`2 / (|cos| + root)`); 0 at exactly
    /// grazing for Beckmann (a set of measure zero).
    #[inline]
    fn g1_over_cos(&self, w: DVec3) -> f64 {
        match self.kind {
            Distribution::Ggx => {
                let denom = w.z.abs() + self.root(w);
                if denom == 0.0 { 0.0 } else { 2.0 / denom }
            }
            Distribution::Beckmann if w.z == 0.0 => 0.0,
            Distribution::Beckmann => self.g1(w) / w.z.abs(),
        }
    }

    /// An upper bound of `G1(w) / |cos w|` over all `w`: `2 / alpha_min` for GGX (the value at
    /// grazing), `2 sqrt(pi) / alpha_min` for Beckmann (its grazing limit, where `Lambda ~
    /// alpha tan / (2 sqrt(pi))`); both checked on a grid in the tests.
    #[must_use]
    pub fn g1_over_cos_max(&self) -> f64 {
        let a = self.alpha_x.min(self.alpha_y);
        match self.kind {
            Distribution::Ggx => 2.0 / a,
            Distribution::Beckmann => 2.0 / (FRAC_1_SQRT_PI * a),
        }
    }

    /// The density of visible normals seen from `w`,
    /// `D_w(wm) = G1(w) max(0, w.wm) D(wm) / |cos w|` (Heitz 2018 eq. 1), as a density of `wm`
    /// per solid angle, with `w` below the surface first mirrored to the upper side (as
    /// [`Self::sample_visible`] does).
    #[must_use]
    #[inline]
    pub fn d_visible(&self, w: DVec3, wm: DVec3) -> f64 {
        let facing = if w.z < 0.0 { -w.dot(wm) } else { w.dot(wm) };
        let g = self.g1_over_cos(w);
        if g == 0.0 || facing <= 0.0 {
            return 0.0;
        }
        // `(2 / denom) * facing * D` for GGX: the historical evaluation order.
        g * facing * self.d(wm)
    }

    /// A microfacet normal (upper hemisphere) drawn with density [`Self::d_visible`] for the
    /// direction `w` (either hemisphere: the visible normals of `w` flipped into the upper one).
    #[must_use]
    #[inline]
    pub fn sample_visible(&self, w: DVec3, u: DVec2) -> DVec3 {
        match self.kind {
            Distribution::Ggx => self.sample_ggx(w, u),
            Distribution::Beckmann => self.sample_beckmann(w, u),
        }
    }

    /// GGX visible normals by Heitz 2018's algorithm as written in pbrt-v4 `Sample_wm`.
    fn sample_ggx(&self, w: DVec3, u: DVec2) -> DVec3 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        // Stretch to the hemisphere configuration (alpha = 1).
        let mut wh = DVec3::new(ax * w.x, ay * w.y, w.z).normalize_or(DVec3::Z);
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            DVec3::Z.cross(wh).normalize()
        } else {
            DVec3::X
        };
        let t2 = wh.cross(t1);
        // Uniform disk (polar), warped to the projected visible hemisphere.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let (px, py0) = (r * phi.cos(), r * phi.sin());
        let h = (1.0 - px * px).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        let py = (1.0 - s) * h + s * py0;
        let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
        let nh = px * t1 + py * t2 + pz * wh;
        // Unstretch.
        DVec3::new(ax * nh.x, ay * nh.y, nh.z.max(1e-6)).normalize()
    }

    /// Beckmann visible normals (pbrt-v3 `BeckmannSample`): stretch `w` to unit roughness, draw
    /// the slopes visible from it, rotate them to its azimuth, unstretch, and turn the slope
    /// into a normal `(-x, -y, 1)`.
    #[inline(never)]
    fn sample_beckmann(&self, w: DVec3, u: DVec2) -> DVec3 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let w = if w.z < 0.0 { -w } else { w };
        let ws = DVec3::new(ax * w.x, ay * w.y, w.z).normalize_or(DVec3::Z);
        let (sx, sy) = beckmann_slopes(ws.z.clamp(0.0, 1.0), u);
        let r = (ws.x * ws.x + ws.y * ws.y).sqrt();
        let (cos_phi, sin_phi) = if r > 0.0 {
            (ws.x / r, ws.y / r)
        } else {
            (1.0, 0.0)
        };
        let (sx, sy) = (cos_phi * sx - sin_phi * sy, sin_phi * sx + cos_phi * sy);
        DVec3::new(-ax * sx, -ay * sy, 1.0).normalize()
    }
}

/// Slopes `(x, y)` of the unit-roughness Beckmann distribution's normals visible from a
/// direction at `cos_theta` in the `xz` plane (Heitz & d'Eon 2014, section 4; pbrt-v3
/// `BeckmannSample11`). `x` has the CDF
/// `F(x) = (1 + erf(x) + tan e^{-x^2} / sqrt(pi)) / (1 + erf(cot) + tan e^{-cot^2} / sqrt(pi))`
/// on `x <= cot theta`, `y` is independent with CDF `(1 + erf(y)) / 2`.
fn beckmann_slopes(cos_theta: f64, u: DVec2) -> (f64, f64) {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    // Below these slopes the densities are under e^-64: the search brackets.
    const LIMIT: f64 = 8.0;
    let x = if sin_theta == 0.0 {
        invert_increasing(u.x, -LIMIT, LIMIT, half_erf_cdf)
    } else {
        let tan = sin_theta / cos_theta.max(1e-300);
        let cot = cos_theta / sin_theta;
        let tail = |x: f64| tan * (-x * x).exp() * FRAC_1_SQRT_PI;
        let norm = 1.0 / (1.0 + libm::erf(cot) + tail(cot));
        invert_increasing(u.x, -LIMIT, cot.min(LIMIT), |x| {
            let f = norm * (1.0 + libm::erf(x) + tail(x));
            let df = norm * 2.0 * FRAC_1_SQRT_PI * (-x * x).exp() * (1.0 - x * tan);
            (f, df)
        })
    };
    let y = invert_increasing(u.y, -LIMIT, LIMIT, half_erf_cdf);
    (x, y)
}

/// The CDF `(1 + erf(x)) / 2` and its density.
fn half_erf_cdf(x: f64) -> (f64, f64) {
    (0.5 * (1.0 + libm::erf(x)), FRAC_1_SQRT_PI * (-x * x).exp())
}

/// The `x` in `[lo, hi]` where the increasing `cdf` (value, derivative) reaches `u`, by Newton
/// steps that fall back to bisection when they leave the bracket (Numerical Recipes `rtsafe`).
fn invert_increasing(u: f64, mut lo: f64, mut hi: f64, cdf: impl Fn(f64) -> (f64, f64)) -> f64 {
    let mut x = 0.5 * (lo + hi);
    for _ in 0..100 {
        let (f, df) = cdf(x);
        let v = f - u;
        if v.abs() < 1e-14 || hi - lo < 1e-13 {
            break;
        }
        if v > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let step = x - v / df;
        x = if df > 0.0 && step > lo && step < hi {
            step
        } else {
            0.5 * (lo + hi)
        };
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta_deg: f64, phi: f64) -> DVec3 {
        let t = theta_deg.to_radians();
        DVec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
    }

    #[test]
    fn isotropic_ggx_is_the_historical_formula() {
        let g = Microfacet::new(0.3);
        let wm = dir(30.0, 0.4);
        let a2 = 0.09;
        let k = wm.z * wm.z + (wm.x * wm.x + wm.y * wm.y) / a2;
        assert_eq!(g.d(wm), 1.0 / (PI * a2 * k * k));
    }

    #[test]
    fn anisotropic_d_reduces_to_isotropic_and_normalises() {
        // Equal alphas through the anisotropic formulas give the isotropic values.
        for kind in [Distribution::Ggx, Distribution::Beckmann] {
            let iso = Microfacet::with(kind, 0.4, 0.4);
            let mut ani = iso;
            ani.alpha_y = 0.4 * (1.0 + 1e-15);
            for th in [0.0, 20.0, 60.0, 85.0] {
                let w = dir(th, 0.7);
                assert!((iso.d(w) - ani.d(w)).abs() <= 1e-12 * iso.d(w).max(1.0));
                assert!((iso.g1(w) - ani.g1(w)).abs() < 1e-12);
            }
        }
        // The projected area is 1: integral of D(wm) cos(wm) over the hemisphere.
        for kind in [Distribution::Ggx, Distribution::Beckmann] {
            let m = Microfacet::with(kind, 0.2, 0.6);
            let n = 800;
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    // Substitution z = cos theta, uniform in z and phi.
                    let z = (i as f64 + 0.5) / n as f64;
                    let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
                    let s = (1.0 - z * z).sqrt();
                    let wm = DVec3::new(s * phi.cos(), s * phi.sin(), z);
                    sum += m.d(wm) * z;
                }
            }
            let integral = sum * 2.0 * PI / (n * n) as f64;
            assert!((integral - 1.0).abs() < 2e-3, "{kind:?}: {integral}");
        }
    }

    #[test]
    fn masking_obeys_the_projected_area_identity() {
        // Heitz 2014 eq. 2: integral of G1(w) max(0, w.wm) D(wm) dwm = cos(w), i.e. the visible
        // normal density integrates to 1 (what makes the exact Lambda necessary).
        for kind in [Distribution::Ggx, Distribution::Beckmann] {
            let m = Microfacet::with(kind, 0.3, 0.7);
            for th in [0.0, 45.0, 80.0] {
                let w = dir(th, 1.1);
                let n = 600;
                let mut sum = 0.0;
                for i in 0..n {
                    for j in 0..n {
                        let z = (i as f64 + 0.5) / n as f64;
                        let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
                        let s = (1.0 - z * z).sqrt();
                        sum += m.d_visible(w, DVec3::new(s * phi.cos(), s * phi.sin(), z));
                    }
                }
                let integral = sum * 2.0 * PI / (n * n) as f64;
                assert!((integral - 1.0).abs() < 3e-3, "{kind:?} {th}: {integral}");
            }
        }
    }

    #[test]
    fn beckmann_rational_fit_is_close_to_the_exact_lambda() {
        // Walter 2007 eq. 27 (PBR 3rd ed. BeckmannDistribution::Lambda, Mitsuba 3 smith_g1).
        let fit = |a: f64| {
            if a >= 1.6 {
                0.0
            } else {
                (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
            }
        };
        let m = Microfacet::with(Distribution::Beckmann, 0.5, 0.5);
        let mut worst = 0.0f64;
        for i in 1..400 {
            let th = 89.9 * f64::from(i) / 400.0;
            let w = dir(th, 0.0);
            let a = w.z / (0.5 * w.x);
            let g_fit = 1.0 / (1.0 + fit(a));
            worst = worst.max((g_fit - m.g1(w)).abs() / m.g1(w));
        }
        assert!(worst < 4e-3 && worst > 1e-5, "{worst}");
    }

    #[test]
    fn g1_over_cos_stays_below_its_bound() {
        for kind in [Distribution::Ggx, Distribution::Beckmann] {
            for (ax, ay) in [(0.05, 0.05), (0.3, 0.9), (1.0, 0.2)] {
                let m = Microfacet::with(kind, ax, ay);
                let max = m.g1_over_cos_max();
                for i in 0..=1000 {
                    let th = 90.0 * f64::from(i) / 1000.0;
                    for phi in [0.0, 0.8, 1.6, 2.9] {
                        let v = m.g1_over_cos(dir(th, phi));
                        assert!(v <= max * (1.0 + 1e-9), "{kind:?} {th} {phi}: {v} > {max}");
                    }
                }
            }
        }
    }

    #[test]
    fn beckmann_slope_inversion_hits_the_cdf() {
        for cos in [1.0, 0.9, 0.5, 0.1, 1e-3] {
            for ux in [1e-6, 0.1, 0.5, 0.93, 1.0 - 1e-9] {
                let (x, _) = beckmann_slopes(cos, DVec2::new(ux, 0.5));
                let sin = (1.0f64 - cos * cos).sqrt();
                let f = |x: f64| {
                    let tail = sin / cos * (-x * x).exp() * FRAC_1_SQRT_PI;
                    1.0 + libm::erf(x) + tail
                };
                let cot = cos / sin;
                let cdf = if sin == 0.0 {
                    0.5 * (1.0 + libm::erf(x))
                } else {
                    f(x) / f(cot)
                };
                assert!((cdf - ux).abs() < 1e-9, "cos {cos} u {ux}: {cdf}");
            }
        }
    }

    #[test]
    fn remaproughness_is_pbrt_v4_sqrt() {
        assert_eq!(roughness_to_alpha(0.25), 0.5);
        assert_eq!(roughness_to_alpha(0.0), 0.0);
    }
}
