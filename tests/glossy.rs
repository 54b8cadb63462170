//! Issue 14's glossy reflection and refraction in the Whitted integrator: tree == pixel bit for
//! bit, roughness 0 is the smooth scene bit for bit, the sampled estimate of a rough mirror and a
//! frosted interface under a uniform sky matches the BSDF's integral (5 standard errors, fixed
//! seed), refracted samples keep the media stack, and bad values are refused.

mod common;
use common::raytree;

use raytree::bsdf::{Lobe, Microfacet};
use raytree::integrator::{Integrator, SceneIntegrator};
use raytree::render::RenderOptions;
use raytree::tree::{RayKind, RayTree};
use raytree::{Scene, render, trace_pixel};
use std::path::Path;

const GLOSSY: &str = include_str!("../fixtures/glossy.json");

fn small(w: u32, h: u32, spp: u32) -> Scene {
    let mut scene = Scene::from_json(GLOSSY).unwrap();
    scene.camera = scene.camera.with_size(w, h);
    scene.settings.spp = spp;
    scene
}

/// The recorded tree equals the rendered pixel bit for bit at 1 and 4 samples per pixel (with
/// 3 glossy samples and the lamp sampled as an area light), and every sampled node's weight is
/// `bsdf cos / pdf / count`.
#[test]
fn tree_equals_pixel_with_glossy_lobes() {
    for spp in [1, 4] {
        let mut scene = small(32, 20, spp);
        scene.settings.whitted.glossy_samples = 3;
        scene.settings.whitted.light_samples = Some(2);
        let img = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        let (mut reflected, mut refracted) = (0, 0);
        for y in 0..20 {
            for x in 0..32 {
                let tree = trace_pixel(&scene, x, y).unwrap();
                assert_eq!(tree.radiance, img.get(x, y), "pixel ({x}, {y}) spp {spp}");
                for n in &tree.nodes {
                    let Some(g) = n.glossy else { continue };
                    let w = g.bsdf * (g.cos / g.pdf / f64::from(g.count));
                    assert!((n.weight - w).abs().max_element() <= 1e-12 * w.max_element());
                    assert!(n.weight.max_element() <= 1.0 / f64::from(g.count) + 1e-12);
                    match n.kind {
                        RayKind::Reflected => reflected += 1,
                        RayKind::Refracted => refracted += 1,
                        _ => panic!("a glossy {:?} ray", n.kind),
                    }
                }
            }
        }
        assert!(
            reflected > 100 && refracted > 100,
            "{reflected} {refracted}"
        );
    }
}

/// `roughness: 0` everywhere renders the scene without the field bit for bit (and packets are
/// on for it, off for the rough scene).
#[test]
fn roughness_zero_is_the_smooth_scene() {
    let zero = GLOSSY
        .replace("\"roughness\": 0.2", "\"roughness\": 0")
        .replace("\"roughness\": 0.15", "\"roughness\": 0.0")
        .replace("\"roughness\": 0.08", "\"roughness\": 0");
    let absent = GLOSSY
        .replace(", \"roughness\": 0.2", "")
        .replace(", \"roughness\": 0.15", "")
        .replace(", \"roughness\": 0.08", "");
    assert!(!absent.contains("roughness") && zero.contains("roughness"));
    let (mut a, mut b) = (
        Scene::from_json(&zero).unwrap(),
        Scene::from_json(&absent).unwrap(),
    );
    for s in [&mut a, &mut b] {
        s.camera = s.camera.with_size(40, 25);
        s.settings.spp = 2;
        s.settings.whitted.glossy_samples = 5;
    }
    assert_eq!(
        render(&SceneIntegrator::new(&a), &RenderOptions::new(), &|_| {})
            .image
            .pixels,
        render(&SceneIntegrator::new(&b), &RenderOptions::new(), &|_| {})
            .image
            .pixels
    );
    assert!(SceneIntegrator::new(&a).traces_packets());
    assert!(!SceneIntegrator::new(&small(4, 4, 1)).traces_packets());
}

/// A plane of `material` (JSON) under a uniform sky of radiance 1, no lights: the camera sees
/// it at 60 degrees, so the pixel is the lobe's directional albedo at 60 degrees.
fn furnace(material: &str, spp: u32) -> RayTree {
    let src = format!(
        r#"{{
  "camera": {{"position": [0, 1, 1.7320508075688772], "look_at": [0, 0, 0], "fov_y": 0.001, "width": 1, "height": 1}},
  "background": [1, 1, 1], "ambient": [0, 0, 0],
  "materials": {{"m": {material}}},
  "objects": [{{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "m"}}],
  "settings": {{"spp": {spp}, "seed": 7, "glossy_samples": 1, "min_weight": 0}}
}}"#
    );
    trace_pixel(&Scene::from_json(&src).unwrap(), 0, 0).unwrap()
}

