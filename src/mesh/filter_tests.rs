//! Tests of the fast path: the `f32` triangle filter never drops a triangle the exact `f64` test
//! hits (rays through shared edges and vertices included), and the 4-wide BVH finds exactly
//! what the binary BVH and a loop over all triangles find.

use super::generate::icosphere;
use super::packed::EdgeRay;
use super::tests::Rng;
use super::triangle::triangle_t;
use super::*;
use crate::bvh::{BoxRay, TraversalCost, Visit};
use crate::math::Ray;

/// An icosphere of `level` subdivisions, rotated, squashed, scaled and moved.
pub(super) fn placed(level: u32, scale: f64, translate: DVec3) -> Mesh {
    let t = Transform {
        translate,
        rotate_deg: DVec3::new(10.0, 20.0, 30.0),
        scale: DVec3::new(1.0, 0.7, 1.3) * scale,
    };
    Mesh::new(&icosphere(level), &t.world_from_object(), MeshNormals::Flat).unwrap()
}

/// Slots the filter keeps for `ray` over the whole mesh (every group, no BVH).
fn kept(mesh: &Mesh, ray: &Ray) -> Vec<usize> {
    let Some(w) = mesh.bvh.ray(ray, f64::INFINITY) else {
        return Vec::new();
    };
    let Some(sheared) = super::triangle::ShearedRay::new(ray) else {
        return Vec::new();
    };
    let edges = EdgeRay::new(&sheared, &w);
    let mut out = Vec::new();
    for (g, group) in mesh.bvh.groups.iter().enumerate() {
        let mask = edges.candidates(&mesh.packs[g], group.count);
        for l in 0..group.count {
            if mask & (1 << l) != 0 {
                out.push((group.first + l) as usize);
            }
        }
    }
    out
}

#[test]
fn f32_filter_keeps_every_triangle_the_f64_test_hits() {
    let mut rng = Rng(5);
    let mut exact_hits = 0;
    let mut through_vertices_and_edges = 0;
    for (scale, translate) in [
        (1.0, DVec3::ZERO),
        (1.0, DVec3::new(3e3, -1e3, 2e3)),
        (1e-5, DVec3::splat(1e-5)),
        (1e6, DVec3::new(0.0, 5e6, 0.0)),
    ] {
        let mesh = placed(3, scale, translate);
        let n = mesh.triangle_count();
        for i in 0..400 {
            // Aim at a vertex, an edge midpoint or an interior point of some triangle.
            let [a, b, c] = mesh.triangle(i * 7 % n);
            let target = match i % 3 {
                0 => a,
                1 => 0.5 * (a + b),
                _ => (a + 2.0 * b + 3.0 * c) / 6.0,
            };
            through_vertices_and_edges += usize::from(i % 3 != 2);
            let dir = if i % 11 == 0 { DVec3::X } else { rng.unit() };
            let ray = Ray::new(target - 4.0 * scale * dir, dir, f64::NEG_INFINITY);
            let keep = kept(&mesh, &ray);
            let hits: Vec<usize> = (0..n)
                .filter(|&s| triangle_t(&mesh.triangle(s), &ray).is_some())
                .collect();
            for s in &hits {
                assert!(keep.contains(s), "slot {s} dropped for {ray:?}");
            }
            exact_hits += hits.len();
            // A filter that keeps everything would pass the loop above: it must be selective.
            assert!(
                keep.len() <= hits.len() + 8,
                "{} kept, {} hit, scale {scale}, {ray:?}, exact {:?}",
                keep.len(),
                hits.len(),
                mesh.bvh.ray(&ray, f64::INFINITY).map(|r| r.exact())
            );
        }
    }
    assert!(exact_hits > 4 * 400 && through_vertices_and_edges > 1000);
}

#[test]
fn wide_bvh_equals_binary_bvh_and_brute_force() {
    let mesh = placed(5, 1.0, DVec3::new(0.3, -0.2, 0.1));
    let n = mesh.triangle_count();
    let boxes: Vec<Aabb> = (0..n)
        .map(|s| {
            let [a, b, c] = mesh.triangle(s);
            Aabb {
                min: a.min(b).min(c),
                max: a.max(b).max(c),
            }
        })
        .collect();
    let binary = Bvh::build(&boxes);
    let mut rng = Rng(17);
    let mut hits = 0;
    for i in 0..3000 {
        let origin = rng.unit() * (0.1 + 3.0 * rng.next_f64());
        // Every fifth ray through a vertex (shared by five or six triangles).
        let dir = if i % 5 == 0 {
            (mesh.triangle(i % n)[0] - origin).normalize()
        } else {
            rng.unit()
        };
        let t_max = if i % 3 == 0 { 1.5 } else { f64::INFINITY };
        let ray = Ray::new(origin, dir, 1e-3 * rng.next_f64());
        let mut best: Option<(f64, usize)> = None;
        binary.traverse(
            &BoxRay::new(&ray),
            t_max,
            &mut TraversalCost::default(),
            |slot, tm| {
                let s = binary.order[slot] as usize;
                match triangle_t(&mesh.triangle(s), &ray) {
                    Some(t) if t > ray.t_min && t < tm => {
                        best = Some((t, s));
                        Visit::Continue(t)
                    }
                    _ => Visit::Continue(tm),
                }
            },
        );
        let brute = (0..n)
            .filter_map(|s| triangle_t(&mesh.triangle(s), &ray).map(|t| (t, s)))
            .filter(|&(t, _)| t > ray.t_min && t < t_max)
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let wide = mesh.intersect(&ray, t_max, &mut TraversalCost::default());
        assert_eq!(wide.map(|h| h.0), best.map(|h| h.0), "{ray:?}");
        assert_eq!(wide.map(|h| h.0), brute.map(|h| h.0), "{ray:?}");
        // Ties (shared edges and vertices) go to the lowest triangle index, whatever the order.
        assert_eq!(wide, brute, "{ray:?}");
        hits += usize::from(wide.is_some());
        let any = mesh.occludes(&ray, t_max, &mut TraversalCost::default());
        assert_eq!(any, brute.is_some());
    }
    assert!(hits > 1000, "{hits}");
}
