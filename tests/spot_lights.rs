//! Spot lights (issue 29): the irradiance a spot light delivers to a diffuse floor against its
//! closed form `albedo / pi * I falloff(w) cos / r^2` under Whitted and the path tracer, for
//! each falloff profile (pbrt-v4 smoothstep, Mitsuba 3 linear, glTF); nothing outside the cone;
//! light tracing and BDPT agree with the path tracer per 8x8 block on `fixtures/spot.json`
//! (Welch t-tests over independent seeds, as `tests/bidirectional.rs`).

mod common;

use common::stats::agreement;
use raytree::SceneIntegrator;
use raytree::lights::{Spot, SpotProfile};
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::scene::IntegratorKind;
use raytree::tree::RayKind;
use raytree::{Scene, render, trace_pixel};
use std::f64::consts::PI;
use std::path::PathBuf;

const ALBEDO: f64 = 0.5;
const INTENSITY: f64 = 7.0;
const POSITION: [f64; 3] = [0.4, 2.5, -0.3];
const AXIS: [f64; 3] = [0.3, -1.0, 0.2];

/// A 12 x 12 floor of albedo 0.5 seen from above, lit by one spot light (black sky).
fn floor(profile: SpotProfile, integrator: &str) -> Scene {
    let json = format!(
        r#"{{"camera": {{"position": [0, 6, 4], "look_at": [0.5, 0, -0.4], "fov_y": 50, "width": 40, "height": 30}},
        "background": [0, 0, 0],
        "materials": {{"floor": {{"diffuse": [{ALBEDO}, {ALBEDO}, {ALBEDO}]}}}},
        "objects": [{{"type": "quad", "corner": [-6, 0, -6], "edge_u": [0, 0, 12], "edge_v": [12, 0, 0], "material": "floor"}}],
        "lights": [{{"type": "spot", "position": {POSITION:?}, "direction": {AXIS:?}, "intensity": [{INTENSITY}, {INTENSITY}, {INTENSITY}],
            "cone_angle": 32, "falloff_angle": 20, "profile": "{}"}}],
        "settings": {{"integrator": "{integrator}", "spp": 1, "max_depth": 4}}}}"#,
        profile.name()
    );
    Scene::from_json(&json).unwrap()
}

fn spot(profile: SpotProfile) -> Spot {
    Spot {
        axis: glam::DVec3::from(AXIS).normalize(),
        cone: 32f64.to_radians(),
        falloff: 20f64.to_radians(),
        profile,
    }
}

