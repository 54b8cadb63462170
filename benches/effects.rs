//! "Simulate only what a scene calls for": a diffuse-only scene through the full tracer versus
//! a plain ray caster (camera and shadow rays only) written here as the baseline.
//!
//! Run: `cargo bench --bench effects`. Figures are in docs/cost.md.

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::bvh::TraversalCost;
use raytree::math::Rgb;
use raytree::sampling::SceneSampler;
use raytree::scene::Film;
use raytree::{NoopRecorder, RayCounts, Scene, Whitted, render_pixel};
use std::hint::black_box;
use std::time::{Duration, Instant};

const DIFFUSE_ONLY: &str = r#"{
  "camera": {"position": [0, 2, 7], "look_at": [0, 0.8, 0], "fov_y": 40, "width": 320, "height": 180},
  "background": [0.3, 0.5, 0.8], "ambient": [0.05, 0.05, 0.05],
  "materials": {
    "floor": {"diffuse": [0.7, 0.7, 0.7]},
    "red": {"diffuse": [0.8, 0.2, 0.2]},
    "blue": {"diffuse": [0.2, 0.3, 0.8]}
  },
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "sphere", "center": [-1.2, 1, 0], "radius": 1, "material": "red"},
    {"type": "sphere", "center": [1.2, 0.8, 0.8], "radius": 0.8, "material": "blue"},
    {"type": "box", "min": [-0.4, 0, -2], "max": [0.4, 2.5, -1.2], "material": "floor"}
  ],
  "lights": [{"type": "point", "position": [4, 7, 6], "intensity": [120, 120, 120]}]
}"#;

/// The baseline: Appel-style ray casting, the lecture's `evaluate_rendering_equation`. Camera
/// rays come from the camera's `film`, as the tracer's do.
fn ray_cast(scene: &Scene, film: &Film, x: u32, y: u32) -> Rgb {
    let ray = film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
    let Some(hit) = scene.intersect(&ray, f64::INFINITY) else {
        return scene.background;
    };
    let p = ray.at(hit.t);
    let n = if ray.direction.dot(hit.normal) < 0.0 {
        hit.normal
    } else {
        -hit.normal
    };
    let albedo = scene.material_of(hit.object).diffuse.at(p);
    let mut color = scene.ambient * albedo;
    let eps = scene.settings.offset.epsilon;
    // `sample_li` does not read a directional light's bounds.
    let bounds = (glam::DVec3::ZERO, 1.0);
    for k in 0..scene.lights.len() {
        let Some(ls) = scene.delta_light(k, bounds).sample_li(p, (0.5, 0.5)) else {
            continue;
        };
        let (wi, dist, e) = (ls.direction, ls.distance, ls.radiance);
        let cos = n.dot(wi);
        if cos > 0.0 {
            let shadow = raytree::math::Ray::new(p + eps * n, wi, 0.0);
            // Any-hit, the query the tracer's opaque shadow rays use.
            if !scene.occluded(&shadow, dist - eps, &mut TraversalCost::default()) {
                color += albedo * std::f64::consts::FRAC_1_PI * cos * e;
            }
        }
    }
    color
}

/// One frame with the caster or the tracer; returns a checksum so nothing is optimised away.
fn frame(scene: &Scene, tracer: &Whitted, caster: bool) -> f64 {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut counts = RayCounts::default();
    let film = scene.camera.film();
    let mut s = 0.0;
    for y in 0..h {
        for x in 0..w {
            s += if caster {
                ray_cast(black_box(scene), &film, x, y).x
            } else {
                render_pixel(
                    black_box(tracer),
                    &mut SceneSampler::for_settings(&black_box(tracer).scene().settings),
                    (x, y),
                    &mut NoopRecorder,
                    &mut counts,
                    |_| {},
                )
                .0
                .x
            };
        }
    }
    s
}

/// The two loops alternated frame by frame, 60 frames each, keeping each one's fastest frame:
/// load from other processes slows both alike and only ever adds time, so the ratio of the
/// minima is steadier on a shared machine than two criterion runs one after the other.
fn interleaved(scene: &Scene, tracer: &Whitted) {
    let (mut caster, mut traced) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..60 {
        let t = Instant::now();
        black_box(frame(scene, tracer, true));
        caster = caster.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        black_box(frame(scene, tracer, false));
        traced = traced.min(t.elapsed().as_secs_f64());
    }
    eprintln!(
        "interleaved, fastest of 60 frames each: plain ray caster {:.3} ms, raytree tracer {:.3} ms, \
         tracer/caster {:+.1}%",
        caster * 1e3,
        traced * 1e3,
        (traced / caster - 1.0) * 100.0
    );
}

fn bench(c: &mut Criterion) {
    let scene = Scene::from_json(DIFFUSE_ONLY).unwrap();
    let (w, h) = (scene.camera.width, scene.camera.height);
    // Same image (up to rounding), so the two loops do the same work.
    let tracer = Whitted::new(&scene);
    let mut counts = RayCounts::default();
    for y in (0..h).step_by(7) {
        for x in (0..w).step_by(5) {
            let a = render_pixel(
                &tracer,
                &mut SceneSampler::for_settings(&tracer.scene().settings),
                (x, y),
                &mut NoopRecorder,
                &mut counts,
                |_| {},
            )
            .0;
            let b = ray_cast(&scene, &scene.camera.film(), x, y);
            assert!(
                (a - b).abs().max_element() < 1e-12,
                "pixel {x},{y}: {a} vs {b}"
            );
        }
    }
    interleaved(&scene, &tracer);
    let mut g = c.benchmark_group("diffuse_only_320x180");
    g.sample_size(30).measurement_time(Duration::from_secs(5));
    g.bench_function("plain_ray_caster", |b| {
        b.iter(|| frame(&scene, &tracer, true))
    });
    g.bench_function("raytree_tracer", |b| {
        b.iter(|| frame(&scene, &tracer, false))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
