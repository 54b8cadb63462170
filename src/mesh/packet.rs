//! Closest hits of a packet of rays (a tile of camera rays) in one walk of the BVH
//! ([`crate::bvh::wide::WideBvh::traverse_packet`]): every node and triangle pack is fetched
//! once for all the rays that reach it. Each ray runs the same `f32` filter and `f64` test as
//! [`Mesh::intersect`], and ties are broken by triangle index, so every answer is the single
//! ray's, bit for bit.

use super::Mesh;
use super::packed::EdgeRay;
use super::query::closer;
use crate::bvh::TraversalCost;
use crate::bvh::wide::{PACKET, WideRay};
use crate::geometry::ShearedRay;
use crate::math::Ray;

/// A ray prepared for the packet walk.
struct Prepared {
    index: usize,
    sheared: ShearedRay,
    edges: EdgeRay,
}

impl Mesh {
    /// [`Mesh::intersect`] of every ray in `rays` (at most [`PACKET`]) below its own limit
    /// `t_max[i]`, into `out[i]`; adds each ray's work to `cost[i]` (nodes: the wide nodes the
    /// packet visited with that ray in it, which can differ from the single ray's count: the
    /// packet visits children in its own order and tests upper levels for the whole packet).
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or a slice is shorter than `rays`.
    pub fn intersect_packet(
        &self,
        rays: &[Ray],
        t_max: &[f64],
        out: &mut [Option<(f64, usize)>],
        cost: &mut [TraversalCost],
    ) {
        assert!(rays.len() <= PACKET);
        let mut wide: Vec<WideRay> = Vec::with_capacity(rays.len());
        let mut prepared: Vec<Prepared> = Vec::with_capacity(rays.len());
        let mut limit = [0f64; PACKET];
        for (i, ray) in rays.iter().enumerate() {
            out[i] = None;
            cost[i].nodes += 1; // the root box
            let Some(w) = self.bvh.ray(ray, t_max[i]) else {
                continue;
            };
            let Some(sheared) = ShearedRay::new(ray) else {
                continue;
            };
            limit[wide.len()] = t_max[i];
            prepared.push(Prepared {
                index: i,
                edges: EdgeRay::new(&sheared, &w),
                sheared,
            });
            wide.push(w);
        }
        let n = wide.len();
        let mut costs = [TraversalCost::default(); PACKET];
        let mut prims = [0u32; PACKET];
        let mut best = [None; PACKET];
        self.bvh.traverse_packet(
            &wide,
            &mut limit[..n],
            &mut costs[..n],
            |r, g, t_max| {
                let p = &prepared[r];
                let group = self.bvh.groups[g];
                prims[r] += group.count;
                let mut mask = p.edges.candidates(&self.packs[g], group.count);
                let mut t_max = t_max;
                while mask != 0 {
                    let slot = group.first as usize + mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let t_min = rays[p.index].t_min;
                    let t = closer(
                        &p.sheared,
                        &self.tris[slot],
                        slot,
                        t_min,
                        t_max,
                        &mut best[r],
                    );
                    if t < t_max {
                        self.prefetch_shading(slot);
                        t_max = t;
                    }
                }
                t_max
            },
            |g| self.prefetch_group(g),
        );
        for (r, p) in prepared.iter().enumerate() {
            out[p.index] = best[r];
            cost[p.index].nodes += costs[r].nodes;
            cost[p.index].prims += prims[r];
        }
    }
}
