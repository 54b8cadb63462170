//! Whole scenes: the tree invariants on every fixture, bit-for-bit agreement of render and
//! trace, and analytic scenes with closed-form answers.

use raytree::SceneIntegrator;
use raytree::analysis::invariants::tree_violations;
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::tree::{EndReason, RayKind};
use raytree::{Scene, render, trace_pixel};
use std::path::PathBuf;

fn fixtures() -> Vec<(String, Scene)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut out: Vec<(String, Scene)> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "json").then(|| {
                let src = std::fs::read_to_string(&p).unwrap();
                let scene =
                    Scene::from_json(&src).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                (p.file_stem().unwrap().to_string_lossy().into_owned(), scene)
            })
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(
        out.len() >= 8,
        "expected the lecture's fixtures, found {}",
        out.len()
    );
    out
}

fn small(mut s: Scene, w: u32, h: u32, spp: u32) -> Scene {
    s.camera = s.camera.with_size(w, h);
    s.settings.spp = spp;
    s
}

#[test]
fn every_fixture_tree_matches_render_bit_for_bit_and_keeps_invariants() {
    for (name, scene) in fixtures() {
        for spp in [1, 4] {
            let (w, h) = if spp == 1 { (40, 24) } else { (12, 8) };
            let scene = small(scene.clone(), w, h, spp);
            // Under automatic antialiasing (the Whitted fixtures at 4 spp) a pixel takes its
            // first pass or spp samples: the tree takes what the render took.
            let (image, stats, map) = raytree::render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {},
            )
            .into_parts();
            assert_eq!(
                image,
                render(
                    &SceneIntegrator::new(&scene),
                    &RenderOptions::new(),
                    &|_| {}
                )
                .image,
                "{name}"
            );
            assert_eq!(stats.nonfinite_pixels, 0, "{name}");
            for y in 0..h {
                for x in 0..w {
                    let tree = trace_pixel(&scene, x, y).unwrap();
                    let px = image.get(x, y);
                    assert_eq!(
                        tree.radiance, px,
                        "{name} spp {spp} pixel {x},{y}: tree != render"
                    );
                    let v = tree_violations(&tree, scene.background);
                    assert!(v.is_empty(), "{name} pixel {x},{y}: {v:#?}");
                    let taken = map.samples[(y * w + x) as usize];
                    // Uniform: spp; automatic antialiasing: its first pass (2) or spp.
                    assert!(taken == spp || taken == 2, "{name} pixel {x},{y}: {taken}");
                    assert_eq!(tree.samples.len(), taken as usize);
                }
            }
        }
    }
}

#[test]
fn fixtures_show_the_effects_they_are_named_for() {
    let all = fixtures();
    let get = |n: &str| small(all.iter().find(|f| f.0 == n).unwrap().1.clone(), 64, 36, 1);
    let any_node = |scene: &Scene, pred: &dyn Fn(&raytree::RayNode) -> bool| {
        (0..36).any(|y| (0..64).any(|x| trace_pixel(scene, x, y).unwrap().nodes.iter().any(pred)))
    };
    assert!(any_node(&get("tir-block"), &|n| n
        .interface
        .as_ref()
        .is_some_and(|i| i.tir)));
    assert!(any_node(&get("nested"), &|n| n
        .interface
        .as_ref()
        .is_some_and(
            |i| (i.n1 - 1.333).abs() < 1e-12 && (i.n2 - 1.5).abs() < 1e-12
        )));
    assert!(any_node(&get("absorption"), &|n| n.attenuation.is_some()));
    assert!(any_node(&get("translucent-shadow"), &|n| n.end
        == EndReason::Attenuated));
    assert!(any_node(&get("mirrors"), &|n| n.end == EndReason::MaxDepth));
}

/// A scene from JSON parts with a camera looking down -z from z = 5.
fn scene(materials: &str, objects: &str, extra: &str) -> Scene {
    let src = format!(
        r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 10, "width": 3, "height": 3}},
            "background": [0.2, 0.5, 1.0], "materials": {{{materials}}}, "objects": [{objects}] {extra}}}"#
    );
    Scene::from_json(&src).unwrap()
}

#[test]
fn lambertian_plane_under_a_directional_light() {
    let s = scene(
        r#""m": {"diffuse": [0.6, 0.3, 0.9]}"#,
        r#"{"type": "plane", "point": [0,0,0], "normal": [0,0,1], "material": "m"}"#,
        r#", "ambient": [0.1, 0.1, 0.1], "lights": [{"type": "directional", "direction": [0,0,-1], "irradiance": [2,2,2]}]"#,
    );
    let t = trace_pixel(&s, 1, 1).unwrap();
    let albedo = Rgb::new(0.6, 0.3, 0.9);
    let expect = albedo / std::f64::consts::PI * 2.0 + 0.1 * albedo;
    assert!(
        (t.radiance - expect).abs().max_element() < 1e-15,
        "{} vs {expect}",
        t.radiance
    );
}

