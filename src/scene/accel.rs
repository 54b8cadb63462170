//! The scene's acceleration structure: a BVH over every bounded object (a mesh is one leaf
//! with its own BVH inside) plus a plain list of unbounded planes, which no box can hold.

use super::{Hit, Object, Scene};
use crate::bvh::{Aabb, BoxRay, Bvh, TraversalCost, Visit};
use crate::geometry::Shape;
use crate::math::Ray;
use rayon::prelude::*;

/// Scenes with at most this many objects are scanned linearly: a few sphere tests cost less
/// than walking boxes (the lecture's classic scene has three objects).
const LINEAR_MAX: usize = 8;

/// Top-level BVH over objects, and the planes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Accel {
    bvh: Bvh,
    planes: Vec<u32>,
    objects: usize,
}

impl Accel {
    /// Build over `objects`.
    #[must_use]
    pub fn build(objects: &[Object]) -> Self {
        let mut boxes = Vec::new();
        let mut bounded = Vec::new();
        let mut planes = Vec::new();
        for (i, o) in objects.iter().enumerate() {
            match o.shape.bounds() {
                Some((min, max)) => {
                    boxes.push(Aabb { min, max });
                    bounded.push(i as u32);
                }
                None => planes.push(i as u32),
            }
        }
        let mut bvh = Bvh::build(&boxes);
        for slot in &mut bvh.order {
            *slot = bounded[*slot as usize];
        }
        Self {
            bvh,
            planes,
            objects: objects.len(),
        }
    }

    /// Whether the top-level BVH serves `n` objects: false for small scenes (scanned
    /// linearly) and for a scene edited without [`Scene::rebuild_accel`] (scanned rather than
    /// missing objects).
    #[must_use]
    pub fn is_for(&self, n: usize) -> bool {
        self.objects == n && n > LINEAR_MAX
    }
}

/// Hit on object `i`: its distance, outward normal and (meshes) stored triangle.
pub(super) fn object_hit(
    o: &Object,
    i: usize,
    ray: &Ray,
    t_max: f64,
    cost: &mut TraversalCost,
) -> Option<Hit> {
    cost.prims += 1;
    let (t, normal, triangle) = match &o.shape {
        Shape::Mesh(m) => {
            let (t, tri) = m.intersect(ray, t_max, cost)?;
            (t, m.geometric_normal(tri), Some(tri as u32))
        }
        s => {
            let h = s.intersect(ray, t_max)?;
            (h.t, h.normal, None)
        }
    };
    Some(Hit {
        t,
        normal,
        object: i,
        triangle,
    })
}

impl Scene {
    /// Rebuild the acceleration structure after editing [`Scene::objects`].
    pub fn rebuild_accel(&mut self) {
        self.accel = Accel::build(&self.objects);
    }

    /// [`Scene::intersect`], adding the work done to `cost`. The closest hit with the lowest
    /// object index among equal distances: exactly what a linear scan in object order finds.
    pub fn intersect_counted(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        if !self.accel.is_for(self.objects.len()) {
            let mut t_max = t_max;
            for (i, o) in self.objects.iter().enumerate() {
                if let Some(h) = object_hit(o, i, ray, t_max, cost) {
                    t_max = h.t;
                    best = Some(h);
                }
            }
            return best;
        }
        for &i in &self.accel.planes {
            self.consider(i as usize, ray, t_max, &mut best, cost);
        }
        let bvh = &self.accel.bvh;
        let limit = best.map_or(t_max, |b| b.t);
        // The BVH would count object tests as primitives; `consider` already does.
        let mut inner = TraversalCost::default();
        bvh.traverse(&BoxRay::new(ray), limit, &mut inner, |slot, _| {
            self.consider(bvh.order[slot] as usize, ray, t_max, &mut best, cost);
            Visit::Continue(best.map_or(t_max, |b| b.t))
        });
        cost.nodes += inner.nodes;
        best
    }

    /// Test object `i` against the best hit so far, with `t_max` just above it so that ties
    /// reach the comparison (lowest index wins, as in a linear scan).
    fn consider(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f64,
        best: &mut Option<Hit>,
        cost: &mut TraversalCost,
    ) {
        let limit = best.map_or(t_max, |b| b.t.next_up());
        if let Some(h) = object_hit(&self.objects[i], i, ray, limit, cost)
            && best.is_none_or(|b| h.t < b.t || (h.t == b.t && i < b.object))
        {
            *best = Some(h);
        }
    }

    /// Whether anything lies on the ray in `(ray.t_min, t_max)`: any-hit, stops at the first.
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f64, cost: &mut TraversalCost) -> bool {
        let blocks = |i: usize, cost: &mut TraversalCost| match &self.objects[i].shape {
            Shape::Mesh(m) => {
                cost.prims += 1;
                m.occludes(ray, t_max, cost)
            }
            _ => object_hit(&self.objects[i], i, ray, t_max, cost).is_some(),
        };
        if !self.accel.is_for(self.objects.len()) {
            return (0..self.objects.len()).any(|i| blocks(i, cost));
        }
        if self.accel.planes.iter().any(|&i| blocks(i as usize, cost)) {
            return true;
        }
        let bvh = &self.accel.bvh;
        let mut hit = false;
        let mut inner = TraversalCost::default();
        bvh.traverse(&BoxRay::new(ray), t_max, &mut inner, |slot, t| {
            if blocks(bvh.order[slot] as usize, cost) {
                hit = true;
                Visit::Stop
            } else {
                Visit::Continue(t)
            }
        });
        cost.nodes += inner.nodes;
        hit
    }

    /// Objects whose bounds the segment `[ray.t_min, t_max]` touches, and every plane, in
    /// object order (for translucent shadow rays, which visit every blocker).
    #[must_use]
    pub fn objects_near(&self, ray: &Ray, t_max: f64, cost: &mut TraversalCost) -> Vec<usize> {
        if !self.accel.is_for(self.objects.len()) {
            return (0..self.objects.len()).collect();
        }
        let mut out: Vec<usize> = self.accel.planes.iter().map(|&i| i as usize).collect();
        let bvh = &self.accel.bvh;
        bvh.traverse(&BoxRay::new(ray), t_max, cost, |slot, t| {
            out.push(bvh.order[slot] as usize);
            Visit::Continue(t)
        });
        out.sort_unstable();
        out
    }
}

/// The traversal cost of every pixel's centre camera ray (closest hit only, no shading), row
/// major, top row first: the data of a traversal heat map. Rows run in parallel.
#[must_use]
pub fn traversal_cost_image(scene: &Scene) -> Vec<TraversalCost> {
    let cam = &scene.camera;
    (0..cam.height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let film = cam.film();
            (0..cam.width).map(move |x| {
                let mut cost = TraversalCost::default();
                let ray = film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
                let _ = scene.intersect_counted(&ray, f64::INFINITY, &mut cost);
                cost
            })
        })
        .collect()
}
