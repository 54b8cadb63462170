//! Hard cases that must stay numerically stable. Models: pbrt-v4's `shapes_test.cpp`
//! Reintersect tests (seeded random shapes at scales 1e-8..1e8, zero re-hits) and Mitsuba 3's
//! `test_fresnel.py` (normal, Brewster, critical and grazing incidence from both sides).

use glam::DVec3;
use proptest::prelude::*;
use raytree::check::tree_violations;
use raytree::geometry::Shape;
use raytree::math::{
    FresnelModel, Ray, Rgb, beer, brewster_angle, critical_angle, fresnel, fresnel_exact, reflect,
    refract,
};
use raytree::scene::{OffsetStrategy, transformed};
use raytree::trace::offset::robust_origin;
use raytree::tree::{EndReason, RayKind};
use raytree::{Scene, render, render_diagnosed, trace_pixel};

const IORS: [(f64, f64); 4] = [(1.0, 1.5), (1.5, 1.0), (1.0, 1.333), (1.333, 1.5)];

fn incident(theta: f64) -> DVec3 {
    DVec3::new(theta.sin(), -theta.cos(), 0.0)
}

fn exact(n1: f64, n2: f64, theta: f64) -> Option<(f64, f64, f64)> {
    let t = refract(incident(theta), DVec3::Y, n1 / n2)?;
    let (rs, rp) = fresnel_exact(n1, n2, theta.cos(), t.cos_t);
    Some((
        rs,
        rp,
        fresnel(FresnelModel::Exact, n1, n2, theta.cos(), t.cos_t).r,
    ))
}

#[test]
fn normal_incidence_from_both_sides() {
    for (n1, n2) in IORS {
        let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
        let (rs, rp, r) = exact(n1, n2, 0.0).unwrap();
        assert!((rs - r0).abs() < 1e-15 && (rp - r0).abs() < 1e-15 && (r - r0).abs() < 1e-15);
        let t = refract(-DVec3::Y, DVec3::Y, n1 / n2).unwrap();
        assert_eq!(t.direction, -DVec3::Y);
    }
}

#[test]
fn brewster_angle_from_both_sides_has_zero_rp() {
    for (n1, n2) in IORS {
        let (rs, rp, _) = exact(n1, n2, brewster_angle(n1, n2)).unwrap();
        assert!(rp < 1e-15, "{n1}->{n2}: rp {rp}");
        assert!(rs > 0.0);
    }
}

#[test]
fn critical_angle_is_the_edge_of_total_internal_reflection() {
    for (n1, n2) in [(1.5, 1.0), (1.333, 1.0), (1.5, 1.333)] {
        let c = critical_angle(n1, n2).unwrap();
        let below = exact(n1, n2, c - 1e-9).unwrap();
        assert!(below.2 < 1.0 && below.2 > 0.99, "{below:?}");
        assert!(refract(incident(c + 1e-9), DVec3::Y, n1 / n2).is_none());
        // Exactly at the critical angle: either TIR or a grazing transmission with R = 1.
        match refract(incident(c), DVec3::Y, n1 / n2) {
            None => {}
            Some(t) => {
                assert!(t.cos_t < 1e-7 && t.direction.is_finite());
                let f = fresnel(FresnelModel::Exact, n1, n2, c.cos(), t.cos_t);
                assert!(f.r > 0.999 && f.r <= 1.0 && (f.r + f.t - 1.0).abs() < 1e-15);
            }
        }
    }
    assert_eq!(critical_angle(1.0, 1.5), None);
}

#[test]
fn grazing_incidence_reflects_everything_without_nan() {
    for (n1, n2) in IORS {
        for model in [FresnelModel::Exact, FresnelModel::Schlick] {
            let cos_t = refract(incident(std::f64::consts::FRAC_PI_2), DVec3::Y, n1 / n2)
                .map_or(0.0, |t| t.cos_t);
            let f = fresnel(model, n1, n2, 0.0, cos_t);
            assert!(
                f.r.is_finite() && (f.r - 1.0).abs() < 1e-12,
                "{model:?} {n1}->{n2}: {f:?}"
            );
        }
    }
}

#[test]
fn index_matched_interface_is_invisible() {
    for theta in [0.0, 0.3, 1.0, 1.5] {
        let d = incident(theta);
        let t = refract(d, DVec3::Y, 1.0).unwrap();
        assert!((t.direction - d).length() < 1e-15);
        let f = fresnel(FresnelModel::Exact, 1.333, 1.333, theta.cos(), t.cos_t);
        assert!(f.r < 1e-20 && (f.r + f.t - 1.0).abs() < 1e-15, "{f:?}");
    }
}