/// `integral over the sphere of f(wo, wi) abs(cos wi)` by the midpoint rule in (cos theta, phi).
fn albedo(lobe: &Lobe, wo: glam::DVec3) -> f64 {
    let (nz, nphi) = (2000, 400);
    let mut sum = 0.0;
    for i in 0..nz {
        let z = -1.0 + 2.0 * (f64::from(i) + 0.5) / f64::from(nz);
        let r = (1.0 - z * z).sqrt();
        for j in 0..nphi {
            let phi = std::f64::consts::TAU * (f64::from(j) + 0.5) / f64::from(nphi);
            let wi = glam::DVec3::new(r * phi.cos(), r * phi.sin(), z);
            sum += lobe.eval(wo, wi).x * z.abs();
        }
    }
    sum * 2.0 * std::f64::consts::TAU / f64::from(nz * nphi)
}

/// The tracer's glossy estimate converges to the BSDF's albedo: within 5 standard errors
/// (measured from the samples) of the quadrature, for a rough mirror and a rough dielectric
/// (reflection and refraction both see the sky), and below 1.
#[test]
fn glossy_estimate_matches_the_lobe_albedo_under_a_uniform_sky() {
    let wo = glam::DVec3::new(60f64.to_radians().sin(), 0.0, 60f64.to_radians().cos());
    let ggx = Microfacet::new(0.3);
    let cases = [
        (
            r#"{"reflectivity": [0.9, 0.9, 0.9], "roughness": 0.3}"#,
            Lobe::RoughMirror {
                weight: glam::DVec3::splat(0.9),
                dist: ggx,
            },
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "ior": 1.5, "roughness": 0.3}"#,
            Lobe::RoughDielectric {
                weight: glam::DVec3::ONE,
                eta: 1.5,
                dist: ggx,
            },
        ),
    ];
    for (material, lobe) in cases {
        let n = 20_000;
        let tree = furnace(material, n);
        let values: Vec<f64> = tree.samples.iter().map(|s| s.radiance.x).collect();
        let mean = values.iter().sum::<f64>() / f64::from(n);
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / f64::from(n - 1);
        let se = (var / f64::from(n)).sqrt();
        let expect = albedo(&lobe, wo);
        eprintln!("{material}: estimate {mean} +- {se}, quadrature {expect}");
        assert!(expect < 1.0 && mean < 1.0, "{material}: {mean} {expect}");
        assert!(se > 0.0 && se < 0.01, "{material}: s.e. {se}");
        assert!(
            (mean - expect).abs() < 5.0 * se,
            "{material}: estimate {mean} +- {se}, quadrature {expect}"
        );
    }
}

/// Refracted samples enter the frosted ball's medium (Beer's law inside it, hits from inside)
/// and reflected ones stay where they were.
#[test]
fn refracted_samples_enter_and_leave_the_medium() {
    let src = GLOSSY.replace(
        "\"ior\": 1.5, \"roughness\": 0.15",
        "\"ior\": 1.5, \"roughness\": 0.15, \"absorption\": [0.3, 0.3, 0.3]",
    );
    let mut scene = Scene::from_json(&src).unwrap();
    scene.camera = scene.camera.with_size(32, 20);
    scene.settings.whitted.glossy_samples = 4;
    let ball = scene
        .objects
        .iter()
        .position(|o| o.name == "frosted ball")
        .unwrap();
    let (mut inside, mut internal) = (0, 0);
    for y in 0..20 {
        for x in 16..32 {
            let tree = trace_pixel(&scene, x, y).unwrap();
            for n in &tree.nodes {
                let (Some(g), Some(parent)) = (n.glossy, n.parent) else {
                    continue;
                };
                let from = tree.node(parent).hit.as_ref().unwrap();
                if from.object != ball {
                    continue;
                }
                // Inside the ball after this ray: entering refraction or internal reflection.
                let in_ball = from.entering == g.transmitted;
                assert_eq!(n.attenuation.is_some(), in_ball, "node {:?}", n.id);
                if in_ball {
                    let hit = n.hit.as_ref().expect("a ray inside a ball hits it");
                    assert_eq!((hit.object, hit.entering), (ball, false));
                    inside += 1;
                    internal += usize::from(!g.transmitted);
                } else if let Some(hit) = &n.hit {
                    assert_ne!(hit.object, ball, "a convex ball is not hit from outside");
                }
            }
        }
    }
    assert!(inside > 50 && internal > 0, "{inside} {internal}");
}

/// Write the glossy scene as `s.json`, then [`common::fails_with`].
fn fails_with(dir: &Path, args: &[&str], text: &str) {
    std::fs::write(dir.join("s.json"), GLOSSY).unwrap();
    common::fails_with(dir, args, text);
}

