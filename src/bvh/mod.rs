//! A bounding volume hierarchy over axis-aligned boxes: binned SAH build (Wald 2007, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies"), depth-first flat layout, ordered
//! traversal with a fixed stack, and a per-ray cost counter for traversal heat maps.
//!
//! Generic over what the boxes bound: the scene uses one over its objects, every mesh one over
//! its triangles. Callers test primitives in a closure, so the BVH knows no geometry.
//!
//! The binned SAH build is in `build`; the 4-wide BVH collapsed from this one in [`wide`].

use crate::math::Ray;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Traversal stack size: `build::SAH_DEPTH` plus a median split per remaining bit of a `u32`
/// count.
const STACK: usize = 100;

/// What one ray cost: BVH nodes visited and primitives tested, over all levels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TraversalCost {
    /// BVH nodes whose box was tested.
    pub nodes: u32,
    /// Primitives (objects, triangles) whose exact test ran.
    pub prims: u32,
}

impl TraversalCost {
    /// Nodes plus primitives: one number for a heat map.
    #[must_use]
    pub fn total(&self) -> u32 {
        self.nodes.saturating_add(self.prims)
    }
}

impl std::ops::AddAssign for TraversalCost {
    fn add_assign(&mut self, o: Self) {
        self.nodes = self.nodes.saturating_add(o.nodes);
        self.prims = self.prims.saturating_add(o.prims);
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: DVec3,
    /// Upper corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (identity of [`Aabb::union`]).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The smallest box holding both.
    #[must_use]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Half the surface area (all the SAH needs); 0 for empty boxes.
    #[must_use]
    pub fn half_area(&self) -> f64 {
        let e = (self.max - self.min).max(DVec3::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// The box grown on every axis by 1e-9 of its largest extent plus 1e-12 of its largest
    /// coordinate, so that a primitive test's rounding never reports a hit the box test has
    /// culled. The same pad on every axis: a flat primitive (an axis-aligned quad or triangle)
    /// gets a thickness, without which a ray hitting it on an edge it shares with another at
    /// `y = 0` could enter its box an ulp beyond the hit and lose it (test
    /// `scene::accel::tests::shared_edges_tie_as_the_linear_scan`).
    #[must_use]
    pub fn padded(&self) -> Aabb {
        let pad = DVec3::splat(
            1e-9 * (self.max - self.min).max_element()
                + 1e-12 * self.min.abs().max(self.max.abs()).max_element(),
        );
        Aabb {
            min: self.min - pad,
            max: self.max + pad,
        }
    }
}

/// A ray with its reciprocal direction, ready for box tests.
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    origin: DVec3,
    inv: DVec3,
    t_min: f64,
}

impl BoxRay {
    /// Precompute for `ray`.
    #[must_use]
    pub fn new(ray: &Ray) -> Self {
        Self {
            origin: ray.origin,
            inv: ray.direction.recip(),
            t_min: ray.t_min,
        }
    }

    /// Entry distance into `b` if the ray's `[t_min, t_max]` overlaps it (inclusive). NaN-safe
    /// in the way of T. Barnes, "Fast, Branchless Ray/Bounding Box Intersections, Part 3": a
    /// ray in a slab's boundary plane counts as inside that slab.
    #[must_use]
    fn enter(&self, min: [f32; 3], max: [f32; 3], t_max: f64) -> Option<f64> {
        let wide = |v: [f32; 3]| DVec3::new(v[0].into(), v[1].into(), v[2].into());
        self.enter_f64(wide(min), wide(max), t_max)
    }

    /// [`BoxRay::enter`] for an `f64` box.
    #[inline(always)]
    fn enter_f64(&self, min: DVec3, max: DVec3, t_max: f64) -> Option<f64> {
        let t1 = (min - self.origin) * self.inv;
        let t2 = (max - self.origin) * self.inv;
        let (mut lo, mut hi) = (self.t_min, t_max);
        for a in 0..3 {
            lo = fmin(fmax(t1[a], lo), fmax(t2[a], lo));
            hi = fmax(fmin(t1[a], hi), fmin(t2[a], hi));
        }
        (lo <= hi).then_some(lo)
    }
}

/// Start loading the cache line that holds `value` into the caches: a hint to the CPU, with
/// no effect on any result. Through the `mem_prefetch` crate (`prefetcht0` on x86_64), because
/// this crate forbids `unsafe` and `std`'s prefetch intrinsic is unsafe or unstable.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    mem_prefetch::prefetch_read_data::<T, 3>(value);
}

/// `x < y ? x : y`: one `minsd`; a NaN in `x` yields `y` (what the slab test relies on).
#[inline(always)]
pub(crate) fn fmin(x: f64, y: f64) -> f64 {
    if x < y { x } else { y }
}

/// `x > y ? x : y`: one `maxsd`; a NaN in `x` yields `y`.
#[inline(always)]
pub(crate) fn fmax(x: f64, y: f64) -> f64 {
    if x > y { x } else { y }
}

/// 32 bytes, two to a cache line: bounds are stored as `f32`, rounded outwards, so the box
/// still contains its primitives exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    min: [f32; 3],
    max: [f32; 3],
    /// Leaf: first slot in [`Bvh::order`]; inner: index of the right child (left is next).
    index: u32,
    /// Leaf: number of primitives; 0 for inner nodes.
    count: u32,
}

