//! A chi-square goodness-of-fit test of a sampling routine against its own pdf, as Nori's
//! `warptest` and Mitsuba 3's `mitsuba.chi2.ChiSquareTest` do: bin the domain finely, integrate
//! the pdf over each bin numerically (expected counts), histogram the samples (observed counts),
//! pool the bins with expected counts below 5, and reject at a Bonferroni-corrected significance.
//!
//! Directions are binned in `(z, phi)`, where `d omega = dz dphi` (Archimedes): equal-area bins
//! and no Jacobian. Samples that fail (`None`) fall into one extra bin whose expected count is the
//! probability mass the pdf does not cover.

use super::SplitMix64;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Samples per test (fixed: with fixed seeds the outcome is deterministic).
pub const SAMPLES: usize = 400_000;
/// Significance of the whole suite; each test uses `ALPHA / TESTS` (Bonferroni).
pub const ALPHA: f64 = 0.01;
/// An upper bound on the number of chi-square tests in the crate, for the Bonferroni correction
/// (about 170 since the conductor, Beckmann and anisotropic tests).
pub const TESTS: f64 = 200.0;

/// The outcome of one test (the figures are read through `Debug` in failure messages).
#[derive(Clone, Debug)]
#[allow(dead_code)]
pub struct Chi2 {
    /// The statistic.
    pub statistic: f64,
    /// Degrees of freedom (bins after pooling, minus 1).
    pub dof: usize,
    /// Probability of a statistic at least this large if the sampler matches the pdf.
    pub p_value: f64,
    /// A reason the test failed outright (a NaN sample, a pdf integrating above 1), if any.
    /// Samples where the pdf is zero land in the pooled bin, where they fail the statistic.
    pub defect: Option<String>,
}

impl Chi2 {
    /// Whether the sampler passes at the Bonferroni-corrected significance.
    #[must_use]
    pub fn passes(&self) -> bool {
        self.defect.is_none() && self.p_value > ALPHA / TESTS
    }

    /// Panics with the figures unless the test passes.
    pub fn assert_passes(&self, what: &str) {
        assert!(self.passes(), "{what}: chi2 rejects the sampler: {self:?}");
    }
}

