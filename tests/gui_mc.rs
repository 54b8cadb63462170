//! The inspector's Monte Carlo debug views (issue 16) through egui_kittest: the noise view is
//! picked in the "show" menu, draws a legend under the image, and its values are the recorded
//! samples' relative standard error; the class shares read the recorded paths.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::gui::InspectorApp;
use raytree::gui::jobs::denoise::DenoiseState;
use raytree::gui::model::stats::DebugView;
use raytree::scene::AdaptiveDesc;

mod gui_support;
use gui_support::*;
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;

const CAUSTIC: &str = include_str!("../fixtures/caustic.json");

/// The caustic fixture with `spp` samples per pixel (and `size`, else the fixture's), in a
/// 1500x950 window, its render finished.
fn caustic(spp: u32, size: Option<(u32, u32)>) -> Harness<'static, InspectorApp> {
    read_only_inspector(
        CAUSTIC,
        Box::new(move |s: &mut raytree::Scene| {
            s.settings.spp = spp;
            if let Some((w, h)) = size {
                s.camera = s.camera.with_size(w, h);
            }
            Ok(())
        }),
    )
}

#[test]
fn the_noise_view_is_picked_from_the_menu_and_shows_a_legend() {
    // The caustic fixture at its size, 8 samples per pixel.
    let mut h = caustic(8, None);
    assert!(h.state().placement().unwrap().legend.is_none());
    h.get_by_label("show").click();
    h.run();
    h.get_by_label("noise (relative standard error)").click();
    h.run();
    h.run();
    let doc = &h.state().session.doc;
    assert_eq!(doc.view.debug, DebugView::Noise);
    let place = h.state().placement().unwrap();
    let legend = place.legend.expect("a legend under the noise view");
    // Below the image (egui's `intersects` counts a shared edge, which a height-limited fit
    // gives, so compare the edges).
    assert!(
        legend.min.y >= place.rect.max.y - 1e-3,
        "{legend:?} {:?}",
        place.rect
    );
    // Each pixel's value is its recorded samples' relative standard error, computed by hand.
    let doc = &h.state().session.doc;
    for (x, y) in [(98, 112), (60, 140)] {
        let tree = raytree::trace_pixel(&doc.scene, x, y).unwrap();
        let l: Vec<f64> = tree
            .samples
            .iter()
            .map(|s| raytree::bsdf::luminance(s.radiance))
            .collect();
        let n = l.len() as f64;
        let mean = l.iter().sum::<f64>() / n;
        let var = l.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let want = ((var / n).sqrt() / mean) as f32;
        let got = DebugView::Noise.value(&doc.stats_at(x, y));
        assert!(
            (got - want).abs() <= 1e-6 * want,
            "{x},{y}: {got} vs {want}"
        );
        assert!(got > 0.0);
        assert_eq!(DebugView::Samples.value(&doc.stats_at(x, y)), 8.0);
    }
    // Under the ball most of the light is the caustic; on the open floor it is direct light.
    let caustics = DebugView::Share(4).value(&doc.stats_at(98, 112));
    let direct = DebugView::Share(2).value(&doc.stats_at(30, 150));
    assert!(caustics > 0.5 && direct > 0.9, "{caustics} {direct}");
    assert_eq!(
        DebugView::Share(4).label(),
        "share: caustics (CS*[DG]S+[LB])"
    );
}

/// Click "denoised image" and run frames (up to 600, 10 ms apart) until the filtered image
/// shows; the frames it took.
fn turn_on_denoised(h: &mut Harness<'static, InspectorApp>) -> u32 {
    h.get_by_label("denoised image").click();
    let mut frames = 0;
    while !h.state().shows_denoised() && frames < 600 {
        h.run();
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames += 1;
    }
    frames
}

