//! Rays and the optics of the lecture: reflection, Snell refraction, Fresnel, Beer's law.
//!
//! Everything here is pure and knows nothing of scenes. Formulas follow
//! `../shared/lecture/raytracing-ii.txt` ("Raytracing II"); each cites its slide.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Linear RGB radiance (or a per-channel weight).
pub type Rgb = DVec3;

/// A ray `origin + t * direction` valid for `t` in `[t_min, t_max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts (after any offset).
    pub origin: DVec3,
    /// Unit direction.
    pub direction: DVec3,
    /// Smallest accepted hit distance (the "ray" offset strategy raises it above zero).
    pub t_min: f64,
}

impl Ray {
    /// A ray from `origin` along unit `direction`, accepting hits from `t_min` on.
    #[must_use]
    pub fn new(origin: DVec3, direction: DVec3, t_min: f64) -> Self {
        Self {
            origin,
            direction,
            t_min,
        }
    }

    /// The point at parameter `t`.
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.direction * t
    }
}

/// Mirror reflection, lecture slide "Reflected Rays": `D - 2 (N.D) N`.
#[must_use]
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * n.dot(d) * n
}

/// The outcome of Snell's law at an interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refraction {
    /// Transmitted unit direction.
    pub direction: DVec3,
    /// Cosine of the transmitted angle, in `[0, 1]`.
    pub cos_t: f64,
}

/// Snell refraction, lecture slide "Transmitted Ray":
/// `D_t = (n1/n2) D - ((n1/n2) N.D + sqrt(1 - (n1/n2)^2 (1 - (N.D)^2))) N`.
///
/// `d` is the unit incident direction, `n` the unit normal on the incident side (`n.d <= 0`),
/// `eta = n1 / n2`. Returns `None` when the square root is negative: total internal reflection
/// (unlike `glam::DVec3::refract`, which returns a silent zero vector).
#[must_use]
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<Refraction> {
    let cos_i = (-n.dot(d)).clamp(0.0, 1.0);
    let mut sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t.is_nan() {
        // eta * eta overflowed to infinity (eta above 1e154) at normal incidence, where
        // 1 - cos_i^2 is 0: squared after the product, sin_t is eta * 0 = 0 as it should be.
        let sin_t = eta * (1.0 - cos_i * cos_i).sqrt();
        sin2_t = sin_t * sin_t;
    }
    let k = 1.0 - sin2_t;
    if k < 0.0 {
        return None;
    }
    let cos_t = k.sqrt();
    let mut direction = (eta * d + (eta * cos_i - cos_t) * n).normalize();
    if !direction.is_finite() {
        // A huge eta cancels eta d against eta cos_i n: the same vector grouped as
        // eta (d + cos_i n) - cos_t n keeps the tangential part exact.
        direction = ((d + cos_i * n) * eta - cos_t * n).normalize();
    }
    Some(Refraction { direction, cos_t })
}

/// Which Fresnel model decides the split between reflection and transmission.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FresnelModel {
    /// The unpolarized mean of the exact `Rs` and `Rp` (lecture slide "Reflection vs
    /// Transmission").
    #[default]
    Exact,
    /// Schlick's approximation, with the cosine taken on the less dense side.
    Schlick,
    /// No Fresnel: `R = 0` (total internal reflection still reflects everything).
    None,
}

/// Fresnel reflectance at one interface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fresnel {
    /// The model used.
    pub model: FresnelModel,
    /// s-polarized reflectance (exact model only; `R` otherwise).
    pub rs: f64,
    /// p-polarized reflectance (exact model only; `R` otherwise).
    pub rp: f64,
    /// Reflected fraction.
    pub r: f64,
    /// Transmitted fraction, `1 - R`.
    pub t: f64,
}

/// Exact dielectric Fresnel terms `(Rs, Rp)` for cosines `cos_i`, `cos_t` (lecture slide
/// "Reflection vs Transmission", Hecht, *Optics*, 4th ed., eq. 4.42-4.43).
#[must_use]
pub fn fresnel_exact(n1: f64, n2: f64, cos_i: f64, cos_t: f64) -> (f64, f64) {
    let rs = ratio_sq(n1 * cos_i - n2 * cos_t, n1 * cos_i + n2 * cos_t);
    let rp = ratio_sq(n1 * cos_t - n2 * cos_i, n1 * cos_t + n2 * cos_i);
    (rs, rp)
}

