//! Tests of the automatic min-weight bound.
use super::*;

fn scene(extra: &str) -> Scene {
    let src = format!(
        r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40,
             "width": 4, "height": 3}},
           "background": [0.1, 0.1, 0.1], "ambient": [0, 0, 0],
           "materials": {{"m": {{"diffuse": [0.5, 0.5, 0.5]}},
                         "g": {{"transmissivity": [0.9, 0.9, 0.9], "ior": 1.5}}}},
           "objects": [{{"type": "plane", "point": [0,-1,0], "normal": [0,1,0],
                         "material": "m"}},
                       {{"type": "sphere", "center": [0,0,0], "radius": 1,
                         "material": "g"}}],
           "lights": [{{"type": "point", "position": [0,3,0], "intensity": [8,8,8]}}]
           {extra}}}"#
    );
    Scene::from_json(&src).unwrap()
}

/// Sampled area lights add their expected direct light to the bound:
/// `(max albedo + pi max specular) x max emission` (pbrt's `E <= pi L_max` over the hemisphere).
#[test]
fn sampled_area_lights_raise_the_bound_by_their_direct_light() {
    let src = include_str!("../../../../fixtures/soft-shadows.json");
    let mut s = Scene::from_json(src).unwrap();
    assert!(s.settings.whitted.light_samples.is_some());
    let on = radiance_bound(&s, 0, ShadowMode::Opaque);
    s.settings.whitted.light_samples = None;
    let off = radiance_bound(&s, 0, ShadowMode::Opaque);
    // The fixture: emission 10 (max channel), albedo 0.8, specular 0.3.
    let expect = (0.8 + std::f64::consts::PI * 0.3) * 10.0;
    assert!((on - off - expect).abs() < 1e-9 * on, "on {on}, off {off}");
}

#[test]
fn the_bound_follows_the_closed_form() {
    let s = scene("");
    // Nearest surface to the light: the sphere, 3 - 1 = 2 away: E <= 8 / 4 = 2; local
    // <= (0.5 / pi + 0) * 2; s = 0.9; 16 bounces.
    let local = 0.5 / std::f64::consts::PI * 2.0;
    let sum = (1.0 - 0.9f64.powi(17)) / 0.1;
    let b = radiance_bound(&s, 16, ShadowMode::Opaque);
    assert!((b - local * sum).abs() < 1e-12, "{b}");
    let w = auto_min_weight(&s, &s.settings);
    assert!(
        (w - (1.0 / 510.0) / (12.92 * local * sum)).abs() < 1e-15,
        "{w}"
    );
    assert_eq!(effective_min_weight(&s), w);
}

