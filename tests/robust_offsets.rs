//! Self-intersection and precision at extreme scales, after pbrt-v4's `shapes_test.cpp`
//! Reintersect tests: seeded random shapes at scales 1e-8..1e8 (zero re-hits), whole scenes
//! moved to 1e4..1e6, tiny and huge spheres far from the origin, a watertight triangle fan and
//! rays that start on a surface.

mod common;
use common::Rng;
use glam::DVec3;
use raytree::SceneIntegrator;
use raytree::geometry::Shape;
use raytree::integrator::offset::robust_origin;
use raytree::math::Ray;
use raytree::render::RenderOptions;
use raytree::scene::{OffsetStrategy, transformed};
use raytree::{Scene, render};

impl Rng {
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn log_scale(&mut self) -> f64 {
        10f64.powf(self.range(-8.0, 8.0))
    }
    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if let Some(u) = v.try_normalize().filter(|_| v.length() <= 1.0) {
                return u;
            }
        }
    }
}

fn random_shape(rng: &mut Rng, kind: u32) -> Shape {
    let s = rng.log_scale();
    let c = rng.unit() * rng.log_scale();
    match kind {
        0 => Shape::Sphere {
            center: c,
            radius: s,
        },
        1 => {
            let v = [c + rng.unit() * s, c + rng.unit() * s, c + rng.unit() * s];
            let normal = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
            Shape::Triangle {
                vertices: v,
                normal,
            }
        }
        2 => Shape::Box {
            min: c - s * DVec3::new(
                rng.range(0.1, 1.0),
                rng.range(0.1, 1.0),
                rng.range(0.1, 1.0),
            ),
            max: c + s * DVec3::new(rng.range(0.1, 1.0), 0.5, 1.0),
        },
        _ => Shape::Plane {
            point: c,
            normal: rng.unit(),
        },
    }
}

/// pbrt-v4 `Sphere.Reintersect` / `Triangle.Reintersect`, for every shape: hit a random shape
/// at a random scale from a random origin, spawn a robust ray in a random direction from the
/// hit, and require that it never meets the same surface at the spawn point again.
#[test]
fn robust_offset_never_reintersects_random_shapes_at_scales_1e_8_to_1e8() {
    let mut rng = Rng(0x5eed);
    let mut hits = 0;
    for i in 0..4000u32 {
        let shape = random_shape(&mut rng, i % 4);
        let bounds = shape.bounds().map_or(DVec3::ZERO, |(a, b)| 0.5 * (a + b));
        let target = bounds + rng.unit() * rng.log_scale() * 1e-3;
        let origin = target + rng.unit() * rng.log_scale();
        let ray = Ray::new(origin, (target - origin).normalize(), 0.0);
        let Some(h) = shape.intersect(&ray, f64::INFINITY) else {
            continue;
        };
        hits += 1;
        let p = ray.at(h.t);
        for _ in 0..8 {
            let mut w = rng.unit();
            let side = if w.dot(h.normal) > 0.0 {
                h.normal
            } else {
                -h.normal
            };
            if w.dot(side).abs() < 1e-12 {
                w = side;
            }
            let spawned = Ray::new(robust_origin(&shape, p, side), w, 0.0);
            if let Some(again) = shape.intersect(&spawned, f64::INFINITY) {
                let d = (spawned.at(again.t) - p).length();
                assert!(
                    d > shape.self_hit_radius(),
                    "case {i}: {shape:?} re-hit at {d:e} from {p}"
                );
            }
        }
    }
    assert!(hits > 1500, "only {hits} hits");
}

fn small(mut s: Scene, w: u32, h: u32) -> Scene {
    s.camera = s.camera.with_size(w, h);
    s
}

#[test]
fn whole_scenes_moved_to_1e4_to_1e6_stay_clean_with_the_robust_offset() {
    let mut base = small(Scene::default_scene(), 32, 24);
    base.settings.offset.strategy = OffsetStrategy::Robust;
    let (reference, _, _) =
        render(&SceneIntegrator::new(&base), &RenderOptions::new(), &|_| {}).into_parts();
    for shift in [1e4, 1e5, 1e6] {
        let moved = transformed(&base, 1.0, DVec3::new(shift, -shift, shift));
        let (img, stats, _) = render(
            &SceneIntegrator::new(&moved),
            &RenderOptions::diagnosed(),
            &|_| {},
        )
        .into_parts();
        assert_eq!(
            (stats.rays.self_hits, stats.rays.leaks),
            (0, 0),
            "shift {shift}"
        );
        assert_eq!(stats.nonfinite_pixels, 0);
        // The checker pattern is anchored in world space; compare the sky and balls only.
        let same = img
            .pixels
            .iter()
            .zip(&reference.pixels)
            .filter(|(a, b)| (**a - **b).abs().max_element() < 1e-3)
            .count();
        assert!(
            same * 10 > img.pixels.len() * 3,
            "shift {shift}: {same} equal pixels"
        );
    }
    // The lecture's fixed epsilon is not clean there: acne at 1e6 with eps 1e-9.
    let mut normal = transformed(&base, 1.0, DVec3::splat(1e6));
    normal.settings.offset.strategy = OffsetStrategy::Normal;
    normal.settings.offset.epsilon = 1e-12;
    let (_, stats, _) = render(
        &SceneIntegrator::new(&normal),
        &RenderOptions::diagnosed(),
        &|_| {},
    )
    .into_parts();
    assert!(stats.rays.self_hits > 0);
}

