//! The interval test of a packet is sound: it never rules out a box one of its rays enters.

use super::*;
use crate::bvh::{Aabb, Bvh};
use crate::math::Ray;
use glam::DVec3;

fn rng(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// The interval test never rules out a box that one of the packet's rays enters by its own
/// `f32` test (the soundness the packet traversal rests on), and it does rule boxes out.
#[test]
fn interval_test_keeps_every_box_a_ray_of_the_packet_enters() {
    let mut s = 7;
    let boxes: Vec<Aabb> = (0..4000)
        .map(|_| {
            let p = DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s)) * 4.0 - 2.0;
            let e = DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s)) * 0.05;
            Aabb { min: p, max: p + e }
        })
        .collect();
    let wide = WideBvh::from_binary(&Bvh::build(&boxes));
    let (mut entered, mut culled) = (0, 0);
    for packet in 0..300 {
        // A tile of rays from one eye, spread from 0.001 to 0.2 radians.
        let eye = DVec3::new(3.0 + rng(&mut s), 2.0 * rng(&mut s), 4.0);
        let aim = DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s)) * 2.0 - 1.0;
        let spread = [1e-3, 1e-2, 0.2][packet % 3];
        let rays: Vec<WideRay> = (0..PACKET)
            .filter_map(|i| {
                let off = DVec3::new((i % 8) as f64, (i / 8) as f64, 0.0) * spread;
                let ray = Ray::new(eye, (aim + off - eye).normalize(), 0.0);
                wide.ray(&ray, f64::INFINITY)
            })
            .collect();
        let Some(interval) = Interval::of(&rays) else {
            continue;
        };
        for node in &wide.nodes {
            let packet_mask = interval.enter(node, 1);
            for ray in &rays {
                let (hit, dist) = enter_f32(node, ray, f32::INFINITY);
                for l in 0..WIDTH {
                    if hit >> l & 1 != 0 {
                        entered += 1;
                        assert_eq!(packet_mask[l].1, 1, "a ray enters lane {l}: {ray:?}");
                        assert!(packet_mask[l].0 <= dist[l]);
                    }
                }
            }
            culled += (0..WIDTH)
                .filter(|&l| node.child[l] != EMPTY && packet_mask[l].1 == 0)
                .count();
        }
    }
    assert!(entered > 10_000 && culled > 10_000, "{entered} {culled}");
}
