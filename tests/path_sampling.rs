//! The path integrator's samplers and light choice (issue 15): the Sobol sampler (its default)
//! and the stratified one estimate the same image, Sobol with lower error at equal samples;
//! lights chosen in proportion to power keep the estimator unbiased (the selection pdf in the
//! light sample and in the MIS weight of emission found by BSDF sampling agree). Welch t-tests
//! per 8x8 block over seeds, as tests/path_stats.rs; fixed seeds; 5 standard errors.

use raytree::SceneIntegrator;
use raytree::integrator::{PathStrategy, PathTracer};
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::sampling::SceneSampler;
use raytree::scene::SamplerKind;
use raytree::{Scene, render};
use std::path::PathBuf;

fn lum(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var)
}

/// Block means (8x8 pixels) of one image `w` pixels wide.
fn blocks(img: &[Rgb], w: usize) -> Vec<f64> {
    let h = img.len() / w;
    let mut out = Vec::new();
    for by in (0..h).step_by(8) {
        for bx in (0..w).step_by(8) {
            let s: f64 = (by..by + 8)
                .flat_map(|y| (bx..bx + 8).map(move |x| y * w + x))
                .map(|i| lum(img[i]))
                .sum();
            out.push(s / 64.0);
        }
    }
    out
}

/// The largest Welch t over blocks between two sets of images (`[seed][pixel]`).
fn worst_block_t(a: &[Vec<Rgb>], b: &[Vec<Rgb>], w: usize) -> f64 {
    let ba: Vec<Vec<f64>> = a.iter().map(|i| blocks(i, w)).collect();
    let bb: Vec<Vec<f64>> = b.iter().map(|i| blocks(i, w)).collect();
    let mut worst: f64 = 0.0;
    for k in 0..ba[0].len() {
        let xa: Vec<f64> = ba.iter().map(|v| v[k]).collect();
        let xb: Vec<f64> = bb.iter().map(|v| v[k]).collect();
        let ((ma, va), (mb, vb)) = (mean_var(&xa), mean_var(&xb));
        let se = (va / xa.len() as f64 + vb / xb.len() as f64).sqrt();
        let t = (ma - mb) / se;
        assert!(t.abs() < 5.0, "block {k}: {ma} vs {mb}, t {t}");
        worst = worst.max(t.abs());
    }
    worst
}

/// The Cornell box fixture at `size`x`size`, max depth `depth`, `spp`, seed, sampler.
fn cornell(size: u32, depth: u32, spp: u32, seed: u64, sampler: SamplerKind) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/cornell-box.json");
    let mut s = Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap();
    s.camera = s.camera.with_size(size, size);
    s.settings.max_depth = depth;
    s.settings.spp = spp;
    s.settings.seed = seed;
    s.settings.sampler = Some(sampler);
    s
}

/// Sobol and stratified samples estimate the same Cornell box: per 8x8 block, the means over
/// 12 seeds agree within 5 standard errors.
#[test]
fn sobol_and_stratified_agree_in_mean() {
    let images = |kind| -> Vec<Vec<Rgb>> {
        (1..=12)
            .map(|seed| {
                render(
                    &SceneIntegrator::new(&cornell(16, 4, 8, seed, kind)),
                    &RenderOptions::new(),
                    &|_| {},
                )
                .image
                .pixels
            })
            .collect()
    };
    let t = worst_block_t(
        &images(SamplerKind::Sobol),
        &images(SamplerKind::Stratified),
        16,
    );
    eprintln!("largest |t| sobol vs stratified {t:.2}");
}

/// At equal samples per pixel, Sobol's error against a high-spp render of the Cornell box is
/// lower than the stratified sampler's (mean squared error over 4 seeds at 32 spp).
#[test]
fn sobol_has_lower_error_at_equal_samples() {
    let reference = render(
        &SceneIntegrator::new(&cornell(24, 4, 2048, 99, SamplerKind::Stratified)),
        &RenderOptions::new(),
        &|_| {},
    )
    .image
    .pixels;
    let mse = |kind| {
        let mut sum = 0.0;
        for seed in 1..=4 {
            let img = render(
                &SceneIntegrator::new(&cornell(24, 4, 32, seed, kind)),
                &RenderOptions::new(),
                &|_| {},
            )
            .image
            .pixels;
            sum += img
                .iter()
                .zip(&reference)
                .map(|(a, r)| (lum(*a) - lum(*r)).powi(2))
                .sum::<f64>();
        }
        sum / 4.0 / reference.len() as f64
    };
    let (sobol, strat) = (mse(SamplerKind::Sobol), mse(SamplerKind::Stratified));
    eprintln!(
        "MSE at 32 spp: sobol {sobol:.3e}, stratified {strat:.3e}, ratio {:.3}",
        sobol / strat
    );
    assert!(sobol < 0.8 * strat, "sobol {sobol} vs stratified {strat}");
}

/// Three area lights whose powers differ by 20x (a bright sphere, a dim wide quad, a
/// middling triangle) over a diffuse floor, direct light only. Power-proportional choice
/// (MIS) and BSDF sampling alone (no light choice at all) agree per block over 16 seeds: a
/// selection pdf in the MIS weight other than the one the light sample used would bias it.
#[test]
fn power_proportional_light_choice_is_unbiased() {
    let scene = |seed: u64| {
        Scene::from_json(&format!(
            r#"{{"camera": {{"position": [0, 2.5, 4], "look_at": [0, 0, 0], "fov_y": 50,
              "width": 32, "height": 24}},
              "materials": {{"floor": {{"diffuse": [0.7, 0.7, 0.7]}},
                "dim": {{"emission": [0.3, 0.3, 0.3]}}, "bright": {{"emission": [12, 10, 8]}},
                "mid": {{"emission": [2, 3, 4]}}}},
              "objects": [
                {{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}},
                {{"type": "quad", "name": "dim", "corner": [-3, 0.8, -3], "edge_u": [6, 0, 0], "edge_v": [0, 0, 2], "material": "dim"}},
                {{"type": "sphere", "name": "bright", "center": [1.2, 2, 0.5], "radius": 0.5, "material": "bright"}},
                {{"type": "triangle", "name": "mid", "vertices": [[-2, 1.5, 1], [-1, 1.5, 2], [-2, 1.5, 2]], "material": "mid"}}],
              "settings": {{"integrator": "path", "spp": 4, "max_depth": 0, "seed": {seed}}}}}"#
        ))
        .unwrap()
    };
    let images = |strategy| -> Vec<Vec<Rgb>> {
        (1..=16)
            .map(|seed| {
                let s = scene(seed);
                let pt = PathTracer::with_strategy(&s, strategy);
                let sampler = SceneSampler::new(SamplerKind::Stratified, 4, seed);
                render(&pt, &RenderOptions::new().with_sampler(sampler), &|_| {})
                    .image
                    .pixels
            })
            .collect()
    };
    let mis = images(PathStrategy::Mis);
    let t2 = worst_block_t(&mis, &images(PathStrategy::LightOnly), 32);
    let t1 = worst_block_t(&mis, &images(PathStrategy::BsdfOnly), 32);
    eprintln!("largest |t| MIS vs BSDF-only {t1:.2}, MIS vs light-only {t2:.2}");
}
