//! The scene's acceleration structure: every object prepared once for ray tests
//! ([`Prepared`]: per-shape constants, the normal only for the closest hit), and for the
//! bounded ones either, in a small scene, the padded bounds of every object but the spheres
//! in groups of four (`small`: one box test per object, exact tests only where the ray enters
//! the box before the best hit; a sphere is tested directly, its exact test costing about
//! what its box test would) or, for larger scenes, a BVH over them all (a mesh is one leaf
//! with its own BVH inside); unbounded planes, which no box can hold, in a plain list.
//!
//! Every query returns what a linear scan of [`Shape::intersect`] in object order returns: the
//! closest hit, the lowest object index among equal distances (tests: `tests.rs`).

use super::{Hit, Object, Scene};
use crate::bvh::{Aabb, BoxRay, Bvh, TraversalCost, Visit};
use crate::geometry::{Prepared, Shape, Shear};
use crate::math::Ray;
use rayon::prelude::*;
use small::Groups;

mod small;
#[cfg(test)]
mod tests;

/// Scenes with at most this many objects and a mesh are scanned linearly in object order, as
/// the packet query ([`Scene::intersect_packet`]) scans them, so both count the same work.
const LINEAR_MAX: usize = 8;

/// Scenes with at most this many bounded objects test every object's bounds (four at a time)
/// instead of walking the BVH.
const SMALL_MAX: usize = 32;

/// Prepared objects, the top-level BVH or the small scene's bounds, and the planes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Accel {
    bvh: Bvh,
    groups: Groups,
    prepared: Vec<Prepared>,
    planes: Vec<u32>,
    /// A small scene's spheres, tested without their bounds (empty with a BVH).
    spheres: Vec<u32>,
    objects: usize,
    /// Whether any object is a mesh.
    mesh: bool,
    /// Objects (ascending) whose sphere, triangle or quad is bit for bit an earlier object's:
    /// no ray ever hits them (equal distances go to the lower index), so they are not sampled
    /// as lights either (issue 27: 100 coincident emitting triangles were counted 100 times).
    coincident: Vec<u32>,
}

/// The bits of a sphere, triangle or quad (the shapes sampled as lights), to find copies.
fn shape_bits(s: &Shape) -> Option<Vec<u64>> {
    let pts: Vec<glam::DVec3> = match *s {
        Shape::Sphere { center, radius } => vec![center, glam::DVec3::splat(radius)],
        Shape::Triangle { vertices, .. } => vertices.to_vec(),
        Shape::Quad { vertices, .. } => vertices.to_vec(),
        _ => return None,
    };
    let tag = match s {
        Shape::Sphere { .. } => 0,
        Shape::Triangle { .. } => 1,
        _ => 2,
    };
    let mut bits = vec![tag];
    bits.extend(pts.iter().flat_map(|p| p.to_array().map(f64::to_bits)));
    Some(bits)
}

