//! Ray queries on a mesh: closest hit, any hit, all crossings of a line, chords. The 4-wide BVH
//! and the `f32` packs ([`super::packed`]) find candidate triangles; the `f64` watertight test
//! ([`crate::geometry::triangle_t`]) on the stored vertices decides, so every answer is exactly
//! what a loop over all triangles with `triangle_t` gives.

use super::Mesh;
use super::packed::EdgeRay;
use super::triangle::ShearedRay;
use crate::bvh::{TraversalCost, Visit};
use crate::math::Ray;

impl Mesh {
    /// Visit every candidate triangle (stored index) of the leaves the ray reaches within
    /// `(ray.t_min, t_max)`, nearest leaves first; `test(sheared, slot, t_max)` (with `sheared`
    /// the ray prepared for `triangle_t`, see [`ShearedRay::t`]) as in
    /// [`crate::bvh::wide::WideBvh::traverse`]. Counts BVH nodes and triangles filtered.
    fn candidates(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
        mut test: impl FnMut(&ShearedRay, usize, f64) -> Visit,
    ) {
        cost.nodes += 1; // the root box
        let Some(wide_ray) = self.bvh.ray(ray, t_max) else {
            return;
        };
        let Some(sheared) = ShearedRay::new(ray) else {
            return; // triangle_t hits nothing
        };
        let edges = EdgeRay::new(&sheared, &wide_ray);
        let mut prims = 0;
        self.bvh.traverse(
            &wide_ray,
            t_max,
            cost,
            |g, mut t_max| {
                let group = self.bvh.groups[g];
                prims += group.count;
                let mut mask = edges.candidates(&self.packs[g], group.count);
                while mask != 0 {
                    let slot = group.first as usize + mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    match test(&sheared, slot, t_max) {
                        Visit::Continue(t) => t_max = t,
                        Visit::Stop => return Visit::Stop,
                    }
                }
                Visit::Continue(t_max)
            },
            |g| self.prefetch_group(g),
        );
        cost.prims += prims;
    }

    /// The closest hit in `(ray.t_min, t_max)`: distance and stored triangle index (the lowest
    /// index among triangles hit at the same distance, so the answer does not depend on the
    /// traversal order; [`Mesh::intersect_packet`] gives the same).
    #[must_use]
    pub fn intersect(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
    ) -> Option<(f64, usize)> {
        let mut best = None;
        self.candidates(ray, t_max, cost, |sheared, slot, t_max| {
            let t = closer(sheared, &self.tris[slot], slot, ray.t_min, t_max, &mut best);
            if t < t_max {
                self.prefetch_shading(slot);
            }
            Visit::Continue(t)
        });
        best
    }

    /// Whether any triangle is hit in `(ray.t_min, t_max)` (stops at the first found).
    #[must_use]
    pub fn occludes(&self, ray: &Ray, t_max: f64, cost: &mut TraversalCost) -> bool {
        let mut hit = false;
        self.candidates(ray, t_max, cost, |sheared, slot, t_max| {
            match sheared.t(&self.tris[slot]) {
                Some(t) if t > ray.t_min && t < t_max => {
                    hit = true;
                    Visit::Stop
                }
                _ => Visit::Continue(t_max),
            }
        });
        hit
    }

    /// Every crossing of the whole line `origin + t direction` (any `t`), sorted. A line
    /// through a shared edge or vertex hits every triangle there: hits closer than a relative
    /// 1e-9 are merged into one crossing.
    #[must_use]
    pub fn crossings(&self, ray: &Ray, cost: &mut TraversalCost) -> Vec<f64> {
        let line = Ray::new(ray.origin, ray.direction, f64::NEG_INFINITY);
        let mut ts = Vec::new();
        self.candidates(&line, f64::INFINITY, cost, |sheared, slot, t_max| {
            ts.extend(sheared.t(&self.tris[slot]));
            Visit::Continue(t_max)
        });
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|b, a| (*b - *a) <= 1e-9 * a.abs().max(b.abs()).max(1.0));
        ts
    }

    /// The part of the segment `(ray.t_min, t_max)` inside the mesh: the first crossing or
    /// entry `t` and the chord length. A line with an even number of crossings is inside
    /// between crossings 0-1, 2-3, ...; with an odd number (an open mesh) every crossing is a
    /// thin sheet with chord 0. `None` when the segment neither crosses nor lies inside.
    #[must_use]
    pub fn segment_inside(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
    ) -> Option<(f64, f64)> {
        let ts = self.crossings(ray, cost);
        let (lo, hi) = (ray.t_min, t_max);
        if !ts.len().is_multiple_of(2) {
            return ts.into_iter().find(|&t| t > lo && t < hi).map(|t| (t, 0.0));
        }
        let mut first = None;
        let mut chord = 0.0;
        for pair in ts.chunks_exact(2) {
            let (a, b) = (pair[0].max(lo), pair[1].min(hi));
            if a < b {
                first.get_or_insert(a);
                chord += b - a;
            }
        }
        first.map(|t| (t, chord))
    }
}

/// Test `slot` (vertices `tri`) for the closest-hit queries: when it is hit in `(t_min, t_max)`,
/// or exactly at the best distance so far with a lower index, it becomes `best`. Returns the
/// new `t_max` (`t_max` equals the best distance once there is one).
#[inline(always)]
pub(super) fn closer(
    sheared: &ShearedRay,
    tri: &[glam::DVec3; 3],
    slot: usize,
    t_min: f64,
    t_max: f64,
    best: &mut Option<(f64, usize)>,
) -> f64 {
    match sheared.t(tri) {
        Some(t)
            if t > t_min && (t < t_max || (t == t_max && best.is_some_and(|(_, s)| slot < s))) =>
        {
            *best = Some((t, slot));
            t
        }
        _ => t_max,
    }
}