/// The "denoised image" toggle (issue 16): once the render has finished the image panel shows
/// the denoised image, computed on its own thread; the document's image (what exports and
/// hovering read) and the selected pixel's tree stay the raw samples; off shows the raw image.
#[test]
fn the_denoise_toggle_shows_the_denoised_image_and_keeps_the_raw_samples() {
    let mut h = caustic(8, Some((96, 72)));
    assert!(h.state().denoise_state().is_none());
    assert!(!h.state().shows_denoised());
    let frames = turn_on_denoised(&mut h);
    assert!(
        h.state().shows_denoised(),
        "no denoised image after {frames} frames"
    );
    assert!(matches!(
        h.state().denoise_state(),
        Some(raytree::gui::jobs::denoise::DenoiseState::Ready(_))
    ));
    let _ = h.get_by_label_contains("denoised in");
    // The raw render is untouched: the document's image is `render`'s, bit for bit.
    let scene = h.state().session.doc.scene.clone();
    let (raw, _, _) = raytree::render::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert!(h.state().session.doc.image.pixels == raw.pixels);
    h.get_by_label("denoised image").click();
    h.run();
    h.run();
    assert!(!h.state().shows_denoised());
    assert!(h.state().denoise_state().is_none());
    // Under progressive rendering the guide pass (the scene's spp) is not the image shown.
    let options = raytree::gui::model::progressive::Options {
        on: true,
        target: 0.0,
        cap: 8,
    };
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::SetProgressive(
            options,
        ));
    // The View section moves while the progressive status line changes: set the view directly.
    let view = raytree::gui::model::document::ViewOptions {
        denoise: true,
        ..h.state().session.doc.view
    };
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::SetView(view));
    h.step();
    h.step();
    assert_eq!(
        h.state().denoise_state(),
        Some(&raytree::gui::jobs::denoise::DenoiseState::Unavailable(
            "not with progressive rendering"
        ))
    );
    assert!(!h.state().shows_denoised());
}

/// Whitted vs path in the inspector (issue 16): the section renders both integrators on its
/// own thread and shows the breakdown `raytree versus` prints; on the caustic fixture the
/// caustics are what Whitted misses most.
#[test]
fn whitted_vs_path_in_the_inspector_names_what_whitted_misses() {
    let mut h = caustic(16, Some((96, 72)));
    assert_eq!(h.state().versus(), (None, false));
    h.get_by_label("Compare integrators").click();
    h.run();
    h.get_by_label("compare Whitted and path").click();
    let mut frames = 0;
    while h.state().versus().0.is_none() && frames < 1000 {
        h.step(); // the spinner repaints every frame: step, do not wait to settle
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames += 1;
    }
    h.run();
    let (summary, running) = h.state().versus();
    let summary = summary.expect("a breakdown").to_owned();
    assert!(!running);
    // The same words and figures as the library's comparison of the same scene.
    let scene = h.state().session.doc.scene.clone();
    let v = raytree::aov::versus(&scene, None, &|_| {}).unwrap();
    assert_eq!(summary, v.summary());
    let top = v
        .breakdown()
        .into_iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .unwrap();
    assert_eq!(top.0, "caustics", "{summary}");
    let _ = h.get_by_label_contains("what Whitted misses here");
    let _ = h.get_by_label("path - Whitted");
    // Issue 32: switching the integrator leaves the comparison current (it renders both)...
    let mut settings = h.state().session.doc.scene.settings;
    settings.integrator = match settings.integrator {
        raytree::scene::IntegratorKind::Path => raytree::scene::IntegratorKind::Whitted,
        _ => raytree::scene::IntegratorKind::Path,
    };
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::SetSettings(
            settings,
        ));
    settle(&mut h);
    assert!(!has(&h, "made before the last settings change"));
    let _ = h.get_by_label("compare again");
    // ...a change of anything else marks it as made before...
    settings.max_depth += 1;
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::SetSettings(
            settings,
        ));
    settle(&mut h);
    assert!(has(&h, "made before the last settings change"));
    // ...and opening another scene clears it, images and numbers.
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::Open(
            "other.json".into(),
        ));
    settle(&mut h);
    assert_eq!(h.state().versus(), (None, false));
    assert!(!has(&h, "path - Whitted"));
}

/// The "denoised image" toggle on an adaptive scene (`settings.adaptive`): the guide pass goes
/// through the render's pixel loop, so the toggle works (it said "not with adaptive
/// antialiasing" before) and the image it filters is the adaptive render's.
#[test]
fn the_denoise_toggle_works_on_an_adaptive_scene() {
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.settings.spp = 2;
        s.settings.adaptive = Some(AdaptiveDesc {
            threshold: 0.1,
            max_spp: Some(8),
        });
        s.camera = s.camera.with_size(64, 48);
        Ok(())
    });
    let mut h = read_only_inspector(CAUSTIC, adjust);
    let frames = turn_on_denoised(&mut h);
    assert!(
        h.state().shows_denoised(),
        "no denoised image after {frames} frames: {:?}",
        h.state().denoise_state()
    );
    assert!(matches!(
        h.state().denoise_state(),
        Some(DenoiseState::Ready(_))
    ));
    let _ = h.get_by_label_contains("denoised in");
    // The document's image is the adaptive render's, some pixels refined.
    let scene = h.state().session.doc.scene.clone();
    let (raw, stats, _) = raytree::render::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert!(stats.refined_pixels > 0);
    assert!(h.state().session.doc.image.pixels == raw.pixels);
}