#[test]
fn exhaustive_and_unbounded_cases_cut_nothing() {
    let s = scene(r#", "settings": {"min_weight": 0}"#);
    assert_eq!(effective_min_weight(&s), 0.0);
    let s = scene(r#", "settings": {"tolerance": 0}"#);
    assert_eq!(effective_min_weight(&s), 0.0);
    // A light on the plane: irradiance without bound.
    let mut s = scene("");
    s.lights[0].kind = LightKind::Point {
        position: DVec3::new(5.0, -1.0, 0.0),
        intensity: Rgb::ONE,
        spot: None,
    };
    assert_eq!(radiance_bound(&s, 4, ShadowMode::Opaque), f64::INFINITY);
    assert_eq!(effective_min_weight(&s), 0.0);
    // The carried bound too, at every depth (the glass passes light on, the lit plane does
    // not: its infinite term must not be lost to `0 x inf`), so no roulette below a weight.
    for depth in [0, 1, 4, 1024] {
        assert_eq!(
            super::carried::carried_bound(&s, depth, ShadowMode::Opaque),
            f64::INFINITY
        );
    }
    assert_eq!(super::carried::effective_roulette_below(&s), 0.0);
}

#[test]
fn distances_never_exceed_the_true_distance() {
    let p = DVec3::new(0.3, 0.2, 0.1);
    assert!((box_surface_distance(DVec3::ZERO, DVec3::ONE, p) - 0.1).abs() < 1e-15);
    assert!(
        (box_surface_distance(DVec3::ZERO, DVec3::ONE, DVec3::splat(2.0)) - 3f64.sqrt()).abs()
            < 1e-12
    );
    let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
    // Above the triangle: the plane distance; beside it in its plane: the box distance.
    assert_eq!(
        triangle_distance(&v, DVec3::Z, DVec3::new(0.2, 0.2, 0.5)),
        0.5
    );
    assert_eq!(
        triangle_distance(&v, DVec3::Z, DVec3::new(3.0, 0.0, 0.0)),
        2.0
    );
    assert_eq!(geometric_sum(1.0, 3), 4.0);
    assert_eq!(geometric_sum(2.0, 3), 15.0);
    assert_eq!(geometric_sum(3.0, 1024), f64::INFINITY);
}

#[test]
fn the_ray_budget_cuts_each_sample_and_keeps_the_tree_whole() {
    use crate::integrator::{NoopRecorder, RayCounts};
    use crate::render::{render_pixel, trace_pixel};
    use crate::tree::EndReason;
    let mut s =
        scene(r#", "settings": {"max_depth": 40, "min_weight": 0, "max_rays": 50, "spp": 2}"#);
    s.camera = s.camera.with_size(8, 6);
    let mut cut_trees = 0;
    for (x, y) in [(4, 3), (3, 2), (0, 0)] {
        let t = trace_pixel(&s, x, y).unwrap();
        assert!(crate::analysis::invariants::tree_violations(&t, s.background).is_empty());
        let cut = t
            .nodes
            .iter()
            .filter(|n| n.end == EndReason::RayBudget)
            .count();
        cut_trees += usize::from(cut > 0);
        // Per sample: at most the budget, plus the last ray's shadow rays.
        assert!(
            t.nodes.len() <= 2 * (50 + s.lights.len() + 1),
            "{}",
            t.nodes.len()
        );
        let mut counts = RayCounts::default();
        let l = render_pixel(
            &crate::integrator::SceneIntegrator::new(&s),
            &mut crate::sampling::SceneSampler::for_settings(&s.settings),
            (x, y),
            &mut NoopRecorder,
            &mut counts,
            |_| {},
        )
        .0;
        assert_eq!(l, t.radiance);
        assert_eq!(counts.budget_samples > 0, cut > 0);
    }
    assert!(cut_trees > 0);
}

mod nested_dielectrics {
    //! Random nested-dielectric scenes: the automatic cut changes each pixel by no more than
    //! its cut branches could carry (strict), and by at most one 8-bit sRGB step.
    use super::super::*;
    use crate::analysis::invariants::tree_violations;
    use crate::math::linear_to_srgb;
    use crate::render::trace_pixel;
    use crate::tree::{EndReason, RayTree};
    use proptest::prelude::*;

    fn scene(ior: (f64, f64), t: (f64, f64), r: f64, depth: u32) -> Scene {
        let src = format!(
            r#"{{"camera": {{"position": [0,1,5], "look_at": [0,0.6,0], "fov_y": 35,
                 "width": 12, "height": 8}},
               "background": [0.35, 0.55, 0.85], "ambient": [0.05, 0.05, 0.05],
               "materials": {{
                 "floor": {{"diffuse": {{"checker": {{"even": [0.9,0.1,0.1],
                            "odd": [0.9,0.9,0.2], "size": 0.5}}}}}},
                 "outer": {{"transmissivity": [{t0},{t0},{t0}], "ior": {i0},
                            "specular": [0.5,0.5,0.5], "shininess": 100}},
                 "inner": {{"transmissivity": [{t1},{t1},{t1}], "ior": {i1},
                            "reflectivity": [{r},{r},{r}]}}}},
               "objects": [
                 {{"type": "plane", "point": [0,-0.4,0], "normal": [0,1,0],
                   "material": "floor"}},
                 {{"type": "sphere", "center": [0,0.6,0], "radius": 1,
                   "material": "outer"}},
                 {{"type": "sphere", "center": [0.1,0.6,0.1], "radius": 0.5,
                   "material": "inner"}}],
               "lights": [{{"type": "point", "position": [3,5,4],
                            "intensity": [60,60,60]}}],
               "settings": {{"max_depth": {depth}}}}}"#,
            i0 = ior.0,
            i1 = ior.1,
            t0 = t.0,
            t1 = t.1,
        );
        Scene::from_json(&src).unwrap()
    }

    /// Every pixel `(x, y)` of the 12x8 image: its tree under `s` and under `s` with the
    /// exhaustive tree (`min_weight` 0).
    fn against_exhaustive(s: &Scene) -> impl Iterator<Item = (u32, u32, RayTree, RayTree)> {
        let mut full = s.clone();
        full.settings.whitted.min_weight = Some(0.0);
        (0..8).flat_map(move |y| {
            let full = full.clone();
            (0..12).map(move |x| {
                let a = trace_pixel(s, x, y).unwrap();
                (x, y, a, trace_pixel(&full, x, y).unwrap())
            })
        })
    }

    /// What the cut branches of `tree` could have carried: their throughput (at most the
    /// parent's times the weight cut) times the radiance `bound`.
    fn cut_could_carry(tree: &RayTree, bound: f64) -> f64 {
        tree.nodes
            .iter()
            .filter(|n| n.end == EndReason::MinWeight)
            .map(|n| (n.throughput * n.truncated).max_element() * bound)
            .sum()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        #[test]
        fn the_cut_changes_pixels_by_less_than_its_bound(
            ior in (1.05f64..2.4, 1.05f64..2.4),
            t in (0.5f64..1.0, 0.3f64..0.9),
            r in 0.0f64..0.1,
            depth in 4u32..14,
        ) {
            let mut cut = scene(ior, t, r, depth);
            // The cut alone (the roulette below a weight has tests of its own).
            cut.settings.whitted.roulette_below = Some(0.0);
            let bound = radiance_bound(&cut, depth, cut.settings.whitted.shadows);
            let w = effective_min_weight(&cut);
            prop_assert!(w > 0.0);
            for (x, y, a, b) in against_exhaustive(&cut) {
                prop_assert!(tree_violations(&a, cut.background).is_empty());
                let could = cut_could_carry(&a, bound);
                let diff = (a.radiance - b.radiance).abs().max_element();
                prop_assert!(diff <= could * (1.0 + 1e-9) + 1e-15,
                    "pixel {x},{y}: {diff} > {could}");
                let enc = |c: Rgb| c.to_array().map(linear_to_srgb);
                let (ea, eb) = (enc(a.radiance), enc(b.radiance));
                for k in 0..3 {
                    prop_assert!((ea[k] - eb[k]).abs() <= 1.0 / 255.0,
                        "pixel {x},{y}: {ea:?} vs {eb:?}");
                }
            }
        }

        /// The suggested roulette weight (opt-in since issue 32): each outermost roulette choice
        /// (no choice above it) at a hit of throughput `tau` moves the pixel by less than
        /// `tau L <= 0.01`, with `L` the carried bound (both its subtree's values, split and
        /// followed, lie in `[0, tau L)`), and the cut branches by what they could carry.
        #[test]
        fn the_suggested_weight_changes_pixels_by_less_than_its_roulette_and_cut_bounds(
            ior in (1.05f64..2.4, 1.05f64..2.4),
            t in (0.5f64..1.0, 0.3f64..0.9),
            r in 0.0f64..0.1,
            depth in 4u32..14,
        ) {
            use super::super::carried::{auto_roulette_below, carried_bound};
            let mut default = scene(ior, t, r, depth);
            let weight = auto_roulette_below(&default, &default.settings);
            default.settings.whitted.roulette_below = Some(weight);
            prop_assert!(weight > 0.0);
            let carried = carried_bound(&default, depth, default.settings.whitted.shadows);
            prop_assert!((weight * carried - 0.01).abs() < 1e-12);
            let bound = radiance_bound(&default, depth, default.settings.whitted.shadows);
            for (x, y, a, b) in against_exhaustive(&default) {
                prop_assert!(tree_violations(&a, default.background).is_empty());
                let played = |n: &crate::tree::RayNode| {
                    n.interface.as_ref().is_some_and(|i| i.roulette.is_some())
                };
                let outermost = |n: &crate::tree::RayNode| {
                    let mut p = n.parent;
                    while let Some(id) = p {
                        if played(a.node(id)) {
                            return false;
                        }
                        p = a.node(id).parent;
                    }
                    true
                };
                let mut could = cut_could_carry(&a, bound);
                for n in a.nodes.iter().filter(|n| played(n) && outermost(n)) {
                    prop_assert!(n.throughput.max_element() < weight);
                    could += n.throughput.max_element() * carried;
                }
                let diff = (a.radiance - b.radiance).abs().max_element();
                prop_assert!(diff <= could * (1.0 + 1e-9) + 1e-15,
                    "pixel {x},{y}: {diff} > {could}");
            }
        }
    }
}

