//! Packet traversal: up to [`PACKET`] rays walk the wide BVH together, for coherent rays such
//! as a tile of camera rays. Each node is fetched once for the whole packet, which saves the
//! memory traffic that dominates single rays on a large mesh (docs/mesh.md).
//!
//! Two tests decide which rays go into which child:
//!
//! - **Interval test** (upper levels): one slab test of the whole packet in interval arithmetic
//!   (the packet culling of Wald, Boulos and Shirley, "Ray Tracing Deformable Scenes using
//!   Dynamic Bounding Volume Hierarchies", ACM TOG 2007): the shifted origins lie in
//!   `[omin, omax]` and the inverse directions in `[imin, imax]` per axis, all of one sign, so
//!   the `f32` entry parameter of every ray on an axis, `fl(fl(plane - o) * inv)`, lies between
//!   the least and the largest of that formula at the four corners (rounding is monotone, so
//!   the `f32` value is monotone in each argument).
//!   When the largest lower bound of entry exceeds the least upper bound of exit, no ray's own
//!   `f32` test could enter the box; otherwise the whole packet goes in. Used when every ray
//!   takes the `f32` path, the direction signs agree and the inverses are finite, and only
//!   while it sends the packet into at most two of a node's children: once the packet spreads
//!   wider, the rest of that subtree uses per-ray tests (a loose interval would drag every ray
//!   into boxes few of them enter; measured on the icosphere benchmark, where always using it
//!   was up to 2x slower on a 1.3M-triangle mesh, and this rule is 3-7% faster than none).
//! - **Per-ray test** (nodes with a leaf child, single rays, and packets the interval test
//!   cannot take): each ray exactly as [`WideBvh::traverse`] tests it (same `f32` or `f64` slab
//!   test, with the ray's own narrowed `t_max`).
//!
//! Either way a ray is taken into every child its own test would enter (the interval test
//! takes a superset), so it reaches every leaf the single-ray traversal can reach with a hit.
//! A popped entry is dropped when its entry bound (a lower bound of every ray's entry) lies
//! beyond every ray's narrowed `t_max`, the single ray's pop test for the whole packet. The
//! order differs from single rays (nearest child by the bound first), so a closest-hit caller
//! whose answer does not depend on the order (ties broken by a key) gets the single ray's
//! answer for each ray.

#[cfg(test)]
use super::enter_f32;
use super::{
    EMPTY, LEAF, Node, STACK, WIDTH, WideBvh, WideRay, enter_f64, max, min, rows, slabs_f32,
};
use crate::bvh::{TraversalCost, up};

/// Most rays in one packet (one bit each in a `u64` mask).
pub const PACKET: usize = 64;

