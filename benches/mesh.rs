//! Mesh and BVH performance: primary-ray throughput on a 1.3M-triangle icosphere (1 and 2
//! threads; single rays and 8x8 packets; also at 1024x1024, a view `benches/embree.py` casts
//! with Embree), the whole direct-only render of that scene (shadow rays in packets too), time
//! per ray from 1K to 1.3M triangles, and the classic scene with the Stanford bunny in glass
//! (skipped when `../shared/data/meshes/` is absent).
//!
//! Run: `cargo bench --bench mesh`. Figures and the comparison with Embree: docs/mesh.md.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use raytree::Scene;
use raytree::SceneIntegrator;
use raytree::bvh::TraversalCost;
use raytree::mesh::{MeshData, parse_obj};
use raytree::render::RenderOptions;
use raytree::scene::icosphere_scene;
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

/// A unit icosphere of `level` subdivisions in front of the camera, filling most of the view.
fn sphere_scene(level: u32, size: u32) -> Scene {
    icosphere_scene(level, size, 3.0)
}

/// Closest hits of every pixel-centre camera ray; returns the number of hits.
fn cast_rows(scene: &Scene, rows: std::ops::Range<u32>) -> u64 {
    let cam = &scene.camera;
    let film = cam.film();
    let mut hits = 0;
    for y in rows {
        for x in 0..cam.width {
            let ray = film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
            hits += u64::from(scene.intersect(&ray, f64::INFINITY).is_some());
        }
    }
    hits
}

/// [`cast_rows`] for rows `y0..y0 + 8` as packets of 8x8 rays (`Scene::intersect_packet`,
/// the render's path for scenes with meshes).
fn cast_band(scene: &Scene, y0: u32) -> u64 {
    let cam = &scene.camera;
    let film = cam.film();
    let y1 = (y0 + 8).min(cam.height);
    let mut hits = 0;
    let mut rays = Vec::with_capacity(64);
    let mut found = [None; 64];
    let mut cost = [TraversalCost::default(); 64];
    for x0 in (0..cam.width).step_by(8) {
        rays.clear();
        for y in y0..y1 {
            for x in x0..(x0 + 8).min(cam.width) {
                rays.push(film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5));
            }
        }
        scene.intersect_packet(&rays, &mut found, &mut cost);
        hits += found[..rays.len()].iter().filter(|h| h.is_some()).count() as u64;
    }
    hits
}

fn cast_parallel(scene: &Scene, packets: bool) -> u64 {
    if packets {
        (0..scene.camera.height.div_ceil(8))
            .into_par_iter()
            .map(|b| cast_band(scene, b * 8))
            .sum()
    } else {
        (0..scene.camera.height)
            .into_par_iter()
            .map(|y| cast_rows(scene, y..y + 1))
            .sum()
    }
}

fn primary_1m(c: &mut Criterion) {
    let start = Instant::now();
    let scene = sphere_scene(8, 512);
    eprintln!(
        "icosphere level 8: {} triangles, scene built (incl. BVH) in {:.2} s",
        20 * 4u64.pow(8),
        start.elapsed().as_secs_f64()
    );
    let rays = u64::from(scene.camera.width * scene.camera.height);
    let hits = cast_rows(&scene, 0..512);
    eprintln!("hit fraction {:.3}", hits as f64 / rays as f64);
    assert_eq!(cast_parallel(&scene, true), hits);
    let mut g = c.benchmark_group("primary_icosphere_1.3M_512x512");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(rays));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for (name, packets) in [("", false), ("_packets8x8", true)] {
            g.bench_function(format!("threads{threads}{name}"), |b| {
                b.iter(|| pool.install(|| cast_parallel(black_box(&scene), packets)))
            });
        }
    }
    g.finish();
}

/// The views `benches/embree.py` also casts, 1 thread, packets (512x512 is above; 256x256 is
/// the scaling group's last row).
fn embree_views(c: &mut Criterion) {
    let scene = sphere_scene(8, 1024);
    let mut g = c.benchmark_group("primary_icosphere_1.3M_1024x1024");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(1024 * 1024));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    g.bench_function("threads1_packets8x8", |b| {
        b.iter(|| pool.install(|| cast_parallel(black_box(&scene), true)))
    });
    g.finish();
}

/// The whole render of the benchmark's scene (a diffuse sphere and a point light: the
/// direct-only path, camera and shadow rays both in 8x8 packets), 1 thread.
fn diffuse_render(c: &mut Criterion) {
    let scene = sphere_scene(8, 512);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("render_diffuse_icosphere_1.3M_512x512");
    g.sample_size(10).measurement_time(Duration::from_secs(6));
    g.throughput(Throughput::Elements(512 * 512));
    g.bench_function("threads1", |b| {
        b.iter(|| {
            pool.install(|| {
                raytree::render(
                    &SceneIntegrator::new(black_box(&scene)),
                    &RenderOptions::new(),
                    &|_| {},
                )
            })
        })
    });
    g.finish();
}

fn scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("primary_scaling_256x256_1thread");
    g.sample_size(10).measurement_time(Duration::from_secs(2));
    g.throughput(Throughput::Elements(256 * 256));
    for level in 3..=8 {
        let scene = sphere_scene(level, 256);
        let tris = 20 * 4u64.pow(level);
        g.bench_function(format!("{tris}_triangles"), |b| {
            b.iter(|| cast_rows(black_box(&scene), 0..256))
        });
        g.bench_function(format!("{tris}_triangles_packets8x8"), |b| {
            b.iter(|| {
                (0..256)
                    .step_by(8)
                    .map(|y| cast_band(black_box(&scene), y))
                    .sum::<u64>()
            })
        });
    }
    g.finish();
}

/// The lecture's classic scene with its glass ball replaced by the Stanford bunny.
fn bunny(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    let path = dir.join("stanford-bunny.obj");
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipping bunny benchmark: {} not found", path.display());
        return;
    };
    let data = parse_obj(&text).unwrap();
    let json = include_str!("../fixtures/mesh/bunny.json");
    let scene = Scene::from_json_with(json, &mut |_| Ok::<MeshData, String>(data.clone())).unwrap();
    let mut g = c.benchmark_group("bunny_glass_640x360_depth16");
    g.sample_size(10).measurement_time(Duration::from_secs(6));
    let rays = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .stats
    .rays
    .total();
    g.throughput(Throughput::Elements(rays));
    g.bench_function("render", |b| {
        b.iter(|| {
            raytree::render(
                &SceneIntegrator::new(black_box(&scene)),
                &RenderOptions::new(),
                &|_| {},
            )
        })
    });
    g.finish();
}

criterion_group!(
    benches,
    primary_1m,
    embree_views,
    diffuse_render,
    scaling,
    bunny
);
criterion_main!(benches);