/// Issue 30: the comparison takes any two integrators. Path and BDPT of the classic scene are
/// compared against the noise, with the words and figures of `raytree versus --pair path,bdpt`
/// (the library's `pair`), and the images captioned by their integrators.
#[test]
fn the_comparison_puts_path_and_bdpt_side_by_side() {
    let classic = include_str!("../fixtures/classic.json");
    let mut h = gui_support::read_only_inspector(
        classic,
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(32, 18);
            s.settings.spp = 4;
            Ok(())
        }),
    );
    h.get_by_label("Compare integrators").click();
    h.run();
    let _ = h.get_by_label("compare Whitted and path");
    for (side, kind) in [("B", "bdpt"), ("A", "path")] {
        h.get_by_label(side).click();
        h.run();
        h.get_by_label(kind).click();
        h.run();
    }
    h.get_by_label("compare path and bdpt").click();
    let mut frames = 0;
    while h.state().versus().0.is_none() && frames < 1000 {
        h.step();
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames += 1;
    }
    h.run();
    let summary = h.state().versus().0.expect("a comparison").to_owned();
    use raytree::scene::IntegratorKind::{Bdpt, Path};
    let scene = h.state().session.doc.scene.clone();
    let want = raytree::aov::pair(&scene, [Path, Bdpt], None, &mut |s| {
        raytree::render::render(&SceneIntegrator::new(s), &RenderOptions::new(), &|_| {})
    });
    assert_eq!(summary, want.summary());
    assert!(
        summary.starts_with("path vs bdpt over pixels 0,0..32,18"),
        "{summary}"
    );
    let _ = h.get_by_label("bdpt - path");
    let _ = h.get_by_label("difference: red where bdpt is brighter, blue where path is");
    let _ = h.get_by_label("compare again");
}

/// Issue 30: Veach's figure in the inspector. The Strategies section splits the scene's BDPT
/// render by strategy on its own thread and captions each part with its share, the shares of
/// `raytree strategies` (the library's `split`), by bounces then strategy.
#[test]
fn the_strategies_section_shows_each_strategys_share() {
    let cornell = include_str!("../fixtures/cornell-box.json");
    let mut h = gui_support::read_only_inspector(
        cornell,
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(16, 16);
            s.settings.spp = 2;
            Ok(())
        }),
    );
    h.get_by_label("Strategies (bdpt)").click();
    h.run();
    h.get_by_label("split by strategy").click();
    let mut frames = 0;
    while h.state().strategies().0.is_empty() && frames < 2000 {
        h.step();
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames += 1;
    }
    h.run();
    let (captions, running) = h.state().strategies();
    assert!(!running);
    let scene = h.state().session.doc.scene.clone();
    let s = raytree::analysis::strategies::split(&scene, 3, &|_| {});
    let mut want: Vec<String> = s
        .shares()
        .into_iter()
        .map(|(p, x)| format!("{}: {:.1}%", p.label(), 100.0 * x))
        .collect();
    want.sort();
    let mut got = captions.clone();
    got.sort();
    assert_eq!(got, want);
    assert!(captions[0].starts_with("s=0 t=2: "), "{captions:?}");
    assert!(captions.iter().any(|c| c.starts_with("s=1 t=2: ")));
    for c in &captions {
        let _ = h.get_by_label(c);
    }
    h.get_by_label("unweighted (MIS off)").click();
    h.run();
    let _ = h.get_by_label("split again");
}

/// Issue 30: under light tracing and BDPT the "denoised image" is refused, as `raytree render
/// --denoise` refuses it (its guide pass is a camera pass: a light-traced image is nearly all
/// splats, and the inspector showed the filter's black image), and the status says why.
#[test]
fn the_denoiser_is_refused_under_light_tracing() {
    let mut h = gui_support::read_only_inspector(
        include_str!("../fixtures/caustic.json"),
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(48, 36);
            s.settings.spp = 2;
            s.settings.integrator = raytree::scene::IntegratorKind::Light;
            Ok(())
        }),
    );
    h.get_by_label("denoised image").click();
    for _ in 0..5 {
        h.run();
    }
    assert!(!h.state().shows_denoised());
    assert!(matches!(
        h.state().denoise_state(),
        Some(raytree::gui::jobs::denoise::DenoiseState::Unavailable(why)) if why.contains("light tracing")
    ));
    let _ = h.get_by_label_contains("denoise: not under light tracing or BDPT");
}
