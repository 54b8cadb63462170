//! A 4-wide BVH collapsed from the binary one, with `f32` boxes stored as structure of arrays so
//! that the four slab tests of a node run as one set of SSE instructions (LLVM vectorises the
//! four-lane loops; SSE2 is baseline on x86_64, no `target-cpu` needed).
//!
//! Leaves are short runs of *groups*: up to [`GROUP`] consecutive primitive slots that a caller
//! tests together (the mesh keeps one `f32` triangle pack per group). The BVH still knows no
//! geometry.
//!
//! Conservative in `f32`: coordinates are stored relative to the root box's centre `c`, and a
//! query first clips the ray to the root box in `f64` and moves its origin there (`t0`), so
//! every `f32` quantity is bounded by the root box's half extent `M` (however far the mesh is
//! from the world origin). The
//! rounding of the origin, the direction and the slab arithmetic then moves a computed plane
//! crossing by at most about `9 u M` (`u = 2^-24`) along each axis; every box is grown by
//! `32 u M` (plus the binary build's own padding), so a box the `f64` ray passes through is never
//! culled. Rays whose origin is so far away that the shift itself loses that precision, and
//! meshes beyond the safe `f32` range, use an `f64` slab test on the same nodes.

mod build;
mod packet;
pub use packet::PACKET;

use super::{TraversalCost, Visit, down, up};
use crate::math::Ray;
use glam::DVec3;

/// Children per node.
pub const WIDTH: usize = 4;
/// Primitive slots per group (one SIMD batch of the caller).
pub const GROUP: usize = 4;
/// Traversal stack on the call stack when the tree needs no more (see [`WideBvh::stack`]).
const STACK: usize = 32;
/// Leaf flag in a child reference; the other bits hold `first_group << 4 | group_count`.
const LEAF: u32 = 1 << 31;
/// An unused child slot.
const EMPTY: u32 = u32::MAX;
/// `f32` unit roundoff.
const U32: f64 = f32::EPSILON as f64 * 0.5;

/// Four child boxes (rows `min x, min y, min z, max x, max y, max z`) and their references.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: [[f32; WIDTH]; 6],
    child: [u32; WIDTH],
}

impl Node {
    /// Prefetch the node's lines (112 bytes at 4-byte alignment: addresses at most 64 bytes
    /// apart, the last in its final word).
    #[inline(always)]
    fn prefetch(&self) {
        super::prefetch(&self.bounds[0]);
        super::prefetch(&self.bounds[3]);
        super::prefetch(&self.child[WIDTH - 1]);
    }
}

/// A run of consecutive primitive slots tested together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Group {
    /// First slot (index into the binary BVH's leaf order).
    pub first: u32,
    /// Number of slots, `1..=GROUP`.
    pub count: u32,
}

/// The 4-wide hierarchy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    nodes: Vec<Node>,
    /// Slot runs in leaf order; leaves refer to ranges of them.
    pub groups: Vec<Group>,
    /// Centre of the root box: every stored `f32` coordinate is relative to it.
    pub center: DVec3,
    /// Largest coordinate magnitude of the root box about `center` (`M` above).
    magnitude: f64,
    /// `f32` cannot represent this tree safely (extreme sizes or offsets): always test in `f64`.
    exact_only: bool,
    /// Root box as the binary BVH had it (`f32`, rounded outwards).
    root: Option<([f32; 3], [f32; 3])>,
    /// Deepest the traversal stack can get: the most entries pushed along any path.
    pub(crate) stack: usize,
}

/// A ray prepared for one query (see the module notes).
#[derive(Clone, Copy, Debug)]
pub struct WideRay {
    /// Shift along the ray: `f32` parameters `s` are `t - t0`.
    pub t0: f64,
    /// Shifted origin `ray.origin + t0 * ray.direction - center`, `f32`.
    pub origin: [f32; 3],
    /// Bound on how far rounding moves a sheared `f32` vertex coordinate from the exact one:
    /// `16 u (M + |origin|)`, twice the `8 u (M + |origin|)` of the analysis in
    /// [`crate::mesh`]'s packed filter, plus the `f64` shift's own error.
    pub slack: f32,
    inv: [f32; 3],
    /// Per axis, whether the direction is negative (the max plane is then the near one).
    neg: [bool; 3],
    s_min: f32,
    /// Test boxes in `f64` (origin too far for the `f32` shift, or mesh out of `f32` range).
    exact: bool,
    box_ray: super::BoxRay,
}

impl WideRay {
    /// Whether this query tests boxes in `f64` (then `f32` filters must keep everything).
    #[must_use]
    pub fn exact(&self) -> bool {
        self.exact
    }
}