impl WideBvh {
    /// Closest-hit traversal of `rays` (at most [`PACKET`], prepared by [`WideBvh::ray`]) with
    /// per-ray limits `t_max`. For every leaf group a ray reaches, `test(ray, group, t_max)`
    /// returns that ray's new `t_max` (smaller narrows it; anything else leaves it). Counts, per
    /// ray, one node for every wide node visited with that ray in the packet.
    ///
    /// `warm(group)` is called for every group of a leaf the packet enters as soon as the node
    /// above it is tested, before the leaf is visited (if it still is): the caller prefetches
    /// the group's primitives there, as the traversal prefetches the inner nodes it enters.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or `t_max`/`cost` are shorter than `rays`.
    pub fn traverse_packet(
        &self,
        rays: &[WideRay],
        t_max: &mut [f64],
        cost: &mut [TraversalCost],
        mut test: impl FnMut(usize, usize, f64) -> f64,
        mut warm: impl FnMut(usize),
    ) {
        assert!(rays.len() <= PACKET && t_max.len() >= rays.len() && cost.len() >= rays.len());
        if self.nodes.is_empty() || rays.is_empty() {
            return;
        }
        let mut s_max = [0f32; PACKET];
        for (r, ray) in rays.iter().enumerate() {
            s_max[r] = up(t_max[r] - ray.t0);
        }
        let interval = Interval::of(rays);
        let mut visits = Counter::default();
        let mut small = [(0u32, 0u64, 0f32, false); STACK];
        let mut large = Vec::new();
        let stack: &mut [(u32, u64, f32, bool)] = if self.stack <= STACK {
            &mut small
        } else {
            large.resize(self.stack, (0, 0, 0.0, false));
            &mut large
        };
        // Whether the interval test still serves this subtree (see the module notes).
        let mut coherent = true;
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
            } else {
                let node = &self.nodes[at as usize];
                visits.add(mask);
                let mut leaf_child = false;
                for c in node.child {
                    leaf_child |= c & LEAF != 0 && c != EMPTY;
                }
                let mut children = None;
                if let Some(i) = &interval
                    && coherent
                    && !leaf_child
                    && mask & (mask - 1) != 0
                {
                    let c = i.enter(node, mask);
                    let entered: u32 = c.iter().map(|e| u32::from(e.1 != 0)).sum();
                    if entered <= 2 {
                        children = Some(c);
                    } else {
                        // The packet spreads over several children: test its rays one by one
                        // from here down.
                        coherent = false;
                    }
                }
                let children =
                    children.unwrap_or_else(|| enter_each(node, rays, mask, &s_max, t_max, self));
                // Start loading every child the packet will visit (see the module notes).
                for (lane, &(_, rays)) in children.iter().enumerate() {
                    if rays != 0 {
                        self.warm(node.child[lane], &mut warm);
                    }
                }
                if let Some(near) = nearest(&children) {
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
                    for &(key, lane) in &order[..n] {
                        stack[top] = (node.child[lane], children[lane].1, key, coherent);
                        top += 1;
                    }
                    (at, mask) = (node.child[near], children[near].1);
                    continue;
                }
            }
            // Pop until an entry some ray of it may still reach within its narrowed t_max.
            loop {
                if top == 0 {
                    visits.add_to(&mut cost[..rays.len()]);
                    return;
                }
                top -= 1;
                let key;
                (at, mask, key, coherent) = stack[top];
                if reachable(key, mask, &s_max, rays) {
                    break;
                }
            }
        }
    }
}

/// Whether some ray of `mask` may enter a box whose entry parameter is at least `key` for
/// every ray (in each ray's own shifted `s`): `key <= s_max` for one of them. `f64` rays keep
/// every entry, as in [`WideBvh::traverse`].
#[inline(always)]
fn reachable(key: f32, mut mask: u64, s_max: &[f32; PACKET], rays: &[WideRay]) -> bool {
    while mask != 0 {
        let r = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if key <= s_max[r] || rays[r].exact {
            return true;
        }
    }
    false
}

/// The lane with the smallest key among those some ray enters.
#[inline(always)]
fn nearest(children: &[(f32, u64); WIDTH]) -> Option<usize> {
    let mut near = None;
    for (l, &(key, rays)) in children.iter().enumerate() {
        if rays != 0 && near.is_none_or(|n: usize| key < children[n].0) {
            near = Some(l);
        }
    }
    near
}

/// Per-ray test of every ray of `mask` against the four boxes of `node`: per child lane the
/// least entry distance over its rays and the mask of rays entering it.
#[inline(always)]
fn enter_each(
    node: &Node,
    rays: &[WideRay],
    mask: u64,
    s_max: &[f32; PACKET],
    t_max: &[f64],
    bvh: &WideBvh,
) -> [(f32, u64); WIDTH] {
    let mut key = [f32::INFINITY; WIDTH];
    // Ray r's four hit bits at bits 4 (r % 16).. of word r / 16: two operations per ray;
    // the per-lane masks are gathered once per node below.
    let mut nibbles = [0u64; PACKET / 16];
    let mut m = mask;
    while m != 0 {
        let r = m.trailing_zeros() as usize;
        m &= m - 1;
        let ray = &rays[r];
        let (hit, entry) = if ray.exact {
            // Entry distances of the f64 test order children but bound nothing.
            let (hit, _) = enter_f64(node, ray, t_max[r], bvh.center);
            let entry = [0, 1, 2, 3].map(|l| {
                if hit >> l & 1 != 0 {
                    f32::NEG_INFINITY
                } else {
                    f32::INFINITY
                }
            });
            (hit, entry)
        } else {
            let (lo, hi) = slabs_f32(node, ray, s_max[r]);
            let mut hit = 0;
            for l in 0..WIDTH {
                hit |= u32::from(lo[l] <= hi[l]) << l;
            }
            // Entry where the box is entered, infinity where not (the least over rays is
            // then one `min` per lane).
            (
                hit,
                [0, 1, 2, 3].map(|l| if lo[l] <= hi[l] { lo[l] } else { f32::INFINITY }),
            )
        };
        nibbles[r / 16] |= u64::from(hit) << (4 * (r % 16));
        for l in 0..WIDTH {
            key[l] = min(key[l], entry[l]);
        }
    }
    [0, 1, 2, 3].map(|l| {
        let mut enter = 0;
        for (w, &n) in nibbles.iter().enumerate() {
            if n != 0 {
                enter |= gather_every_fourth(n >> l) << (16 * w);
            }
        }
        (key[l], enter)
    })
}

