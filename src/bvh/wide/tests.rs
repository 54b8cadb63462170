//! Wide BVH unit tests: the collapse keeps every slot once, and the `f32` traversal never culls
//! a box the `f64` slab test enters (random rays, axis-parallel rays, rays in face planes, far
//! origins, large and small coordinates).

use super::build::LEAF_MAX;
use super::*;
use crate::bvh::{Aabb, BoxRay, Bvh};
use glam::DVec3;

/// SplitMix64 in [0, 1).
fn rng(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// `n` small random boxes in `centre +- scale`, some flat (zero extent on one axis).
fn boxes(n: usize, centre: DVec3, scale: f64, seed: u64) -> Vec<Aabb> {
    let mut s = seed;
    (0..n)
        .map(|i| {
            let p = centre + scale * DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s)) * 2.0
                - DVec3::splat(scale);
            let mut e = 0.05 * scale * DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s));
            e[i % 4 % 3] *= f64::from(u8::from(i % 4 != 0));
            Aabb { min: p, max: p + e }
        })
        .collect()
}

/// The slots of every group the traversal tests; checks that each was offered for prefetching
/// before its test.
fn visited(wide: &WideBvh, ray: &Ray, t_max: f64) -> Vec<u32> {
    let mut out = Vec::new();
    let warmed = std::cell::RefCell::new(Vec::new());
    if let Some(r) = wide.ray(ray, t_max) {
        wide.traverse(
            &r,
            t_max,
            &mut TraversalCost::default(),
            |g, t| {
                assert!(warmed.borrow().contains(&g), "group {g} tested before warm");
                let grp = wide.groups[g];
                out.extend(grp.first..grp.first + grp.count);
                Visit::Continue(t)
            },
            |g| warmed.borrow_mut().push(g),
        );
    }
    out
}

#[test]
fn groups_cover_every_slot_once() {
    for n in [1, 2, 5, 9, 100, 3000] {
        let bvh = Bvh::build(&boxes(n, DVec3::ZERO, 1.0, n as u64));
        let wide = WideBvh::from_binary(&bvh);
        let mut slots: Vec<u32> = wide
            .groups
            .iter()
            .inspect(|g| assert!((1..=GROUP as u32).contains(&g.count)))
            .flat_map(|g| g.first..g.first + g.count)
            .collect();
        slots.sort_unstable();
        assert_eq!(slots, (0..n as u32).collect::<Vec<_>>());
        assert!(wide.stack >= 1 && wide.node_count() * WIDTH >= n.div_ceil(LEAF_MAX as usize));
    }
    assert!(
        WideBvh::from_binary(&Bvh::build(&[]))
            .ray(&Ray::new(DVec3::ZERO, DVec3::X, 0.0), 1.0)
            .is_none()
    );
}

#[test]
fn f32_traversal_never_culls_a_box_the_f64_test_enters() {
    let mut s = 99;
    // (centre, scale, origin distance): ordinary, far from the origin, tiny, huge, and a ray
    // origin so far away that the query falls back to f64 boxes.
    let cases = [
        (DVec3::ZERO, 1.0, 3.0),
        (DVec3::new(1e4, -2e4, 5e3), 10.0, 40.0),
        (DVec3::splat(1e-6), 1e-7, 1e-6),
        (DVec3::ZERO, 1e15, 1e16),
        (DVec3::ZERO, 1.0, 1e12),
        (DVec3::ZERO, 1e20, 1e21),
    ];
    for (k, &(centre, scale, dist)) in cases.iter().enumerate() {
        let b = boxes(2000, centre, scale, k as u64);
        let bvh = Bvh::build(&b);
        let wide = WideBvh::from_binary(&bvh);
        let mut exact_queries = 0;
        for i in 0..600 {
            // Aim at a box corner or face centre (grazing), or at a random point.
            let target = match i % 3 {
                0 => b[i % b.len()].min,
                1 => b[i % b.len()].center(),
                _ => centre + scale * DVec3::new(rng(&mut s), rng(&mut s), rng(&mut s)),
            };
            let mut dir =
                DVec3::new(rng(&mut s) - 0.5, rng(&mut s) - 0.5, rng(&mut s) - 0.5).normalize();
            if i % 7 == 0 {
                dir = DVec3::Z; // axis-parallel: zero components, infinite reciprocals
            }
            let origin = target - dist * dir;
            let t_max = if i % 2 == 0 { f64::INFINITY } else { dist };
            let t_min = if i % 5 == 0 { f64::NEG_INFINITY } else { 0.0 };
            let ray = Ray::new(origin, dir, t_min);
            exact_queries += usize::from(wide.ray(&ray, t_max).is_some_and(|r| r.exact()));
            let got = visited(&wide, &ray, t_max);
            let box_ray = BoxRay::new(&ray);
            for (slot, &prim) in bvh.order.iter().enumerate() {
                let bb = b[prim as usize];
                let (lo, hi) = (bb.min.to_array().map(down), bb.max.to_array().map(up));
                if box_ray.enter(lo, hi, t_max).is_some() {
                    assert!(got.contains(&(slot as u32)), "case {k}, ray {i}: {ray:?}");
                }
            }
        }
        // The far origin and the huge boxes take the f64 path; the others stay in f32.
        assert_eq!(exact_queries > 0, k >= 4, "case {k}: {exact_queries}");
    }
}

