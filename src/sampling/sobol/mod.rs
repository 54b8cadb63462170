//! A per-pixel sampler: hash-based Owen-scrambled, shuffled Sobol points (Burley 2020,
//! "Practical Hash-based Owen Scrambling", JCGT 9(4); the same scheme as pbrt-v4's
//! `ZSobolSampler`'s scrambling and Mitsuba 3's `independent`-seeded `sobol` padding).
//!
//! Every value is a pure function of (seed, pixel, sample index, dimension): re-tracing one pixel
//! reproduces the render bit for bit, whatever order pixels and samples are visited in.
//!
//! Each call to [`SobolSampler::next_2d`] takes one *dimension pair* and returns the first two
//! Sobol dimensions of a shuffled index, each Owen-scrambled with its own seed ("padding", Burley
//! section 4). Shuffling the index by a nested uniform scramble keeps the first `2^m` samples of a
//! pixel an aligned block of `2^m` Sobol points, hence a (0, m, 2)-net in every pair.

use glam::DVec2;

/// `1 / 2^32`: maps a 32-bit fixed-point value to `[0, 1)`; never returns 1.
const TO_UNIT: f64 = 1.0 / 4_294_967_296.0;

/// The Laine-Karras permutation with Vegdahl's constants (Burley 2020, listing 2): each output bit
/// depends only on the same and lower input bits.
#[must_use]
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Owen (nested uniform) scrambling of a base-2 fixed-point value: each bit is flipped depending
/// only on the more significant bits (Burley 2020, listing 3).
#[must_use]
#[inline]
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// The first Sobol dimension (van der Corput in base 2) as 32-bit fixed point.
#[must_use]
#[cfg(test)]
fn sobol_dim0(index: u32) -> u32 {
    index.reverse_bits()
}

/// The second Sobol dimension (primitive polynomial x + 1: direction numbers
/// `v_0 = 2^31`, `v_k = v_{k-1} ^ (v_{k-1} >> 1)`; Joe and Kuo 2008) as 32-bit fixed point:
/// the XOR of `v_k` over the set bits `k` of `index`. The definition; the render reads it
/// through [`dim1_reversed`].
#[cfg(test)]
#[must_use]
fn sobol_dim1(mut index: u32) -> u32 {
    let mut v: u32 = 1 << 31;
    let mut x = 0;
    while index != 0 {
        if index & 1 != 0 {
            x ^= v;
        }
        index >>= 1;
        v ^= v >> 1;
    }
    x
}

/// `sobol_dim1(r.reverse_bits()).reverse_bits()`, a byte of `r` at a time from
/// [`DIM1_REVERSED`]: four table look-ups instead of a loop over up to 32 bits (the shuffled
/// index has all 32 bits in play; the loop was a quarter of a path-traced render's time) and
/// no bit reversal (the Owen scramble works on reversed bits).
#[must_use]
#[inline]
fn dim1_reversed(r: u32) -> u32 {
    let b = r.to_le_bytes();
    DIM1_REVERSED[0][b[0] as usize]
        ^ DIM1_REVERSED[1][b[1] as usize]
        ^ DIM1_REVERSED[2][b[2] as usize]
        ^ DIM1_REVERSED[3][b[3] as usize]
}

/// `DIM1_REVERSED[j][b]`: the XOR of `v_{31 - (8j + i)}.reverse_bits()` over the set bits `i`
/// of the byte `b` (bit `8j + i` of a reversed index is bit `31 - 8j - i` of the index).
static DIM1_REVERSED: [[u32; 256]; 4] = dim1_tables();

const fn dim1_tables() -> [[u32; 256]; 4] {
    let mut v = [0u32; 32];
    let mut k = 0;
    let mut d: u32 = 1 << 31;
    while k < 32 {
        v[k] = d.reverse_bits();
        d ^= d >> 1;
        k += 1;
    }
    let mut t = [[0u32; 256]; 4];
    let mut j = 0;
    while j < 4 {
        let mut b = 0;
        while b < 256 {
            let mut x = 0;
            let mut i = 0;
            while i < 8 {
                if b & (1 << i) != 0 {
                    x ^= v[31 - (8 * j + i)];
                }
                i += 1;
            }
            t[j][b] = x;
            b += 1;
        }
        j += 1;
    }
    t
}

/// A 64-bit finaliser (splitmix64 / Stafford's Mix13) to derive independent seeds.
#[must_use]
#[inline]
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The hash of a dimension pair alone, `mix64(pair + 0x9e37...)`: the part of
/// [`pair_seeds`] that does not depend on the pixel.
#[must_use]
#[inline]
const fn pair_hash(pair: u32) -> u64 {
    mix64((pair as u64).wrapping_add(0x9e37_79b9_7f4a_7c15))
}

