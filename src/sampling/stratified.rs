//! [`StratifiedJitter`], the default [`PixelSampler`]: jittered strata in the pixel, today's
//! positions bit for bit at seed 0; and the small hashes the samplers share.

use super::PixelSampler;

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, well-mixed hash for per-pixel seeds.
#[must_use]
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The top 53 bits of `h` as a double in `[0, 1)`.
#[must_use]
pub fn unit(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The default sampler: the film offset of sample `s` is the pixel centre for one sample per
/// pixel, otherwise jittered stratified on a `cols x rows` grid with `cols x rows = spp` exactly
/// (`cols` the smallest divisor of `spp` not below its square root, see `grid`), jittered by a SplitMix64 hash of (pixel, sample, seed); further dimensions are independent
/// uniform values from a counter-based hash of (pixel, sample, seed, dimension).
///
/// The seed enters as `key ^ (splitmix64(seed) ^ splitmix64(0))`, which is `key` for seed 0:
/// seed 0 gives exactly the positions raytree has always used.
#[derive(Clone, Copy, Debug)]
pub struct StratifiedJitter {
    /// Samples of the current pass (`spp`, or the second pass's count after
    /// [`PixelSampler::refine`]).
    spp: u32,
    /// The index of the pass's first sample (0; `spp` for adaptive antialiasing's second pass).
    base: u32,
    /// The strata grid's columns and rows ([`grid`]; `(1, 1)` for one sample).
    cols: u32,
    rows: u32,
    seed_mix: u64,
    /// The current sample's hash key (pixel, index, seed) of the film offset (the historical
    /// key: it repeats across pixels for sample indices from 512 on, see [`Self::hashed`]).
    key: u64,
    /// The current pixel `y << 32 | x`, hashed with the seed for the dimensions after the film
    /// offset (only when one is drawn: the Whitted render draws none and pays nothing).
    pixel: u64,
    /// The current sample index.
    sample: u32,
    /// The next dimension (0 and 1 are the film offset).
    dim: u32,
}

impl StratifiedJitter {
    /// A sampler for `spp` samples per pixel (at least 1) and `seed`.
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Self {
        let spp = spp.max(1);
        let (cols, rows) = if spp > 1 { grid(spp) } else { (1, 1) };
        Self {
            spp,
            base: 0,
            cols,
            rows,
            // Branch-free would hash twice per construction, and `render_pixel`'s callers build one
            // per pixel; at seed 0 the mix is 0 by definition.
            seed_mix: if seed == 0 {
                0
            } else {
                splitmix64(seed) ^ splitmix64(0)
            },
            key: 0,
            pixel: 0,
            sample: 0,
            dim: 0,
        }
    }

    /// The sampler of `settings` (its `spp` and `seed`).
    #[must_use]
    pub fn for_settings(settings: &crate::Settings) -> Self {
        Self::new(settings.spp, settings.seed)
    }

    /// A dimension after the film offset: a fresh hash of (pixel, seed, index, dimension).
    ///
    /// Not of the film offset's `key`: that key puts the index's bits 9 to 15 on the column's
    /// bits 0 to 6 (`(s << 48).rotate_left(7)`), so pixel (x, y) sample s and pixel (x ^ 1, y)
    /// sample s ^ 512 share it, and a lens sample drawn from it would repeat across neighbouring
    /// pixels at 512 samples per pixel and more (the render-path chi-square of the lens points
    /// rejected exactly that). Here the pixel is hashed before the index is mixed in: SplitMix64
    /// is a bijection, so distinct (pixel, index) pairs collide only by chance.
    #[inline]
    fn hashed(&mut self) -> f64 {
        self.dim = self.dim.max(2);
        let sample = splitmix64(splitmix64(self.pixel ^ self.seed_mix) ^ u64::from(self.sample));
        let h = splitmix64(sample ^ splitmix64(u64::from(self.dim) << 40));
        self.dim += 1;
        unit(h)
    }
}

impl PixelSampler for StratifiedJitter {
    #[inline]
    fn start_sample(&mut self, (x, y): (u32, u32), s: u32) {
        self.key = ((u64::from(y) << 32 | u64::from(x)) ^ (u64::from(s) << 48).rotate_left(7))
            ^ self.seed_mix;
        self.pixel = u64::from(y) << 32 | u64::from(x);
        self.sample = s;
        self.dim = 0;
    }

    /// Dimensions past the film offset (a 1D request at dimension 0 skips the film offset).
    #[inline]
    fn next_1d(&mut self) -> f64 {
        self.hashed()
    }

    /// The film offset inside the pixel at dimension 0, hashed pairs after it.
    #[inline]
    fn next_2d(&mut self) -> (f64, f64) {
        if self.dim == 0 {
            self.dim = 2;
            if self.spp <= 1 {
                return (0.5, 0.5);
            }
            let s = self.sample.wrapping_sub(self.base);
            return jittered(self.key, s, self.cols, self.rows);
        }
        (self.hashed(), self.hashed())
    }

    /// Samples `first..first + count` on their own `grid(count)` (the pixel centre for one),
    /// jittered by the same hash of (pixel, index, seed) as the first pass.
    fn refine(&mut self, first: u32, count: u32) {
        self.spp = count.max(1);
        self.base = first;
        (self.cols, self.rows) = if self.spp > 1 { grid(self.spp) } else { (1, 1) };
    }
}

/// The strata grid for `spp > 1` samples: `cols x rows = spp` exactly, `cols` the smallest
/// divisor of `spp` that is at least `sqrt(spp)` (a square grid for square counts, `8 x 4` for
/// 32, a row of strips for a prime). Every stratum holds one sample, so the pixel mean is
/// unbiased: a `ceil(sqrt(spp))`-column grid with an incomplete last row (raytree before
/// 2026-11-28, e.g. 32 samples on 6 x 6) leaves strata empty and over-weights the rest. Where
/// that grid was complete it equals this one, so those counts keep their positions bit for bit.
/// Out of line, so its square root is not hoisted into one-sample renders.
#[inline(never)]
#[must_use]
pub fn grid(spp: u32) -> (u32, u32) {
    let mut cols = (f64::from(spp).sqrt().ceil() as u32).max(1);
    while !spp.is_multiple_of(cols) {
        cols += 1;
    }
    (cols, spp / cols)
}

/// The stratified film offset of sample `s` on the `cols x rows` grid.
#[inline]
fn jittered(key: u64, s: u32, cols: u32, rows: u32) -> (f64, f64) {
    let seed = splitmix64(key);
    let jx = unit(seed);
    let jy = unit(splitmix64(seed));
    let sx = (f64::from(s % cols) + jx) / f64::from(cols);
    let sy = (f64::from(s / cols) + jy) / f64::from(rows);
    (sx, sy)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn draw(spp: u32, seed: u64, pixel: (u32, u32), s: u32) -> [f64; 5] {
        let mut sm = StratifiedJitter::new(spp, seed);
        sm.start_sample(pixel, s);
        let (a, b) = sm.next_2d();
        let c = sm.next_1d();
        let (d, e) = sm.next_2d();
        [a, b, c, d, e]
    }

    #[test]
    fn offsets_are_stratified_and_in_the_unit_square() {
        for spp in [2, 4, 5, 16] {
            let (cols, _) = grid(spp);
            for s in 0..spp {
                let v = draw(spp, 0, (3, 7), s);
                assert!(v.iter().all(|u| (0.0..1.0).contains(u)), "{v:?}");
                assert_eq!((v[0] * f64::from(cols)).floor() as u32, s % cols);
            }
        }
        assert_eq!(draw(1, 0, (3, 7), 0)[..2], [0.5, 0.5]);
        assert_eq!(draw(1, 9, (3, 7), 0)[..2], [0.5, 0.5]);
    }

    /// Every stratum of the grid holds exactly one sample, for every count up to 300, so the
    /// mean of the film offsets' strata is the pixel centre (unbiased). Fails on the old
    /// `ceil(sqrt(spp))` grid (32 samples left 4 of 36 strata empty).
    #[test]
    fn every_stratum_holds_one_sample() {
        for spp in 2..=300u32 {
            let (cols, rows) = grid(spp);
            assert_eq!(cols * rows, spp);
            assert!(cols >= rows, "{spp}: {cols} x {rows}");
            let mut seen = vec![false; spp as usize];
            let mut mean = (0.0, 0.0);
            for s in 0..spp {
                let v = draw(spp, 0, (3, 7), s);
                let (i, j) = (
                    (v[0] * f64::from(cols)) as u32,
                    (v[1] * f64::from(rows)) as u32,
                );
                assert!(
                    !seen[(j * cols + i) as usize],
                    "{spp}: stratum {i},{j} twice"
                );
                seen[(j * cols + i) as usize] = true;
                mean.0 += (f64::from(i) + 0.5) / f64::from(cols) / f64::from(spp);
                mean.1 += (f64::from(j) + 0.5) / f64::from(rows) / f64::from(spp);
            }
            assert!(
                (mean.0 - 0.5).abs() < 1e-12 && (mean.1 - 0.5).abs() < 1e-12,
                "{spp}"
            );
        }
        // Counts whose old ceil(sqrt) grid was complete keep it (their images stay the same).
        assert_eq!(grid(16), (4, 4));
        assert_eq!(grid(2), (2, 1));
        assert_eq!(grid(12), (4, 3));
        assert_eq!(grid(32), (8, 4));
        assert_eq!(grid(7), (7, 1));
    }

    /// Independent of [`grid`]: the film offsets of every count average to the pixel centre
    /// (over 1000 pixels, within 5 sigma of a uniform jitter's mean, an upper bound on the
    /// stratified one's). The old grid put 3 samples' mean at y = 0.417, 32 samples' at 0.448.
    #[test]
    fn film_offsets_average_to_the_pixel_centre() {
        for spp in 2..=64u32 {
            let (mut mx, mut my) = (0.0, 0.0);
            for p in 0..1000 {
                for s in 0..spp {
                    let v = draw(spp, 0, (p, 2 * p + 1), s);
                    mx += v[0];
                    my += v[1];
                }
            }
            let n = f64::from(spp * 1000);
            let tol = 5.0 * (1.0f64 / 12.0).sqrt() / n.sqrt();
            assert!(
                (mx / n - 0.5).abs() < tol && (my / n - 0.5).abs() < tol,
                "{spp}"
            );
        }
    }

    #[test]
    fn deterministic_and_different_per_pixel_sample_dimension_and_seed() {
        let a = draw(4, 0, (3, 7), 2);
        assert_eq!(a, draw(4, 0, (3, 7), 2));
        assert_ne!(a, draw(4, 0, (4, 7), 2));
        assert_ne!(a, draw(4, 0, (3, 7), 1));
        assert_ne!(a, draw(4, 1, (3, 7), 2));
        // Later dimensions differ from each other (no repeated hash).
        assert!(a[2] != a[3] && a[3] != a[4] && a[2] != a[4]);
        // At one sample per pixel the seed changes the later dimensions only.
        let (b, c) = (draw(1, 0, (3, 7), 0), draw(1, 5, (3, 7), 0));
        assert_eq!(b[..2], c[..2]);
        assert_ne!(b[2..], c[2..]);
    }

    /// Seed 0 is the historical position formula, written out independently.
    #[test]
    fn seed_zero_is_the_historical_jitter() {
        let (x, y, s, spp) = (5u32, 11u32, 3u32, 9u32);
        let seed =
            splitmix64((u64::from(y) << 32 | u64::from(x)) ^ (u64::from(s) << 48).rotate_left(7));
        let want = (
            (f64::from(s % 3) + unit(seed)) / 3.0,
            (f64::from(s / 3) + unit(splitmix64(seed))) / 3.0,
        );
        assert_eq!(draw(spp, 0, (x, y), s)[..2], [want.0, want.1]);
        assert_ne!(draw(spp, 1, (x, y), s)[..2], [want.0, want.1]);
    }

    /// Later dimensions do not repeat across pixels (the film offset's key does, from sample
    /// index 512 on: pixel (1, 0) sample 0 and pixel (0, 0) sample 512).
    #[test]
    fn later_dimensions_differ_where_the_film_key_repeats() {
        let (a, b) = (draw(1024, 0, (1, 0), 0), draw(1024, 0, (0, 0), 512));
        assert_ne!(a[2..], b[2..]);
        let mut seen = std::collections::HashSet::new();
        for x in 0..64 {
            for s in (0..4096).step_by(7) {
                let v = draw(4096, 5, (x, 3), s);
                assert!(seen.insert(v[2].to_bits()), "repeat at ({x}, 3) sample {s}");
            }
        }
    }

    /// Adaptive antialiasing's second pass fills its own grid: every stratum of `grid(count)`
    /// holds exactly one of samples `first..first + count`, for pass sizes the default factor
    /// gives and odd ones.
    #[test]
    fn a_refined_pass_fills_its_own_grid() {
        for (spp, max) in [(4, 64), (2, 32), (4, 5), (9, 144), (16, 256), (3, 10)] {
            let count = max - spp;
            let mut sm = StratifiedJitter::new(spp, 7);
            sm.refine(spp, count);
            let (cols, rows) = if count > 1 { grid(count) } else { (1, 1) };
            let mut seen = vec![false; count as usize];
            for s in spp..max {
                sm.start_sample((5, 9), s);
                let (u, v) = sm.next_2d();
                assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
                let (i, j) = ((u * f64::from(cols)) as u32, (v * f64::from(rows)) as u32);
                let k = (j * cols + i) as usize;
                assert!(!seen[k], "{spp}..{max}: stratum {i},{j} twice");
                seen[k] = true;
            }
            assert!(seen.iter().all(|&b| b), "{spp}..{max}");
        }
    }

    /// Later dimensions are uniform: a coarse histogram over many samples.
    #[test]
    fn later_dimensions_fill_the_unit_interval() {
        let mut bins = [0u32; 10];
        for s in 0..4000 {
            let v = draw(16, 3, (s % 13, s / 13), s);
            for u in &v[2..] {
                bins[(u * 10.0) as usize] += 1;
            }
        }
        // 1200 expected per bin; 6 sigma is about 200.
        assert!(bins.iter().all(|&b| (1000..1400).contains(&b)), "{bins:?}");
    }
}
