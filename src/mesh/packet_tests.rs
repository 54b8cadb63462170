//! Packets of rays get exactly the single ray's answers: coherent tiles, random rays, rays
//! through shared vertices and edges (ties), per-ray limits and `t_min`, packets of every size,
//! and rays that take the `f64` box test mixed with `f32` ones.

use super::filter_tests::placed;
use super::tests::Rng;
use super::*;
use crate::bvh::TraversalCost;
use crate::bvh::wide::PACKET;
use crate::math::Ray;

/// The packet's answers against one `Mesh::intersect` per ray; returns the hits.
fn check(mesh: &Mesh, rays: &[Ray], t_max: &[f64]) -> usize {
    let mut out = vec![Some((-1.0, usize::MAX)); rays.len()];
    let mut cost = vec![TraversalCost::default(); rays.len()];
    mesh.intersect_packet(rays, t_max, &mut out, &mut cost);
    let mut hits = 0;
    for (i, ray) in rays.iter().enumerate() {
        let mut single = TraversalCost::default();
        let want = mesh.intersect(ray, t_max[i], &mut single);
        assert_eq!(
            out[i],
            want,
            "ray {i} of {}: {ray:?} t_max {}",
            rays.len(),
            t_max[i]
        );
        // The packet tests the same triangle packs, in its own order.
        assert!(cost[i].nodes >= 1 && (want.is_none() || cost[i].prims >= 1));
        hits += usize::from(want.is_some());
    }
    // Any-hit: the same rays and limits, against `Mesh::occludes` per ray.
    let mut blocked = vec![false; rays.len()];
    mesh.occludes_packet(rays, t_max, &mut blocked);
    for (i, ray) in rays.iter().enumerate() {
        let want = mesh.occludes(ray, t_max[i], &mut TraversalCost::default());
        assert_eq!(
            blocked[i], want,
            "occludes, ray {i}: {ray:?} t_max {}",
            t_max[i]
        );
    }
    hits
}

#[test]
fn shadow_packets_equal_single_shadow_rays() {
    // Shadow rays from points on the mesh (offset along the normal, some not) towards lights
    // in and around it, limited to the light's distance: blocked and free ones in one packet.
    let mesh = placed(3, 1.0, DVec3::ZERO);
    let n = mesh.triangle_count();
    let mut rng = Rng(5);
    let (mut blocked, mut free) = (0, 0);
    for round in 0..60 {
        let light = rng.unit() * [0.5, 2.0, 6.0][round % 3];
        let first = (round * 37) % n;
        let mut rays = Vec::new();
        let mut t_max = Vec::new();
        for i in 0..[PACKET, 5, 40][round % 3] {
            let [a, b, c] = mesh.triangle((first + i) % n);
            let p = (a + b + c) / 3.0;
            let lift = if i % 2 == 0 { 1e-6 } else { 0.0 };
            let origin = p + lift * mesh.geometric_normal((first + i) % n);
            let to = light - origin;
            rays.push(Ray::new(origin, to.normalize(), 0.0));
            t_max.push(to.length());
        }
        let mut got = vec![false; rays.len()];
        mesh.occludes_packet(&rays, &t_max, &mut got);
        for (i, ray) in rays.iter().enumerate() {
            let want = mesh.occludes(ray, t_max[i], &mut TraversalCost::default());
            assert_eq!(got[i], want, "round {round} ray {i}");
            (blocked, free) = if want {
                (blocked + 1, free)
            } else {
                (blocked, free + 1)
            };
        }
    }
    assert!(
        blocked > 300 && free > 300,
        "{blocked} blocked, {free} free"
    );
}

#[test]
fn packet_hits_equal_single_ray_hits() {
    let mut rng = Rng(11);
    let mut hits = 0;
    let mut ties = 0;
    for (scale, translate) in [
        (1.0, DVec3::ZERO),
        (1e-4, DVec3::splat(3e-4)),
        (1e5, DVec3::new(2e5, 0.0, -1e5)),
    ] {
        let mesh = placed(4, scale, translate);
        let n = mesh.triangle_count();
        for round in 0..40 {
            // Every other round from off the axes, so that a whole tile shares its direction
            // signs and the packet takes the interval test at the upper levels.
            let eye = if round % 2 == 0 {
                translate + DVec3::new(0.2, 0.1, 3.0) * scale
            } else {
                translate + DVec3::new(2.5, 1.5, 3.0) * scale
            };
            let len = [PACKET, 1, 7, 33][round % 4];
            let mut rays = Vec::new();
            let mut t_max = Vec::new();
            for i in 0..len {
                let ray = match (round / 4) % 5 {
                    // A coherent tile of camera rays.
                    0 | 1 => {
                        let (u, v) = ((i % 8) as f64, (i / 8) as f64);
                        let at = translate
                            + scale
                                * DVec3::new(
                                    u / 6.0 - 0.6 + 0.01 * round as f64,
                                    0.6 - v / 6.0,
                                    0.0,
                                );
                        Ray::new(eye, (at - eye).normalize(), 0.0)
                    }
                    // Through a vertex or an edge midpoint of some triangle: ties.
                    2 | 3 => {
                        let [a, b, _] = mesh.triangle((round * 97 + i * 13) % n);
                        let target = if i % 2 == 0 { a } else { 0.5 * (a + b) };
                        ties += 1;
                        Ray::new(eye, (target - eye).normalize(), 0.0)
                    }
                    // Random, with random t_min, origins inside and outside.
                    _ => {
                        let origin = translate + rng.unit() * scale * (0.1 + 3.0 * rng.next_f64());
                        Ray::new(origin, rng.unit(), scale * 1e-3 * rng.next_f64())
                    }
                };
                t_max.push(if i % 3 == 1 {
                    2.9 * scale
                } else {
                    f64::INFINITY
                });
                rays.push(ray);
            }
            if round % 10 == 9 {
                // A ray from so far away that its boxes are tested in f64.
                let far = translate + DVec3::new(1e12, 3.0, -2.0) * scale;
                rays[0] = Ray::new(far, (translate - far).normalize(), 0.0);
                assert!(mesh.bvh.ray(&rays[0], f64::INFINITY).unwrap().exact());
            }
            hits += check(&mesh, &rays, &t_max);
        }
    }
    assert!(hits > 2000 && ties > 1000, "{hits} hits, {ties} tie rays");
}

#[test]
fn empty_and_missing_packets() {
    let mesh = placed(2, 1.0, DVec3::ZERO);
    assert_eq!(check(&mesh, &[], &[]), 0);
    // Every ray misses the root box, or has a zero direction.
    let away = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::Z, 0.0);
    let zero = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 0.0);
    assert_eq!(check(&mesh, &[away, zero, away], &[f64::INFINITY; 3]), 0);
}