/// Dimension pairs whose [`pair_hash`] is tabulated (a path of depth 16 with light samples and
/// Russian roulette draws about 80 pairs).
const HASHED_PAIRS: usize = 128;

/// [`pair_hash`] of the first [`HASHED_PAIRS`] pairs, computed at compile time.
static PAIR_HASH: [u64; HASHED_PAIRS] = {
    let mut t = [0u64; HASHED_PAIRS];
    let mut i = 0;
    while i < HASHED_PAIRS {
        t[i] = pair_hash(i as u32);
        i += 1;
    }
    t
};

/// The per-(pixel, dimension pair) seeds: index shuffle, x scramble, y scramble.
#[must_use]
#[inline]
fn pair_seeds(pixel_key: u64, pair: u32) -> (u32, u32, u32) {
    let ph = match PAIR_HASH.get(pair as usize) {
        Some(&h) => h,
        None => pair_hash(pair),
    };
    let h = mix64(pixel_key ^ ph);
    let h2 = mix64(h);
    (h as u32, (h >> 32) as u32, h2 as u32)
}

/// The 2D point of dimension pair `pair` of sample `index` in the pixel keyed by `pixel_key`,
/// as 32-bit fixed point: `nested_uniform_scramble(sobol_dim0(i), s_x)` and
/// `nested_uniform_scramble(sobol_dim1(i), s_y)` of the shuffled index `i`, with the bit
/// reversals that cancel left out (4 reversals instead of 7).
#[must_use]
#[inline]
fn sobol_pair_bits(pixel_key: u64, index: u32, pair: u32) -> (u32, u32) {
    pair_bits(pair_seeds(pixel_key, pair), index.reverse_bits())
}

/// [`sobol_pair_bits`] from the pair's seeds and the sample index reversed, `index_rev`
/// (a sampler reverses it once per sample, not once per draw). `r = laine_karras(index_rev,
/// s_index)` is the shuffled index `i = nested_uniform_scramble(index, s_index)` reversed,
/// which is also its first Sobol dimension (`sobol_dim0(i) = reverse(i)`).
#[must_use]
#[inline]
fn pair_bits((s_index, s_x, s_y): (u32, u32, u32), index_rev: u32) -> (u32, u32) {
    let r = laine_karras(index_rev, s_index);
    (
        laine_karras(r.reverse_bits(), s_x).reverse_bits(),
        laine_karras(dim1_reversed(r), s_y).reverse_bits(),
    )
}

/// The first coordinate of [`sobol_pair_bits`] alone (a 1D draw), the same bits.
#[must_use]
#[inline]
#[cfg(test)]
fn sobol_first_bits(pixel_key: u64, index: u32, pair: u32) -> u32 {
    let (s_index, s_x, _) = pair_seeds(pixel_key, pair);
    first_bits(s_index, s_x, index.reverse_bits())
}

/// [`sobol_first_bits`] from the pair's index and x seeds.
#[must_use]
#[inline]
fn first_bits(s_index: u32, s_x: u32, index_rev: u32) -> u32 {
    let r = laine_karras(index_rev, s_index);
    laine_karras(r.reverse_bits(), s_x).reverse_bits()
}

/// The key of one pixel under one seed.
#[must_use]
#[inline]
pub fn pixel_key(seed: u64, (x, y): (u32, u32)) -> u64 {
    mix64(mix64(seed) ^ (u64::from(x) << 32 | u64::from(y)))
}

/// The 2D point of dimension pair `pair` of sample `index` of `pixel` under `seed`, in
/// `[0, 1)^2`. Stateless: what [`SobolSampler`] returns for its `pair`-th 2D draw.
#[must_use]
pub fn sample_2d(seed: u64, pixel: (u32, u32), index: u32, pair: u32) -> DVec2 {
    let (x, y) = sobol_pair_bits(pixel_key(seed, pixel), index, pair);
    DVec2::new(f64::from(x) * TO_UNIT, f64::from(y) * TO_UNIT)
}

/// Dimension pairs whose seeds a [`SobolSampler`] keeps per pixel (bits of a `u32` mask).
const CACHED_PAIRS: usize = 32;

