use super::*;
use crate::gui::jobs::worker::Worker;
use crate::integrator::SceneIntegrator;
use crate::scene::{SamplerKind, Scene};
use std::sync::Arc;

fn cornell(size: u32) -> Scene {
    let mut scene =
        Scene::from_json(include_str!("../../../../fixtures/cornell-box.json")).unwrap();
    scene.camera = scene.camera.with_size(size, size);
    scene.settings.adaptive = None;
    scene
}

/// Welford's running mean and variance of the mean equal the two-pass direct computation.
#[test]
fn welford_matches_a_direct_computation() {
    let mut rng = crate::sampling::SplitMix64::new(7);
    let samples: Vec<Rgb> = (0..37)
        .map(|_| {
            let v = rng.next_f64() * 3.0;
            Rgb::new(v, 0.5 * v, rng.next_f64())
        })
        .collect();
    let mut p = PixelAcc::default();
    for (k, &l) in samples.iter().enumerate() {
        p.add(k as u32, l);
    }
    let n = samples.len() as f64;
    let ys: Vec<f64> = samples.iter().map(|&l| luminance(l)).collect();
    let mean = ys.iter().sum::<f64>() / n;
    let var = ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let (m, v) = p.mean_and_variance(samples.len() as u32);
    assert!((m - mean).abs() < 1e-12, "{m} {mean}");
    assert!((v - var / n).abs() < 1e-12 * var, "{v} {}", var / n);
    assert!(v > 0.0);
}

fn accumulate(scene: &Scene, totals: &[u32]) -> Vec<(u32, f64, Vec<Rgb>)> {
    let integrator = SceneIntegrator::new(scene);
    let sampler = SceneSampler::for_settings(&scene.settings);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut acc = Accumulator::new(w, h);
    totals
        .iter()
        .map(|&n| {
            let first = acc.samples();
            acc.trace(&integrator, &sampler, (first, n - first), 0..h, &|| false);
            acc.finish_pass(n - first);
            (n, acc.error(), acc.rows(0, h, n))
        })
        .collect()
}

/// Under Sobol the image after N accumulated samples is `render` at spp N bit for bit; the
/// estimate falls as the passes accumulate (about as 1/sqrt(N)).
#[test]
fn sobol_passes_equal_render_and_the_estimate_falls() {
    let mut scene = cornell(32);
    assert_eq!(scene.settings.sampler_kind(), SamplerKind::Sobol);
    let passes = accumulate(&scene, &[4, 8, 16, 64]);
    for (n, _, image) in &passes {
        scene.settings.spp = *n;
        let (want, _, _) = crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        assert_eq!(image, &want.pixels, "{n} spp");
    }
    let errors: Vec<f64> = passes.iter().map(|p| p.1).collect();
    assert!(
        errors.iter().all(|e| e.is_finite() && *e > 0.0),
        "{errors:?}"
    );
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "{errors:?}");
    // 16 times the samples: the error should fall by about 4 (at least 2).
    assert!(errors[0] / errors[3] > 2.0, "{errors:?}");
}

/// Under the stratified sampler the first pass is `render` at 4 spp; later passes use other
/// sample positions (each pass on its own grid), so the image changes and the error falls.
#[test]
fn stratified_first_pass_equals_render_and_later_passes_add_new_samples() {
    let mut scene = cornell(16);
    scene.settings.sampler = Some(SamplerKind::Stratified);
    let passes = accumulate(&scene, &[4, 8]);
    scene.settings.spp = 4;
    assert_eq!(
        passes[0].2,
        crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {}
        )
        .image
        .pixels
    );
    assert_ne!(passes[0].2, passes[1].2);
    assert!(passes[1].1 < passes[0].1, "{} {}", passes[1].1, passes[0].1);
}

#[test]
fn the_stop_rule() {
    let o = Options {
        on: true,
        target: 0.05,
        cap: 64,
    };
    assert_eq!(stop_rule(&o, 8, 0.2), None);
    assert_eq!(stop_rule(&o, 8, 0.05), Some(Stop::Target));
    assert_eq!(stop_rule(&o, 64, 0.2), Some(Stop::Cap));
    assert_eq!(stop_rule(&o, 64, 0.01), Some(Stop::Target));
}