/// Bits 0, 4, 8, ..., 60 of `x`, packed into bits 0..16.
#[inline(always)]
fn gather_every_fourth(x: u64) -> u64 {
    let mut x = x & 0x1111_1111_1111_1111;
    x = (x | x >> 3) & 0x0303_0303_0303_0303;
    x = (x | x >> 6) & 0x000F_000F_000F_000F;
    x = (x | x >> 12) & 0x0000_00FF_0000_00FF;
    (x | x >> 24) & 0xFFFF
}

/// The packet's shifted origins and inverse directions as per-axis intervals (see the module
/// notes); `None` when the interval test does not apply: some ray takes the `f64` test, the
/// direction signs differ, or an inverse direction is infinite.
struct Interval {
    omin: [f32; 3],
    omax: [f32; 3],
    imin: [f32; 3],
    imax: [f32; 3],
    neg: [bool; 3],
}

impl Interval {
    fn of(rays: &[WideRay]) -> Option<Self> {
        let first = rays.first()?;
        let mut i = Interval {
            omin: first.origin,
            omax: first.origin,
            imin: first.inv,
            imax: first.inv,
            neg: first.neg,
        };
        for ray in rays {
            if ray.exact || ray.neg != i.neg || !ray.inv.iter().all(|v| v.is_finite()) {
                return None;
            }
            for a in 0..3 {
                i.omin[a] = min(i.omin[a], ray.origin[a]);
                i.omax[a] = max(i.omax[a], ray.origin[a]);
                i.imin[a] = min(i.imin[a], ray.inv[a]);
                i.imax[a] = max(i.imax[a], ray.inv[a]);
            }
        }
        Some(i)
    }

    /// The whole packet `mask` into every child whose box the interval test cannot rule out;
    /// the key is the lower bound of entry.
    #[inline(always)]
    fn enter(&self, node: &Node, mask: u64) -> [(f32, u64); WIDTH] {
        let b = &node.bounds;
        let mut lo = [f32::NEG_INFINITY; WIDTH];
        let mut hi = [f32::INFINITY; WIDTH];
        for a in 0..3 {
            let (near, far) = rows(b, a, self.neg[a]);
            let (o0, o1, i0, i1) = (self.omin[a], self.omax[a], self.imin[a], self.imax[a]);
            for l in 0..WIDTH {
                let (n0, n1) = (near[l] - o1, near[l] - o0);
                let (f0, f1) = (far[l] - o1, far[l] - o0);
                let tn = min(min(n0 * i0, n0 * i1), min(n1 * i0, n1 * i1));
                let tf = max(max(f0 * i0, f0 * i1), max(f1 * i0, f1 * i1));
                lo[l] = max(lo[l], tn);
                hi[l] = min(hi[l], tf);
            }
        }
        [0, 1, 2, 3].map(|l| (lo[l], if lo[l] <= hi[l] { mask } else { 0 }))
    }
}

/// Per-ray visit counts as bit-sliced counters: plane `k` holds bit `k` of every ray's count,
/// so adding one to the rays of a mask is a ripple carry over a few words.
#[derive(Default)]
struct Counter {
    planes: [u64; 32],
}

impl Counter {
    #[inline(always)]
    fn add(&mut self, mut carry: u64) {
        for p in &mut self.planes {
            if carry == 0 {
                return;
            }
            let next = *p & carry;
            *p ^= carry;
            carry = next;
        }
    }

    /// Add every ray's count to its `cost`.
    fn add_to(&self, cost: &mut [TraversalCost]) {
        let used = self
            .planes
            .iter()
            .rposition(|&p| p != 0)
            .map_or(0, |k| k + 1);
        for (k, &plane) in self.planes[..used].iter().enumerate() {
            for (r, c) in cost.iter_mut().enumerate().take(PACKET) {
                c.nodes += (((plane >> r) & 1) as u32) << k;
            }
        }
    }
}

#[cfg(test)]
mod tests;