#[test]
fn glass_ball_in_a_uniform_background_conserves_energy() {
    // A furnace test for dielectrics: no absorption and R + T = 1, so every pixel sees the
    // background except the energy cut at max depth, which the tree reports.
    for fresnel in ["exact", "schlick", "none"] {
        let mut s = scene(
            r#""glass": {"transmissivity": [1,1,1], "ior": 1.5}"#,
            r#"{"type": "sphere", "center": [0,0,0], "radius": 0.4, "material": "glass"}"#,
            &format!(r#", "settings": {{"fresnel": "{fresnel}"}}"#),
        );
        s.camera = s.camera.with_size(9, 9);
        s.background = Rgb::ONE;
        for (x, y) in [(4, 4), (5, 4), (6, 6), (7, 5)] {
            let t = trace_pixel(&s, x, y).unwrap();
            let cut: f64 = t.nodes.iter().map(|n| (n.throughput * n.truncated).x).sum();
            assert!(
                t.nodes.len() > 1,
                "{fresnel}: pixel {x},{y} should hit the ball"
            );
            assert!(
                (t.radiance.x + cut - 1.0).abs() < 1e-12,
                "{fresnel} {x},{y}: {} + {cut}",
                t.radiance.x
            );
        }
    }
}

#[test]
fn beer_law_through_an_index_matched_slab() {
    let s = scene(
        r#""ink": {"transmissivity": [1,1,1], "absorption": [0.5, 1.0, 2.0]}"#,
        r#"{"type": "box", "min": [-1,-1,-0.75], "max": [1,1,0.75], "material": "ink"}"#,
        "",
    );
    let t = trace_pixel(&s, 1, 1).unwrap();
    let d: f64 = 1.5;
    let expect = Rgb::new(0.2, 0.5, 1.0) * Rgb::new((-0.5 * d).exp(), (-d).exp(), (-2.0 * d).exp());
    assert!(
        (t.radiance - expect).abs().max_element() < 1e-12,
        "{} vs {expect}",
        t.radiance
    );
    let inside = t.nodes.iter().find(|n| n.attenuation.is_some()).unwrap();
    assert!((inside.attenuation.as_ref().unwrap().distance - d).abs() < 1e-9);
}

#[test]
fn facing_mirrors_sum_a_geometric_series() {
    // Camera between two mirrors, looking at one at normal incidence: each bounce adds the
    // ambient term a*d and multiplies by r, up to max_depth bounces.
    let (r, ad): (f64, f64) = (0.5, 0.1 * 0.2);
    for depth in [0u32, 1, 2, 5, 16] {
        let mut s = scene(
            r#""mirror": {"diffuse": [0.2, 0.2, 0.2], "reflectivity": [0.5, 0.5, 0.5]}"#,
            r#"{"type": "plane", "point": [0,0,-1], "normal": [0,0,1], "material": "mirror"},
               {"type": "plane", "point": [0,0,6], "normal": [0,0,-1], "material": "mirror"}"#,
            r#", "ambient": [0.1, 0.1, 0.1]"#,
        );
        s.settings.max_depth = depth;
        s.settings.whitted.min_weight = Some(0.0); // the exhaustive series
        let t = trace_pixel(&s, 1, 1).unwrap();
        let expect: f64 = (0..=depth).map(|k| ad * r.powi(k as i32)).sum();
        assert!(
            (t.radiance.x - expect).abs() < 1e-15,
            "depth {depth}: {} vs {expect}",
            t.radiance.x
        );
        let last = t.nodes.last().unwrap();
        assert_eq!(last.end, EndReason::MaxDepth);
        assert_eq!(last.depth, depth);
    }
}

#[test]
fn slab_displaces_but_keeps_direction() {
    let mut s = scene(
        r#""glass": {"transmissivity": [1,1,1], "ior": 1.5}"#,
        r#"{"type": "box", "min": [-5,-5,-0.5], "max": [5,5,0.5], "material": "glass"}"#,
        "",
    );
    s.camera.position = glam::DVec3::new(3.0, 0.0, 5.0);
    s.camera.forward = (glam::DVec3::ZERO - s.camera.position).normalize();
    s.camera.right = s.camera.forward.cross(glam::DVec3::Y).normalize();
    s.camera.up = s.camera.right.cross(s.camera.forward);
    let t = trace_pixel(&s, 1, 1).unwrap();
    let cam = &t.nodes[0];
    let inside = t
        .nodes
        .iter()
        .find(|n| n.kind == RayKind::Refracted)
        .unwrap();
    let out = t.node(
        inside
            .children
            .iter()
            .copied()
            .find(|c| t.node(*c).kind == RayKind::Refracted)
            .unwrap(),
    );
    assert!((out.direction - cam.direction).length() < 1e-12);
    let i = cam.hit.as_ref().unwrap().cos_i;
    let sin_i = (1.0 - i * i).sqrt();
    let ct = cam.interface.as_ref().unwrap().cos_t.unwrap();
    assert!(
        (sin_i - 1.5 * (1.0 - ct * ct).sqrt()).abs() < 1e-12,
        "Snell"
    );
}

#[test]
fn switching_off_unused_effects_is_bit_identical() {
    use raytree::effects::EffectPlan;
    use raytree::{Whitted, render};
    let mut scenes = fixtures();
    // A diffuse-and-mirror scene in translucent mode: translucent shadows are planned off.
    let mut m = scenes.iter().find(|f| f.0 == "mirrors").unwrap().1.clone();
    m.settings.whitted.shadows = raytree::scene::ShadowMode::Translucent;
    scenes.push(("mirrors-translucent".into(), m));
    for (name, scene) in scenes {
        let scene = small(scene, 48, 27, 1);
        let planned = EffectPlan::for_scene(&scene);
        let all = EffectPlan::everything(&scene);
        let a = render(
            &Whitted::with_plan(&scene, planned),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        let b = render(
            &Whitted::with_plan(&scene, all),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        assert!(
            a == b,
            "{name}: planned render differs from everything-on ({planned:?})"
        );
    }
}

#[test]
fn effect_plan_of_each_fixture() {
    use raytree::effects::EffectPlan;
    // (fixture, reflection, refraction, tir, absorption, translucent shadows)
    let expect = [
        ("absorption", true, true, true, true, true),
        ("classic", true, true, true, false, false),
        ("diffuse", false, false, false, false, false),
        ("mirrors", true, false, false, false, false),
        ("nested", true, true, true, true, true),
        ("slab", true, true, true, false, true),
        ("tir-block", true, true, true, false, true),
        ("translucent-shadow", true, true, true, true, true),
        ("water-grazing", true, true, true, true, true),
    ];
    let all = fixtures();
    for (name, refl, refr, tir, abs, trans) in expect {
        let s = &all.iter().find(|f| f.0 == name).unwrap().1;
        let p = EffectPlan::for_scene(s);
        assert_eq!(
            (
                p.reflection,
                p.refraction,
                p.tir,
                p.absorption,
                p.translucent_shadows
            ),
            (refl, refr, tir, abs, trans),
            "{name}"
        );
        assert_eq!(p.fresnel, refr, "{name}");
        assert!(p.light_on(0), "{name}");
    }
}

/// The direct-only render path (a plan without secondary rays, unrecorded) against the general
/// recursive tracer (the everything-on plan) and the recorded tree: the same bits on every
/// pixel, for each offset strategy, with a smooth mesh, a highlight, an emitter, a checker
/// texture, a directional light, and a light below the floor (behind every upward surface).
#[test]
fn direct_only_path_equals_the_recursive_tracer_bit_for_bit() {
    use raytree::effects::EffectPlan;
    use raytree::mesh::{MeshData, generate::icosphere};
    use raytree::scene::OffsetStrategy;
    use raytree::{Whitted, render};
    let diffuse = fixtures().into_iter().find(|f| f.0 == "diffuse").unwrap().1;
    let json = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/diffuse.json"),
    )
    .unwrap()
    .replace(
        r#"{"type": "box", "name": "pillar""#,
        r#"{"type": "mesh", "name": "smooth ball", "file": "ico", "normals": "smooth",
            "translate": [0.2, 0.5, 1.8], "scale": 0.5, "material": "red"},
           {"type": "box", "name": "pillar""#,
    );
    let mesh = Scene::from_json_with(&json, &mut |_| Ok::<MeshData, String>(icosphere(2))).unwrap();
    for (name, scene) in [("diffuse", diffuse), ("diffuse + smooth mesh", mesh)] {
        let planned = EffectPlan::for_scene(&scene);
        assert!(
            !planned.reflection && !planned.refraction,
            "{name}: {planned:?}"
        );
        for strategy in [
            OffsetStrategy::Normal,
            OffsetStrategy::Ray,
            OffsetStrategy::Scaled,
            OffsetStrategy::Robust,
        ] {
            let mut scene = small(scene.clone(), 64, 36, 1);
            scene.settings.offset.strategy = strategy;
            let (fast, stats, _) = render(
                &Whitted::with_plan(&scene, planned),
                &RenderOptions::new(),
                &|_| {},
            )
            .into_parts();
            let all = EffectPlan::everything(&scene);
            let (general, general_stats, _) = render(
                &Whitted::with_plan(&scene, all),
                &RenderOptions::new(),
                &|_| {},
            )
            .into_parts();
            assert!(
                fast == general,
                "{name} {strategy:?}: direct-only != recursive"
            );
            assert_eq!(
                stats.rays, general_stats.rays,
                "{name} {strategy:?}: ray counts"
            );
            assert!(stats.rays.shadow > 0, "{name}");
            let mut lit = 0;
            for y in (0..36).step_by(5) {
                for x in (0..64).step_by(3) {
                    let tree = trace_pixel(&scene, x, y).unwrap();
                    assert_eq!(tree.radiance, fast.get(x, y), "{name} {strategy:?} {x},{y}");
                    lit += usize::from(tree.radiance != scene.background);
                }
            }
            assert!(lit > 100, "{name}: the view shows the objects");
        }
    }
}
