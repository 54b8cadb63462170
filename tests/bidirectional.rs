//! Light tracing and bidirectional path tracing end to end (issue 30): tree == pixel bit for bit
//! on every fixture (the splats recorded), the white furnace's closed form, agreement with the
//! path tracer per 8x8 block (Welch t-tests over independent seeds, as `tests/path_stats.rs`)
//! on scenes the path tracer samples completely (point, directional, sphere and quad lights;
//! pinhole and thin lens; for light tracing no specular surface in view), BDPT's lower noise,
//! and the command line. Fixed seeds; tolerances from the measured spread (5 sigma).

mod common;

use common::raytree;
use common::stats::{agreement, lum, mean_var};
use raytree::SceneIntegrator;
use raytree::analysis::invariants::tree_violations;
use raytree::render::RenderOptions;
use raytree::scene::{IntegratorKind, MisHeuristic};
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

/// Every fixture under light tracing and BDPT at spp 1 and 16: each pixel's recorded tree (its
/// camera samples and every splat that landed in it) gives the rendered value bit for bit and
/// keeps the invariants; the splats' trees are `light` paths with `connection` nodes.
#[test]
fn every_fixture_tree_equals_pixel_under_light_tracing_and_bdpt() {
    for kind in [IntegratorKind::Light, IntegratorKind::Bdpt] {
        tree_equals_pixel_on_every_fixture(kind);
    }
}

