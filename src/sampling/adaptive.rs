//! Adaptive antialiasing's decision (`settings.adaptive`): does a pixel's first pass of samples
//! disagree enough to take more?
//!
//! Whitted (1980, "An improved illumination model for shaded display", section 5) sampled the
//! corners of each pixel and subdivided where they differed; Mitchell (1987, "Generating
//! antialiased images at low sampling densities") measured the difference as the contrast
//! `(max - min) / (max + min)` per channel, which follows the eye's relative sensitivity. Here
//! the first pass is the pixel's own stratified samples and the contrast has 0.01 added to its
//! denominator (the offset of the relative error `(img - ref) / (ref + 0.01)` the Mitsuba bench
//! measures), so that differences between nearly black samples, which nobody sees, do not
//! refine. The decision depends on the pixel's own samples only: re-tracing one pixel
//! (`raytree trace`) makes the same decision and records the same samples.
//!
//! Deciding from the samples that then enter the mean biases it slightly (Kirk and Arvo 1991,
//! "Unbiased sampling techniques for image synthesis"): a refined pixel's mean is over all of its
//! samples, each pass stratified on its own complete grid (every stratum one sample, see
//! [`super::stratified`]), so each pass alone is unbiased and only the choice between "first
//! pass" and "both passes" depends on the data. For the Whitted integrator, whose samples are
//! deterministic functions of their film positions, a pixel is refined exactly where the
//! image has an edge (or a gradient) inside it.

use crate::math::Rgb;

/// Added to the contrast's denominator: differences between samples darker than about this
/// count for little.
pub const CONTRAST_FLOOR: f64 = 0.01;

/// The per-channel minimum and maximum of a pixel's samples so far.
#[derive(Clone, Copy, Debug)]
pub struct Spread {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Default for Spread {
    fn default() -> Self {
        Self {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
        }
    }
}

impl Spread {
    /// Take one sample's radiance into account (a NaN channel is ignored).
    #[inline]
    pub fn add(&mut self, l: Rgb) {
        for (i, c) in l.to_array().into_iter().enumerate() {
            self.lo[i] = self.lo[i].min(c);
            self.hi[i] = self.hi[i].max(c);
        }
    }

    /// The largest per-channel contrast `(max - min) / (|max| + |min| + CONTRAST_FLOOR)` of the
    /// samples added (0 for none or one; infinite samples give 1 or NaN, and NaN compares as
    /// no refinement).
    #[must_use]
    pub fn contrast(&self) -> f64 {
        (0..3)
            .map(|i| {
                let (lo, hi) = (self.lo[i], self.hi[i]);
                if hi <= lo {
                    0.0
                } else {
                    (hi - lo) / (hi.abs() + lo.abs() + CONTRAST_FLOOR)
                }
            })
            .fold(0.0, f64::max)
    }
}

/// The contrast of `samples` ([`Spread::contrast`]).
#[must_use]
pub fn contrast(samples: &[Rgb]) -> f64 {
    let mut s = Spread::default();
    for &l in samples {
        s.add(l);
    }
    s.contrast()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_samples_have_no_contrast_and_an_edge_has_much() {
        let a = Rgb::new(0.2, 0.3, 0.4);
        assert_eq!(contrast(&[a, a, a]), 0.0);
        assert_eq!(contrast(&[a]), 0.0);
        assert_eq!(contrast(&[]), 0.0);
        // Background 0.2 against an emitter of 1.0 in one channel: 0.8 / 1.21.
        let b = Rgb::new(1.0, 0.3, 0.4);
        assert!((contrast(&[a, b]) - 0.8 / 1.21).abs() < 1e-12);
        // Scale-invariant far above the floor, damped near black.
        let k = contrast(&[a * 100.0, b * 100.0]);
        assert!((k - 80.0 / 120.01).abs() < 1e-12);
        assert!(contrast(&[Rgb::ZERO, Rgb::splat(0.001)]) < 0.1);
    }

    #[test]
    fn nan_does_not_refine() {
        let n = Rgb::new(f64::NAN, 0.0, 0.0);
        assert_eq!(contrast(&[n, n]), 0.0);
    }
}
