//! Importance-sampled pixel filters: the camera ray's offset from the pixel centre is drawn from
//! the filter's own (normalised, non-negative) distribution, so every sample's filter weight is
//! exactly 1, each sample belongs to one pixel and the pixel is the plain mean of its samples
//! (pbrt-v4 section 8.8.3 "Filter Importance Sampling"; Ernst et al. 2006). Every filter here is
//! separable and non-negative, so it is sampled exactly by inverting its 1D CDF per axis (pbrt-v4
//! instead tabulates its filters; exact inversion keeps the weight exactly 1).

use glam::DVec2;
use std::f64::consts::{PI, SQRT_2};

/// A pixel filter, in pixel units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// Uniform over the pixel, `[-1/2, 1/2]^2` (today's box).
    Box,
    /// Separable tent `(r - |x|) (r - |y|) / r^4` over `[-r, r]^2`.
    Tent {
        /// Radius in pixels (> 0).
        radius: f64,
    },
    /// Separable Gaussian of standard deviation `sigma`, truncated to `[-r, r]^2` and
    /// renormalised (not shifted to zero at the edge).
    Gaussian {
        /// Standard deviation in pixels (> 0).
        sigma: f64,
        /// Truncation radius in pixels (> 0).
        radius: f64,
    },
}

impl PixelFilter {
    /// Half-width of the support per axis.
    #[must_use]
    pub fn radius(&self) -> f64 {
        match *self {
            Self::Box => 0.5,
            Self::Tent { radius } | Self::Gaussian { radius, .. } => radius,
        }
    }

    /// The offset from the pixel centre, in pixels, drawn with density [`Self::pdf`].
    #[must_use]
    pub fn sample(&self, u: DVec2) -> DVec2 {
        match *self {
            Self::Box => u - DVec2::splat(0.5),
            Self::Tent { radius } => {
                DVec2::new(tent_inv_cdf(u.x, radius), tent_inv_cdf(u.y, radius))
            }
            Self::Gaussian { sigma, radius } => DVec2::new(
                gaussian_inv_cdf(u.x, sigma, radius),
                gaussian_inv_cdf(u.y, sigma, radius),
            ),
        }
    }

    /// The density of [`Self::sample`] at `offset` (pixels^-2); it integrates to 1.
    #[must_use]
    pub fn pdf(&self, offset: DVec2) -> f64 {
        match *self {
            Self::Box => {
                if offset.abs().max_element() <= 0.5 {
                    1.0
                } else {
                    0.0
                }
            }
            Self::Tent { radius } => tent_pdf(offset.x, radius) * tent_pdf(offset.y, radius),
            Self::Gaussian { sigma, radius } => {
                gaussian_pdf(offset.x, sigma, radius) * gaussian_pdf(offset.y, sigma, radius)
            }
        }
    }
}

/// 1D tent density `(r - |x|) / r^2` on `[-r, r]`.
fn tent_pdf(x: f64, r: f64) -> f64 {
    ((r - x.abs()) / (r * r)).max(0.0)
}

/// Inverse CDF of the 1D tent: the two halves are linear densities (pbrt-v4 `SampleTent`).
fn tent_inv_cdf(u: f64, r: f64) -> f64 {
    if u < 0.5 {
        r * ((2.0 * u).sqrt() - 1.0)
    } else {
        r * (1.0 - (2.0 - 2.0 * u).max(0.0).sqrt())
    }
}

/// 1D truncated Gaussian density `exp(-x^2 / 2 s^2) / Z` on `[-r, r]`,
/// `Z = s sqrt(2 pi) erf(r / (s sqrt 2))`.
fn gaussian_pdf(x: f64, s: f64, r: f64) -> f64 {
    if x.abs() > r {
        return 0.0;
    }
    let z = s * (2.0 * PI).sqrt() * libm::erf(r / (s * SQRT_2));
    (-x * x / (2.0 * s * s)).exp() / z
}

