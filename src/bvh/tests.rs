//! BVH unit tests: build invariants, traversal against brute force, the slab test.

use super::*;

fn boxes(n: usize) -> Vec<Aabb> {
    (0..n)
        .map(|i| {
            let p = DVec3::new((i % 7) as f64, (i / 7 % 5) as f64, (i * 13 % 11) as f64);
            Aabb {
                min: p,
                max: p + 0.5,
            }
        })
        .collect()
}

#[test]
fn every_primitive_is_in_exactly_one_leaf() {
    for n in [0, 1, 2, 9, 100, 1000] {
        let bvh = Bvh::build(&boxes(n));
        let mut seen = bvh.order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n as u32).collect::<Vec<_>>());
        let covered: u32 = bvh.nodes.iter().map(|n| n.count).sum();
        assert_eq!(covered as usize, n);
    }
}

#[test]
fn identical_boxes_make_one_leaf() {
    let b = vec![
        Aabb {
            min: DVec3::ZERO,
            max: DVec3::ONE
        };
        50
    ];
    let bvh = Bvh::build(&b);
    assert_eq!(bvh.node_count(), 1);
}

#[test]
fn traversal_finds_boxes_on_the_ray_and_counts_cost() {
    let b = boxes(200);
    let bvh = Bvh::build(&b);
    let ray = Ray::new(DVec3::new(-1.0, 0.25, 0.25), DVec3::X, 0.0);
    let mut found = Vec::new();
    let mut cost = TraversalCost::default();
    bvh.traverse(&BoxRay::new(&ray), f64::INFINITY, &mut cost, |slot, t| {
        found.push(bvh.order[slot]);
        Visit::Continue(t)
    });
    found.sort_unstable();
    let expect: Vec<u32> = (0..200u32)
        .filter(|&i| {
            let bb = b[i as usize];
            bb.min.y <= 0.25 && bb.max.y >= 0.25 && bb.min.z <= 0.25 && bb.max.z >= 0.25
        })
        .collect();
    assert_eq!(found, expect);
    assert_eq!(cost.prims as usize, found.len());
    assert!(cost.nodes >= 1 && (cost.nodes as usize) < bvh.node_count() + 1);
}

#[test]
fn ray_in_a_face_plane_counts_as_inside() {
    let r = BoxRay::new(&Ray::new(DVec3::new(-1.0, 0.0, 0.5), DVec3::X, 0.0));
    assert_eq!(r.enter([0.0; 3], [1.0; 3], f64::INFINITY), Some(1.0));
    assert!(f64::from(down(0.1)) <= 0.1 && f64::from(up(0.1)) >= 0.1);
    assert_eq!((down(1e300), up(-1e300)), (f32::MAX, f32::MIN));
}
