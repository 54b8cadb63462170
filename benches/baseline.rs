//! Throughput beside a baseline measured in the same run (issue 18): the classic scene's
//! rays/s through the full tracer (`raytree::render`: depth 16, every ray kind) and through a
//! plain ray caster over the same scene and view (camera rays at the same sample positions,
//! closest hit through the same object BVH, no shading, no secondary or shadow rays), both
//! over rayon's pool. The ratio, not the absolute rays/s, is the figure to compare across
//! machines (absolute figures have moved 2x between machines of one kind).
//!
//! The two are alternated frame by frame and each keeps its fastest frame: load from other
//! processes only ever adds time and hits both alike.
//!
//! Run: `cargo bench --bench baseline` (about a minute; `-- --frames N` to change the number
//! of 1-spp frames, 16 spp uses a quarter as many, at least 2). Figures: docs/cost.md.

use rayon::prelude::*;
use raytree::render::sample_position;
use raytree::{Scene, render};
use std::hint::black_box;
use std::time::Instant;

fn classic(spp: u32) -> Scene {
    let mut s = Scene::default_scene();
    s.camera = s.camera.with_size(1280, 720);
    s.settings.spp = spp;
    s.settings.max_depth = 16;
    s
}

/// The baseline: one closest-hit query per camera ray; returns (rays, hits).
fn ray_cast(scene: &Scene) -> (u64, u64) {
    let film = scene.camera.film();
    let (w, h, spp) = (scene.camera.width, scene.camera.height, scene.settings.spp);
    (0..h)
        .into_par_iter()
        .map(|y| {
            let mut hits = 0u64;
            for x in 0..w {
                for s in 0..spp {
                    let (fx, fy) = sample_position(x, y, s, spp);
                    let ray = film.ray(fx, fy);
                    hits += u64::from(black_box(scene).intersect(&ray, f64::INFINITY).is_some());
                }
            }
            (u64::from(w * spp), hits)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let frames: u32 = args
        .iter()
        .position(|a| a == "--frames")
        .and_then(|i| args.get(i + 1)?.parse().ok())
        .unwrap_or(12);
    eprintln!(
        "classic scene, 1280x720, depth 16, {} threads; fastest frame of each, alternated",
        rayon::current_num_threads()
    );
    for spp in [1, 16] {
        let scene = classic(spp);
        let n = if spp == 1 {
            frames
        } else {
            (frames / 4).max(2)
        };
        let (mut tracer_s, mut caster_s) = (f64::INFINITY, f64::INFINITY);
        let (mut tracer_rays, mut caster_rays) = (0, 0);
        // One untimed frame of each warms the pool and the caches.
        black_box(ray_cast(&scene));
        black_box(render(&scene, &|_| {}));
        for _ in 0..n {
            let t = Instant::now();
            let (rays, _) = black_box(ray_cast(&scene));
            caster_s = caster_s.min(t.elapsed().as_secs_f64());
            caster_rays = rays;
            let t = Instant::now();
            let (_, stats) = black_box(render(&scene, &|_| {}));
            tracer_s = tracer_s.min(t.elapsed().as_secs_f64());
            tracer_rays = stats.rays.total();
        }
        let tracer = tracer_rays as f64 / tracer_s / 1e6;
        let caster = caster_rays as f64 / caster_s / 1e6;
        eprintln!(
            "spp {spp:>2}: tracer {tracer_rays} rays in {:.1} ms = {tracer:.2} Mrays/s; plain ray \
             caster {caster_rays} camera rays in {:.1} ms = {caster:.2} Mrays/s; tracer/caster \
             rays/s {:.3}, time {:.2}x ({n} frames each)",
            tracer_s * 1e3,
            caster_s * 1e3,
            tracer / caster,
            tracer_s / caster_s
        );
    }
}