/// Inverse CDF of the truncated Gaussian: solve `erf(x / (s sqrt 2)) = (2u - 1) erf(r / (s sqrt 2))`
/// by Newton's method safeguarded by bisection on `[-r, r]` (libm's `erf` is accurate to about
/// 1 ulp, so the sample follows the stated density to rounding).
fn gaussian_inv_cdf(u: f64, s: f64, r: f64) -> f64 {
    let k = 1.0 / (s * SQRT_2);
    let target = (2.0 * u - 1.0) * libm::erf(r * k);
    let f = |x: f64| libm::erf(x * k) - target;
    let (mut lo, mut hi) = (-r, r);
    // Start from Giles' single-precision erfinv (relative error about 1e-7), so Newton
    // converges in two or three steps instead of bisecting from a rough guess.
    let mut x = (erfinv_approx(target) / k).clamp(lo, hi);
    for _ in 0..100 {
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let dfdx = 2.0 / PI.sqrt() * k * (-(x * k) * (x * k)).exp();
        let newton = x - fx / dfdx;
        let next = if newton > lo && newton < hi && dfdx > 0.0 {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 1e-15 * r.max(1.0) || hi - lo <= 1e-15 * r {
            return next;
        }
        x = next;
    }
    x
}

/// Giles 2010, "Approximating the erfinv function" (GPU Computing Gems Jade, ch. 10), the
/// single-precision polynomial in `w = -ln((1 - x)(1 + x))`; a starting point for Newton.
fn erfinv_approx(x: f64) -> f64 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    if !w.is_finite() {
        return x.signum() * f64::MAX;
    }
    let p = if w < 5.0 {
        let w = w - 2.5;
        [
            3.432_739_39e-7,
            -3.523_387_7e-6,
            -4.391_506_54e-6,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ]
        .iter()
        .fold(2.810_226_36e-8, |p, c| c + p * w)
    } else {
        let w = w.sqrt() - 3.0;
        [
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ]
        .iter()
        .fold(-0.000_200_214_257, |p, c| c + p * w)
    };
    p * x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_stay_in_the_support_and_are_finite_at_the_edges() {
        let filters = [
            PixelFilter::Box,
            PixelFilter::Tent { radius: 1.5 },
            PixelFilter::Gaussian {
                sigma: 0.5,
                radius: 1.5,
            },
            PixelFilter::Gaussian {
                sigma: 0.01,
                radius: 2.0,
            },
            PixelFilter::Gaussian {
                sigma: 100.0,
                radius: 0.5,
            },
        ];
        let edge = 1.0 - f64::EPSILON / 2.0;
        for f in filters {
            for u in [0.0, 1e-300, 0.25, 0.5, 0.75, edge] {
                let o = f.sample(DVec2::new(u, 1.0 - u.min(edge)));
                assert!(o.is_finite(), "{f:?} u {u}");
                assert!(o.abs().max_element() <= f.radius(), "{f:?} u {u}: {o}");
                assert!(f.pdf(o).is_finite());
            }
        }
    }

    #[test]
    fn gaussian_inverse_cdf_hits_known_quantiles() {
        // Nearly untruncated (r = 8 sigma): the 0.8413 quantile is 1 sigma.
        let x = gaussian_inv_cdf(0.841_344_746_068_542_9, 0.7, 5.6);
        assert!((x - 0.7).abs() < 1e-9, "{x}");
        assert_eq!(gaussian_inv_cdf(0.5, 0.7, 5.6), 0.0);
        // Odd symmetry.
        let a = gaussian_inv_cdf(0.1, 0.5, 1.0);
        let b = gaussian_inv_cdf(0.9, 0.5, 1.0);
        assert!((a + b).abs() < 1e-12);
    }

    #[test]
    fn the_erfinv_start_is_close() {
        for x in [-0.999_999, -0.9, -0.3, 0.0, 1e-12, 0.5, 0.99, 0.999_999_9] {
            let y = erfinv_approx(x);
            assert!(
                (libm::erf(y) - x).abs() < 1e-6 * (1.0 - x.abs()).max(1e-3),
                "{x}: {y}"
            );
        }
    }

    #[test]
    fn tent_inverse_cdf_is_monotone_and_centred() {
        assert_eq!(tent_inv_cdf(0.5, 2.0), 0.0);
        let mut last = -3.0;
        for i in 0..=1000 {
            let x = tent_inv_cdf(f64::from(i) / 1000.0, 2.0);
            assert!(x >= last);
            last = x;
        }
        // CDF at x = -1 (r = 2) is (r + x)^2 / (2 r^2) = 1/8.
        assert!((tent_inv_cdf(0.125, 2.0) + 1.0).abs() < 1e-12);
    }
}
