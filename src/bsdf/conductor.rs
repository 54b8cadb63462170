//! The Fresnel reflectance of a conductor: a complex index of refraction `eta + i k` per RGB
//! channel, and the named metals' values.
//!
//! The formula is pbrt-v4's `FrComplex` (`src/pbrt/util/scattering.h`; PBR 4th ed. section
//! 9.5, "Conductor BRDF"): Snell's law with a complex `eta` gives a complex `cos theta_t`, and
//! the unpolarised reflectance is the mean of `|r_parallel|^2` and `|r_perpendicular|^2` of
//! the Fresnel equations. With `k = 0` it is the dielectric Fresnel (and total internal
//! reflection where `eta < 1`); at normal incidence it is `((n-1)^2 + k^2) / ((n+1)^2 + k^2)`.

use crate::math::Rgb;

/// A complex index of refraction per channel, relative to the outside medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    /// Real part (the refractive index `n`).
    pub eta: Rgb,
    /// Imaginary part (the extinction coefficient `k`).
    pub k: Rgb,
}

/// The named metals: RGB `eta` and `k` projected from pbrt-v4's tabulated spectra
/// (`src/pbrt/util/spectrum.cpp`, `metal-Cu-eta` ... `metal-Al-k`; the same data as Mitsuba
/// 3's `data/ior`) by `benches/metal_rgb.py`: each spectrum is integrated against the CIE 1931
/// colour matching functions as a reflectance lit by D65 and taken to linear sRGB, so a flat
/// spectrum keeps its value. The normal-incidence reflectance of these RGB values is within
/// 0.05 of the spectral one projected the same way (gold's red is the worst: 0.975 against
/// 1.02, the spectral value being outside the sRGB gamut).
pub const METALS: [(&str, [f64; 3], [f64; 3]); 4] = [
    (
        "Cu",
        [0.104495, 0.978170, 1.204670],
        [3.273344, 2.592350, 2.369242],
    ),
    (
        "Au",
        [0.080051, 0.404654, 1.561352],
        [3.390473, 2.503771, 1.770891],
    ),
    (
        "Ag",
        [0.128470, 0.123528, 0.150892],
        [4.064894, 3.286320, 2.391747],
    ),
    (
        "Al",
        [1.407425, 0.926654, 0.584035],
        [7.740424, 6.602603, 5.360286],
    ),
];

impl ComplexIor {
    /// The named metal (`"Cu"`, `"Au"`, `"Ag"`, `"Al"`), if it is one of [`METALS`].
    #[must_use]
    pub fn metal(name: &str) -> Option<Self> {
        METALS
            .iter()
            .find(|m| m.0 == name)
            .map(|&(_, eta, k)| Self {
                eta: Rgb::from(eta),
                k: Rgb::from(k),
            })
    }

    /// The reflectance per channel at incidence cosine `cos_i` ([`fr_complex`]).
    #[must_use]
    pub fn fresnel(&self, cos_i: f64) -> Rgb {
        Rgb::new(
            fr_complex(cos_i, self.eta.x, self.k.x),
            fr_complex(cos_i, self.eta.y, self.k.y),
            fr_complex(cos_i, self.eta.z, self.k.z),
        )
    }
}

/// A complex number, just enough for [`fr_complex`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn scale(self, s: f64) -> Self {
        Self::new(self.re * s, self.im * s)
    }
    /// `|z|^2` (`std::norm`).
    fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    fn div(self, o: Self) -> Self {
        let d = o.norm();
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    /// The principal square root (non-negative real part), as pbrt-v4's `pstd::sqrt`.
    fn sqrt(self) -> Self {
        let m = self.norm().sqrt();
        if m == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let re = (0.5 * (m + self.re)).max(0.0).sqrt();
        let im = (0.5 * (m - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
    }
}

/// Unpolarised Fresnel reflectance of an interface of complex relative index `eta + i k` at
/// incidence cosine `cos_i` (its absolute value, clamped to 1): pbrt-v4 `FrComplex`.
#[must_use]
pub fn fr_complex(cos_i: f64, eta: f64, k: f64) -> f64 {
    let c = cos_i.abs().min(1.0);
    let e = Complex::new(eta, k);
    let sin2_i = 1.0 - c * c;
    let sin2_t = Complex::new(sin2_i, 0.0).div(e.mul(e));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ec = e.scale(c);
    let ci = Complex::new(c, 0.0);
    let r_parl = ec.sub(cos_t).div(ec.add(cos_t));
    let et = e.mul(cos_t);
    let r_perp = ci.sub(et).div(ci.add(et));
    let f = 0.5 * (r_parl.norm() + r_perp.norm());
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fr_dielectric;

    #[test]
    fn normal_incidence_is_the_closed_form() {
        for (n, k) in [(0.2, 3.9), (1.5, 0.0), (0.05, 4.8), (2.7, 1.3)] {
            let want = ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k);
            let got = fr_complex(1.0, n, k);
            assert!((got - want).abs() < 1e-14, "{n} {k}: {got} vs {want}");
        }
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        for (n, k) in [(0.2, 3.9), (1.5, 0.0), (1.4, 7.7)] {
            assert!((fr_complex(0.0, n, k) - 1.0).abs() < 1e-12);
            // and it rises to 1 continuously.
            assert!(fr_complex(1e-4, n, k) > 0.99);
        }
    }

    #[test]
    fn zero_extinction_is_the_dielectric_fresnel() {
        for eta in [1.5, 1.0 / 1.5, 1.33, 2.4] {
            for i in 0..=100 {
                let c = f64::from(i) / 100.0;
                let (a, b) = (fr_complex(c, eta, 0.0), fr_dielectric(c, eta));
                assert!((a - b).abs() < 1e-12, "eta {eta} cos {c}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn metals_reflect_in_their_colours_and_dip_before_grazing() {
        let cu = ComplexIor::metal("Cu").unwrap();
        let f0 = cu.fresnel(1.0);
        // Copper is red: more red than blue at normal incidence.
        assert!(f0.x > 0.9 && f0.z < 0.6, "{f0:?}");
        // Metals have a shallow minimum near grazing (the "dip" of the p polarisation) and
        // then rise to 1.
        let al = ComplexIor::metal("Al").unwrap();
        let curve: Vec<f64> = (0..=90)
            .map(|d| al.fresnel(f64::from(d).to_radians().cos()).y)
            .collect();
        let min = curve.iter().copied().fold(1.0, f64::min);
        assert!(min < curve[0] && curve[90] > 0.999, "{curve:?}");
        assert!(ComplexIor::metal("Pt").is_none());
    }

    #[test]
    fn complex_sqrt_is_principal() {
        let z = Complex::new(-4.0, 0.0).sqrt();
        assert!((z.re).abs() < 1e-15 && (z.im - 2.0).abs() < 1e-15);
        let w = Complex::new(3.0, -4.0).sqrt();
        assert!((w.re - 2.0).abs() < 1e-15 && (w.im + 1.0).abs() < 1e-15);
    }
}
