//! Light tracing end to end (issue 30): tree == pixel bit for bit on every fixture (the splats
//! recorded), the white furnace's closed form, agreement with the path tracer per 8x8 block
//! (Welch t-tests over independent seeds, as `tests/path_stats.rs`) on scenes whose camera sees
//! no specular surface (point, directional, sphere and quad lights; pinhole and thin lens), and
//! the command line. Fixed seeds; tolerances from the measured spread (5 sigma).

mod common;

use common::raytree;
use raytree::analysis::invariants::tree_violations;
use raytree::math::Rgb;
use raytree::scene::IntegratorKind;
use raytree::tree::{RayKind, TREE_SCHEMA_SPLATS};
use raytree::{Scene, render, trace_pixel};
use std::path::PathBuf;

fn fixture(name: &str) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn fixtures() -> Vec<(String, Scene)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "json").then(|| p.file_name().unwrap().to_string_lossy().into())
        })
        .collect();
    names.sort();
    assert!(names.len() >= 13, "{}", names.len());
    names
        .into_iter()
        .map(|n| (n.clone(), fixture(&n)))
        .collect()
}

fn lum(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// Every fixture under light tracing at spp 1 and 16: each pixel's recorded tree (its camera
/// samples and every splat that landed in it) gives the rendered value bit for bit and keeps
/// the invariants; the splats' trees are `light` paths with `connection` nodes.
#[test]
fn every_fixture_tree_equals_pixel_under_light_tracing() {
    let mut splatted = 0;
    for (name, mut scene) in fixtures() {
        scene.settings.integrator = IntegratorKind::Light;
        for (spp, w, h) in [(1, 16, 10), (16, 4, 3)] {
            scene.camera = scene.camera.with_size(w, h);
            scene.settings.spp = spp;
            let (image, _) = render(&scene, &|_| {});
            for y in 0..h {
                for x in 0..w {
                    let tree = trace_pixel(&scene, x, y).unwrap();
                    assert_eq!(
                        tree.radiance,
                        image.get(x, y),
                        "{name} spp {spp} pixel {x},{y}: tree != render"
                    );
                    let v = tree_violations(&tree, scene.background);
                    assert!(v.is_empty(), "{name} spp {spp} pixel {x},{y}: {v:#?}");
                    if !tree.splats.is_empty() {
                        splatted += 1;
                        assert_eq!(tree.schema, TREE_SCHEMA_SPLATS);
                        assert_eq!(tree.splat_divisor, spp);
                        let s = &tree.splats[0];
                        assert_eq!(tree.node(s.root).kind, RayKind::Light);
                        assert_eq!(tree.node(s.connection).kind, RayKind::Connection);
                    }
                }
            }
        }
    }
    assert!(splatted > 100, "{splatted} pixels with splats");
}

/// A closed box of six inward-facing quads (outer sides inside) of albedo `a` emitting `le`:
/// radiance `le (1 - a^(M+2)) / (1 - a)` for max depth `M`. The camera ray sees `le`; light
/// paths from the walls add the rest.
fn furnace(a: f64, le: f64, max_depth: u32, rr_depth: u32, seed: u64) -> Scene {
    let q = |name: &str, c: [f64; 3], u: [f64; 3], v: [f64; 3]| {
        format!(
            r#"{{"type": "quad", "name": "{name}", "corner": {c:?}, "edge_u": {u:?}, "edge_v": {v:?}, "material": "wall"}}"#
        )
    };
    let walls = [
        q("floor", [-1., -1., -1.], [0., 0., 2.], [2., 0., 0.]),
        q("ceiling", [-1., 1., -1.], [2., 0., 0.], [0., 0., 2.]),
        q("back", [-1., -1., -1.], [2., 0., 0.], [0., 2., 0.]),
        q("front", [-1., -1., 1.], [0., 2., 0.], [2., 0., 0.]),
        q("left", [-1., -1., -1.], [0., 2., 0.], [0., 0., 2.]),
        q("right", [1., -1., -1.], [0., 0., 2.], [0., 2., 0.]),
    ];
    let json = format!(
        r#"{{"camera": {{"position": [0.1, 0.05, 0.2], "look_at": [0.3, -0.2, -1], "fov_y": 70,
          "width": 16, "height": 16}},
          "materials": {{"wall": {{"diffuse": [{a}, {a}, {a}], "emission": [{le}, {le}, {le}]}}}},
          "objects": [{}],
          "settings": {{"integrator": "light", "spp": 8, "max_depth": {max_depth},
                        "rr_depth": {rr_depth}, "seed": {seed}}}}}"#,
        walls.join(",")
    );
    Scene::from_json(&json).unwrap()
}

/// The white furnace: the image mean over 8 seeds within 5 standard errors of the closed form,
/// with and without Russian roulette.
#[test]
fn white_furnace_under_light_tracing() {
    for (a, le, max_depth, rr_depth) in [(0.5, 1.0, 3, 64), (0.8, 0.5, 6, 2), (0.3, 2.0, 0, 64)] {
        let expect = le * (1.0 - f64::powi(a, max_depth as i32 + 2)) / (1.0 - a);
        let means: Vec<f64> = (1..=8)
            .map(|seed| {
                let scene = furnace(a, le, max_depth, rr_depth, seed);
                let (image, _) = render(&scene, &|_| {});
                image.pixels.iter().map(|p| lum(*p)).sum::<f64>() / image.pixels.len() as f64
            })
            .collect();
        let (m, var) = mean_var(&means);
        let se = (var / means.len() as f64).sqrt();
        assert!(
            (m - expect).abs() <= 5.0 * se + 1e-9,
            "a {a} le {le} depth {max_depth} rr {rr_depth}: {m} vs {expect} (se {se})"
        );
        // Light paths do the work: more than the camera's own `le`.
        assert!(m > le * (1.0 + 0.5 * a), "{m}");
    }
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var)
}