/// [`Accel::coincident`] of `objects`.
fn coincident(objects: &[Object]) -> Vec<u32> {
    let mut seen = std::collections::HashSet::new();
    (0..objects.len() as u32)
        .filter(|&i| shape_bits(&objects[i as usize].shape).is_some_and(|b| !seen.insert(b)))
        .collect()
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
        let prepared: Vec<Prepared> = objects.iter().map(|o| Prepared::new(&o.shape)).collect();
        let mut spheres = Vec::new();
        let (bvh, groups) = if bounded.len() <= SMALL_MAX {
            // A sphere's exact test costs about what its box test would.
            let (mut b, mut ids) = (Vec::new(), Vec::new());
            for (k, &i) in bounded.iter().enumerate() {
                if matches!(prepared[i as usize], Prepared::Sphere { .. }) {
                    spheres.push(i);
                } else {
                    b.push(boxes[k]);
                    ids.push(i);
                }
            }
            (Bvh::default(), Groups::new(&b, &ids))
        } else {
            let mut bvh = Bvh::build(&boxes);
            for slot in &mut bvh.order {
                *slot = bounded[*slot as usize];
            }
            (bvh, Groups::default())
        };
        Self {
            bvh,
            groups,
            mesh: prepared.contains(&Prepared::Mesh),
            prepared,
            planes,
            spheres,
            objects: objects.len(),
            coincident: coincident(objects),
        }
    }

    /// Whether object `i` of `n` is a copy of an earlier one (bit for bit the same sphere,
    /// triangle or quad), hidden by it (false when the accel was built for another object
    /// count).
    #[must_use]
    pub fn is_coincident_copy(&self, i: usize, n: usize) -> bool {
        self.objects == n
            && u32::try_from(i).is_ok_and(|i| self.coincident.binary_search(&i).is_ok())
    }

    /// Whether the top-level BVH serves `n` objects: false for small scenes (scanned
    /// linearly) and for a scene edited without [`Scene::rebuild_accel`] (scanned rather than
    /// missing objects).
    #[must_use]
    pub fn is_for(&self, n: usize) -> bool {
        self.objects == n && n > LINEAR_MAX
    }

    /// Whether single-ray queries should serve a packet of rays over `n` objects: the scene is
    /// prepared for them, and a small one has no mesh whose walk the packet could share.
    pub(super) fn single_rays(&self, n: usize) -> bool {
        self.is_for(n) || (self.objects == n && !self.mesh)
    }

    /// Whether no object has a box to test (planes and spheres only): scanned in object order.
    fn unboxed(&self) -> bool {
        self.groups.is_empty() && self.bvh.node_count() == 0
    }

    /// Whether the linear scan of [`object_hit`] serves `n` objects: an edited scene, or a
    /// small one with a mesh (as the packet query scans it).
    fn linear(&self, n: usize) -> bool {
        self.objects != n || (self.mesh && n <= LINEAR_MAX)
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
    ///
    /// `cost.prims` counts the exact object tests run (and a mesh's triangles), `cost.nodes`
    /// the boxes tested: BVH nodes (the object BVH's and the meshes'), or in a small scene one
    /// padded bounding box per bounded object.
    pub fn intersect_counted(
        &self,
        ray: &Ray,
        t_max: f64,
        cost: &mut TraversalCost,
    ) -> Option<Hit> {
        let n = self.objects.len();
        if self.accel.linear(n) {
            let mut best: Option<Hit> = None;
            let mut t_max = t_max;
            for (i, o) in self.objects.iter().enumerate() {
                if let Some(h) = object_hit(o, i, ray, t_max, cost) {
                    t_max = h.t;
                    best = Some(h);
                }
            }
            return best;
        }
        let mut q = Query::new(self, ray);
        let mut best: Option<Best> = None;
        if self.accel.unboxed() {
            // Planes and spheres only: no mesh, no shear; the tests inlined into the loop.
            let mut t_max = t_max;
            for (i, p) in self.accel.prepared.iter().enumerate() {
                if let Some(t) = p.t_inline(ray, &mut q.sheared, t_max) {
                    t_max = t;
                    best = Some(Best {
                        t,
                        object: i,
                        triangle: None,
                    });
                }
            }
            cost.prims += n as u32;
            return best.map(|b| q.hit(b));
        }
        for &i in self.accel.planes.iter().chain(&self.accel.spheres) {
            q.consider(i as usize, t_max, &mut best, cost);
        }
        let limit = best.map_or(t_max, |b| b.t);
        if self.accel.bvh.node_count() == 0 {
            self.accel.groups.closest(ray, limit, cost, |i, cost| {
                q.consider(i, t_max, &mut best, cost);
                best.map(|b| b.t)
            });
        } else {
            let bvh = &self.accel.bvh;
            // The BVH would count object tests as primitives; `consider` already does.
            let mut inner = TraversalCost::default();
            bvh.traverse(&BoxRay::new(ray), limit, &mut inner, |slot, _| {
                q.consider(bvh.order[slot] as usize, t_max, &mut best, cost);
                Visit::Continue(best.map_or(t_max, |b| b.t))
            });
            cost.nodes += inner.nodes;
        }
        best.map(|b| q.hit(b))
    }

    /// The distance of [`Shape::intersect`]`(ray, t_max)` on object `i` alone, bit for bit,
    /// without the normal: the prepared object's test (a scene edited without
    /// [`Scene::rebuild_accel`]: the shape's own).
    #[must_use]
    pub fn object_t(&self, i: usize, ray: &Ray, t_max: f64) -> Option<f64> {
        if self.accel.objects != self.objects.len() {
            return self.objects[i].shape.intersect(ray, t_max).map(|h| h.t);
        }
        let mut cost = TraversalCost::default();
        Query::new(self, ray)
            .test(i, t_max, &mut cost)
            .map(|(t, _)| t)
    }

    /// Whether anything lies on the ray in `(ray.t_min, t_max)`: any-hit, stops at the first.
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f64, cost: &mut TraversalCost) -> bool {
        let n = self.objects.len();
        if self.accel.linear(n) {
            return (0..n).any(|i| match &self.objects[i].shape {
                Shape::Mesh(m) => {
                    cost.prims += 1;
                    m.occludes(ray, t_max, cost)
                }
                _ => object_hit(&self.objects[i], i, ray, t_max, cost).is_some(),
            });
        }
        let mut q = Query::new(self, ray);
        if self.accel.unboxed() {
            let prepared = &self.accel.prepared;
            let hit = prepared
                .iter()
                .position(|p| p.t_inline(ray, &mut q.sheared, t_max).is_some());
            cost.prims += hit.map_or(n, |i| i + 1) as u32;
            return hit.is_some();
        }
        if (self.accel.planes.iter().chain(&self.accel.spheres))
            .any(|&i| q.blocks(i as usize, t_max, cost))
        {
            return true;
        }
        if self.accel.bvh.node_count() == 0 {
            return self
                .accel
                .groups
                .any(ray, t_max, cost, |i, cost| q.blocks(i, t_max, cost));
        }
        let bvh = &self.accel.bvh;
        let mut hit = false;
        let mut inner = TraversalCost::default();
        bvh.traverse(&BoxRay::new(ray), t_max, &mut inner, |slot, t| {
            if q.blocks(bvh.order[slot] as usize, t_max, cost) {
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
    /// object order (for translucent shadow rays, which visit every blocker); every object in
    /// a scene without an object BVH.
    #[must_use]
    pub fn objects_near(&self, ray: &Ray, t_max: f64, cost: &mut TraversalCost) -> Vec<usize> {
        if !self.accel.is_for(self.objects.len()) || self.accel.bvh.node_count() == 0 {
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

/// The closest hit so far: distance, object, (meshes) stored triangle.
#[derive(Clone, Copy, Debug)]
struct Best {
    t: f64,
    object: usize,
    triangle: Option<u32>,
}

/// One ray's queries over the prepared objects: the watertight test's shear computed once,
/// when the first flat object needs it.
struct Query<'a> {
    scene: &'a Scene,
    ray: &'a Ray,
    sheared: Shear,
}

impl<'a> Query<'a> {
    fn new(scene: &'a Scene, ray: &'a Ray) -> Self {
        Self {
            scene,
            ray,
            sheared: Shear::new(),
        }
    }

    /// The exact test of object `i` over `(ray.t_min, t_max)`: distance and (meshes) triangle.
    #[inline]
    fn test(
        &mut self,
        i: usize,
        t_max: f64,
        cost: &mut TraversalCost,
    ) -> Option<(f64, Option<u32>)> {
        cost.prims += 1;
        match &self.scene.accel.prepared[i] {
            Prepared::Mesh => {
                let Shape::Mesh(m) = &self.scene.objects[i].shape else {
                    unreachable!("prepared from this object")
                };
                let (t, tri) = m.intersect(self.ray, t_max, cost)?;
                Some((t, Some(tri as u32)))
            }
            p => Some((p.t(self.ray, &mut self.sheared, t_max)?, None)),
        }
    }

    /// Test object `i` against the best hit so far, with `t_max` just above it so that ties
    /// reach the comparison (lowest index wins, as in a linear scan).
    #[inline]
    fn consider(
        &mut self,
        i: usize,
        t_max: f64,
        best: &mut Option<Best>,
        cost: &mut TraversalCost,
    ) {
        let limit = best.map_or(t_max, |b| b.t.next_up());
        if let Some((t, triangle)) = self.test(i, limit, cost)
            && best.is_none_or(|b| t < b.t || (t == b.t && i < b.object))
        {
            *best = Some(Best {
                t,
                object: i,
                triangle,
            });
        }
    }

    /// Whether object `i` blocks the ray in `(ray.t_min, t_max)`.
    #[inline]
    fn blocks(&mut self, i: usize, t_max: f64, cost: &mut TraversalCost) -> bool {
        match &self.scene.objects[i].shape {
            Shape::Mesh(m) => {
                cost.prims += 1;
                m.occludes(self.ray, t_max, cost)
            }
            _ => self.test(i, t_max, cost).is_some(),
        }
    }

    /// The hit of `best`, with the normal [`Shape::intersect`] gives it.
    fn hit(&self, b: Best) -> Hit {
        let normal = match (&self.scene.objects[b.object].shape, b.triangle) {
            (Shape::Mesh(m), Some(tri)) => m.geometric_normal(tri as usize),
            _ => self.scene.accel.prepared[b.object].normal(self.ray, b.t),
        };
        Hit {
            t: b.t,
            normal,
            object: b.object,
            triangle: b.triangle,
        }
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