/// Run a progressive job to its end; the reports of its passes and the image it left.
fn run_job(scene: &Scene, options: Options) -> (Vec<Report>, Vec<Rgb>) {
    let w = Worker::new(Arc::new(|| {}));
    let (width, height) = (scene.camera.width, scene.camera.height);
    let g = w.start_progressive(Arc::new(scene.clone()), options);
    let mut image = vec![Rgb::ZERO; (width * height) as usize];
    let mut reports = Vec::new();
    let mut done = false;
    loop {
        match w.recv().unwrap() {
            Delivery::Band { y0, pixels, .. } => {
                assert!(!done);
                let at = (y0 * width) as usize;
                image[at..at + pixels.len()].copy_from_slice(&pixels);
            }
            Delivery::Pass { generation, report } => {
                assert_eq!(generation, g);
                reports.push(report);
            }
            Delivery::Done { .. } => done = true,
            Delivery::StatsDone { .. } => break,
            _ => {}
        }
    }
    assert!(done);
    (reports, image)
}

/// A progressive job delivers passes of 4, 8, 16, ... samples with a falling estimate, stops
/// at the cap when the target is out of reach, and at the target's pass when it is reached;
/// its last image is `render` at that many samples.
#[test]
fn a_progressive_job_refines_and_stops_at_the_target() {
    let mut scene = cornell(24);
    let capped = Options {
        on: true,
        target: 0.0,
        cap: 32,
    };
    let (reports, _) = run_job(&scene, capped);
    let spp: Vec<u32> = reports.iter().map(|r| r.spp).collect();
    assert_eq!(spp, [4, 8, 16, 32]);
    assert!(reports.windows(2).all(|w| w[1].error < w[0].error));
    assert!(reports[..3].iter().all(|r| r.stop.is_none()));
    assert_eq!(reports[3].stop, Some(Stop::Cap));
    // A target between the 8- and 16-sample estimates: the run stops after 16.
    let target = Options {
        target: (reports[1].error + reports[2].error) / 2.0,
        cap: 1024,
        ..capped
    };
    let (reports2, image) = run_job(&scene, target);
    let spp: Vec<u32> = reports2.iter().map(|r| r.spp).collect();
    assert_eq!(spp, [4, 8, 16]);
    assert_eq!(reports2[2].stop, Some(Stop::Target));
    assert_eq!(reports2[2].error, reports[2].error);
    scene.settings.spp = 16;
    assert_eq!(
        image,
        crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {}
        )
        .image
        .pixels
    );
}

/// Issue 32: the estimate's composition. Its terms are what the estimate is the RMS of; on the
/// caustic fixture a few pixels under the glass ball (the caustic, found by rare BSDF samples)
/// carry most of the squared error, so the estimate plateaus; on the Cornell box the noise is
/// spread.
#[test]
fn the_composition_says_when_rare_event_pixels_dominate() {
    let compose = |scene: &Scene, spp: u32| {
        let integrator = SceneIntegrator::new(scene);
        let sampler = SceneSampler::for_settings(&scene.settings);
        let mut acc = Accumulator::new(scene.camera.width, scene.camera.height);
        acc.trace(
            &integrator,
            &sampler,
            (0, spp),
            0..scene.camera.height,
            &|| false,
        );
        acc.finish_pass(spp);
        let terms = acc.terms();
        let mean = terms.iter().sum::<f64>() / terms.len() as f64;
        assert!((mean.sqrt() - acc.error()).abs() <= 1e-12 * acc.error());
        (acc.composition().expect("a composition"), acc.error())
    };
    let mut caustic = Scene::from_json(include_str!("../../../../fixtures/caustic.json")).unwrap();
    caustic.camera = caustic.camera.with_size(80, 60);
    let (c, error) = compose(&caustic, 64);
    assert!(c.dominated(), "{c:?} {error}");
    // Under the ball, whose contact point is below the image centre.
    let [wx, wy] = c.worst;
    assert!((20..60).contains(&wx) && (25..55).contains(&wy), "{c:?}");
    assert!(c.rest_error < 0.75 * error, "{c:?} {error}");
    let (spread, error) = compose(&cornell(32), 64);
    assert!(!spread.dominated(), "{spread:?} {error}");
}