impl WideBvh {
    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Prepare `ray` for a query over `(ray.t_min, t_max)`; `None` when it misses the root box.
    #[must_use]
    #[inline]
    pub fn ray(&self, ray: &Ray, t_max: f64) -> Option<WideRay> {
        let (min, max) = self.root?;
        let box_ray = super::BoxRay::new(ray);
        let lo = box_ray.enter(min, max, t_max)?;
        let t0 = if lo.is_finite() { lo } else { 0.0 };
        let d = ray.direction;
        let o = ray.origin + t0 * d - self.center;
        let o_mag = o.abs().max_element();
        // How far the f64 shift itself may be off the line, against the build-time padding.
        let shift_error = 4.0
            * f64::EPSILON
            * (ray.origin.abs() + (t0 * d).abs() + self.center.abs()).max_element();
        // f32 is safe when the magnitudes are well inside its range, the shifted origin lies
        // in the root box (NaN fails this too) and the shift kept its precision.
        let safe = !self.exact_only
            && o_mag <= 2.0 * self.magnitude
            && shift_error <= 4.0 * U32 * self.magnitude;
        let exact = !safe;
        let inv = box_ray.inv;
        let neg = [0, 1, 2].map(|a| inv[a].is_sign_negative());
        Some(WideRay {
            t0,
            origin: [o.x as f32, o.y as f32, o.z as f32],
            slack: (16.0 * U32 * (self.magnitude + o_mag) + 16.0 * shift_error) as f32,
            inv: [inv.x as f32, inv.y as f32, inv.z as f32],
            neg,
            s_min: down(ray.t_min - t0),
            exact,
            box_ray,
        })
    }

    /// Visit the groups of every leaf whose box the prepared ray enters within
    /// `(ray.t_min, t_max)`, nearest child first. `test(group, t_max)` returns the new `t_max`
    /// (in the caller's `t`, not shifted) or asks to stop. Counts one node per wide node
    /// visited (its four boxes are tested together). `warm(group)` is called for the groups
    /// of every leaf the ray enters when the node above it is tested, for the caller to
    /// prefetch (as in [`WideBvh::traverse_packet`]).
    pub fn traverse(
        &self,
        ray: &WideRay,
        t_max: f64,
        cost: &mut TraversalCost,
        test: impl FnMut(usize, f64) -> Visit,
        warm: impl FnMut(usize),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut small = [0u64; STACK];
        let mut large = Vec::new();
        let stack: &mut [u64] = if self.stack <= STACK {
            &mut small
        } else {
            large.resize(self.stack, 0);
            &mut large
        };
        self.walk(ray, t_max, cost, test, warm, stack);
    }

    /// Prefetch child reference `child`: an inner node's box data here, a leaf's groups
    /// through `warm` (the caller's data, see [`WideBvh::traverse`]).
    #[inline(always)]
    fn warm(&self, child: u32, warm: &mut impl FnMut(usize)) {
        if child & LEAF == 0 {
            self.nodes[child as usize].prefetch();
        } else {
            let first = ((child & !LEAF) >> 4) as usize;
            for g in first..first + (child & 15) as usize {
                warm(g);
            }
        }
    }

    /// [`WideBvh::traverse`] with a stack of at least [`WideBvh::stack`] entries, each
    /// `entry distance bits << 32 | child reference`.
    #[inline(always)]
    fn walk(
        &self,
        ray: &WideRay,
        mut t_max: f64,
        cost: &mut TraversalCost,
        mut test: impl FnMut(usize, f64) -> Visit,
        mut warm: impl FnMut(usize),
        stack: &mut [u64],
    ) {
        let mut s_max = up(t_max - ray.t0);
        let mut top = 0;
        let mut at = 0u32;
        let mut nodes = 0;
        loop {
            if at & LEAF != 0 {
                let first = ((at & !LEAF) >> 4) as usize;
                for g in first..first + (at & 15) as usize {
                    match test(g, t_max) {
                        Visit::Continue(t) if t < t_max => {
                            t_max = t;
                            s_max = up(t_max - ray.t0);
                        }
                        Visit::Continue(_) => {}
                        Visit::Stop => {
                            cost.nodes += nodes;
                            return;
                        }
                    }
                }
            } else {
                let node = &self.nodes[at as usize];
                nodes += 1;
                let (mut hit, dist) = if ray.exact {
                    enter_f64(node, ray, t_max, self.center)
                } else {
                    enter_f32(node, ray, s_max)
                };
                let mut entered = hit;
                while entered != 0 {
                    self.warm(node.child[entered.trailing_zeros() as usize], &mut warm);
                    entered &= entered - 1;
                }
                if hit != 0 {
                    // Continue with the nearest child; push the others, farthest first.
                    let mut near = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    if hit != 0 {
                        // At most three others: insertion sort, farthest first.
                        let mut order = [(0f32, 0u32); WIDTH - 1];
                        let mut n = 0;
                        while hit != 0 {
                            let mut lane = hit.trailing_zeros() as usize;
                            hit &= hit - 1;
                            if dist[lane] < dist[near] {
                                std::mem::swap(&mut near, &mut lane);
                            }
                            let mut j = n;
                            while j > 0 && order[j - 1].0 < dist[lane] {
                                order[j] = order[j - 1];
                                j -= 1;
                            }
                            order[j] = (dist[lane], node.child[lane]);
                            n += 1;
                        }
                        for &(d, c) in &order[..n] {
                            stack[top] = u64::from(d.to_bits()) << 32 | u64::from(c);
                            top += 1;
                        }
                    }
                    at = node.child[near];
                    continue;
                }
            }
            // Pop until an entry the ray still reaches within the narrowed t_max.
            loop {
                if top == 0 {
                    cost.nodes += nodes;
                    return;
                }
                top -= 1;
                let e = stack[top];
                if ray.exact || f32::from_bits((e >> 32) as u32) <= s_max {
                    at = e as u32;
                    break;
                }
            }
        }
    }
}