/// The rough lobes' highlight bound `weight / (2 pi a^3)` holds for every direction pair and is
/// nearly reached (grazing `wo`, `wi` on the mirror direction): it is the strict maximum of
/// `f cos_i`, for the rough mirror and the rough dielectric's reflection.
#[test]
fn the_rough_lobes_highlight_bound_holds_and_is_tight() {
    use crate::bsdf::{Lobe, Microfacet};
    for a in [0.05, 0.2, 0.6, 1.0] {
        let bound = 1.0 / (2.0 * std::f64::consts::PI * a * a * a);
        let ggx = Microfacet::new(a);
        let lobes = [
            Lobe::RoughMirror {
                weight: Rgb::ONE,
                dist: ggx,
            },
            Lobe::RoughDielectric {
                weight: Rgb::ONE,
                eta: 1.5,
                dist: ggx,
            },
        ];
        let mut most = 0.0f64;
        for i in 0..=400 {
            let to = f64::from(i) / 400.0 * (std::f64::consts::FRAC_PI_2 - 1e-4);
            let wo = DVec3::new(to.sin(), 0.0, to.cos());
            for j in 0..=400 {
                let ti = f64::from(j) / 400.0 * (std::f64::consts::FRAC_PI_2 - 1e-4);
                for phi in [0.0, 1.0, 3.0, std::f64::consts::PI] {
                    let wi =
                        DVec3::new(ti.sin() * f64::cos(phi), ti.sin() * f64::sin(phi), ti.cos());
                    for lobe in &lobes {
                        let v = lobe.eval(wo, wi).x * wi.z;
                        assert!(v <= bound * (1.0 + 1e-12), "alpha {a}: {v} > {bound}");
                        most = most.max(v);
                    }
                }
            }
        }
        assert!(most > 0.3 * bound, "alpha {a}: at most {most} of {bound}");
    }
}

