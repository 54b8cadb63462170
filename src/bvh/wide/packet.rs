//! Packet traversal: up to [`PACKET`] rays walk the wide BVH together, for coherent rays such
//! as a tile of camera rays. Each node is fetched once for the whole packet and each ray of the
//! packet is tested against its four boxes exactly as [`WideBvh::traverse`] tests a single ray
//! (the same `f32` or `f64` slab test with the ray's own narrowed `t_max`), so a ray is only
//! ever taken into a child whose box it enters. What differs from single rays is the order:
//! the packet goes to the child nearest to any of its rays first, and a popped node is not
//! culled by distance (its rays are tested against its boxes again). A closest-hit caller whose
//! answer does not depend on the order (ties broken by a key, not by which came first) gets the
//! same answer per ray as from [`WideBvh::traverse`].
//!
//! What it buys is memory traffic: on a large mesh a single ray spends most of its time
//! waiting for nodes and triangle packs that neighbouring rays fetch again (docs/mesh.md).

use super::{EMPTY, LEAF, STACK, WIDTH, WideBvh, WideRay, enter_f32, enter_f64};
use crate::bvh::{TraversalCost, up};

/// Most rays in one packet (one bit each in a `u64` mask).
pub const PACKET: usize = 64;

impl WideBvh {
    /// Closest-hit traversal of `rays` (at most [`PACKET`], prepared by [`WideBvh::ray`]) with
    /// per-ray limits `t_max`. For every leaf group a ray reaches, `test(ray, group, t_max)`
    /// returns that ray's new `t_max` (smaller narrows it; anything else leaves it). Counts, per
    /// ray, one node for every wide node whose boxes that ray was tested against.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or `t_max`/`cost` are shorter than `rays`.
    pub fn traverse_packet(
        &self,
        rays: &[WideRay],
        t_max: &mut [f64],
        cost: &mut [TraversalCost],
        mut test: impl FnMut(usize, usize, f64) -> f64,
    ) {
        assert!(rays.len() <= PACKET && t_max.len() >= rays.len() && cost.len() >= rays.len());
        if self.nodes.is_empty() || rays.is_empty() {
            return;
        }
        let mut s_max = [0f32; PACKET];
        for (r, ray) in rays.iter().enumerate() {
            s_max[r] = up(t_max[r] - ray.t0);
        }
        let mut small = [(0u32, 0u64); STACK];
        let mut large = Vec::new();
        let stack: &mut [(u32, u64)] = if self.stack <= STACK {
            &mut small
        } else {
            large.resize(self.stack, (0, 0));
            &mut large
        };
        let mut top = 0;
        let (mut at, mut mask) = (0u32, u64::MAX >> (PACKET - rays.len()));
        loop {
            if at & LEAF != 0 {
                let first = ((at & !LEAF) >> 4) as usize;
                for g in first..first + (at & 15) as usize {
                    let mut m = mask;
                    while m != 0 {
                        let r = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let t = test(r, g, t_max[r]);
                        if t < t_max[r] {
                            t_max[r] = t;
                            s_max[r] = up(t - rays[r].t0);
                        }
                    }
                }
            } else if let Some((near, children)) = self.enter_packet(at, rays, mask, &s_max, t_max)
            {
                let node = &self.nodes[at as usize];
                let mut m = mask;
                while m != 0 {
                    let r = m.trailing_zeros() as usize;
                    m &= m - 1;
                    cost[r].nodes += 1;
                }
                // Push the other children farthest first, continue with the nearest.
                let mut order = [(0f32, 0usize); WIDTH];
                let mut n = 0;
                for (lane, &(key, rays)) in children.iter().enumerate() {
                    if rays != 0 && lane != near {
                        let mut j = n;
                        while j > 0 && order[j - 1].0 < key {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = (key, lane);
                        n += 1;
                    }
                }
                for &(_, lane) in &order[..n] {
                    stack[top] = (node.child[lane], children[lane].1);
                    top += 1;
                }
                (at, mask) = (node.child[near], children[near].1);
                continue;
            } else {
                let mut m = mask;
                while m != 0 {
                    let r = m.trailing_zeros() as usize;
                    m &= m - 1;
                    cost[r].nodes += 1;
                }
            }
            if top == 0 {
                return;
            }
            top -= 1;
            (at, mask) = stack[top];
        }
    }

    /// Test every ray of `mask` against the four boxes of inner node `at`: per child lane the
    /// nearest entry distance over its rays (for the order) and the mask of rays entering it,
    /// and the nearest lane entered; `None` when no ray enters any child.
    #[inline(always)]
    fn enter_packet(
        &self,
        at: u32,
        rays: &[WideRay],
        mask: u64,
        s_max: &[f32; PACKET],
        t_max: &[f64],
    ) -> Option<(usize, [(f32, u64); WIDTH])> {
        let node = &self.nodes[at as usize];
        let mut key = [f32::INFINITY; WIDTH];
        let mut enter = [0u64; WIDTH];
        let mut m = mask;
        while m != 0 {
            let r = m.trailing_zeros() as usize;
            m &= m - 1;
            let ray = &rays[r];
            let (hit, dist) = if ray.exact {
                enter_f64(node, ray, t_max[r], self.center)
            } else {
                enter_f32(node, ray, s_max[r])
            };
            for l in 0..WIDTH {
                let h = (hit >> l) & 1;
                enter[l] |= u64::from(h) << r;
                if h != 0 && dist[l] < key[l] {
                    key[l] = dist[l];
                }
            }
        }
        let mut near = None;
        for l in 0..WIDTH {
            if enter[l] != 0 && near.is_none_or(|n: usize| key[l] < key[n]) {
                near = Some(l);
            }
        }
        debug_assert!(
            node.child
                .iter()
                .zip(enter)
                .all(|(&c, e)| c != EMPTY || e == 0)
        );
        near.map(|n| (n, [0, 1, 2, 3].map(|l| (key[l], enter[l]))))
    }
}
