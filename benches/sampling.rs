//! Samples per second of the Monte Carlo building blocks: the pixel sampler, every warp, the
//! pixel filters, the light samplers and each BSDF's `sample`. Each iteration draws a batch of
//! 1024 samples (criterion's throughput gives samples/s). Figures: `docs/monte-carlo.md`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use raytree::bsdf::{Bsdf, Frame, Lobe, Microfacet};
use raytree::lights::{PlanarEmitter, sample_sphere};
use raytree::math::Rgb;
use raytree::sampling::{PixelFilter, SobolSampler, SplitMix64, warp};
use std::hint::black_box;
use std::time::Duration;

const BATCH: usize = 1024;

/// A fixed batch of uniform points so that the benchmarks time the warp, not the generator.
fn points() -> Vec<DVec2> {
    let mut rng = SplitMix64::new(1);
    (0..BATCH).map(|_| rng.next_2d()).collect()
}

fn bench(c: &mut Criterion) {
    let us = points();
    let mut g = c.benchmark_group("sampling");
    g.measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(500))
        .sample_size(20)
        .throughput(Throughput::Elements(BATCH as u64));

    g.bench_function("sobol_pixel_sampler_2d", |b| {
        b.iter(|| {
            let mut acc = DVec2::ZERO;
            for i in 0..BATCH as u32 {
                acc += SobolSampler::new(7, (i & 63, i >> 6), i).next_2d();
            }
            black_box(acc)
        });
    });
    let mut warp_bench = |name: &str, f: &dyn Fn(DVec2) -> DVec3| {
        g.bench_function(name, |b| {
            b.iter(|| us.iter().fold(DVec3::ZERO, |a, &u| a + f(black_box(u))));
        });
    };
    warp_bench("cosine_hemisphere", &warp::square_to_cosine_hemisphere);
    warp_bench("uniform_cone", &|u| {
        warp::square_to_uniform_cone(u, 0.9, 0.19)
    });
    warp_bench("concentric_disk", &|u| {
        warp::square_to_concentric_disk(u).extend(0.0)
    });
    warp_bench(
        "triangle_barycentrics",
        &warp::square_to_triangle_barycentrics,
    );
    for (name, f) in [
        ("filter_box", PixelFilter::Box),
        ("filter_tent", PixelFilter::Tent { radius: 1.5 }),
        (
            "filter_gaussian",
            PixelFilter::Gaussian {
                sigma: 0.5,
                radius: 1.5,
            },
        ),
    ] {
        warp_bench(name, &move |u| f.sample(u).extend(0.0));
    }
    let p = DVec3::new(0.1, 0.0, 0.2);
    warp_bench("light_sphere", &|u| {
        sample_sphere(p, DVec3::new(0.0, 3.0, 0.0), 0.5, Rgb::ONE, u)
            .map_or(DVec3::ZERO, |s| s.direction)
    });
    let quad = PlanarEmitter::quad(DVec3::new(-1.0, 2.0, -1.0), DVec3::X * 2.0, DVec3::Z * 2.0);
    warp_bench("light_quad", &|u| {
        quad.sample(p, Rgb::ONE, u)
            .map_or(DVec3::ZERO, |s| s.direction)
    });
    let tri = PlanarEmitter::triangle(
        DVec3::new(-1.0, 2.0, -1.0),
        DVec3::new(1.0, 2.0, -1.0),
        DVec3::new(-1.0, 2.0, 1.0),
    );
    warp_bench("light_triangle", &|u| {
        tri.sample(p, Rgb::ONE, u)
            .map_or(DVec3::ZERO, |s| s.direction)
    });
    let ggx = Microfacet::new(0.3);
    let wo = DVec3::new(0.5, 0.1, 0.8).normalize();
    warp_bench("ggx_visible_normal", &|u| ggx.sample_visible(wo, u));
    let frame = Frame::from_normal(DVec3::Z);
    let bsdfs = [
        (
            "bsdf_lambert",
            Lobe::Lambert {
                albedo: Rgb::splat(0.5),
            },
        ),
        ("bsdf_mirror", Lobe::Mirror { weight: Rgb::ONE }),
        (
            "bsdf_dielectric",
            Lobe::Dielectric {
                weight: Rgb::ONE,
                eta: 1.5,
            },
        ),
        (
            "bsdf_rough_mirror",
            Lobe::RoughMirror {
                weight: Rgb::ONE,
                dist: ggx,
            },
        ),
        (
            "bsdf_rough_dielectric",
            Lobe::RoughDielectric {
                weight: Rgb::ONE,
                eta: 1.5,
                dist: ggx,
            },
        ),
    ];
    for (name, lobe) in bsdfs {
        let bsdf = Bsdf::new(frame, &[lobe]);
        warp_bench(name, &move |u| {
            bsdf.sample_local(wo, u.y, u).map_or(DVec3::ZERO, |s| s.wi)
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
