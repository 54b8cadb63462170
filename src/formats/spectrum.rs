//! Spectra as RGB: a blackbody of temperature T, and sampled spectra, integrated against the
//! CIE 1931 colour-matching functions in the analytic multi-lobe Gaussian fit of Wyman, Sloan and
//! Shirley ("Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2),
//! 2013, equation 2), then taken to linear sRGB (IEC 61966-2-1 matrix).

/// Wyman et al.'s piecewise Gaussian `g(x; mu, s1, s2)`.
fn g(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let s = if x < mu { s1 } else { s2 };
    (-0.5 * ((x - mu) / s).powi(2)).exp()
}

/// CIE 1931 `(x, y, z)` bar at wavelength `l` nanometres (Wyman et al. 2013, eq. 2).
#[must_use]
pub fn cmf(l: f64) -> [f64; 3] {
    [
        1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7)
            - 0.065 * g(l, 501.1, 20.4, 26.2),
        0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1),
        1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8),
    ]
}

/// Linear sRGB of CIE XYZ (IEC 61966-2-1, D65 white).
#[must_use]
pub fn xyz_to_srgb([x, y, z]: [f64; 3]) -> [f64; 3] {
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// XYZ of `f` over 360..830 nm in 1 nm steps.
fn integrate(f: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for l in 360..=830 {
        let l = f64::from(l);
        let v = f(l);
        let c = cmf(l);
        for k in 0..3 {
            xyz[k] += v * c[k];
        }
    }
    xyz
}

/// Planck's law: spectral radiance of a blackbody at `t` kelvin, wavelength `l` nm (arbitrary
/// scale).
fn planck(l: f64, t: f64) -> f64 {
    const C2: f64 = 1.438_776_877e-2; // h c / k_B, m K
    let m = l * 1e-9;
    1.0 / (m.powi(5) * ((C2 / (m * t)).exp_m1()))
}

/// Linear sRGB of a blackbody at `t` kelvin with luminance `Y = 1`: pbrt-v4 divides every
/// light's spectrum by its luminance (`SpectrumToPhotometric`), so this times the light's
/// `scale` is what it emits. Negative channels (outside the sRGB gamut) are clamped to 0.
#[must_use]
pub fn blackbody_rgb(t: f64) -> [f64; 3] {
    let xyz = integrate(|l| planck(l, t));
    let y = xyz[1];
    xyz_to_srgb(xyz.map(|c| c / y)).map(|c| c.max(0.0))
}

/// Linear sRGB of a sampled spectrum given as `(wavelength nm, value)` pairs (linear
/// interpolation, constant beyond the ends), relative to an equal-energy white: a reflectance of
/// 1 everywhere gives about `[1, 1, 1]` (the white point differs from D65 by a few percent).
#[must_use]
pub fn sampled_rgb(pairs: &[(f64, f64)]) -> [f64; 3] {
    let at = |l: f64| -> f64 {
        match pairs.iter().position(|&(w, _)| w >= l) {
            None => pairs.last().map_or(0.0, |p| p.1),
            Some(0) => pairs[0].1,
            Some(i) => {
                let ((w0, v0), (w1, v1)) = (pairs[i - 1], pairs[i]);
                v0 + (v1 - v0) * (l - w0) / (w1 - w0)
            }
        }
    };
    let white = integrate(|_| 1.0);
    let xyz = integrate(at);
    // Scale so that the equal-energy white has Y = 1.
    let rgb = xyz_to_srgb(xyz.map(|c| c / white[1]));
    let w = xyz_to_srgb(white.map(|c| c / white[1]));
    [0, 1, 2].map(|k| (rgb[k] / w[k]).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_peaks_where_the_cie_functions_do() {
        // y-bar peaks near 555 nm at about 1 (CIE 1931: 1.0 at 555 nm).
        let (peak, _) = (400..700)
            .map(|l| (l, cmf(f64::from(l))[1]))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert!((550..=570).contains(&peak), "{peak}");
        assert!((cmf(555.0)[1] - 1.0).abs() < 0.03);
    }

    #[test]
    fn blackbodies_go_from_red_to_blue_with_unit_luminance() {
        let warm = blackbody_rgb(2700.0);
        let d65ish = blackbody_rgb(6500.0);
        let cold = blackbody_rgb(12000.0);
        assert!(warm[0] > warm[1] && warm[1] > warm[2], "{warm:?}");
        assert!(cold[2] > cold[0], "{cold:?}");
        // About white near 6500 K.
        assert!(d65ish.iter().all(|&c| (c - 1.0).abs() < 0.15), "{d65ish:?}");
        let y = 0.2126 * warm[0] + 0.7152 * warm[1] + 0.0722 * warm[2];
        assert!((y - 1.0).abs() < 0.02, "{y}");
        let flat = sampled_rgb(&[(400.0, 0.5), (700.0, 0.5)]);
        assert!(flat.iter().all(|&c| (c - 0.5).abs() < 1e-9), "{flat:?}");
    }
}