#[test]
fn tiny_and_huge_spheres_far_from_the_origin() {
    for (r, c) in [(1e-6, 1e5), (1e-3, 1e7), (1e6, -1e7)] {
        let s = Shape::Sphere {
            center: DVec3::new(c, 0.0, 0.0),
            radius: r,
        };
        let o = DVec3::new(c, 0.0, 0.0) - DVec3::new(0.0, 0.0, 3.0 * r);
        let h = s
            .intersect(&Ray::new(o, DVec3::Z, 0.0), f64::INFINITY)
            .unwrap();
        assert!(
            (h.t - 2.0 * r).abs() <= 1e-9 * r.max(c.abs()),
            "r {r} c {c}: t {}",
            h.t
        );
        let p = o + DVec3::Z * h.t;
        let inside = robust_origin(&s, p, -h.normal);
        let far = s
            .intersect(&Ray::new(inside, DVec3::Z, 0.0), f64::INFINITY)
            .unwrap();
        assert!(
            (far.t - 2.0 * r).abs() <= 1e-6 * r.max(c.abs() * 1e-9),
            "far side {}",
            far.t
        );
    }
}

#[test]
fn triangles_sharing_edges_and_vertices_are_watertight() {
    // A fan of 8 triangles around a shared centre vertex, at an awkward offset and scale.
    let c = DVec3::new(1234.567, -89.1, 0.3);
    let ring: Vec<DVec3> = (0..8)
        .map(|k| {
            let a = f64::from(k) * std::f64::consts::TAU / 8.0 + 0.1;
            c + DVec3::new(a.cos(), a.sin(), 0.01 * f64::from(k % 3)) * 3.7
        })
        .collect();
    let tris: Vec<Shape> = (0..8)
        .map(|k| {
            let v = [c, ring[k], ring[(k + 1) % 8]];
            let normal = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
            Shape::Triangle {
                vertices: v,
                normal,
            }
        })
        .collect();
    let mut rng = Rng(7);
    let mut misses = 0;
    for i in 0..20_000 {
        let k = i % 8;
        // A point exactly on an edge shared by two triangles, or the shared vertex.
        let u = if i % 50 == 0 { 0.0 } else { rng.next() };
        let target = c + (ring[k] - c) * u;
        let origin = target
            + DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(0.2, 1.0),
            ) * 10.0;
        let ray = Ray::new(origin, target - origin, 0.0);
        if tris
            .iter()
            .all(|t| t.intersect(&ray, f64::INFINITY).is_none())
        {
            misses += 1;
        }
    }
    assert_eq!(misses, 0, "rays passed between neighbouring triangles");
}

#[test]
fn rays_that_start_on_a_surface() {
    let s = Shape::Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    };
    let p = DVec3::new(0.0, 0.6, 0.8);
    // Outward from the surface: nothing (t = 0 is not accepted).
    assert!(
        s.intersect(&Ray::new(p, p, 0.0), f64::INFINITY)
            .is_none_or(|h| h.t < 1e-12)
    );
    // Inward: the far side, at the chord length 2.
    let h = s.intersect(&Ray::new(p, -p, 0.0), f64::INFINITY).unwrap();
    assert!((h.t - 2.0).abs() < 1e-12 && h.normal.dot(p) < 0.0);
    let plane = Shape::Plane {
        point: DVec3::ZERO,
        normal: DVec3::Y,
    };
    assert!(
        plane
            .intersect(&Ray::new(DVec3::ZERO, DVec3::Y, 0.0), f64::INFINITY)
            .is_none()
    );
    assert!(
        plane
            .intersect(&Ray::new(DVec3::ZERO, DVec3::X, 0.0), f64::INFINITY)
            .is_none()
    );
}