/// Every pixel of the floor under `integrator` equals the closed form at its camera ray's hit
/// point (relative 1e-12); returns how many pixels lie (lit, in the falloff band, dark).
fn check_closed_form(profile: SpotProfile, integrator: &str) -> (u32, u32, u32) {
    let scene = floor(profile, integrator);
    let (image, _, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let cone = spot(profile);
    let light = glam::DVec3::from(POSITION);
    let mut counts = (0, 0, 0);
    for y in 0..scene.camera.height {
        for x in 0..scene.camera.width {
            let tree = trace_pixel(&scene, x, y).unwrap();
            assert_eq!(tree.radiance, image.get(x, y), "{integrator} {x},{y}");
            let cam = tree
                .nodes
                .iter()
                .find(|n| n.kind == RayKind::Camera)
                .unwrap();
            let Some(hit) = &cam.hit else {
                assert_eq!(tree.radiance, Rgb::ZERO);
                continue;
            };
            let to = light - hit.point;
            let r2 = to.length_squared();
            let w = -to / r2.sqrt();
            let f = cone.falloff(w);
            let expected = ALBEDO / PI * INTENSITY * f * (to.y / r2.sqrt()) / r2;
            let got = tree.radiance.x;
            assert!(
                (got - expected).abs() <= 1e-12 * expected.max(1e-300),
                "{integrator} {profile:?} pixel {x},{y}: {got} vs {expected} (falloff {f})"
            );
            assert!(tree.radiance.x == tree.radiance.y && tree.radiance.y == tree.radiance.z);
            match f {
                1.0 => counts.0 += 1,
                0.0 => {
                    counts.2 += 1;
                    // "Why is this pixel black?" names the cone.
                    let e = raytree::analysis::explain::explain(&tree, &scene);
                    let text = &e.sentences[0].text;
                    assert!(
                        text.contains("outside the cone of light#0")
                            && text.contains("its cone 32.0 deg"),
                        "{x},{y}: {text}"
                    );
                }
                _ => counts.1 += 1,
            }
        }
    }
    counts
}

/// Whitted and the path tracer (next-event estimation of a delta light) give the closed form
/// on every pixel, under every profile, and the image holds full, falling and dark pixels.
#[test]
fn a_spot_light_on_a_floor_is_its_closed_form() {
    for profile in [
        SpotProfile::Smoothstep,
        SpotProfile::Linear,
        SpotProfile::Gltf,
    ] {
        for integrator in ["whitted", "path"] {
            let (lit, band, dark) = check_closed_form(profile, integrator);
            assert!(
                lit > 20 && band > 20 && dark > 20,
                "{integrator} {profile:?}: {lit} lit, {band} falling, {dark} dark"
            );
        }
    }
}

/// `fixtures/spot.json` (three spot lights, one per profile, over diffuse walls, a clay ball
/// and a glass ball) without its glass, which light tracing cannot see through: light tracing
/// and BDPT agree with path tracing in every 8x8 block (largest Welch |t| below 5 over 8 seeds).
#[test]
fn light_tracing_and_bdpt_agree_with_path_tracing_under_spot_lights() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/spot.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["materials"]["glass"] = serde_json::json!({"diffuse": [0.3, 0.6, 0.4]});
    v["background"] = serde_json::json!([0, 0, 0]);
    let mut scene = Scene::from_json(&v.to_string()).unwrap();
    scene.camera = scene.camera.with_size(32, 24);
    scene.settings.spp = 16;
    scene.settings.max_depth = 3;
    for kind in [IntegratorKind::Light, IntegratorKind::Bdpt] {
        let (worst, mean) = agreement(&scene, kind, 8);
        assert!(
            mean > 0.01 && worst < 5.0,
            "{}: largest block |t| {worst}, mean {mean}",
            kind.name()
        );
    }
}

/// Bad spot lights are refused with the JSON path of the field at fault.
#[test]
fn bad_spot_lights_name_their_field() {
    let base = r#"{"camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov_y": 40, "width": 4, "height": 3},
        "objects": [], "lights": [LIGHT]}"#;
    for (light, needle) in [
        (
            r#"{"type": "spot", "position": [0, 2, 0], "intensity": [1, 1, 1], "cone_angle": 30}"#,
            "lights[0]: a spot light needs direction or look_at",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "look_at": [0, 0, 0], "intensity": [1, 1, 1], "cone_angle": 30}"#,
            "lights[0].look_at: give direction or look_at, not both",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "look_at": [0, 2, 0], "intensity": [1, 1, 1], "cone_angle": 30}"#,
            "lights[0].look_at: must differ from position",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1], "cone_angle": 180}"#,
            "lights[0].cone_angle: must be in (0, 180) degrees",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1], "cone_angle": 30, "falloff_angle": 31}"#,
            "lights[0].falloff_angle: must be in [0, cone_angle] degrees",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "direction": [0, 0, 0], "intensity": [1, 1, 1], "cone_angle": 30}"#,
            "lights[0].direction: must be a non-zero direction",
        ),
        (
            r#"{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [1, 1, 1], "cone_angle": 30, "profile": "cosine"}"#,
            "lights[0].profile",
        ),
    ] {
        let err = Scene::from_json(&base.replace("LIGHT", light))
            .unwrap_err()
            .to_string();
        assert!(err.contains(needle), "{err}\n  wanted: {needle}");
    }
}
