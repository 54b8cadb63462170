//! Closest hits of a packet of camera rays: meshes are walked once for the whole packet
//! ([`crate::mesh::Mesh::intersect_packet`]), other objects ray by ray.

use super::accel::object_hit;
use super::{Hit, Scene};
use crate::bvh::TraversalCost;
use crate::bvh::wide::PACKET;
use crate::geometry::Shape;
use crate::math::Ray;

impl Scene {
    /// [`Scene::intersect_counted`] over `(ray.t_min, infinity)` for each of `rays` (at most
    /// [`PACKET`]), into `hits`; adds each ray's work to `cost`. The hits are the single rays'
    /// bit for bit (the closest, lowest object index among equal distances, and in a mesh the
    /// lowest triangle index). Scenes large enough for the object BVH, and scenes without a
    /// mesh, take their rays one by one (the single-ray query culls by the objects' boxes);
    /// the others (a few objects, typically one big mesh) share each mesh walk.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or a slice is shorter than `rays`.
    pub fn intersect_packet(
        &self,
        rays: &[Ray],
        hits: &mut [Option<Hit>],
        cost: &mut [TraversalCost],
    ) {
        assert!(rays.len() <= PACKET && hits.len() >= rays.len() && cost.len() >= rays.len());
        if self.accel.single_rays(self.objects.len()) {
            for (i, ray) in rays.iter().enumerate() {
                hits[i] = self.intersect_counted(ray, f64::INFINITY, &mut cost[i]);
            }
            return;
        }
        // The linear scan of `intersect_counted`, object by object for the whole packet.
        let n = rays.len();
        hits[..n].fill(None);
        let mut limit = [f64::INFINITY; PACKET];
        let mut found = [None; PACKET];
        for (object, o) in self.objects.iter().enumerate() {
            if let Shape::Mesh(m) = &o.shape {
                m.intersect_packet(rays, &limit[..n], &mut found[..n], cost);
                for i in 0..n {
                    cost[i].prims += 1;
                    if let Some((t, tri)) = found[i] {
                        limit[i] = t;
                        hits[i] = Some(Hit {
                            t,
                            normal: m.geometric_normal(tri),
                            object,
                            triangle: Some(tri as u32),
                        });
                    }
                }
            } else {
                for (i, ray) in rays.iter().enumerate() {
                    if let Some(h) = object_hit(o, object, ray, limit[i], &mut cost[i]) {
                        limit[i] = h.t;
                        hits[i] = Some(h);
                    }
                }
            }
        }
    }

    /// [`Scene::occluded`] of each of `rays` (at most [`PACKET`]) over `(ray.t_min, t_max[i])`,
    /// into `blocked`: the single rays' answers. Shadow rays towards one light from a tile's
    /// hits are coherent, so each mesh is walked once for all the rays no other object blocked
    /// before it ([`crate::mesh::Mesh::occludes_packet`]); other objects take the rays one by
    /// one, and scenes large enough for the object BVH or without a mesh take every ray alone.
    ///
    /// # Panics
    /// If there are more than [`PACKET`] rays or a slice is shorter than `rays`.
    pub fn occluded_packet(&self, rays: &[Ray], t_max: &[f64], blocked: &mut [bool]) {
        let n = rays.len();
        assert!(n <= PACKET && t_max.len() >= n && blocked.len() >= n);
        let mut cost = TraversalCost::default();
        if self.accel.single_rays(self.objects.len()) {
            for i in 0..n {
                blocked[i] = self.occluded(&rays[i], t_max[i], &mut cost);
            }
            return;
        }
        blocked[..n].fill(false);
        let mut open = Vec::with_capacity(n);
        let (mut sub, mut limit, mut hit) = (Vec::with_capacity(n), [0.0; PACKET], [false; PACKET]);
        for (object, o) in self.objects.iter().enumerate() {
            open.clear();
            open.extend((0..n).filter(|&i| !blocked[i]));
            if open.is_empty() {
                return;
            }
            if let Shape::Mesh(m) = &o.shape {
                sub.clear();
                for (k, &i) in open.iter().enumerate() {
                    sub.push(rays[i]);
                    limit[k] = t_max[i];
                    hit[k] = false;
                }
                m.occludes_packet(&sub, &limit[..sub.len()], &mut hit[..sub.len()]);
                for (k, &i) in open.iter().enumerate() {
                    blocked[i] = hit[k];
                }
            } else {
                for &i in &open {
                    blocked[i] = object_hit(o, object, &rays[i], t_max[i], &mut cost).is_some();
                }
            }
        }
    }
}