/// The material-by-material bound: the plane's local term `0.5 / pi x 2` at every depth, since
/// the glass (split 0.9) has no local term and the plane passes nothing on; the shared bound
/// multiplies it by `1 + 0.9 + ... + 0.9^16`.
#[test]
fn the_carried_bound_follows_each_material() {
    use super::carried::carried_bound;
    let s = scene("");
    let local = 0.5 / std::f64::consts::PI * 2.0;
    for depth in [0, 1, 16, 1024] {
        let b = carried_bound(&s, depth, ShadowMode::Opaque);
        assert!((b - local).abs() < 1e-15, "depth {depth}: {b}");
    }
    // A glass that also glows: L_k = 0.2 + 0.9 L_(k-1) from L_0 = 0.318 (the plane).
    let mut s = scene("");
    let g = s.materials.iter().position(|m| m.name == "g").unwrap();
    s.materials[g].emission = Rgb::splat(0.2);
    let mut want = local;
    for _ in 0..5 {
        want = (0.2 + 0.9 * want).max(local);
    }
    let b = carried_bound(&s, 5, ShadowMode::Opaque);
    assert!((b - want).abs() < 1e-12, "{b} vs {want}");
    assert!(b <= radiance_bound(&s, 5, ShadowMode::Opaque));
    // Translucent shadows through a material that amplifies: unbounded, as the shared bound.
    s.materials[g].transmissivity = Rgb::splat(1.5);
    assert_eq!(carried_bound(&s, 5, ShadowMode::Translucent), f64::INFINITY);
}

/// A coated base can return slightly more than `albedo / pi` (the coating's base factor
/// reaches 1.016 at normal incidence for eta 1.5): the bound takes `base_scale` on the albedo,
/// and the Whitted light term of a coated surface lit head-on stays below it.
#[test]
fn a_coated_base_raises_the_local_bound_by_its_base_scale() {
    let mut s = scene("");
    let m = s.materials.iter().position(|m| m.name == "m").unwrap();
    let plain = super::carried::carried_bound(&s, 0, ShadowMode::Opaque);
    let coating = crate::bsdf::Coating::smooth(1.5);
    s.materials[m].coating = Some(coating);
    s.materials[m].reflectivity = Rgb::ZERO;
    let coated = super::carried::carried_bound(&s, 0, ShadowMode::Opaque);
    assert!(
        (coated - plain * coating.base_scale()).abs() < 1e-12,
        "{coated} {plain}"
    );
    let head_on = coating.base_factor(1.0, 1.0);
    assert!(
        head_on > 1.0 && head_on <= coating.base_scale(),
        "{head_on}"
    );
}

/// The automatic roulette weight: 0.01 over the carried bound, off where the tree is asked to
/// be exhaustive or the integrator samples anyway.
#[test]
fn the_automatic_roulette_weight_and_when_it_is_off() {
    use super::carried::{ROULETTE_RADIANCE, auto_roulette_below, effective_roulette_below};
    let s = scene("");
    let local = 0.5 / std::f64::consts::PI * 2.0;
    assert!((auto_roulette_below(&s, &s.settings) - ROULETTE_RADIANCE / local).abs() < 1e-15);
    for extra in [
        r#", "settings": {"min_weight": 0}"#,
        r#", "settings": {"tolerance": 0}"#,
        r#", "settings": {"dielectric_roulette": 3}"#,
        r#", "settings": {"integrator": "path"}"#,
    ] {
        let s = scene(extra);
        assert_eq!(auto_roulette_below(&s, &s.settings), 0.0, "{extra}");
    }
    let s = scene(r#", "settings": {"roulette_below": 0.25, "min_weight": 0}"#);
    assert_eq!(effective_roulette_below(&s), 0.25);
}
