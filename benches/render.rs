//! Render throughput (Mrays/s), the cost of the recorder hooks, and one pixel's tree.
//!
//! Run: `cargo bench --bench render`. Figures are in README.md ("Performance"); throughput is
//! reported there as a ratio to a plain ray caster from `cargo bench --bench baseline`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::sampling::SceneSampler;
use raytree::tree::{NodeId, RayNode};
use raytree::{NoopRecorder, RayCounts, Recorder, Scene, render, render_pixel, trace_pixel};
use std::hint::black_box;
use std::time::Duration;

/// Counts hook calls but never builds a node: the cheapest recorder that does anything.
#[derive(Default)]
struct CountingRecorder {
    pushes: u64,
}

impl Recorder for CountingRecorder {
    const RECORDS: bool = false;

    fn push(&mut self, _: Option<NodeId>, _: impl FnOnce() -> RayNode) -> Option<NodeId> {
        self.pushes += 1;
        None
    }

    fn update(&mut self, _: Option<NodeId>, _: impl FnOnce(&mut RayNode)) {}
}

fn classic(w: u32, h: u32, spp: u32) -> Scene {
    let mut s = Scene::default_scene();
    s.camera = s.camera.with_size(w, h);
    s.settings.spp = spp;
    s.settings.max_depth = 16;
    s
}

fn throughput(c: &mut Criterion) {
    let mut g = c.benchmark_group("classic_1280x720_depth16");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for spp in [1, 16] {
        let scene = classic(1280, 720, spp);
        let rays = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .stats
        .rays
        .total();
        g.throughput(Throughput::Elements(rays));
        g.bench_function(format!("spp{spp}"), |b| {
            b.iter(|| {
                render(
                    &SceneIntegrator::new(black_box(&scene)),
                    &RenderOptions::new(),
                    &|_| {},
                )
            })
        });
    }
    g.finish();
}

/// Single-threaded full-image loops so the comparison is not blurred by the thread pool.
fn image_loop<R: Recorder>(scene: &Scene, rec: &mut R) -> f64 {
    let mut counts = RayCounts::default();
    let mut sum = 0.0;
    for y in 0..scene.camera.height {
        for x in 0..scene.camera.width {
            sum += render_pixel(
                &SceneIntegrator::new(scene),
                &mut SceneSampler::for_settings(&scene.settings),
                (x, y),
                rec,
                &mut counts,
                |_| {},
            )
            .0
            .x;
        }
    }
    sum
}

fn recorder_cost(c: &mut Criterion) {
    let scene = classic(320, 180, 1);
    let mut g = c.benchmark_group("recorder_320x180");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    g.bench_function("noop", |b| {
        b.iter(|| image_loop(black_box(&scene), &mut NoopRecorder))
    });
    g.bench_function("counting", |b| {
        b.iter(|| image_loop(black_box(&scene), &mut CountingRecorder::default()))
    });
    g.finish();
}

fn one_tree(c: &mut Criterion) {
    let scene = classic(640, 360, 1);
    let mut g = c.benchmark_group("trace_pixel");
    // A glass-ball pixel (deep binary tree) and a mirror-ball pixel.
    for (name, x, y) in [("glass_400_200", 400, 200), ("mirror_250_170", 250, 170)] {
        let nodes = trace_pixel(&scene, x, y).unwrap().nodes.len();
        g.bench_function(format!("{name}_{nodes}_nodes"), |b| {
            b.iter(|| trace_pixel(black_box(&scene), x, y))
        });
    }
    g.finish();
}

criterion_group!(benches, throughput, recorder_cost, one_tree);
criterion_main!(benches);
