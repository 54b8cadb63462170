//! Cost of the offset strategies and of the diagnostics: the plain render (no-op recorder,
//! which must not pay for diagnostics) against the diagnosed render.

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::scene::OffsetStrategy;
use raytree::{Scene, render};
use std::hint::black_box;
use std::time::Duration;

fn scene(strategy: OffsetStrategy) -> Scene {
    let mut s = Scene::default_scene();
    s.camera = s.camera.with_size(96, 72);
    s.settings.offset.strategy = strategy;
    s
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("numerics");
    g.measurement_time(Duration::from_secs(3)).sample_size(15);
    for st in [OffsetStrategy::Normal, OffsetStrategy::Robust] {
        let s = scene(st);
        g.bench_function(format!("render_{}", st.name()), |b| {
            b.iter(|| {
                render(
                    &SceneIntegrator::new(black_box(&s)),
                    &RenderOptions::new(),
                    &|_| {},
                )
            });
        });
    }
    let s = scene(OffsetStrategy::Normal);
    g.bench_function("render_diagnosed_normal", |b| {
        b.iter(|| {
            render(
                &SceneIntegrator::new(black_box(&s)),
                &RenderOptions::diagnosed(),
                &|_| {},
            )
            .into_parts()
        });
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