/// `(a / b)^2`, with `0/0` (grazing incidence on both sides) taken as total reflection.
fn ratio_sq(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        1.0
    } else {
        ((a / b) * (a / b)).clamp(0.0, 1.0)
    }
}

/// Schlick's reflectance at normal incidence, `R0 = ((n1 - n2) / (n1 + n2))^2`.
#[must_use]
pub fn schlick_r0(n1: f64, n2: f64) -> f64 {
    let r = (n1 - n2) / (n1 + n2);
    r * r
}

/// Schlick's approximation `R0 + (1 - R0)(1 - cos)^5` (lecture slide "Schlick's Approximation").
///
/// `cos` must be the cosine on the less dense side: `cos_i` when `n1 <= n2`, else `cos_t`.
/// Using the incident cosine inside glass is a known bug: it misses total internal reflection
/// and underestimates R near the critical angle (Schlick 1994; pbrt-v3 §8.2.1 discussion).
#[must_use]
pub fn schlick(r0: f64, cos: f64) -> f64 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    r0 + (1.0 - r0) * m2 * m2 * m
}

/// Fresnel reflectance with the chosen model for a non-TIR interface.
#[must_use]
pub fn fresnel(model: FresnelModel, n1: f64, n2: f64, cos_i: f64, cos_t: f64) -> Fresnel {
    let (rs, rp, r) = match model {
        FresnelModel::Exact => {
            let (rs, rp) = fresnel_exact(n1, n2, cos_i, cos_t);
            (rs, rp, 0.5 * (rs + rp))
        }
        FresnelModel::Schlick => {
            let cos = if n1 <= n2 { cos_i } else { cos_t };
            let r = schlick(schlick_r0(n1, n2), cos);
            (r, r, r)
        }
        FresnelModel::None => (0.0, 0.0, 0.0),
    };
    Fresnel {
        model,
        rs,
        rp,
        r,
        t: 1.0 - r,
    }
}

/// Fresnel record of total internal reflection: everything reflects.
#[must_use]
pub fn fresnel_tir(model: FresnelModel) -> Fresnel {
    Fresnel {
        model,
        rs: 1.0,
        rp: 1.0,
        r: 1.0,
        t: 0.0,
    }
}

/// Beer's law `exp(-c d)` per channel (lecture slide "Attenuation").
///
/// A zero coefficient gives exactly 1 even for an infinite distance (no `0 * inf = NaN`).
#[must_use]
pub fn beer(absorption: Rgb, distance: f64) -> Rgb {
    let f = |c: f64| {
        if c == 0.0 || distance == 0.0 {
            1.0
        } else {
            (-c * distance).exp()
        }
    };
    Rgb::new(f(absorption.x), f(absorption.y), f(absorption.z))
}

/// The critical angle `asin(n2 / n1)` in radians, or `None` when `n1 <= n2`.
#[must_use]
pub fn critical_angle(n1: f64, n2: f64) -> Option<f64> {
    (n1 > n2).then(|| (n2 / n1).asin())
}

/// Brewster's angle `atan(n2 / n1)` in radians, where `Rp = 0`.
#[must_use]
pub fn brewster_angle(n1: f64, n2: f64) -> f64 {
    (n2 / n1).atan()
}

