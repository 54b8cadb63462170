//! Closest hits of a packet of rays (a tile of camera rays) in one walk of the BVH
//! ([`crate::bvh::wide::WideBvh::traverse_packet`]): every node and triangle pack is fetched
//! once for all the rays that reach it. Each ray runs the same `f32` filter and `f64` test as
//! [`Mesh::intersect`], and ties are broken by triangle index, so every answer is the single
//! ray's, bit for bit.

use super::Mesh;
use super::packed::EdgeRay;
use super::query::closer;
use super::triangle::ShearedRay;
use crate::bvh::TraversalCost;
use crate::bvh::wide::{PACKET, WideRay};
use crate::math::Ray;

/// A ray prepared for the packet walk.
struct Prepared {
    index: usize,
    sheared: ShearedRay,
    edges: EdgeRay,
}

/// The rays of a packet that reach the mesh's root box, prepared for the walk.
struct Packet {
    wide: Vec<WideRay>,
    prepared: Vec<Prepared>,
    /// Per prepared ray, its limit.
    limit: [f64; PACKET],
}

impl Mesh {
    /// Prepare `rays` (each under its limit `t_max[i]`) for [`WideBvh::traverse_packet`]:
    /// those that miss the root box or have no direction are left out (they hit nothing).
    ///
    /// [`WideBvh::traverse_packet`]: crate::bvh::wide::WideBvh::traverse_packet
    fn packet(&self, rays: &[Ray], t_max: &[f64]) -> Packet {
        assert!(rays.len() <= PACKET);
        let mut p = Packet {
            wide: Vec::with_capacity(rays.len()),
            prepared: Vec::with_capacity(rays.len()),
            limit: [0.0; PACKET],
        };
        for (i, ray) in rays.iter().enumerate() {
            let Some(w) = self.bvh.ray(ray, t_max[i]) else {
                continue;
            };
            let Some(sheared) = ShearedRay::new(ray) else {
                continue;
            };
            p.limit[p.wide.len()] = t_max[i];
            p.prepared.push(Prepared {
                index: i,
                edges: EdgeRay::new(&sheared, &w),
                sheared,
            });
            p.wide.push(w);
        }
        p
    }

    /// Walk `rays` (each under its limit `t_max[i]`) through the BVH as one packet: for every
    /// triangle the `f32` filter lets through on ray `i`'s way, `test(i, sheared, slot,
    /// t_max)` returns that ray's new limit (below the old narrows it; minus infinity takes
    /// the ray out of the walk). Adds each ray's nodes and filtered triangles to `cost[i]`.
    fn walk_packet(
        &self,
        rays: &[Ray],
        t_max: &[f64],
        cost: &mut [TraversalCost],
        mut test: impl FnMut(usize, &ShearedRay, usize, f64) -> f64,
    ) {
        let Packet {
            wide,
            prepared,
            mut limit,
        } = self.packet(rays, t_max);
        let n = wide.len();
        let mut costs = [TraversalCost::default(); PACKET];
        let mut prims = [0u32; PACKET];
        self.bvh.traverse_packet(
            &wide,
            &mut limit[..n],
            &mut costs[..n],
            |r, g, mut t_max| {
                let p = &prepared[r];
                let group = self.bvh.groups[g];
                prims[r] += group.count;
                let mut mask = p.edges.candidates(&self.packs[g], group.count);
                while mask != 0 && t_max > f64::NEG_INFINITY {
                    let slot = group.first as usize + mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    t_max = test(p.index, &p.sheared, slot, t_max);
                }
                t_max
            },
            |g| self.prefetch_group(g),
        );
        for (r, p) in prepared.iter().enumerate() {
            cost[p.index].nodes += costs[r].nodes;
            cost[p.index].prims += prims[r];
        }
    }

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
        for i in 0..rays.len() {
            out[i] = None;
            cost[i].nodes += 1; // the root box
        }
        self.walk_packet(rays, t_max, cost, |i, sheared, slot, t_max| {
            let tri = &self.tris[slot];
            let t = closer(sheared, tri, slot, rays[i].t_min, t_max, &mut out[i]);
            if t < t_max {
                self.prefetch_shading(slot);
            }
            t
        });
    }

    /// [`Mesh::occludes`] of every ray in `rays` (at most [`PACKET`]) below its own limit
    /// `t_max[i]`: sets `blocked[i]` when some triangle is hit in `(t_min, t_max[i])` and
    /// leaves it otherwise. A ray leaves the walk at its first hit. The answer is the single
    /// ray's: the walk takes each ray into every box its own test enters, and a ray's limit
    /// only falls to minus infinity once it is blocked.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or a slice is shorter than `rays`.
    pub fn occludes_packet(&self, rays: &[Ray], t_max: &[f64], blocked: &mut [bool]) {
        let mut cost = [TraversalCost::default(); PACKET];
        self.walk_packet(rays, t_max, &mut cost, |i, sheared, slot, t_max| {
            let t_min = rays[i].t_min;
            if sheared
                .t(&self.tris[slot])
                .is_some_and(|t| t > t_min && t < t_max)
            {
                blocked[i] = true;
                f64::NEG_INFINITY
            } else {
                t_max
            }
        });
    }
}