/// Entry test of a node's four boxes in `f32`: hit mask and entry parameters `s`. Barnes'
/// NaN-safe order: a ray in a slab's boundary plane counts as inside.
#[inline(always)]
fn enter_f32(node: &Node, ray: &WideRay, s_max: f32) -> (u32, [f32; WIDTH]) {
    let (lo, hi) = slabs_f32(node, ray, s_max);
    let mut mask = 0;
    for l in 0..WIDTH {
        mask |= u32::from(lo[l] <= hi[l]) << l;
    }
    (mask, lo)
}

/// The parameter interval `[lo, hi]` of the ray inside each of the four boxes, clipped to
/// `[s_min, s_max]` (empty when `lo > hi`; NaNs never narrow it).
#[inline(always)]
fn slabs_f32(node: &Node, ray: &WideRay, s_max: f32) -> ([f32; WIDTH], [f32; WIDTH]) {
    let b = &node.bounds;
    let (o, inv) = (ray.origin, ray.inv);
    let mut lo = [ray.s_min; WIDTH];
    let mut hi = [s_max; WIDTH];
    for a in 0..3 {
        let (near, far) = rows(b, a, ray.neg[a]);
        for l in 0..WIDTH {
            let tn = (near[l] - o[a]) * inv[a];
            let tf = (far[l] - o[a]) * inv[a];
            lo[l] = if tn > lo[l] { tn } else { lo[l] };
            hi[l] = if tf < hi[l] { tf } else { hi[l] };
        }
    }
    (lo, hi)
}

/// The near and far plane rows of axis `a` (`0..3`) for a direction of sign `neg`: constant
/// indices and a select, no bounds check in the slab loop.
#[inline(always)]
fn rows(b: &[[f32; WIDTH]; 6], a: usize, neg: bool) -> (&[f32; WIDTH], &[f32; WIDTH]) {
    let (min, max) = match a {
        0 => (&b[0], &b[3]),
        1 => (&b[1], &b[4]),
        _ => (&b[2], &b[5]),
    };
    if neg { (max, min) } else { (min, max) }
}

/// `x < y ? x : y`: one `minps` lane. Unlike `f32::min`, no NaN handling (a NaN in `x` yields
/// `y`): the packet's interval test and the triangle filter need none (a NaN edge function
/// already passes the filter).
#[inline(always)]
pub(crate) fn min(x: f32, y: f32) -> f32 {
    if x < y { x } else { y }
}

/// `x > y ? x : y`: one `maxps` lane; a NaN in `x` yields `y` (see [`min`]).
#[inline(always)]
pub(crate) fn max(x: f32, y: f32) -> f32 {
    if x > y { x } else { y }
}

/// The same test in `f64` on the original ray (entry distances are then only for the order).
/// Boxes go back to world space in `f64`, widened by that addition's rounding.
fn enter_f64(node: &Node, ray: &WideRay, t_max: f64, center: DVec3) -> (u32, [f32; WIDTH]) {
    let b = &node.bounds;
    let slop = 2.0 * f64::EPSILON * center.abs();
    let mut mask = 0;
    let mut dist = [0.0; WIDTH];
    for l in 0..WIDTH {
        let min = DVec3::new(b[0][l].into(), b[1][l].into(), b[2][l].into());
        let max = DVec3::new(b[3][l].into(), b[4][l].into(), b[5][l].into());
        if min.x > max.x {
            continue; // empty slot
        }
        if let Some(t) = ray
            .box_ray
            .enter_f64(min + center - slop, max + center + slop, t_max)
        {
            mask |= 1 << l;
            dist[l] = t as f32;
        }
    }
    (mask, dist)
}

#[cfg(test)]
mod tests;
