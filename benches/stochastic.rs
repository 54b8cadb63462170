//! Samples per second of the stochastic fixtures (issue 14: "samples per second for the new
//! fixtures"; issue 15: the path tracer's), each beside the classic Whitted scene at the same
//! size and spp in the same run, so the ratio carries over between machines where the absolute
//! figure does not.
//!
//! Run: `cargo bench --bench stochastic`. Criterion reports elements/s, an element being one
//! camera sample (`width x height x spp`). Figures: docs/monte-carlo.md ("Samples per second").

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::{Scene, render};
use std::hint::black_box;
use std::time::Duration;

/// The fixtures, by name, with their JSON; `classic` is the built-in scene.
const FIXTURES: [(&str, &str); 5] = [
    (
        "soft-shadows",
        include_str!("../fixtures/soft-shadows.json"),
    ),
    ("glossy", include_str!("../fixtures/glossy.json")),
    (
        "depth-of-field",
        include_str!("../fixtures/depth-of-field.json"),
    ),
    (
        "cornell-box-path",
        include_str!("../fixtures/cornell-box.json"),
    ),
    ("caustic-path", include_str!("../fixtures/caustic.json")),
];

/// `scene` at 160x100 and 4 spp (the fixtures' own settings otherwise: light and glossy
/// samples, integrator, depth).
fn sized(mut s: Scene) -> Scene {
    s.camera = s.camera.with_size(160, 100);
    s.settings.spp = 4;
    s
}

fn samples_per_second(c: &mut Criterion) {
    let mut g = c.benchmark_group("samples_160x100_spp4");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    let mut scenes = vec![("classic-whitted", sized(Scene::default_scene()))];
    for (name, json) in FIXTURES {
        scenes.push((name, sized(Scene::from_json(json).expect("fixture loads"))));
    }
    for (name, scene) in &scenes {
        g.throughput(Throughput::Elements(160 * 100 * 4));
        g.bench_function(*name, |b| {
            b.iter(|| {
                render(
                    &SceneIntegrator::new(black_box(scene)),
                    &RenderOptions::new(),
                    &|_| {},
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, samples_per_second);
criterion_main!(benches);