/// Linear to sRGB transfer (IEC 61966-2-1), clamped to `[0, 1]`; NaN maps to 0.
#[must_use]
pub fn linear_to_srgb(v: f64) -> f64 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB-encoded value in `[0, 1]` to linear (IEC 61966-2-1).
#[must_use]
pub fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear radiance to an 8-bit sRGB code value.
#[must_use]
pub fn linear_to_srgb8(v: f64) -> u8 {
    (linear_to_srgb(v) * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLASS: f64 = 1.5;

    fn incident(theta_deg: f64) -> DVec3 {
        let t = theta_deg.to_radians();
        DVec3::new(t.sin(), -t.cos(), 0.0)
    }

    /// An index ratio whose square overflows (eta = 1e300, from n1 = 1e300 into air): at
    /// normal incidence the ray goes straight through with cos_t 1 (it was NaN, and a diagram
    /// label read "θt = NaN°"); off normal it is total internal reflection.
    #[test]
    fn a_huge_index_ratio_refracts_at_normal_incidence_and_reflects_otherwise() {
        let n = DVec3::Y;
        let t = refract(-DVec3::Y, n, 1e300).unwrap();
        assert_eq!(t.cos_t, 1.0);
        assert!(t.direction.is_finite() && (t.direction + DVec3::Y).length() < 1e-12);
        assert!(refract(incident(10.0), n, 1e300).is_none());
        // Ordinary ratios are untouched.
        assert_eq!(refract(-DVec3::Y, n, 1.0 / GLASS).unwrap().cos_t, 1.0);
    }

    #[test]
    fn r0_is_four_percent_for_glass() {
        assert!((schlick_r0(1.0, GLASS) - 0.04).abs() < 1e-15);
        let f = fresnel(FresnelModel::Exact, 1.0, GLASS, 1.0, 1.0);
        assert!((f.r - 0.04).abs() < 1e-15);
        assert!((f.rs - f.rp).abs() < 1e-15);
    }

    #[test]
    fn brewster_angle_has_zero_rp() {
        let theta_b = brewster_angle(1.0, GLASS);
        assert!((theta_b.to_degrees() - 56.309_932_474).abs() < 1e-6);
        let n = DVec3::Y;
        let d = incident(theta_b.to_degrees());
        let t = refract(d, n, 1.0 / GLASS).unwrap();
        let (rs, rp) = fresnel_exact(1.0, GLASS, theta_b.cos(), t.cos_t);
        assert!(rp < 1e-15, "Rp = {rp}");
        assert!(rs > 0.1);
    }

    #[test]
    fn critical_angle_glass_to_air() {
        let c = critical_angle(GLASS, 1.0).unwrap();
        assert!((c.to_degrees() - 41.810_314_895_8).abs() < 1e-8);
        assert!(critical_angle(1.0, GLASS).is_none());
        let n = DVec3::Y;
        assert!(refract(incident(41.80), n, GLASS).is_some());
        assert!(refract(incident(41.82), n, GLASS).is_none());
    }

    #[test]
    fn snell_law_holds() {
        for deg in [0.0, 10.0, 30.0, 60.0, 89.0] {
            let d = incident(deg);
            let t = refract(d, DVec3::Y, 1.0 / GLASS).unwrap();
            let sin_i = d.x;
            let sin_t = t.direction.x;
            assert!((sin_i - GLASS * sin_t).abs() < 1e-12, "{deg}");
            assert!((t.direction.length() - 1.0).abs() < 1e-12);
            assert!((t.direction.y + t.cos_t).abs() < 1e-12);
        }
    }

    #[test]
    fn schlick_tracks_exact() {
        // For glass Schlick's error peaks near grazing: 0.0357 at 85 degrees (checked
        // independently), and is below 0.02 up to 70 degrees.
        let mut worst: f64 = 0.0;
        for deg in (0..90).step_by(5) {
            let cos_i = (deg as f64).to_radians().cos();
            let t = refract(incident(deg as f64), DVec3::Y, 1.0 / GLASS).unwrap();
            let e = fresnel(FresnelModel::Exact, 1.0, GLASS, cos_i, t.cos_t);
            let s = fresnel(FresnelModel::Schlick, 1.0, GLASS, cos_i, t.cos_t);
            worst = worst.max((e.r - s.r).abs());
            if deg <= 70 {
                assert!((e.r - s.r).abs() < 0.02, "{deg}: {} vs {}", e.r, s.r);
            }
            // Reciprocity: from inside, Schlick with cos_t equals the outside value.
            let s_in = fresnel(FresnelModel::Schlick, GLASS, 1.0, t.cos_t, cos_i);
            assert!((s_in.r - s.r).abs() < 1e-15);
        }
        assert!((worst - 0.0357).abs() < 1e-3, "worst {worst}");
    }

    #[test]
    fn grazing_reflects_everything() {
        let f = fresnel(FresnelModel::Exact, 1.0, GLASS, 0.0, 0.745);
        assert!((f.r - 1.0).abs() < 1e-12);
        assert_eq!(fresnel(FresnelModel::Schlick, 1.0, GLASS, 0.0, 0.7).r, 1.0);
    }

    #[test]
    fn beer_law_closed_form() {
        let a = Rgb::new(0.0, 0.5, 2.0);
        let f = beer(a, 2.0);
        assert_eq!(f.x, 1.0);
        assert!((f.y - (-1.0f64).exp()).abs() < 1e-15);
        assert!((f.z - (-4.0f64).exp()).abs() < 1e-15);
        let inf = beer(a, f64::INFINITY);
        assert_eq!(inf, Rgb::new(1.0, 0.0, 0.0));
        assert_eq!(beer(Rgb::ZERO, f64::INFINITY), Rgb::ONE);
    }

    #[test]
    fn reflect_mirrors_about_normal() {
        let r = reflect(incident(30.0), DVec3::Y);
        assert!((r - DVec3::new(0.5, 30f64.to_radians().cos(), 0.0)).length() < 1e-12);
    }

    #[test]
    fn srgb_endpoints() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(f64::NAN), 0);
        assert!((linear_to_srgb(0.214_041_14) - 0.5).abs() < 1e-6);
        for v in [0.0, 0.002, 0.04, 0.3, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(v)) - v).abs() < 1e-12);
        }
    }
}

