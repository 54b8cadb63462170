//! Progressive rendering in the inspector (issue 16) through egui_kittest: ticking
//! "progressive" starts passes whose noise estimate, samples and time appear under the
//! checkbox, and a run that reaches its cap says so. Also the automatic antialiasing toggle
//! (issue 18).

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::gui::model::progressive::{Options, Stop};
use raytree::gui::{Command, InspectorApp};

mod gui_support;
use gui_support::*;
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;

const CORNELL: &str = include_str!("../fixtures/cornell-box.json");

fn has(h: &Harness<'_, InspectorApp>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}

#[test]
fn ticking_progressive_shows_the_noise_estimate_and_the_stop() {
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(48, 48);
        Ok(())
    });
    let mut h = read_only_inspector(CORNELL, adjust);
    assert!(!h.state().session.doc.progressive.options.on);
    assert!(!has(&h, "stop at error"));
    assert!(!has(&h, "noise "));
    h.get_by_label("progressive").click();
    h.run();
    assert!(h.state().session.doc.progressive.options.on);
    assert!(has(&h, "stop at error"));
    // Wait for the first pass's report (delivered by the worker; no time limit).
    while h.state().session.doc.progressive.report.is_none() {
        h.state_mut().session.pump();
        std::thread::yield_now();
    }
    h.run();
    assert!(has(&h, "noise "), "the estimate is shown");
    assert!(has(&h, "at 4 spp") || has(&h, "at 8 spp") || has(&h, " spp, "));
    // A run capped at 16 samples with an unreachable target says that it stopped at the cap.
    let capped = Options {
        on: true,
        target: 0.0,
        cap: 16,
    };
    h.state_mut().session.apply(Command::SetProgressive(capped));
    h.state_mut().session.wait_image();
    h.run();
    let report = h.state().session.doc.progressive.report.unwrap();
    assert_eq!((report.spp, report.stop), (16, Some(Stop::Cap)));
    assert!(has(&h, "stopped: cap of 16 spp reached"));
    // Unticking returns to the one render at the scene's samples per pixel.
    h.get_by_label("progressive").click();
    h.run();
    h.state_mut().session.wait_render();
    h.run();
    assert!(h.state().session.doc.progressive.report.is_none());
    assert!(!has(&h, "noise "));
}

/// "antialias edges only" (automatic antialiasing, the default) shows the render's image;
/// unticking it renders every pixel at the scene's samples per pixel (the uniform render).
#[test]
fn unticking_antialias_edges_only_gives_the_uniform_render() {
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(40, 24);
        s.settings.spp = 8;
        Ok(())
    });
    let mut h = read_only_inspector(src, adjust);
    h.state_mut().session.wait_render();
    h.run();
    let mut scene: raytree::Scene = (*h.state().session.doc.scene).clone();
    assert_eq!(
        scene.settings.antialiasing,
        raytree::scene::Antialiasing::Auto
    );
    let auto = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_eq!(h.state().session.doc.image, auto);
    h.get_by_label("antialias edges only").click();
    h.run();
    h.state_mut().session.wait_render();
    h.run();
    scene.settings.antialiasing = raytree::scene::Antialiasing::Uniform;
    assert_eq!(h.state().session.doc.scene.settings, scene.settings);
    let uniform = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_ne!(uniform, auto);
    assert_eq!(h.state().session.doc.image, uniform);
}

/// The roulette below a weight (off by default since issue 32, shown for glass scenes):
/// unticking its "default (off)" box starts the slider at the weight suggested for the scene,
/// and the inspector's image is then the render of `roulette_below: 0.01`; the default image is
/// the split one (`roulette_below: 0`), bit for bit.
#[test]
fn the_roulette_weight_is_opt_in_from_the_suggested_weight() {
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(40, 24);
        Ok(())
    });
    let mut h = read_only_inspector(src, adjust);
    h.state_mut().session.wait_render();
    h.run();
    let mut scene: raytree::Scene = (*h.state().session.doc.scene).clone();
    assert_eq!(scene.settings.whitted.roulette_below, None);
    assert!(has(&h, "roulette below"));
    let default = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_eq!(h.state().session.doc.image, default);
    let mut split = scene.clone();
    split.settings.whitted.roulette_below = Some(0.0);
    assert_eq!(
        raytree::render(
            &SceneIntegrator::new(&split),
            &RenderOptions::new(),
            &|_| {}
        )
        .image,
        default,
        "the default splits"
    );
    // The box on the roulette slider's row (the slider and its text both carry the label).
    let row = h
        .query_all_by_label("roulette below")
        .next()
        .unwrap()
        .rect()
        .center()
        .y;
    let theirs = h
        .query_all_by_label("default (off)")
        .min_by(|a, b| {
            let (da, db) = (a.rect().center().y - row, b.rect().center().y - row);
            da.abs().total_cmp(&db.abs())
        })
        .unwrap();
    assert!((theirs.rect().center().y - row).abs() < 4.0);
    theirs.click();
    h.run();
    h.state_mut().session.wait_render();
    h.run();
    assert_eq!(
        h.state().session.doc.scene.settings.whitted.roulette_below,
        Some(0.01),
        "the slider starts at the suggested weight"
    );
    scene.settings.whitted.roulette_below = Some(0.01);
    let roulette = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_ne!(roulette, default);
    assert_eq!(h.state().session.doc.image, roulette);
}

/// Issue 32 item 11: the progressive panel says what the noise estimate is made of; on the
/// caustic fixture a few rare-event pixels (the caustic under the glass ball) carry most of
/// its squared error, and the panel says so and why the estimate plateaus, in the library's
/// words ([`raytree::gui::model::progressive::Composition::sentence`]).
#[test]
fn the_progressive_panel_says_when_rare_event_pixels_dominate() {
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(80, 60);
        Ok(())
    });
    let mut h = read_only_inspector(include_str!("../fixtures/caustic.json"), adjust);
    let capped = Options {
        on: true,
        target: 0.0,
        cap: 64,
    };
    h.state_mut().session.apply(Command::SetProgressive(capped));
    h.state_mut().session.wait_image();
    h.run();
    let report = h.state().session.doc.progressive.report.unwrap();
    assert_eq!((report.spp, report.stop), (64, Some(Stop::Cap)));
    let c = report.composition.expect("a composition");
    assert!(c.dominated(), "{c:?}");
    let sentence = c.sentence();
    assert!(sentence.starts_with("A few rare-event pixels dominate"));
    assert!(has(&h, &sentence), "the panel shows {sentence}");
    // On the Cornell box the noise is spread, and the panel says that instead.
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(32, 32);
        Ok(())
    });
    let mut h = read_only_inspector(CORNELL, adjust);
    h.state_mut().session.apply(Command::SetProgressive(capped));
    h.state_mut().session.wait_image();
    h.run();
    let c = h
        .state()
        .session
        .doc
        .progressive
        .report
        .unwrap()
        .composition
        .unwrap();
    assert!(!c.dominated(), "{c:?}");
    assert!(has(&h, "The noise is spread over the image"));
}
