//! The bounded objects of a small scene (at most [`SMALL_MAX`]) without a hierarchy: their
//! padded bounds in groups of four, structure of arrays, so one pass of plain `f64` arithmetic
//! over the lanes (which the compiler vectorises) finds every object the ray's segment enters;
//! the exact tests then run only for those whose entry distance is not beyond the best hit so
//! far (object order: no candidate list to sort, which cost more than it saved here).
//!
//! Conservative as the object BVH's leaves are: each box is the object's bounds padded by
//! [`Aabb::padded`] (on every axis 1e-9 of the largest extent plus 1e-12 of the largest
//! coordinate, far above the rounding of an exact test's hit point, about 1e-16 of the
//! coordinates) and rounded outwards to `f32` (the box a one-object BVH leaf holds), and the
//! slab test is [`BoxRay`]'s (a NaN from a ray in a slab's boundary plane counts as inside
//! that slab). A hit lies strictly inside its object's box, so its entry distance is below
//! the hit's: skipping an entry beyond the best hit skips no closer hit and no tie.
//!
//! [`BoxRay`]: crate::bvh::BoxRay

use super::SMALL_MAX;
use crate::bvh::{Aabb, TraversalCost, down, fmax, fmin, up};
use crate::math::Ray;

/// Four boxes, one per lane; `lo[axis][lane]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Group {
    lo: [[f64; 4]; 3],
    hi: [[f64; 4]; 3],
}

impl Group {
    /// Entry distance of each lane's box over `[t_min, t_max]`, and whether the ray enters it.
    #[inline(always)]
    fn enter(&self, o: [f64; 3], inv: [f64; 3], t_min: f64, t_max: f64) -> ([f64; 4], [bool; 4]) {
        let (mut lo, mut hi) = ([t_min; 4], [t_max; 4]);
        for a in 0..3 {
            for l in 0..4 {
                let t1 = (self.lo[a][l] - o[a]) * inv[a];
                let t2 = (self.hi[a][l] - o[a]) * inv[a];
                lo[l] = fmin(fmax(t1, lo[l]), fmax(t2, lo[l]));
                hi[l] = fmax(fmin(t1, hi[l]), fmin(t2, hi[l]));
            }
        }
        (lo, std::array::from_fn(|l| lo[l] <= hi[l]))
    }
}

/// The boxes of the bounded objects and their object indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Groups {
    groups: Vec<Group>,
    ids: Vec<u32>,
}

impl Groups {
    /// Boxes `boxes[k]` of objects `ids[k]` (at most [`SMALL_MAX`]).
    pub(super) fn new(boxes: &[Aabb], ids: &[u32]) -> Self {
        assert!(boxes.len() == ids.len() && ids.len() <= SMALL_MAX);
        let mut groups = vec![Group::default(); ids.len().div_ceil(4)];
        for (k, b) in boxes.iter().enumerate() {
            let p = b.padded();
            let g = &mut groups[k / 4];
            for a in 0..3 {
                g.lo[a][k % 4] = f64::from(down(p.min[a]));
                g.hi[a][k % 4] = f64::from(up(p.max[a]));
            }
        }
        Self {
            groups,
            ids: ids.to_vec(),
        }
    }

    /// Whether there is no box.
    pub(super) fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Closest-hit search: `test(object, cost)` runs the exact test of each object whose box
    /// the ray's segment `[ray.t_min, t_max]` enters, in object order, and returns the best
    /// hit's distance so far; objects whose entry lies beyond it are skipped. One box test per
    /// object is added to `cost.nodes`.
    #[inline]
    pub(super) fn closest(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
        mut test: impl FnMut(usize, &mut TraversalCost) -> Option<f64>,
    ) {
        let o = ray.origin.to_array();
        let inv = ray.direction.recip().to_array();
        let mut best = t_max;
        for (g, ids) in self.groups.iter().zip(self.ids.chunks(4)) {
            let (entry, inside) = g.enter(o, inv, ray.t_min, best);
            for (l, &id) in ids.iter().enumerate() {
                if inside[l] && entry[l] <= best {
                    best = test(id as usize, cost).unwrap_or(best);
                }
            }
        }
        cost.nodes += self.ids.len() as u32;
    }

    /// Any-hit search: whether `test(object, cost)` holds for some object whose box the
    /// segment `[ray.t_min, t_max]` enters (tried in object order, stopping at the first).
    #[inline]
    pub(super) fn any(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
        mut test: impl FnMut(usize, &mut TraversalCost) -> bool,
    ) -> bool {
        let o = ray.origin.to_array();
        let inv = ray.direction.recip().to_array();
        for (k, (g, ids)) in self.groups.iter().zip(self.ids.chunks(4)).enumerate() {
            let (_, inside) = g.enter(o, inv, ray.t_min, t_max);
            for (l, &id) in ids.iter().enumerate() {
                if inside[l] && test(id as usize, cost) {
                    cost.nodes += (4 * k + ids.len()) as u32;
                    return true;
                }
            }
        }
        cost.nodes += self.ids.len() as u32;
        false
    }
}