#[test]
fn cosines_rounding_above_one_stay_in_range() {
    // A direction a hair longer than unit: -n.d rounds above 1.
    let d = -DVec3::Y * (1.0 + 2.0 * f64::EPSILON);
    assert!(-d.dot(DVec3::Y) > 1.0);
    for (n1, n2) in IORS {
        let t = refract(d, DVec3::Y, n1 / n2).unwrap();
        assert!(t.cos_t <= 1.0 && t.direction.is_finite());
        for cos_i in [1.0 + f64::EPSILON, 1.0] {
            let f = fresnel(FresnelModel::Exact, n1, n2, cos_i.min(1.0), t.cos_t);
            assert!((0.0..=1.0).contains(&f.r), "{f:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Random interfaces: R in [0, 1], R + T = 1, unit directions and Snell's law.
    #[test]
    fn fresnel_and_snell_sweep(n1 in 1.0f64..3.0, n2 in 1.0f64..3.0, theta in 0.0..std::f64::consts::FRAC_PI_2, phi in 0.0..std::f64::consts::TAU) {
        let d = DVec3::new(theta.sin() * phi.cos(), -theta.cos(), theta.sin() * phi.sin());
        let r = reflect(d, DVec3::Y);
        prop_assert!((r.length() - 1.0).abs() < 1e-14);
        if let Some(t) = refract(d, DVec3::Y, n1 / n2) {
            prop_assert!((t.direction.length() - 1.0).abs() < 1e-14);
            let sin_t = t.direction.cross(DVec3::Y).length();
            prop_assert!((n1 * theta.sin() - n2 * sin_t).abs() < 1e-12);
            for model in [FresnelModel::Exact, FresnelModel::Schlick] {
                let f = fresnel(model, n1, n2, theta.cos(), t.cos_t);
                prop_assert!((0.0..=1.0).contains(&f.r) && (f.r + f.t - 1.0).abs() < 1e-15);
            }
        } else {
            prop_assert!(n1 > n2 && n1 * theta.sin() > n2 * (1.0 - 1e-12));
        }
    }

    /// Intersections do not assume unit directions: the hit point is the same.
    #[test]
    fn unnormalized_directions_hit_the_same_point(len in 1e-3f64..1e3, x in -0.1f64..0.1, y in -0.1f64..0.1) {
        let dir = DVec3::new(x, y, 1.0).normalize();
        let o = DVec3::new(0.0, 0.0, -5.0);
        for shape in [
            Shape::Sphere { center: DVec3::ZERO, radius: 1.0 },
            Shape::Triangle { vertices: [DVec3::new(-2.0, -2.0, 0.0), DVec3::new(2.0, -2.0, 0.0), DVec3::new(0.0, 2.0, 0.0)], normal: -DVec3::Z },
            Shape::Box { min: DVec3::splat(-1.0), max: DVec3::splat(1.0) },
        ] {
            let a = shape.intersect(&Ray::new(o, dir, 0.0), f64::INFINITY).unwrap();
            let b = shape.intersect(&Ray::new(o, dir * len, 0.0), f64::INFINITY).unwrap();
            let (pa, pb) = (o + dir * a.t, o + dir * len * b.t);
            prop_assert!((pa - pb).length() < 1e-12, "{shape:?}: {pa} vs {pb}");
        }
    }
}

/// SplitMix64: deterministic random numbers for the seeded loops.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
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
    let (reference, _) = render(&base, &|_| {});
    for shift in [1e4, 1e5, 1e6] {
        let moved = transformed(&base, 1.0, DVec3::new(shift, -shift, shift));
        let (img, stats, _) = render_diagnosed(&moved, &|_| {});
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
    let (_, stats, _) = render_diagnosed(&normal, &|_| {});
    assert!(stats.rays.self_hits > 0);
}

fn scene(materials: &str, objects: &str, settings: &str) -> Scene {
    Scene::from_json(&format!(
        r#"{{"camera": {{"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30, "width": 9, "height": 9}},
            "background": [1, 1, 1], "materials": {{{materials}}}, "objects": [{objects}],
            "lights": [{{"type": "point", "position": [0, 5, 5], "intensity": [10, 10, 10]}}],
            "settings": {{{settings}}}}}"#
    ))
    .unwrap()
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
fn thin_shell_is_not_skipped_by_the_robust_offset_but_is_by_a_large_epsilon() {
    let mats = r#""glass": {"transmissivity": [1, 1, 1], "ior": 1.5}"#;
    let objs = r#"{"type": "box", "name": "shell", "min": [-1, -1, -1e-7], "max": [1, 1, 1e-7], "material": "glass"}"#;
    let robust = scene(mats, objs, r#""offset": {"strategy": "robust"}"#);
    let (_, st, _) = render_diagnosed(&robust, &|_| {});
    assert_eq!((st.rays.self_hits, st.rays.leaks), (0, 0));
    assert!(st.rays.refracted > 0);
    let coarse = scene(
        mats,
        objs,
        r#""offset": {"strategy": "normal", "epsilon": 1e-4}"#,
    );
    let (_, st, _) = render_diagnosed(&coarse, &|_| {});
    assert!(st.rays.leaks > 0, "a 1e-4 offset must jump the 2e-7 shell");
    let tree = trace_pixel(&coarse, 4, 4).unwrap();
    let leak = tree.nodes.iter().find_map(|n| n.leak.as_ref()).unwrap();
    assert_eq!(leak.object_name, "shell");
    assert!(raytree::text::tree_text(&tree).contains("LEAK (offset skipped shell"));
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
fn beer_law_limits_give_no_nan() {
    let c = Rgb::new(0.5, 0.0, 2.0);
    assert_eq!(beer(c, 0.0), Rgb::ONE);
    assert_eq!(beer(Rgb::ZERO, f64::INFINITY), Rgb::ONE);
    assert_eq!(beer(c, f64::INFINITY), Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(beer(Rgb::ZERO, 0.0), Rgb::ONE);
}

#[test]
fn nested_dielectrics_record_glass_in_water() {
    let mut s = Scene::from_json(include_str!("../fixtures/nested.json")).unwrap();
    s.camera = s.camera.with_size(64, 36);
    let mut found = false;
    for x in 28..36 {
        let tree = trace_pixel(&s, x, 16).unwrap();
        assert!(tree_violations(&tree, s.background).is_empty());
        found |= tree
            .nodes
            .iter()
            .filter_map(|n| n.interface.as_ref())
            .any(|i| (i.n1 - 1.333).abs() < 1e-12 && (i.n2 - 1.5).abs() < 1e-12);
    }
    assert!(found, "no water -> glass interface recorded");
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

#[test]
fn long_tir_chain_ends_exactly_at_max_depth() {
    // Inside a glass block seen through its top at a steep angle, light bounces by total
    // internal reflection until max_depth cuts it.
    let mut s = Scene::from_json(include_str!("../fixtures/tir-block.json")).unwrap();
    s.camera = s.camera.with_size(48, 27);
    for max_depth in [3, 7, 16] {
        s.settings.max_depth = max_depth;
        let (mut tir, mut deepest) = (0, 0);
        for (x, y) in [(10, 14), (24, 14), (38, 14), (24, 20)] {
            let tree = trace_pixel(&s, x, y).unwrap();
            assert!(tree_violations(&tree, s.background).is_empty());
            assert!(tree.nodes.iter().all(|n| n.depth <= max_depth));
            tir += tree
                .nodes
                .iter()
                .filter(|n| n.interface.as_ref().is_some_and(|i| i.tir))
                .count();
            for n in tree.nodes.iter().filter(|n| n.end == EndReason::MaxDepth) {
                assert_eq!(n.depth, max_depth);
                assert!(n.truncated.max_element() > 0.0);
            }
            let d = tree
                .nodes
                .iter()
                .filter(|n| n.kind != RayKind::Shadow)
                .map(|n| n.depth);
            deepest = deepest.max(d.max().unwrap_or(0));
        }
        assert_eq!(deepest, max_depth, "the chain must reach max_depth exactly");
        assert!(tir > 0, "max_depth {max_depth}: no TIR seen");
    }
}

#[test]
fn no_nan_or_infinity_reaches_an_image() {
    // Two emitters of the largest finite radiance, one seen through the other: their sum
    // overflows to infinity.
    let s = scene(
        r#""hot": {"emission": [1.7e308, 1.7e308, 1.7e308], "transmissivity": [1, 1, 1]},
           "hotter": {"emission": [1.7e308, 1.7e308, 1.7e308]}"#,
        r#"{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "hot"},
           {"type": "sphere", "center": [0, 0, -4], "radius": 2, "material": "hotter"}"#,
        "",
    );
    let (img, stats) = render(&s, &|_| {});
    assert!(img.pixels.iter().all(|p| p.is_finite()));
    assert!(stats.nonfinite_pixels > 0);
    let (x, y) = stats.first_nonfinite.unwrap();
    let tree = trace_pixel(&s, x, y).unwrap();
    assert!(!tree.radiance.is_finite());
}
