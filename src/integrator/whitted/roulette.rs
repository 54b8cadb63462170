//! Russian-roulette splitting at dielectrics (`settings.dielectric_roulette`, issue 18): from a
//! chosen depth on, a smooth dielectric hit follows one of its reflected and refracted rays
//! instead of both, chosen with probability proportional to their weights (max channel), and
//! the chosen ray's weight is divided by its probability. The expectation of the two-branch
//! estimate `p (w_r / p) L_r + (1 - p) (w_t / (1 - p)) L_t` is the split's `w_r L_r + w_t L_t`
//! (Arvo and Kirk 1990, "Particle transport and image synthesis", section 3.2; pbrt-v4 section
//! 9.5's `DielectricBxDF` samples the same choice with `R / (R + T)`), so deep glass stays exact
//! in expectation at linear cost instead of the 2^depth tree.
//!
//! The choice's random number is a SplitMix64 hash of the hit point, the incident direction and
//! `settings.seed`: no sampler dimension is drawn (the Whitted integrator draws none, and its
//! camera packets rely on that), and a re-traced pixel makes the same choices bit for bit.
//! Different seeds give independent-looking choices at the same pixel, which is what the
//! expectation test varies.

use crate::math::Rgb;
use crate::sampling::{splitmix64, unit};
use crate::tree::SplitRoulette;
use glam::DVec3;

/// The uniform number in `[0, 1)` of the choice at hit point `p` for incident direction `d`.
#[must_use]
pub fn choice(seed: u64, p: DVec3, d: DVec3) -> f64 {
    let mut h = splitmix64(seed);
    for v in [p.x, p.y, p.z, d.x, d.y, d.z] {
        h = splitmix64(h ^ v.to_bits());
    }
    unit(h)
}

/// Play the roulette between reflection weight `reflect` and refraction weight `refract` with
/// uniform number `u`: the weights of the ray to follow (the other is zero) and the choice made
/// (`None`, both weights unchanged, when one weight is zero: nothing to choose).
#[must_use]
pub fn decide(reflect: Rgb, refract: Rgb, u: f64) -> (Rgb, Rgb, Option<SplitRoulette>) {
    let (a, b) = (reflect.max_element(), refract.max_element());
    if a <= 0.0 || b <= 0.0 {
        return (reflect, refract, None);
    }
    let p = a / (a + b);
    if u < p {
        let choice = SplitRoulette {
            reflected: true,
            probability: p,
        };
        (reflect / p, Rgb::ZERO, Some(choice))
    } else {
        let choice = SplitRoulette {
            reflected: false,
            probability: 1.0 - p,
        };
        (Rgb::ZERO, refract / (1.0 - p), Some(choice))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two outcomes, weighted by their probabilities, sum to the split's weights.
    #[test]
    fn the_expectation_is_the_split() {
        let (r, t) = (Rgb::new(0.04, 0.05, 0.06), Rgb::new(0.96, 0.9, 0.94));
        let p = 0.06 / (0.06 + 0.96);
        let (r1, t1, c1) = decide(r, t, p * 0.5);
        let (r2, t2, c2) = decide(r, t, p + (1.0 - p) * 0.5);
        assert_eq!(t1, Rgb::ZERO);
        assert_eq!(r2, Rgb::ZERO);
        let c1 = c1.expect("a choice");
        let c2 = c2.expect("a choice");
        assert!(c1.reflected && !c2.reflected);
        assert_eq!((c1.probability, c2.probability), (p, 1.0 - p));
        assert!((r1 * p + r2 * (1.0 - p) - r).abs().max_element() < 1e-15);
        assert!((t1 * p + t2 * (1.0 - p) - t).abs().max_element() < 1e-15);
        // One branch only (TIR, or nothing transmitted): no roulette.
        assert_eq!(decide(r, Rgb::ZERO, 0.3), (r, Rgb::ZERO, None));
        let u = choice(1, DVec3::ONE, DVec3::X);
        assert!((0.0..1.0).contains(&u) && u != choice(2, DVec3::ONE, DVec3::X));
    }
}