fn tree_equals_pixel_on_every_fixture(kind: IntegratorKind) {
    let mut splatted = 0;
    for (name, mut scene) in fixtures() {
        scene.settings.integrator = kind;
        for (spp, w, h) in [(1, 16, 10), (16, 4, 3)] {
            scene.camera = scene.camera.with_size(w, h);
            scene.settings.spp = spp;
            let (image, _, _) = render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {},
            )
            .into_parts();
            for y in 0..h {
                for x in 0..w {
                    let tree = trace_pixel(&scene, x, y).unwrap();
                    let at = format!("{} {name} spp {spp} pixel {x},{y}", kind.name());
                    assert_eq!(tree.radiance, image.get(x, y), "{at}: tree != render");
                    let v = tree_violations(&tree, scene.background);
                    assert!(v.is_empty(), "{at}: {v:#?}");
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
fn furnace(
    kind: IntegratorKind,
    a: f64,
    le: f64,
    max_depth: u32,
    rr_depth: u32,
    seed: u64,
) -> Scene {
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
          "settings": {{"integrator": "{}", "spp": 8, "max_depth": {max_depth},
                        "rr_depth": {rr_depth}, "seed": {seed}}}}}"#,
        walls.join(","),
        kind.name()
    );
    Scene::from_json(&json).unwrap()
}

/// The white furnace: the image mean over 8 seeds within 5 standard errors of the closed form,
/// with and without Russian roulette, under light tracing and BDPT.
#[test]
fn white_furnace_under_light_tracing_and_bdpt() {
    let cases = [(0.5, 1.0, 3, 64), (0.8, 0.5, 6, 2), (0.3, 2.0, 0, 64)];
    for (kind, (a, le, max_depth, rr_depth)) in [IntegratorKind::Light, IntegratorKind::Bdpt]
        .into_iter()
        .flat_map(|k| cases.map(|c| (k, c)))
    {
        let expect = le * (1.0 - f64::powi(a, max_depth as i32 + 2)) / (1.0 - a);
        let means: Vec<f64> = (1..=8)
            .map(|seed| {
                let scene = furnace(kind, a, le, max_depth, rr_depth, seed);
                let (image, _, _) = render(
                    &SceneIntegrator::new(&scene),
                    &RenderOptions::new(),
                    &|_| {},
                )
                .into_parts();
                image.pixels.iter().map(|p| lum(*p)).sum::<f64>() / image.pixels.len() as f64
            })
            .collect();
        let (m, var) = mean_var(&means);
        let se = (var / means.len() as f64).sqrt();
        assert!(
            (m - expect).abs() <= 5.0 * se + 1e-9,
            "{} a {a} le {le} depth {max_depth} rr {rr_depth}: {m} vs {expect} (se {se})",
            kind.name()
        );
        // Light paths do the work: more than the camera's own `le`.
        assert!(m > le * (1.0 + 0.5 * a), "{m}");
    }
}

/// The Cornell box (a quad lamp, diffuse walls and boxes, interreflection up to depth 64)
/// under light tracing and BDPT agrees with the path tracer in every 8x8 block.
#[test]
fn light_tracing_and_bdpt_agree_with_path_tracing_on_the_cornell_box() {
    let mut scene = fixture("cornell-box.json");
    scene.camera = scene.camera.with_size(32, 32);
    scene.settings.spp = 16;
    for kind in [IntegratorKind::Light, IntegratorKind::Bdpt] {
        let (worst, mean) = agreement(&scene, kind, 8);
        assert!(mean > 0.05, "{mean}");
        assert!(worst < 5.0, "{}: largest block |t| {worst}", kind.name());
    }
}

/// The power heuristic (`settings.mis` `"power"`): each pixel's tree is its value bit for bit
/// (the recorded weights are the ones applied), the weights differ from the balance
/// heuristic's, and the render agrees with path tracing per 8x8 block on the Cornell box.
#[test]
fn the_power_heuristic_is_recorded_and_unbiased() {
    let mut scene = fixture("cornell-box.json");
    scene.settings.integrator = IntegratorKind::Bdpt;
    scene.settings.path.mis = MisHeuristic::Power;
    scene.camera = scene.camera.with_size(12, 12);
    scene.settings.spp = 2;
    let (image, _, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let mut balance = scene.clone();
    balance.settings.path.mis = MisHeuristic::Balance;
    let mut differ = 0;
    for (x, y) in [(6, 6), (3, 9), (9, 3), (6, 11)] {
        let tree = trace_pixel(&scene, x, y).unwrap();
        assert_eq!(tree.radiance, image.get(x, y), "pixel {x},{y}");
        let weights = |t: &raytree::RayTree| -> Vec<f64> {
            t.nodes
                .iter()
                .filter_map(|n| n.path.as_ref()?.mis_weight)
                .collect()
        };
        let (p, b) = (
            weights(&tree),
            weights(&trace_pixel(&balance, x, y).unwrap()),
        );
        assert_eq!(p.len(), b.len(), "the same strategies, other weights");
        differ += p.iter().zip(&b).filter(|(a, b)| a != b).count();
    }
    assert!(differ > 0);
    scene.camera = scene.camera.with_size(32, 32);
    scene.settings.spp = 16;
    let (worst, mean) = agreement(&scene, IntegratorKind::Bdpt, 8);
    assert!(mean > 0.05 && worst < 5.0, "|t| {worst}, mean {mean}");
}

/// BDPT's point: on the Cornell box its per-pixel variance at equal spp is below the path
/// tracer's (measured over 8 seeds, summed over the pixels off the lamp).
#[test]
fn bdpt_is_less_noisy_than_path_tracing_on_the_cornell_box() {
    let mut scene = fixture("cornell-box.json");
    scene.camera = scene.camera.with_size(32, 32);
    scene.settings.spp = 4;
    let spread = |kind| -> f64 {
        let r: Vec<Vec<f64>> = (1..=8)
            .map(|seed| {
                let mut scene = scene.clone();
                scene.settings.integrator = kind;
                scene.settings.seed = seed;
                render(
                    &SceneIntegrator::new(&scene),
                    &RenderOptions::new(),
                    &|_| {},
                )
                .image
                .pixels
                .iter()
                .map(|p| lum(*p))
                .collect()
            })
            .collect();
        // Off the lamp: its edge pixels (a hit or a miss of radiance 11) weigh the same in both.
        (0..r[0].len())
            .map(|i| mean_var(&r.iter().map(|v| v[i]).collect::<Vec<_>>()))
            .filter(|(m, _)| *m < 1.0)
            .map(|(_, v)| v)
            .sum()
    };
    let (bdpt, path) = (spread(IntegratorKind::Bdpt), spread(IntegratorKind::Path));
    assert!(bdpt < 0.8 * path, "bdpt {bdpt} vs path {path}");
}

/// A wall and a quad 0.4 in front of it, facing each other, under a quad lamp: a connection
/// between them must not cross the far surface before its end (it did, with the normal
/// offset, before its far end was offset too: 0.3% of the light was lost).
#[test]
fn bdpt_connections_between_facing_surfaces_are_not_self_blocked() {
    let json = r#"{"camera": {"position": [0, 1, 3.4], "look_at": [0, 1, 0], "fov_y": 40,
        "width": 32, "height": 32},
      "materials": {"white": {"diffuse": [0.73, 0.73, 0.73]}, "lamp": {"emission": [17, 12, 4]}},
      "objects": [
        {"type": "quad", "name": "wall", "corner": [-1, 0, -1], "edge_u": [2, 0, 0],
         "edge_v": [0, 2, 0], "material": "white"},
        {"type": "quad", "name": "lamp", "corner": [-0.25, 1.998, -0.25], "edge_u": [0.5, 0, 0],
         "edge_v": [0, 0, 0.5], "material": "lamp"},
        {"type": "quad", "name": "panel", "corner": [-0.65, 0, -0.6], "edge_u": [0, 1.2, 0],
         "edge_v": [0.55, 0, 0], "material": "white"}],
      "settings": {"spp": 64, "max_depth": 2}}"#;
    let scene = Scene::from_json(json).unwrap();
    let (worst, mean) = agreement(&scene, IntegratorKind::Bdpt, 8);
    assert!(mean > 0.01 && worst < 5.0, "|t| {worst}, mean {mean}");
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
fn light_tracing_and_bdpt_agree_with_path_tracing_for_delta_lights_and_a_lens() {
    let mut scene = bounded_diffuse();
    scene.camera = scene.camera.with_size(32, 24);
    scene.settings.spp = 16;
    scene.settings.max_depth = 3;
    for kind in [IntegratorKind::Light, IntegratorKind::Bdpt] {
        let k = kind.name();
        let mut scene = scene.clone();
        let (worst, mean) = agreement(&scene, kind, 8);
        assert!(
            mean > 0.02 && worst < 5.0,
            "{k} pinhole: |t| {worst}, mean {mean}"
        );
        scene.camera.aperture_radius = 0.15;
        scene.camera.focus_distance = 6.0;
        let (worst, mean) = agreement(&scene, kind, 8);
        assert!(
            mean > 0.02 && worst < 5.0,
            "{k} thin lens: |t| {worst}, mean {mean}"
        );
    }
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
    // BDPT: the trace lists strategies with their MIS weights.
    let o = raytree(
        &[
            "trace",
            s,
            "--integrator",
            "bdpt",
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
    assert!(
        text.contains("integrator bdpt") && text.contains("s=1 t=2"),
        "{text}"
    );
    let o = raytree(&["effects", s, "--integrator", "bdpt"], d.path());
    assert!(String::from_utf8_lossy(&o.stdout).contains("bidirectional path tracing"));
    // Images built from camera samples alone are refused (exit 2, nothing written).
    for extra in [
        &["--denoise"][..],
        &["--aov", "caustic=C<RD>S+L"],
        &["--debug-view", "noise"],
    ] {
        let refused = d.path().join("refused.png");
        let mut args = vec!["render", s, "--integrator", "bdpt", "--size", "8x8", "-o"];
        args.push(refused.to_str().unwrap());
        args.extend_from_slice(extra);
        let o = raytree(&args, d.path());
        assert_eq!(
            o.status.code(),
            Some(2),
            "{extra:?}: {}",
            common::stderr(&o)
        );
        assert!(
            common::stderr(&o).contains("light-path splats"),
            "{}",
            common::stderr(&o)
        );
        assert!(!refused.exists(), "{extra:?} wrote an image");
    }
}

/// The caustic under the glass ball (`C<RD><TS><TS>L`) comes from the light's side under BDPT:
/// the light-tracing strategy (s = 4, t = 1) carries most of the MIS weight of the splats that
/// land in a caustic pixel (0.02 to 0.08 before the densities through delta vertices kept
/// their cosines; about 0.96 after).
#[test]
fn bdpt_weights_the_caustic_to_the_light_strategy() {
    let mut scene = fixture("caustic.json");
    scene.settings.integrator = IntegratorKind::Bdpt;
    scene.settings.spp = 4;
    let tree = trace_pixel(&scene, 105, 116).unwrap();
    let caustic: Vec<f64> = tree
        .splats
        .iter()
        .filter(|s| s.lpe == "C<RD><TS><TS>L")
        .map(|s| s.mis_weight)
        .collect();
    assert!(caustic.len() >= 3, "{} caustic splats", caustic.len());
    let mean = caustic.iter().sum::<f64>() / caustic.len() as f64;
    assert!(mean > 0.8, "mean MIS weight {mean} of {caustic:?}");
}

/// `trace` under light tracing keeps the light paths that land in the pixel within half of
/// `--max-memory`: a 1x1 Cornell box at 64 spp (every light path that reaches the camera lands
/// in the one pixel) is refused in 1 MiB with the count, exit 2 and nothing on stdout, and
/// traced with the default budget.
#[test]
fn trace_refuses_a_pixel_whose_splats_exceed_the_memory_budget() {
    let d = tempfile::tempdir().unwrap();
    let cb = common::fixture("cornell-box.json");
    let args = |mem: Option<&'static str>| {
        let mut v = vec![
            "trace",
            cb.as_str(),
            "--integrator",
            "light",
            "--size",
            "1x1",
            "--spp",
            "64",
            "--pixel",
            "0,0",
        ];
        if let Some(m) = mem {
            v.extend(["--max-memory", m]);
        }
        v.into_iter().map(str::to_string).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        raytree(&refs, d.path())
    };
    let o = run(args(Some("1")));
    let err = common::fails(&o);
    assert!(
        err.contains("light paths land in pixel 0,0") && err.contains("raise --max-memory"),
        "{err}"
    );
    assert!(o.stdout.is_empty());
    let o = run(args(None));
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("splat"));
}