/// The hierarchy. Primitive slots `0..n` are in leaf order; `order[slot]` is the caller's
/// primitive index, so callers may reorder their data by it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Caller's primitive index of each slot.
    pub order: Vec<u32>,
}

/// What a primitive test tells the traversal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Visit {
    /// Keep going with this (possibly narrowed) `t_max`.
    Continue(f64),
    /// Stop the traversal (any-hit queries).
    Stop,
}

impl Bvh {
    /// The root box (`None` when empty).
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        let wide = |v: [f32; 3]| DVec3::new(v[0].into(), v[1].into(), v[2].into());
        self.nodes.first().map(|n| Aabb {
            min: wide(n.min),
            max: wide(n.max),
        })
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Visit the slots of every leaf whose box the ray enters within `[t_min, t_max]`, near
    /// child first. `test(slot, t_max)` returns the new `t_max` or asks to stop.
    pub fn traverse(
        &self,
        ray: &BoxRay,
        mut t_max: f64,
        cost: &mut TraversalCost,
        mut test: impl FnMut(usize, f64) -> Visit,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut top = 0;
        let mut at = 0usize;
        cost.nodes += 1;
        let root = &self.nodes[0];
        if ray.enter(root.min, root.max, t_max).is_none() {
            return;
        }
        loop {
            let node = &self.nodes[at];
            if node.count > 0 {
                let first = node.index as usize;
                for slot in first..first + node.count as usize {
                    cost.prims += 1;
                    match test(slot, t_max) {
                        Visit::Continue(t) => t_max = t,
                        Visit::Stop => return,
                    }
                }
            } else {
                let (l, r) = (at + 1, node.index as usize);
                let (ln, rn) = (&self.nodes[l], &self.nodes[r]);
                cost.nodes += 2;
                let tl = ray.enter(ln.min, ln.max, t_max);
                let tr = ray.enter(rn.min, rn.max, t_max);
                match (tl, tr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, r) } else { (r, l) };
                        stack[top] = far as u32;
                        top += 1;
                        at = near;
                        continue;
                    }
                    (Some(_), None) => {
                        at = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        at = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop until a node the ray still reaches within the narrowed t_max.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let n = &self.nodes[stack[top] as usize];
                if ray.enter(n.min, n.max, t_max).is_some() {
                    at = stack[top] as usize;
                    break;
                }
            }
        }
    }
}

/// The largest `f32` not above `x`.
pub(crate) fn down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x { f.next_down() } else { f }
}

/// The smallest `f32` not below `x`.
pub(crate) fn up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x { f.next_up() } else { f }
}

mod build;

pub mod wide;

#[cfg(test)]
mod tests;
