//! The render with feature buffers: the same samples as [`crate::render::render_sampled`] (the
//! same camera samples, integrator calls and sum, so the same image bit for bit), plus per pixel
//! the mean albedo and normal of its samples' feature rays and the variance of its mean
//! luminance.

use super::Features;
use super::features::first_non_delta;
use crate::bsdf::luminance;
use crate::math::Rgb;
use crate::render::{Image, RenderStats, camera_sample};
use crate::sampling::{PixelSampler, SceneSampler};
use crate::scene::IntegratorKind;
use crate::trace::{Integrator, NoopRecorder, RayCounts, Tracer};
use glam::DVec3;
use rayon::prelude::*;

/// One pixel's beauty value and features.
struct Px {
    color: Rgb,
    albedo: Rgb,
    normal: DVec3,
    variance: f64,
    albedo_variance: f64,
}

/// [`gather_sampled`] with the scene's default sampler, as [`crate::render::render_with`].
pub fn gather<I: Integrator>(
    integrator: &I,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, Features) {
    let sampler = SceneSampler::for_settings(&integrator.scene().settings);
    gather_sampled(integrator, &sampler, progress)
}

/// Render every pixel as [`crate::render::render_sampled`] does (rows in parallel, copies of
/// `sampler`), and gather the features. `progress` is called with the rows finished so far.
pub fn gather_sampled<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, Features) {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let filter = scene.settings.filter.filter();
    let film = integrator.film();
    let tracer = Tracer::new(scene);
    let whitted = integrator.kind() == IntegratorKind::Whitted;
    let done = std::sync::atomic::AtomicU32::new(0);
    let rows: Vec<(Vec<Px>, RayCounts)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut counts = RayCounts::default();
            let mut sampler = sampler.clone();
            let row = (0..w)
                .map(|x| {
                    let (mut sum, mut albedo, mut normal) = (Rgb::ZERO, Rgb::ZERO, DVec3::ZERO);
                    let (mut m1, mut m2, mut n) = (0.0, 0.0, 0u32);
                    let (mut a1, mut a2) = (0.0, 0.0);
                    for s in 0..spp {
                        let (_, ray) = camera_sample(film, filter, &mut sampler, x, y, s);
                        let f = first_non_delta(&tracer, ray);
                        let (l, _) = integrator.camera_radiance(
                            ray,
                            &mut sampler,
                            &mut NoopRecorder,
                            &mut counts,
                        );
                        if counts.keep_sample(l, whitted, (x, y, s)) {
                            sum += l;
                        }
                        if l.is_finite() {
                            let y = luminance(l);
                            m1 += y;
                            m2 += y * y;
                            n += 1;
                        }
                        albedo += f.albedo;
                        let ya = luminance(f.albedo);
                        a1 += ya;
                        a2 += ya * ya;
                        normal += f.normal;
                    }
                    let k = f64::from(spp);
                    // Variance of the mean: the unbiased sample variance over n.
                    let variance = variance_of_mean(m1, m2, n);
                    let albedo_variance = variance_of_mean(a1, a2, spp);
                    Px {
                        color: sum / k,
                        albedo: albedo / k,
                        normal: normal / k,
                        variance,
                        albedo_variance,
                    }
                })
                .collect();
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            (row, counts)
        })
        .collect();
    let mut stats = RenderStats::default();
    let n = (w * h) as usize;
    let mut pixels = Vec::with_capacity(n);
    let mut features = Features {
        width: w,
        height: h,
        albedo: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        variance: Vec::with_capacity(n),
        albedo_variance: Vec::with_capacity(n),
        spp,
        stochastic: !integrator.traces_packets() || film.has_lens(),
    };
    for (y, (row, counts)) in rows.into_iter().enumerate() {
        stats.rays += counts;
        for (x, p) in row.into_iter().enumerate() {
            pixels.push(stats.admit_pixel(p.color, x, y));
            let finite = |v: Rgb| if v.is_finite() { v } else { Rgb::ZERO };
            features.albedo.push(finite(p.albedo));
            features.normal.push(finite(p.normal));
            let finite_f = |v: f64| if v.is_finite() { v } else { 0.0 };
            features.variance.push(finite_f(p.variance));
            features.albedo_variance.push(finite_f(p.albedo_variance));
        }
    }
    let image = Image {
        width: w,
        height: h,
        pixels,
    };
    (image, stats, features)
}

/// The variance of the mean of `n` values from their sum `s1` and sum of squares `s2` (the
/// unbiased sample variance over `n`); 0 for fewer than two values.
fn variance_of_mean(s1: f64, s2: f64, n: u32) -> f64 {
    if n < 2 {
        return 0.0;
    }
    let nf = f64::from(n);
    let mean = s1 / nf;
    (s2 / nf - mean * mean).max(0.0) / (nf - 1.0)
}