#[test]
fn identical_boxes_beyond_one_leaf_are_split_and_all_visited() {
    // Issue 13: 61 identical triangles made one binary leaf of 61 slots, more than the 15
    // groups a wide leaf reference holds ("leaf of at most 15 groups").
    let b = Aabb {
        min: DVec3::ZERO,
        max: DVec3::ONE,
    };
    for n in [60, 61, 64, 240, 241, 961, 5000] {
        let bvh = Bvh::build(&vec![b; n]);
        let wide = WideBvh::from_binary(&bvh);
        let ray = Ray::new(DVec3::new(0.5, 0.5, -1.0), DVec3::Z, 0.0);
        let mut got = visited(&wide, &ray, f64::INFINITY);
        got.sort_unstable();
        assert_eq!(got, (0..n as u32).collect::<Vec<_>>(), "{n} boxes");
        let ray = Ray::new(DVec3::new(2.5, 0.5, -1.0), DVec3::Z, 0.0);
        assert!(visited(&wide, &ray, f64::INFINITY).is_empty(), "{n} boxes");
    }
}

mod duplicated_triangles {
    //! The wide BVH over meshes of duplicated, coplanar and sliver triangles (many sharing one
    //! centroid) answers exactly as a loop over every triangle.
    use crate::bvh::TraversalCost;
    use crate::geometry::triangle_t;
    use crate::math::Ray;
    use crate::mesh::{Mesh, MeshNormals, parse_obj};
    use glam::{DAffine3, DVec3};
    use proptest::prelude::*;
    use std::fmt::Write;

    /// An OBJ of `shapes` triangles, each written `copies` times (and a sliver: its third
    /// vertex moved `sliver` towards the midpoint of the first two).
    fn obj(shapes: &[([f64; 9], usize)], sliver: f64) -> String {
        let mut s = String::new();
        let mut v = 0;
        for (p, copies) in shapes {
            for c in 0..*copies {
                let mut q = *p;
                if c % 3 == 2 {
                    for a in 0..3 {
                        let mid = 0.5 * (p[a] + p[3 + a]);
                        q[6 + a] = p[6 + a] + sliver * (mid - p[6 + a]);
                    }
                }
                for k in 0..3 {
                    writeln!(s, "v {} {} {}", q[3 * k], q[3 * k + 1], q[3 * k + 2]).unwrap();
                }
                writeln!(s, "f {} {} {}", v + 1, v + 2, v + 3).unwrap();
                v += 3;
            }
        }
        s
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn wide_bvh_equals_brute_force(
            shapes in prop::collection::vec(
                (prop::array::uniform9(-1.0f64..1.0), 1usize..200), 1..5),
            sliver in prop_oneof![Just(0.0), Just(1.0 - 1e-9), 0.0f64..1.0],
            rays in prop::collection::vec(
                (prop::array::uniform3(-3.0f64..3.0), prop::array::uniform3(-1.0f64..1.0)),
                40),
        ) {
            let data = parse_obj(&obj(&shapes, sliver)).unwrap();
            let Some(mesh) = Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::Flat) else {
                return Ok(()); // every triangle had zero area
            };
            for (o, d) in rays {
                let Some(dir) = DVec3::from(d).try_normalize() else { continue };
                // Aim at a triangle's centroid half the time (many hits, many ties).
                let tri = mesh.triangle(0);
                let origin = DVec3::from(o);
                let dir = if d[0] > 0.0 {
                    ((tri[0] + tri[1] + tri[2]) / 3.0 - origin).try_normalize().unwrap_or(dir)
                } else {
                    dir
                };
                let ray = Ray::new(origin, dir, 0.0);
                let brute = (0..mesh.triangle_count())
                    .filter_map(|i| triangle_t(&mesh.triangle(i), &ray).map(|t| (t, i)))
                    .filter(|&(t, _)| t > 0.0)
                    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let cost = &mut TraversalCost::default();
                prop_assert_eq!(mesh.intersect(&ray, f64::INFINITY, cost), brute);
                prop_assert_eq!(mesh.occludes(&ray, f64::INFINITY, cost), brute.is_some());
                let line = Ray::new(origin, dir, f64::NEG_INFINITY);
                let mut all: Vec<f64> = (0..mesh.triangle_count())
                    .filter_map(|i| triangle_t(&mesh.triangle(i), &line))
                    .collect();
                // Merged as `Mesh::crossings` documents (duplicates are one crossing).
                all.sort_by(f64::total_cmp);
                all.dedup_by(|b, a| (*b - *a) <= 1e-9 * a.abs().max(b.abs()).max(1.0));
                prop_assert_eq!(mesh.crossings(&ray, cost), all);
            }
        }
    }
}
