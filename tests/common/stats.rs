//! Block statistics shared by the estimator-agreement tests (`tests/bidirectional.rs`,
//! `tests/spot_lights.rs`): 8x8 block means of independent renders and Welch t statistics
//! between two integrators.

use ::raytree::math::Rgb;
use ::raytree::scene::IntegratorKind;
use ::raytree::{Scene, render};
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;

/// The mean of the three channels.
pub fn lum(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// Sample mean and (unbiased) variance.
pub fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var)
}

/// The mean luminance of each 8x8 block of `scene` rendered by `kind` at `seed`.
pub fn blocks(scene: &Scene, kind: IntegratorKind, seed: u64) -> Vec<f64> {
    let mut scene = scene.clone();
    scene.settings.integrator = kind;
    scene.settings.seed = seed;
    let (image, _, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let (w, h) = (image.width as usize, image.height as usize);
    let mut out = vec![0.0; (w / 8) * (h / 8)];
    for y in 0..h / 8 * 8 {
        for x in 0..w / 8 * 8 {
            out[(y / 8) * (w / 8) + x / 8] += lum(image.get(x as u32, y as u32)) / 64.0;
        }
    }
    out
}

/// The blocks of `seeds` independent renders by `kind`: `[seed][block]`.
pub fn renders(scene: &Scene, kind: IntegratorKind, seeds: u64) -> Vec<Vec<f64>> {
    (1..=seeds).map(|s| blocks(scene, kind, s)).collect()
}

/// Welch t statistics per block between `kind` and path tracing over `seeds` independent
/// renders each; returns the largest |t| and the mean block value.
pub fn agreement(scene: &Scene, kind: IntegratorKind, seeds: u64) -> (f64, f64) {
    let (light, path) = (
        renders(scene, kind, seeds),
        renders(scene, IntegratorKind::Path, seeds),
    );
    let mut worst: f64 = 0.0;
    let mut total = 0.0;
    for b in 0..light[0].len() {
        let l: Vec<f64> = light.iter().map(|v| v[b]).collect();
        let p: Vec<f64> = path.iter().map(|v| v[b]).collect();
        let ((ml, vl), (mp, vp)) = (mean_var(&l), mean_var(&p));
        let se = (vl / l.len() as f64 + vp / p.len() as f64).sqrt();
        total += mp;
        if se > 0.0 {
            worst = worst.max((ml - mp).abs() / se);
        } else {
            assert_eq!(ml, mp, "block {b}: no spread, different means");
        }
    }
    (worst, total / light[0].len() as f64)
}
