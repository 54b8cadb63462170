//! The render worker: supersession, the debug-view pass, growth statistics.

use super::*;
use crate::gui::model::stats::PixelStats;
use crate::integrator::RayCounts;
use crate::math::Rgb;

#[test]
fn a_newer_job_supersedes_an_older_one_and_matches_render() {
    let w = Worker::new(Arc::new(|| {}));
    let mut scene = Scene::default_scene();
    scene.camera = scene.camera.with_size(64, 36);
    let g1 = w.start(Arc::new(scene.clone()), true);
    scene.settings.max_depth = 0;
    let g2 = w.start(Arc::new(scene.clone()), true);
    assert!(g2 > g1);
    let mut pixels = vec![Rgb::ZERO; 64 * 36];
    let mut stats = vec![PixelStats::default(); 64 * 36];
    let (mut image_done, mut stats_rows) = (false, 0);
    loop {
        match w.recv().unwrap() {
            Delivery::Band {
                generation,
                y0,
                pixels: p,
            } if generation == g2 => {
                assert_eq!(stats_rows, 0, "the image comes first");
                let at = y0 as usize * 64;
                pixels[at..at + p.len()].copy_from_slice(&p);
            }
            Delivery::Done { generation, .. } if generation == g2 => image_done = true,
            Delivery::Stats {
                generation,
                y0,
                stats: s,
            } if generation == g2 => {
                assert!(image_done);
                let at = y0 as usize * 64;
                stats[at..at + s.len()].copy_from_slice(&s);
                stats_rows += s.len() / 64;
            }
            Delivery::StatsDone { generation, .. } if generation == g2 => break,
            d => assert_eq!(d.generation(), g1),
        }
    }
    assert_eq!(stats_rows, 36);
    let (image, _, _) = crate::render(
        &crate::integrator::SceneIntegrator::new(&scene),
        &crate::render::RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert_eq!(pixels, image.pixels);
    // The statistics are those of each pixel's recorded tree.
    for (x, y) in [(10, 5), (40, 20), (63, 35)] {
        let tree = crate::render::trace_pixel(&scene, x, y).unwrap();
        let want = crate::gui::model::stats::summarize(&tree.nodes, 1);
        assert_eq!(stats[(y * 64 + x) as usize], want, "pixel {x},{y}");
    }
}

#[test]
fn with_a_debug_view_one_recorded_pass_delivers_the_same_image_and_statistics() {
    let mut scene = Scene::default_scene();
    scene.camera = scene.camera.with_size(48, 27);
    let scene = Arc::new(scene);
    let collect = |image_first: bool| {
        let w = Worker::new(Arc::new(|| {}));
        let g = w.start(Arc::clone(&scene), image_first);
        let mut pixels = vec![Rgb::ZERO; 48 * 27];
        let mut stats = vec![PixelStats::default(); 48 * 27];
        let mut rays = None;
        loop {
            match w.recv().unwrap() {
                Delivery::Band { y0, pixels: p, .. } => {
                    let at = y0 as usize * 48;
                    pixels[at..at + p.len()].copy_from_slice(&p);
                }
                Delivery::Stats { y0, stats: s, .. } => {
                    let at = y0 as usize * 48;
                    stats[at..at + s.len()].copy_from_slice(&s);
                }
                Delivery::Done { rays: r, .. } => rays = Some(r),
                Delivery::StatsDone { generation, .. } => {
                    assert_eq!(generation, g);
                    break;
                }
                Delivery::Growth { .. } => unreachable!("comes after the statistics"),
                Delivery::Pass { .. } => unreachable!("not a progressive job"),
            }
        }
        (pixels, stats, rays.expect("the image is reported done"))
    };
    let (a, b) = (collect(true), collect(false));
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert_eq!(a.2, b.2);
    assert_eq!(
        a.0,
        crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {}
        )
        .image
        .pixels
    );
}

#[test]
fn after_the_statistics_the_tree_growth_and_what_the_cut_saves() {
    let nested = include_str!("../../../../fixtures/nested.json");
    for (json, want, fewer) in [
        (nested, "ray tree exponential", true),
        (
            include_str!("../../../../fixtures/diffuse.json"),
            "ray tree bounded",
            false,
        ),
        // Path-traced: no tree of its own; Whitted's, labelled as such.
        (
            include_str!("../../../../fixtures/caustic.json"),
            "path integrator: one path per sample, no split, no cut; under Whitted the ray tree \
             would be linear",
            true,
        ),
    ] {
        let mut scene = Scene::from_json(json).unwrap();
        scene.camera = scene.camera.with_size(64, 36);
        let w = Worker::new(Arc::new(|| {}));
        let g = w.start(Arc::new(scene), true);
        let mut stats_done = false;
        let line = loop {
            match w.recv().unwrap() {
                Delivery::StatsDone { .. } => stats_done = true,
                Delivery::Growth { generation, line } => {
                    assert_eq!(generation, g);
                    break line;
                }
                _ => {}
            }
        };
        assert!(stats_done, "{line}");
        assert!(line.starts_with(want), "{line}");
        assert_eq!(line.contains("x fewer) on a 16x9 sample"), fewer, "{line}");
    }
}