/// The sample stream of one (pixel, sample index): each draw takes the next dimension pair.
///
/// `next_1d` also takes a whole pair (its first coordinate), so that the dimensions a draw uses
/// depend only on how many draws came before it, not on whether they were 1D or 2D.
///
/// The seeds of a pair depend only on the pixel (not on the sample index), so the sampler
/// keeps those of the first `CACHED_PAIRS` pairs while it stays on one pixel: the samples
/// after a pixel's first draw each pair with three hashes fewer. The values are the same bits
/// either way (a pure function of seed, pixel, index and pair).
#[derive(Clone, Copy, Debug)]
pub struct SobolSampler {
    seed: u64,
    key: u64,
    pixel: (u32, u32),
    index: u32,
    /// `index.reverse_bits()`.
    index_rev: u32,
    pair: u32,
    /// Bit `p` set: `seeds[p]` holds `pair_seeds(key, p)`.
    cached: u32,
    seeds: [[u32; 3]; CACHED_PAIRS],
}

/// Equal when they draw the same stream (the seed cache is not compared).
impl PartialEq for SobolSampler {
    fn eq(&self, other: &Self) -> bool {
        (self.seed, self.key, self.pixel, self.index, self.pair)
            == (other.seed, other.key, other.pixel, other.index, other.pair)
    }
}

impl Eq for SobolSampler {}

impl SobolSampler {
    /// The stream of sample `index` of `pixel` under `seed`, starting at dimension pair 0.
    #[must_use]
    pub fn new(seed: u64, pixel: (u32, u32), index: u32) -> Self {
        Self {
            seed,
            key: pixel_key(seed, pixel),
            pixel,
            index,
            index_rev: index.reverse_bits(),
            pair: 0,
            cached: 0,
            seeds: [[0; 3]; CACHED_PAIRS],
        }
    }

    /// Jumps to dimension pair `pair` (e.g. a fixed pair per use, so that a change in one use
    /// does not shift the others).
    #[must_use]
    pub fn at_pair(self, pair: u32) -> Self {
        Self { pair, ..self }
    }

    /// The next dimension pair's index.
    #[must_use]
    pub fn pair(&self) -> u32 {
        self.pair
    }

    /// The seeds of dimension pair `pair` of this pixel, from the cache when they are there.
    #[inline]
    fn seeds(&mut self, pair: u32) -> (u32, u32, u32) {
        let p = pair as usize;
        if p >= CACHED_PAIRS {
            return pair_seeds(self.key, pair);
        }
        let bit = 1u32 << p;
        if self.cached & bit == 0 {
            let (a, b, c) = pair_seeds(self.key, pair);
            self.seeds[p] = [a, b, c];
            self.cached |= bit;
        }
        let [a, b, c] = self.seeds[p];
        (a, b, c)
    }

    /// The next value in `[0, 1)`: the first coordinate of the next pair (the pair is used up).
    #[inline]
    pub fn next_1d(&mut self) -> f64 {
        let (s_index, s_x, _) = self.seeds(self.pair);
        let x = first_bits(s_index, s_x, self.index_rev);
        self.pair = self.pair.wrapping_add(1);
        f64::from(x) * TO_UNIT
    }

    /// The next point in `[0, 1)^2`.
    #[inline]
    pub fn next_2d(&mut self) -> DVec2 {
        let seeds = self.seeds(self.pair);
        let (x, y) = pair_bits(seeds, self.index_rev);
        self.pair = self.pair.wrapping_add(1);
        DVec2::new(f64::from(x) * TO_UNIT, f64::from(y) * TO_UNIT)
    }
}

/// A small counter-free PRNG (splitmix64) for tests and benches, where independent uniform
/// numbers are wanted (chi-square tests assume independent samples).
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator seeded with `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.state)
    }

    /// A uniform value in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// A uniform point in `[0, 1)^2`.
    pub fn next_2d(&mut self) -> DVec2 {
        DVec2::new(self.next_f64(), self.next_f64())
    }
}

/// The Sobol sampler behind the render's sampler seam: each camera sample restarts the
/// sample's stream at dimension pair 0, and a 1D draw takes a whole pair, as
/// [`SobolSampler::next_1d`] does.
impl super::PixelSampler for SobolSampler {
    /// Keeps the pixel's key and cached pair seeds when the pixel stays the same.
    #[inline]
    fn start_sample(&mut self, pixel: (u32, u32), index: u32) {
        if pixel == self.pixel {
            self.index = index;
            self.index_rev = index.reverse_bits();
            self.pair = 0;
        } else {
            *self = Self::new(self.seed, pixel, index);
        }
    }

    #[inline]
    fn next_1d(&mut self) -> f64 {
        SobolSampler::next_1d(self)
    }

    #[inline]
    fn next_2d(&mut self) -> (f64, f64) {
        let u = SobolSampler::next_2d(self);
        (u.x, u.y)
    }
}

#[cfg(test)]
mod tests;