/// Bad roughness and glossy_samples are refused with their JSON path and line:column, and
/// `--glossy-samples 0` on every tracing command with exit 2 and nothing written.
#[test]
fn bad_roughness_and_glossy_samples_are_refused() {
    for (from, to, path) in [
        (
            "\"roughness\": 0.2",
            "\"roughness\": -0.1",
            "materials.brushed.roughness",
        ),
        (
            "\"roughness\": 0.2",
            "\"roughness\": 1.5",
            "materials.brushed.roughness",
        ),
        (
            "\"roughness\": 0.2",
            "\"roughness\": \"x\"",
            "materials.brushed.roughness",
        ),
        // The fixture writes its settings in the new spelling: the error is where it writes
        // the key (a type error inside the tagged value names the key in its message).
        (
            "\"glossy_samples\": 4",
            "\"glossy_samples\": 0",
            "settings.integrator.glossy_samples",
        ),
        (
            "\"glossy_samples\": 4",
            "\"glossy_samples\": -2",
            "settings.integrator.glossy_samples",
        ),
    ] {
        let e = Scene::from_json(&GLOSSY.replace(from, to)).unwrap_err();
        assert_eq!(e.path, path, "{e}");
        if to.ends_with("-2") {
            assert!(e.message.starts_with("invalid value: integer `-2`"), "{e}");
        }
        assert!(e.line.is_some() && e.column.is_some(), "{e}");
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for cmd in [
        &["render", "s.json", "--size", "8x5", "-o", "out.png"][..],
        &["trace", "s.json", "--pixel", "1,1"],
        &["diagram", "s.json", "--pixel", "1,1", "-o", "d.svg"],
        &["effects", "s.json"],
        &["explain", "s.json", "--pixel", "1,1"],
        &["cost", "s.json", "--quick", "--repeats", "1", "-o", "cost"],
        &[
            "acne",
            "s.json",
            "--size",
            "8x6",
            "--scales",
            "1",
            "--epsilons",
            "1e-4",
            "-o",
            "acne",
        ],
    ] {
        fails_with(
            d,
            &[cmd, &["--glossy-samples", "0"]].concat(),
            "--glossy-samples: must be in 1..=65536, got 0",
        );
    }
    let o = raytree(
        &[
            "trace",
            "s.json",
            "--pixel",
            "215,110",
            "--glossy-samples",
            "2",
        ],
        d,
    );
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("sampled rough dielectric 2/2 (through)"),
        "{text}"
    );
}

/// `raytree effects` names the rough materials.
#[test]
fn effects_say_glossy_is_simulated() {
    let plan = raytree::effects::EffectPlan::for_scene(&small(4, 4, 1));
    assert!(plan.glossy);
    let lines = plan.explain(&small(4, 4, 1));
    let line = lines
        .iter()
        .find(|l| l.effect.starts_with("glossy"))
        .unwrap();
    assert!(
        line.on && line.reason.contains("brushed, frosted, wall"),
        "{line:?}"
    );
    // A rough dielectric draws one ray per sample: the frosted ball does not split (the smooth
    // copy's glass does, and its tree can grow exponentially).
    use raytree::analysis::growth::{Growth, tree_growth};
    assert_eq!(tree_growth(&small(4, 4, 1)).growth, Growth::Polynomial(1));
    let smooth = Scene::from_json(&GLOSSY.replace(", \"roughness\": 0.15", "")).unwrap();
    assert_eq!(tree_growth(&smooth).growth, Growth::Exponential);
}

/// The min-weight cut compares one sample's estimate (`n x` the throughput of a sampled ray,
/// as with spp), so more glossy samples do not cut more: at min weight 0.05, each of 64 samples
/// of the brushed ball (weight about 0.9 / 64 = 0.014) is traced.
#[test]
fn the_cut_compares_one_samples_estimate() {
    let mut scene = Scene::from_json(GLOSSY).unwrap();
    scene.settings.whitted.min_weight = Some(0.05);
    scene.settings.whitted.glossy_samples = 64;
    let tree = trace_pixel(&scene, 100, 110).unwrap();
    let root = tree.node(tree.samples[0].root);
    assert_eq!(root.hit.as_ref().unwrap().object_name, "brushed ball");
    let sampled: Vec<_> = root
        .children
        .iter()
        .map(|&c| tree.node(c))
        .filter(|n| n.glossy.is_some())
        .collect();
    assert!(sampled.len() > 60, "{}", sampled.len());
    assert!(sampled.iter().all(|n| n.weight.max_element() < 0.05));
    assert_eq!(root.truncated, glam::DVec3::ZERO);
}

/// Glossy trees keep every tree invariant (sums, throughputs, finiteness) and `explain`'s
/// shares add up to the pixel value, at 1 and 4 samples per pixel.
#[test]
fn glossy_trees_keep_the_invariants_and_explain_adds_up() {
    use raytree::analysis::{explain::explain, invariants::tree_violations};
    for spp in [1, 4] {
        let mut scene = Scene::from_json(GLOSSY).unwrap();
        scene.settings.spp = spp;
        scene.settings.whitted.light_samples = Some(2);
        for (x, y) in [(100, 110), (215, 110), (160, 40), (60, 60), (250, 160)] {
            let tree = trace_pixel(&scene, x, y).unwrap();
            let v = tree_violations(&tree, scene.background);
            assert!(v.is_empty(), "({x}, {y}) spp {spp}: {v:?}");
            let e = explain(&tree, &scene);
            let sum = e.shares.iter().fold(glam::DVec3::ZERO, |a, s| a + s.value);
            let d = (sum - tree.radiance).abs().max_element();
            assert!(
                d <= 1e-12 * (1.0 + tree.radiance.max_element()),
                "({x}, {y}): {sum} vs {}",
                tree.radiance
            );
        }
    }
}