/// A pixel's running sum of sample radiances that keeps a finite mean finite: beside the plain
/// sum (whose mean is returned bit for bit whenever it is finite) a copy scaled by 2^-64
/// (exact: a power of two), used only when finite samples near `f64::MAX` overflow the plain
/// sum. Issue 27: 4 samples of 1.19e308 summed to infinity and the pixel was written black.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSum {
    sum: Rgb,
    scaled: Rgb,
}

/// 2^-64, the scale of [`PixelSum`]'s overflow copy.
const PIXEL_SUM_SCALE: f64 = 1.0 / 18_446_744_073_709_551_616.0;

impl PixelSum {
    /// The plain sum.
    #[must_use]
    pub fn plain(self) -> Rgb {
        self.sum
    }

    /// The mean of `n` samples: the plain `sum / n` where that is finite, else the mean from
    /// the scaled copy (channel by channel).
    #[must_use]
    pub fn mean(self, n: f64) -> Rgb {
        let plain = self.sum / n;
        if plain.is_finite() {
            return plain;
        }
        let rescued = self.scaled / n / PIXEL_SUM_SCALE;
        Rgb::from_array(std::array::from_fn(|i| {
            if plain[i].is_finite() || !rescued[i].is_finite() {
                plain[i]
            } else {
                rescued[i]
            }
        }))
    }
}

impl std::ops::AddAssign<Rgb> for PixelSum {
    fn add_assign(&mut self, l: Rgb) {
        self.sum += l;
        self.scaled += l * PIXEL_SUM_SCALE;
    }
}

impl std::ops::Div<f64> for PixelSum {
    type Output = Rgb;
    fn div(self, n: f64) -> Rgb {
        self.mean(n)
    }
}

#[cfg(test)]
mod pixel_sum_tests {
    use super::*;

    #[test]
    fn a_finite_mean_of_samples_whose_sum_overflows_stays_finite() {
        let mut s = PixelSum::default();
        for _ in 0..4 {
            s += Rgb::new(1.19e308, 0.5, 1.0);
        }
        assert!(s.plain().x.is_infinite());
        let m = s / 4.0;
        assert!((m.x - 1.19e308).abs() <= 1e-12 * 1.19e308, "{m}");
        assert_eq!(
            (m.y, m.z),
            (0.5, 1.0),
            "channels that did not overflow are the plain mean"
        );
    }

    #[test]
    fn an_ordinary_mean_is_the_plain_one_bit_for_bit() {
        let mut s = PixelSum::default();
        let mut plain = Rgb::ZERO;
        for i in 0..37 {
            let l = Rgb::new(0.1 * f64::from(i), 1e-300, 3.7e10 / f64::from(i + 1));
            s += l;
            plain += l;
        }
        assert_eq!(s / 37.0, plain / 37.0);
        let mut inf = PixelSum::default();
        inf += Rgb::splat(f64::INFINITY);
        assert!(
            (inf / 1.0).x.is_infinite(),
            "an infinite sample stays infinite"
        );
    }
}