/// Everything a job delivers, folded: the image, the statistics, the rays, the growth line and
/// each progressive pass's samples, error and stop (not its seconds).
#[derive(Debug, PartialEq)]
struct Folded {
    pixels: Vec<Rgb>,
    stats: Vec<PixelStats>,
    rays: Option<RayCounts>,
    growth: Option<String>,
    passes: Vec<(u32, u64, Option<crate::gui::model::progressive::Stop>)>,
}

impl Folded {
    fn new(scene: &Scene) -> Self {
        let n = (scene.camera.width * scene.camera.height) as usize;
        Self {
            pixels: vec![Rgb::ZERO; n],
            stats: vec![PixelStats::default(); n],
            rays: None,
            growth: None,
            passes: Vec::new(),
        }
    }

    /// Fold `d` in; returns whether the job is over (its growth line came).
    fn fold(&mut self, d: Delivery, width: u32) -> bool {
        match d {
            Delivery::Band { y0, pixels, .. } => {
                let at = (y0 * width) as usize;
                self.pixels[at..at + pixels.len()].copy_from_slice(&pixels);
            }
            Delivery::Stats { y0, stats, .. } => {
                let at = (y0 * width) as usize;
                self.stats[at..at + stats.len()].copy_from_slice(&stats);
            }
            Delivery::Done { rays, .. } => self.rays = Some(rays),
            Delivery::StatsDone { .. } => {}
            Delivery::Growth { line, .. } => {
                self.growth = Some(line);
                return true;
            }
            Delivery::Pass { report, .. } => {
                self.passes
                    .push((report.spp, report.error.to_bits(), report.stop));
            }
        }
        false
    }
}

#[test]
fn slices_on_the_calling_thread_deliver_what_the_worker_thread_does() {
    // The wasm32 path: one row per slice, one slice per call, on this thread.
    let progressive = crate::gui::model::progressive::Options {
        on: true,
        target: 0.0,
        cap: 8,
    };
    for (json, options) in [
        (include_str!("../../../../fixtures/classic.json"), None),
        (include_str!("../../../../fixtures/nested.json"), None),
        (
            include_str!("../../../../fixtures/caustic.json"),
            Some(progressive),
        ),
    ] {
        let mut scene = Scene::from_json(json).unwrap();
        scene.camera = scene.camera.with_size(40, 24);
        let scene = Arc::new(scene);
        let w = Worker::new(Arc::new(|| {}));
        let g = match options {
            Some(o) => w.start_progressive(Arc::clone(&scene), o),
            None => w.start(Arc::clone(&scene), true),
        };
        let mut threaded = Folded::new(&scene);
        while !threaded.fold(w.recv().unwrap(), 40) {}
        let current = AtomicU64::new(g);
        // Row bands, one per call; then a pixel per call (no time left after each pixel).
        for (by_pixels, budget_ms, at_least) in
            [(false, f64::INFINITY, 2 * 24), (true, 0.0, 40 * 24)]
        {
            let (tx, rx) = channel();
            let job = Job {
                generation: g,
                scene: Arc::clone(&scene),
                image_first: true,
                progressive: options,
            };
            let mut run = if by_pixels {
                JobRun::by_pixels(job)
            } else {
                JobRun::new(job, 1, 1)
            };
            let mut inline = Folded::new(&scene);
            let mut slices = 0;
            while run_slices(&mut run, &current, &tx, budget_ms, 1) {
                slices += 1;
            }
            while let Ok(d) = rx.try_recv() {
                inline.fold(d, 40);
            }
            assert!(slices >= at_least, "{slices} slices");
            assert!(inline.growth.is_some());
            assert_eq!(inline, threaded, "by pixels: {by_pixels}");
            if options.is_some() {
                assert_eq!(inline.passes.len(), 2, "4 then 8 samples");
            }
        }
    }
}

#[test]
fn a_newer_generation_stops_the_sliced_job() {
    let mut scene = Scene::default_scene();
    scene.camera = scene.camera.with_size(16, 8);
    let current = AtomicU64::new(1);
    let (tx, rx) = channel();
    let job = Job {
        generation: 1,
        scene: Arc::new(scene),
        image_first: true,
        progressive: None,
    };
    let mut run = JobRun::new(job, 1, 1);
    assert!(run_slices(&mut run, &current, &tx, f64::INFINITY, 3));
    current.store(2, Ordering::SeqCst);
    assert!(!run_slices(&mut run, &current, &tx, f64::INFINITY, 3));
    assert_eq!(rx.try_iter().count(), 3, "three bands, then nothing");
}
