//! Tests of the Owen-scrambled Sobol sampler.

use super::*;

/// Every elementary interval of area 1/n (n = 2^m; shapes 2^k x 2^(m-k)) holds exactly one
/// of the first n samples: the (0, m, 2)-net property of Sobol's first two dimensions,
/// preserved by Owen scrambling and the index shuffle.
fn assert_net(points: &[(u32, u32)], m: u32) {
    for k in 0..=m {
        let (bx, by) = (1u64 << k, 1u64 << (m - k));
        let mut seen = vec![false; 1 << m];
        for &(x, y) in points {
            let cx = (u64::from(x) * bx) >> 32;
            let cy = (u64::from(y) * by) >> 32;
            let cell = (cy * bx + cx) as usize;
            assert!(!seen[cell], "two points in cell {cell} of {bx}x{by}");
            seen[cell] = true;
        }
    }
}

#[test]
fn first_2_pow_m_samples_of_each_pair_are_a_0_m_2_net() {
    for seed in [0u64, 7, 1 << 40] {
        for pixel in [(0, 0), (17, 3), (639, 359)] {
            let key = pixel_key(seed, pixel);
            for pair in [0, 1, 2, 9] {
                for m in [0, 2, 4, 6, 8] {
                    let pts: Vec<_> = (0..1u32 << m)
                        .map(|i| sobol_pair_bits(key, i, pair))
                        .collect();
                    assert_net(&pts, m);
                }
            }
        }
    }
}

#[test]
fn an_unscrambled_wrong_generator_fails_the_net_check() {
    // The test can fail: the same dimension twice is no net (diagonal).
    let pts: Vec<_> = (0..16u32).map(|i| (sobol_dim0(i), sobol_dim0(i))).collect();
    let r = std::panic::catch_unwind(|| assert_net(&pts, 4));
    assert!(r.is_err());
}

/// The fast form equals the definition: Owen-scrambled dimensions 0 and 1 of the
/// Owen-shuffled index, with every reversal written out.
#[test]
fn pair_bits_equal_the_written_out_scramble() {
    let mut rng = SplitMix64::new(5);
    for _ in 0..20_000 {
        let (key, index, pair) = (rng.next_u64(), rng.next_u64() as u32, rng.next_u64() as u32);
        let (s_index, s_x, s_y) = pair_seeds(key, pair);
        let i = nested_uniform_scramble(index, s_index);
        let want = (
            nested_uniform_scramble(sobol_dim0(i), s_x),
            nested_uniform_scramble(sobol_dim1(i), s_y),
        );
        assert_eq!(sobol_pair_bits(key, index, pair), want);
        assert_eq!(sobol_first_bits(key, index, pair), want.0);
        let r = rng.next_u64() as u32;
        assert_eq!(
            dim1_reversed(r),
            sobol_dim1(r.reverse_bits()).reverse_bits()
        );
    }
}

#[test]
fn sobol_dim1_matches_known_values() {
    // 1/2, 3/4 1/4, 3/8 7/8 5/8 1/8: the classic second Sobol dimension for i = 1..7
    // (Joe and Kuo's table), in Gray-code-free (direct) index order.
    let want = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
    for (i, w) in want.iter().enumerate() {
        assert_eq!(f64::from(sobol_dim1(i as u32)) * TO_UNIT, *w, "index {i}");
    }
}

#[test]
fn sampler_is_deterministic_bit_for_bit_and_matches_the_stateless_form() {
    let mut a = SobolSampler::new(42, (12, 34), 5);
    let mut b = SobolSampler::new(42, (12, 34), 5);
    for pair in 0..20 {
        let (pa, pb) = (a.next_2d(), b.next_2d());
        assert_eq!(pa.x.to_bits(), pb.x.to_bits());
        assert_eq!(pa.y.to_bits(), pb.y.to_bits());
        assert_eq!(pa, sample_2d(42, (12, 34), 5, pair));
    }
    assert_eq!(
        SobolSampler::new(42, (12, 34), 5).at_pair(3).next_2d(),
        sample_2d(42, (12, 34), 5, 3)
    );
}

#[test]
fn pixels_seeds_and_pairs_decorrelate() {
    let a = sample_2d(0, (1, 2), 0, 0);
    assert_ne!(a, sample_2d(0, (2, 1), 0, 0));
    assert_ne!(a, sample_2d(1, (1, 2), 0, 0));
    assert_ne!(a, sample_2d(0, (1, 2), 0, 1));
    // Across many pixels the first sample's mean is near 1/2 (no shared offset).
    let n = 4096;
    let mean: f64 = (0..n).map(|i| sample_2d(3, (i, 0), 0, 0).x).sum::<f64>() / f64::from(n);
    // Uniform mean: sd of the mean = sqrt(1/12 / n) = 0.0045; 5 sd.
    assert!((mean - 0.5).abs() < 0.023, "mean {mean}");
}

#[test]
fn values_lie_in_the_half_open_unit_square() {
    let mut s = SobolSampler::new(u64::MAX, (u32::MAX, u32::MAX), u32::MAX);
    for _ in 0..1000 {
        let p = s.next_2d();
        assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
    }
}

/// The per-pixel seed cache changes no bit: one sampler moved through pixels, back to an
/// earlier one and through more pairs than it caches draws what the stateless form and a fresh
/// sampler per sample draw (a cache kept across a change of pixel, or filled for the wrong
/// pair, fails this).
#[test]
fn the_seed_cache_draws_the_stateless_values() {
    use crate::sampling::PixelSampler;
    let mut s = SobolSampler::new(11, (0, 0), 0);
    for (pixel, index) in [
        ((3, 4), 0),
        ((3, 4), 1),
        ((4, 3), 0),
        ((3, 4), 7),
        ((3, 5), 2),
    ] {
        PixelSampler::start_sample(&mut s, pixel, index);
        let mut fresh = SobolSampler::new(11, pixel, index);
        for pair in 0..(CACHED_PAIRS as u32 + 9) {
            if pair % 3 == 1 {
                let x = PixelSampler::next_1d(&mut s);
                assert_eq!(x.to_bits(), sample_2d(11, pixel, index, pair).x.to_bits());
                assert_eq!(x.to_bits(), fresh.next_1d().to_bits());
            } else {
                let (x, y) = PixelSampler::next_2d(&mut s);
                assert_eq!(DVec2::new(x, y), sample_2d(11, pixel, index, pair));
                assert_eq!(DVec2::new(x, y), fresh.next_2d());
            }
        }
    }
    // The tabulated pair hashes are the hash itself, past the table too.
    for pair in [0, 1, 127, 128, 4000] {
        let key = pixel_key(5, (1, 2));
        let h = mix64(key ^ pair_hash(pair));
        assert_eq!(
            pair_seeds(key, pair),
            (h as u32, (h >> 32) as u32, mix64(h) as u32)
        );
    }
}
