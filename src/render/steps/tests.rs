//! A render by [`Steps`] is [`crate::render::render`]'s, bit for bit: one pixel a step and
//! everything in one step, under every integrator, with the diagnostics, through mesh packets,
//! adaptive and automatic antialiasing (a pixel a step there too).

use super::*;
use crate::integrator::SceneIntegrator;
use crate::render::{RenderOptions, render};
use crate::scene::{AdaptiveDesc, IntegratorKind, Scene};

fn fixture(name: &str, (w, h): (u32, u32), spp: u32) -> Scene {
    let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    let mut s = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.camera = s.camera.with_size(w, h);
    s.settings.spp = spp;
    s
}

/// The stepped render of `scene` with `more_time` always `answer`, and the steps it took.
fn stepped(scene: &Scene, diagnose: bool, answer: bool) -> (Rendered, usize) {
    let integrator = SceneIntegrator::new(scene);
    let mut steps = Steps::new(&integrator, diagnose);
    let mut n = 1;
    while steps.step_plain(&integrator, &|| answer) {
        n += 1;
    }
    (steps.rendered(), n)
}

/// The render and its steps agree in every pixel's bits, every count and the map.
fn assert_same(scene: &Scene, diagnose: bool) {
    let options = if diagnose {
        RenderOptions::diagnosed()
    } else {
        RenderOptions::new()
    };
    let whole = render(&SceneIntegrator::new(scene), &options, &|_| {});
    let bits = |r: &Rendered| -> Vec<[u64; 3]> {
        r.image
            .pixels
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect()
    };
    for answer in [false, true] {
        let (s, n) = stepped(scene, diagnose, answer);
        let what = format!(
            "{:?} diagnose {diagnose} more_time {answer}",
            scene.settings.integrator
        );
        assert_eq!(bits(&s), bits(&whole), "{what}");
        assert_eq!(
            format!("{:?}", s.stats),
            format!("{:?}", whole.stats),
            "{what}"
        );
        assert_eq!(format!("{:?}", s.map), format!("{:?}", whole.map), "{what}");
        if !answer {
            let pixels = (scene.camera.width * scene.camera.height) as usize;
            let passes = if scene.settings.integrator.splats() {
                2
            } else {
                1
            };
            assert_eq!(n, pixels * passes, "{what}: a pixel a step");
        }
    }
}

#[test]
fn every_integrator_stepped_is_the_render() {
    for (name, spp) in [
        ("caustic.json", 3),
        ("cornell-box.json", 2),
        ("classic.json", 1),
    ] {
        for kind in [
            IntegratorKind::Whitted,
            IntegratorKind::Path,
            IntegratorKind::Light,
            IntegratorKind::Bdpt,
        ] {
            let mut scene = fixture(name, (13, 9), spp);
            scene.settings.integrator = kind;
            assert_same(&scene, false);
        }
    }
}

#[test]
fn diagnosed_stepped_is_the_diagnosed_render() {
    let mut scene = fixture("classic.json", (24, 14), 1);
    scene.settings.offset.epsilon = 0.0;
    let whole = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::diagnosed(),
        &|_| {},
    );
    assert!(whole.stats.self_hit_pixels > 0, "the test needs acne");
    assert_same(&scene, true);
}

#[test]
fn mesh_packets_and_adaptive_plans_stepped_are_the_render() {
    let scene = crate::scene::icosphere_scene(2, 12, 3.0);
    assert!(crate::render::uses_packets::<NoopRecorder, _>(
        &SceneIntegrator::new(&scene)
    ));
    assert_same(&scene, false);
    let mut adaptive = fixture("soft-shadows.json", (10, 8), 2);
    adaptive.settings.adaptive = Some(AdaptiveDesc {
        max_spp: Some(8),
        threshold: 0.01,
    });
    assert!(crate::render::adaptive_plan(&SceneIntegrator::new(&adaptive)).is_some());
    assert_same(&adaptive, false);
    let mut auto = fixture("classic.json", (10, 8), 4);
    auto.settings.antialiasing = crate::scene::Antialiasing::Auto;
    assert!(crate::render::adaptive_plan(&SceneIntegrator::new(&auto)).is_some_and(|p| p.auto));
    assert_same(&auto, false);
}

#[test]
fn an_empty_image_takes_one_step() {
    let scene = fixture("classic.json", (0, 0), 1);
    let (r, n) = stepped(&scene, false, false);
    assert_eq!((r.image.pixels.len(), n), (0, 1));
}

/// Renders of `scene` stepped with a clock that allows `pattern[i % len]` more pixels at call
/// `i` (0: one pixel, the least a call does), so that the pieces end anywhere: within a row, at
/// a row's end, between the camera pass and the light pass.
fn stepped_by(scene: &Scene, pattern: &[u8]) -> Rendered {
    let integrator = SceneIntegrator::new(scene);
    let mut steps = Steps::new(&integrator, false);
    let mut call = 0;
    loop {
        let budget = std::cell::Cell::new(pattern[call % pattern.len()]);
        let more_time = || {
            let b = budget.get();
            budget.set(b.saturating_sub(1));
            b > 0
        };
        call += 1;
        if !steps.step_plain(&integrator, &more_time) {
            return steps.rendered();
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
    #[test]
    fn pieces_of_any_length_give_the_render(
        fixture_index in 0usize..3,
        kind_index in 0usize..4,
        w in 1u32..7,
        h in 1u32..5,
        spp in 1u32..4,
        pattern in proptest::collection::vec(0u8..9, 1..6),
    ) {
        let name = ["caustic.json", "cornell-box.json", "classic.json"][fixture_index];
        let mut scene = fixture(name, (w, h), spp);
        scene.settings.integrator = [
            IntegratorKind::Whitted,
            IntegratorKind::Path,
            IntegratorKind::Light,
            IntegratorKind::Bdpt,
        ][kind_index];
        let whole = render(&SceneIntegrator::new(&scene), &RenderOptions::new(), &|_| {});
        let s = stepped_by(&scene, &pattern);
        let bits = |r: &Rendered| -> Vec<[u64; 3]> {
            r.image.pixels.iter().map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]).collect()
        };
        proptest::prop_assert_eq!(bits(&s), bits(&whole));
        proptest::prop_assert_eq!(format!("{:?}", s.stats), format!("{:?}", whole.stats));
        proptest::prop_assert_eq!(format!("{:?}", s.map), format!("{:?}", whole.map));
    }
}