/// Unit direction from `(z, phi)`.
#[must_use]
pub fn direction(z: f64, phi: f64) -> DVec3 {
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Test a direction sampler over the band `z in [z_min, z_max]` (use `[-1, 1]` for the whole
/// sphere; narrower for a cone or a hemisphere to align bins with the support).
pub fn test_directions(
    (z_min, z_max): (f64, f64),
    seed: u64,
    mut sample: impl FnMut(&mut SplitMix64) -> Option<DVec3>,
    pdf: impl Fn(DVec3) -> f64,
) -> Chi2 {
    let min = DVec2::new(z_min, -PI);
    let max = DVec2::new(z_max, PI);
    test_rect(
        (min, max),
        (32, 64),
        seed,
        |rng| sample(rng).map(|w| DVec2::new(w.z, w.y.atan2(w.x))),
        |p| pdf(direction(p.x, p.y)),
    )
}

/// Test a sampler of points in the rectangle `[min, max]` against an area pdf.
pub fn test_plane(
    (min, max): (DVec2, DVec2),
    seed: u64,
    sample: impl FnMut(&mut SplitMix64) -> Option<DVec2>,
    pdf: impl Fn(DVec2) -> f64,
) -> Chi2 {
    test_rect((min, max), (48, 48), seed, sample, pdf)
}

/// The common core over a rectangle with `res` bins per axis.
fn test_rect(
    (min, max): (DVec2, DVec2),
    (nx, ny): (usize, usize),
    seed: u64,
    mut sample: impl FnMut(&mut SplitMix64) -> Option<DVec2>,
    pdf: impl Fn(DVec2) -> f64,
) -> Chi2 {
    let cell = (max - min) / DVec2::new(nx as f64, ny as f64);
    let mut observed = vec![0.0f64; nx * ny + 1];
    let mut rng = SplitMix64::new(seed);
    for _ in 0..SAMPLES {
        let bin = match sample(&mut rng) {
            Some(p) if p.is_finite() => {
                let c = ((p - min) / cell).floor();
                let (ix, iy) = (c.x as i64, c.y as i64);
                // On the upper edge (z = 1 exactly) count in the last bin.
                let ix = if ix == nx as i64 && p.x == max.x {
                    ix - 1
                } else {
                    ix
                };
                let iy = if iy == ny as i64 && p.y == max.y {
                    iy - 1
                } else {
                    iy
                };
                if ix < 0 || iy < 0 || ix >= nx as i64 || iy >= ny as i64 {
                    nx * ny // outside the tested band: counts as a miss
                } else {
                    iy as usize * nx + ix as usize
                }
            }
            Some(_) => {
                return defect("a sample is NaN or infinite");
            }
            None => nx * ny,
        };
        observed[bin] += 1.0;
    }
    let mut expected = vec![0.0f64; nx * ny + 1];
    for iy in 0..ny {
        for ix in 0..nx {
            let lo = min + cell * DVec2::new(ix as f64, iy as f64);
            expected[iy * nx + ix] = integrate(&pdf, lo, lo + cell, 8) * SAMPLES as f64;
        }
    }
    let covered: f64 = expected[..nx * ny].iter().sum::<f64>() / SAMPLES as f64;
    if covered > 1.0 + 2e-3 {
        return defect(&format!("the pdf integrates to {covered} > 1"));
    }
    expected[nx * ny] = (1.0 - covered).max(0.0) * SAMPLES as f64;
    let (statistic, dof) = pooled_statistic(&observed, &expected);
    Chi2 {
        statistic,
        dof,
        p_value: chi2_survival(statistic, dof as f64),
        defect: None,
    }
}

fn defect(why: &str) -> Chi2 {
    Chi2 {
        statistic: f64::INFINITY,
        dof: 0,
        p_value: 0.0,
        defect: Some(why.to_owned()),
    }
}

/// Pearson's statistic with every bin of expected count below 5 pooled into one (Mitsuba 3's
/// rule), and its degrees of freedom.
fn pooled_statistic(observed: &[f64], expected: &[f64]) -> (f64, usize) {
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    let mut stat = 0.0;
    let mut bins = 0usize;
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            bins += 1;
        }
    }
    if pool_e >= 5.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        bins += 1;
    } else if pool_o > pool_e + 5.0 {
        // Many samples where almost no mass is expected: a gross mismatch.
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e.max(1.0);
        bins += 1;
    }
    (stat, bins.saturating_sub(1).max(1))
}

/// The integral of `f` over `[lo, hi]`, adaptive: a cell's 6x6 midpoint estimate is compared
/// with the sum of its four quadrants' and refined until they agree to `TOL` (in probability,
/// i.e. well under one expected sample) or to depth `depth` (peaked GGX lobes and support edges
/// inside one bin need it; Mitsuba 3's chi2 integrates with adaptive cubature for this reason).
fn integrate(f: &impl Fn(DVec2) -> f64, lo: DVec2, hi: DVec2, depth: u32) -> f64 {
    let coarse = midpoint(f, lo, hi);
    refine(f, lo, hi, coarse, depth)
}

/// Absolute tolerance per bin, in probability (0.004 expected samples at 400k; 1e-7 was too
/// loose for the rough dielectric at grazing incidence, alpha 0.9: 0.2% of the mass missed).
const TOL: f64 = 1e-8;

