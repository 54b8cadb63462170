//! Cost of the offset strategies and of the diagnostics: the plain render (no-op recorder,
//! which must not pay for diagnostics) against the diagnosed render.

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::scene::OffsetStrategy;
use raytree::{Scene, render, render_diagnosed};
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
            b.iter(|| render(black_box(&s), &|_| {}));
        });
    }
    let s = scene(OffsetStrategy::Normal);
    g.bench_function("render_diagnosed_normal", |b| {
        b.iter(|| render_diagnosed(black_box(&s), &|_| {}));
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
