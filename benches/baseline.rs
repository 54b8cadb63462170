//! Throughput beside a baseline measured in the same run (issue 18): the classic scene's
//! rays/s through the full tracer (`raytree::render`: depth 16, every ray kind) and through a
//! plain ray caster over the same scene and view (camera rays at the same sample positions,
//! closest hit through the same object BVH, no shading, no secondary or shadow rays), both
//! over rayon's pool. The ratio, not the absolute rays/s, is the figure to compare across
//! machines (absolute figures have moved 2x between machines of one kind).
//!
//! The two are alternated band by band (16 rows, a few to a hundred milliseconds each): every
//! pass times the caster and then the tracer on each band, each band keeps its fastest time
//! over the passes, and a frame's time is the sum of its bands' fastest. Load from other
//! processes only ever adds time and hits both alike; short bands find the quiet moments that
//! whole frames of several seconds do not on a shared machine.
//!
//! Run: `cargo bench --bench baseline` (about a minute; `-- --passes N` to change the number
//! of passes at 1 spp, default 12; 16 spp makes a quarter as many, at least 3). Figures:
//! docs/cost.md.

use rayon::prelude::*;
use raytree::render::render_rows;
use raytree::render::sample_position;
use raytree::{Scene, Whitted};
use std::hint::black_box;
use std::time::Instant;

fn classic(spp: u32) -> Scene {
    let mut s = Scene::default_scene();
    s.camera = s.camera.with_size(1280, 720);
    s.settings.spp = spp;
    s.settings.max_depth = 16;
    s
}

/// The baseline: one closest-hit query per camera ray over `rows`; returns the rays.
fn ray_cast(scene: &Scene, rows: std::ops::Range<u32>) -> u64 {
    let film = scene.camera.film();
    let (w, spp) = (scene.camera.width, scene.settings.spp);
    rows.into_par_iter()
        .map(|y| {
            let mut hits = 0u64;
            for x in 0..w {
                for s in 0..spp {
                    let (fx, fy) = sample_position(x, y, s, spp);
                    let ray = film.ray(fx, fy);
                    hits += u64::from(black_box(scene).intersect(&ray, f64::INFINITY).is_some());
                }
            }
            black_box(hits);
            u64::from(w * spp)
        })
        .sum()
}

const BAND: u32 = 16;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let passes: u32 = args
        .iter()
        .position(|a| a == "--passes")
        .and_then(|i| args.get(i + 1)?.parse().ok())
        .unwrap_or(12);
    eprintln!(
        "classic scene, 1280x720, depth 16, {} threads; bands of {BAND} rows alternated, fastest \
         of each band summed",
        rayon::current_num_threads()
    );
    for spp in [1, 16] {
        let scene = classic(spp);
        let tracer = Whitted::new(&scene);
        let n = if spp == 1 {
            passes
        } else {
            (passes / 4).max(3)
        };
        let h = scene.camera.height;
        let bands: Vec<std::ops::Range<u32>> = (0..h)
            .step_by(BAND as usize)
            .map(|y| y..(y + BAND).min(h))
            .collect();
        let (mut tracer_t, mut caster_t) = (
            vec![f64::INFINITY; bands.len()],
            vec![f64::INFINITY; bands.len()],
        );
        let (mut tracer_rays, mut caster_rays) = (0, 0);
        // One untimed frame of each warms the pool and the caches.
        for b in &bands {
            black_box(ray_cast(&scene, b.clone()));
            black_box(render_rows(&tracer, b.clone()));
        }
        for _ in 0..n {
            (tracer_rays, caster_rays) = (0, 0);
            for (i, b) in bands.iter().enumerate() {
                let t = Instant::now();
                caster_rays += black_box(ray_cast(&scene, b.clone()));
                caster_t[i] = caster_t[i].min(t.elapsed().as_secs_f64());
                let t = Instant::now();
                let (_, counts) = black_box(render_rows(&tracer, b.clone()));
                tracer_t[i] = tracer_t[i].min(t.elapsed().as_secs_f64());
                tracer_rays += counts.total();
            }
        }
        let (tracer_s, caster_s): (f64, f64) = (tracer_t.iter().sum(), caster_t.iter().sum());
        let tracer = tracer_rays as f64 / tracer_s / 1e6;
        let caster = caster_rays as f64 / caster_s / 1e6;
        eprintln!(
            "spp {spp:>2}: tracer {tracer_rays} rays in {:.1} ms = {tracer:.2} Mrays/s; plain ray \
             caster {caster_rays} camera rays in {:.1} ms = {caster:.2} Mrays/s; tracer/caster \
             rays/s {:.3}, time {:.2}x ({n} passes)",
            tracer_s * 1e3,
            caster_s * 1e3,
            tracer / caster,
            tracer_s / caster_s
        );
    }
}