/// The mean luminance of each 8x8 block of `scene` rendered by `kind` at `seed`.
fn blocks(scene: &Scene, kind: IntegratorKind, seed: u64) -> Vec<f64> {
    let mut scene = scene.clone();
    scene.settings.integrator = kind;
    scene.settings.seed = seed;
    let (image, _) = render(&scene, &|_| {});
    let (w, h) = (image.width as usize, image.height as usize);
    let mut out = vec![0.0; (w / 8) * (h / 8)];
    for y in 0..h / 8 * 8 {
        for x in 0..w / 8 * 8 {
            out[(y / 8) * (w / 8) + x / 8] += lum(image.get(x as u32, y as u32)) / 64.0;
        }
    }
    out
}

/// Welch t statistics per block between light tracing and path tracing over `seeds`
/// independent renders each; returns the largest |t| and the mean block value.
fn agreement(scene: &Scene, seeds: u64) -> (f64, f64) {
    let per = |kind| -> Vec<Vec<f64>> { (1..=seeds).map(|s| blocks(scene, kind, s)).collect() };
    let (light, path) = (per(IntegratorKind::Light), per(IntegratorKind::Path));
    let mut worst: f64 = 0.0;
    let mut total = 0.0;
    for b in 0..light[0].len() {
        let l: Vec<f64> = light.iter().map(|v| v[b]).collect();
        let p: Vec<f64> = path.iter().map(|v| v[b]).collect();
        let ((ml, vl), (mp, vp)) = (mean_var(&l), mean_var(&p));
        let se = (vl / l.len() as f64 + vp / p.len() as f64).sqrt();
        total += mp;
        if se > 0.0 {
            worst = worst.max((ml - mp).abs() / se);
        } else {
            assert_eq!(ml, mp, "block {b}: no spread, different means");
        }
    }
    (worst, total / light[0].len() as f64)
}

/// The Cornell box (a quad lamp, diffuse walls and boxes, interreflection up to depth 64)
/// under light tracing agrees with the path tracer in every 8x8 block.
#[test]
fn light_tracing_agrees_with_path_tracing_on_the_cornell_box() {
    let mut scene = fixture("cornell-box.json");
    scene.camera = scene.camera.with_size(32, 32);
    scene.settings.spp = 16;
    let (worst, mean) = agreement(&scene, 8);
    assert!(mean > 0.05, "{mean}");
    assert!(worst < 5.0, "largest block |t| {worst}");
}

/// `diffuse.json` (point, directional and sphere lights over diffuse surfaces; its Phong
/// highlights are Whitted-only) with its infinite floor plane made a 12 x 12 quad and a black
/// sky: light tracing emits directional light over the bounded objects' sphere and takes no
/// light from the background (`docs/bidirectional.md`).
fn bounded_diffuse() -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/diffuse.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["background"] = serde_json::json!([0.0, 0.0, 0.0]);
    v["objects"][0] = serde_json::json!({"type": "quad", "name": "floor",
        "corner": [-6.0, 0.0, -6.0], "edge_u": [0.0, 0.0, 12.0], "edge_v": [12.0, 0.0, 0.0],
        "material": "floor"});
    Scene::from_json(&v.to_string()).unwrap()
}

/// Point, directional and sphere lights over diffuse surfaces, and the same through a thin
/// lens.
#[test]
fn light_tracing_agrees_with_path_tracing_for_delta_lights_and_a_lens() {
    let mut scene = bounded_diffuse();
    scene.camera = scene.camera.with_size(32, 24);
    scene.settings.spp = 16;
    scene.settings.max_depth = 3;
    let (worst, mean) = agreement(&scene, 8);
    assert!(
        mean > 0.02 && worst < 5.0,
        "pinhole: |t| {worst}, mean {mean}"
    );
    scene.camera.aperture_radius = 0.15;
    scene.camera.focus_distance = 6.0;
    let (worst, mean) = agreement(&scene, 8);
    assert!(
        mean > 0.02 && worst < 5.0,
        "thin lens: |t| {worst}, mean {mean}"
    );
}

/// `--integrator light` on the command line: render, trace (the splats listed) and effects.
#[test]
fn command_line_light_tracing() {
    let d = tempfile::tempdir().unwrap();
    let scene = d.path().join("cb.json");
    std::fs::copy(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/cornell-box.json"),
        &scene,
    )
    .unwrap();
    let s = scene.to_str().unwrap();
    let out = d.path().join("out.png");
    let o = raytree(
        &[
            "render",
            s,
            "--integrator",
            "light",
            "--size",
            "32x32",
            "--spp",
            "2",
            "-o",
            out.to_str().unwrap(),
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned() + &common::stderr(&o);
    assert!(text.contains("light paths"), "{text}");
    let o = raytree(
        &[
            "trace",
            s,
            "--integrator",
            "light",
            "--size",
            "32x32",
            "--spp",
            "2",
            "--pixel",
            "16,20",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("splat"), "{text}");
    let o = raytree(&["effects", s, "--integrator", "light"], d.path());
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("light tracing"), "{text}");
}