fn refine(f: &impl Fn(DVec2) -> f64, lo: DVec2, hi: DVec2, coarse: f64, depth: u32) -> f64 {
    let mid = 0.5 * (lo + hi);
    let quads = [
        (lo, mid),
        (DVec2::new(mid.x, lo.y), DVec2::new(hi.x, mid.y)),
        (DVec2::new(lo.x, mid.y), DVec2::new(mid.x, hi.y)),
        (mid, hi),
    ];
    let parts = quads.map(|(a, b)| midpoint(f, a, b));
    let fine: f64 = parts.iter().sum();
    if depth == 0 || (fine - coarse).abs() <= TOL {
        return fine;
    }
    quads
        .iter()
        .zip(parts)
        .map(|(&(a, b), c)| refine(f, a, b, c, depth - 1))
        .sum()
}

/// 6x6 midpoint rule.
fn midpoint(f: &impl Fn(DVec2) -> f64, lo: DVec2, hi: DVec2) -> f64 {
    const K: usize = 6;
    let h = (hi - lo) / K as f64;
    let mut sum = 0.0;
    for j in 0..K {
        for i in 0..K {
            sum += f(lo + h * DVec2::new(i as f64 + 0.5, j as f64 + 0.5));
        }
    }
    sum * h.x * h.y
}

/// `P(X >= x)` for a chi-square variable with `k` degrees of freedom: the regularised upper
/// incomplete gamma `Q(k/2, x/2)` (Numerical Recipes 3rd ed., section 6.2: series below
/// `a + 1`, Lentz's continued fraction above).
#[must_use]
pub fn chi2_survival(x: f64, k: f64) -> f64 {
    let (a, x) = (0.5 * k, 0.5 * x);
    if x <= 0.0 {
        return 1.0;
    }
    let ln_pre = a * x.ln() - x - libm::lgamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * ln_pre.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -f64::from(i) * (f64::from(i) - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        ln_pre.exp() * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp;

    #[test]
    fn survival_function_matches_tables() {
        // chi2 critical values: P(X >= 3.841) = 0.05 at k = 1; P(X >= 124.342) = 0.05 at
        // k = 100; P(X >= 2) = e^-1 at k = 2.
        assert!((chi2_survival(3.841_458_820_694_124, 1.0) - 0.05).abs() < 1e-9);
        assert!((chi2_survival(124.342_113_404_9, 100.0) - 0.05).abs() < 1e-8);
        assert!((chi2_survival(2.0, 2.0) - (-1.0f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn the_test_catches_a_mismatched_pdf() {
        // Cosine-weighted samples tested against the uniform hemisphere pdf: must fail.
        let r = test_directions(
            (0.0, 1.0),
            1,
            |rng| Some(warp::square_to_cosine_hemisphere(rng.next_2d())),
            |w| if w.z > 0.0 { 0.5 / PI } else { 0.0 },
        );
        assert!(!r.passes(), "{r:?}");
        // A subtler error: a cone pdf 3% too small (a wrong normalisation) also fails,
        // through the failure bin's missing mass.
        let (c, s2) = (0.8, 0.36);
        let r = test_directions(
            (c, 1.0),
            2,
            |rng| Some(warp::square_to_uniform_cone(rng.next_2d(), c, s2)),
            |w| 0.97 * warp::uniform_cone_pdf(w, c, s2),
        );
        assert!(!r.passes(), "{r:?}");
        // And a shape error that keeps the normalisation: cos^1.1 instead of cos.
        let r = test_directions(
            (0.0, 1.0),
            3,
            |rng| Some(warp::square_to_cosine_hemisphere(rng.next_2d())),
            |w| {
                if w.z > 0.0 {
                    w.z.powf(1.1) * 2.1 / (2.0 * PI)
                } else {
                    0.0
                }
            },
        );
        assert!(!r.passes(), "{r:?}");
    }

    #[test]
    fn the_test_rejects_samples_where_the_pdf_is_zero() {
        let r = test_plane(
            (DVec2::splat(-1.0), DVec2::splat(1.0)),
            4,
            |rng| Some(2.0 * rng.next_2d() - DVec2::ONE),
            |p| if p.x < 0.9 { 1.0 / 3.8 } else { 0.0 },
        );
        assert!(!r.passes(), "{r:?}");
    }
}
