//! Statistical tests of the path integrator (issue 15): the white furnace, light sampling vs
//! BSDF sampling vs MIS (Welch t-tests per pixel block, as Nori's `ttest`), the convergence
//! rate against a high-spp render, and convergence to the Whitted image where light transport
//! has no diffuse interreflection. Fixed seeds; tolerances from measured variances (5 sigma).

use raytree::integrator::{PathStrategy, PathTracer};
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::render::render;
use raytree::sampling::{PixelSampler, StratifiedJitter, splitmix64, unit};
use raytree::scene::IntegratorKind;
use raytree::{Scene, SceneIntegrator};

fn lum(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// The image of `scene` under the path tracer with `strategy`.
fn path_image(scene: &Scene, strategy: PathStrategy) -> Vec<Rgb> {
    let pt = PathTracer::with_strategy(scene, strategy);
    let sampler = StratifiedJitter::for_settings(&scene.settings);
    render(&pt, &RenderOptions::new().with_sampler(sampler), &|_| {})
        .image
        .pixels
}

fn mean_var(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var)
}

/// A closed box of six inward-facing quads (outer sides inside), albedo `a`, emission `le`,
/// camera at its centre.
fn furnace(a: f64, le: f64, max_depth: u32, rr_depth: u32) -> Scene {
    let q = |name: &str, c: [f64; 3], u: [f64; 3], v: [f64; 3]| {
        format!(
            r#"{{"type": "quad", "name": "{name}", "corner": {c:?}, "edge_u": {u:?}, "edge_v": {v:?}, "material": "wall"}}"#
        )
    };
    let walls = [
        q("floor", [-1., -1., -1.], [0., 0., 2.], [2., 0., 0.]),
        q("ceiling", [-1., 1., -1.], [2., 0., 0.], [0., 0., 2.]),
        q("back", [-1., -1., -1.], [2., 0., 0.], [0., 2., 0.]),
        q("front", [-1., -1., 1.], [0., 2., 0.], [2., 0., 0.]),
        q("left", [-1., -1., -1.], [0., 2., 0.], [0., 0., 2.]),
        q("right", [1., -1., -1.], [0., 0., 2.], [0., 2., 0.]),
    ];
    let json = format!(
        r#"{{"camera": {{"position": [0.1, 0.05, 0.2], "look_at": [0.3, -0.2, -1], "fov_y": 70,
          "width": 24, "height": 24}},
          "materials": {{"wall": {{"diffuse": [{a}, {a}, {a}], "emission": [{le}, {le}, {le}]}}}},
          "objects": [{}],
          "settings": {{"integrator": "path", "spp": 8, "max_depth": {max_depth},
                        "rr_depth": {rr_depth}, "seed": 11}}}}"#,
        walls.join(",")
    );
    Scene::from_json(&json).unwrap()
}

/// White furnace: radiance Le (1 - a^(M+2)) / (1 - a) for max depth M (bounces up to M + 1),
/// within 5 standard errors of the pixel mean, with and without Russian roulette, with every
/// strategy.
#[test]
fn white_furnace() {
    let (a, le): (f64, f64) = (0.6, 1.5);
    for (max_depth, rr_depth) in [(60, 5), (60, 1024), (2, 1024)] {
        let expect = le * (1.0 - a.powi(max_depth as i32 + 2)) / (1.0 - a);
        let scene = furnace(a, le, max_depth, rr_depth);
        for strategy in [
            PathStrategy::Mis,
            PathStrategy::LightOnly,
            PathStrategy::BsdfOnly,
        ] {
            let px: Vec<f64> = path_image(&scene, strategy).iter().map(|p| p.x).collect();
            let (m, var) = mean_var(&px);
            let se = (var / px.len() as f64).sqrt();
            eprintln!(
                "furnace M {max_depth} rr {rr_depth} {strategy:?}: {m:.5} vs {expect:.5}, se {se:.2e}"
            );
            assert!(
                (m - expect).abs() < 5.0 * se + 1e-9,
                "M {max_depth} rr {rr_depth} {strategy:?}: {m} vs {expect} (se {se})"
            );
            // The furnace is a test of the estimator, not of luck: the error bar is tight.
            assert!(se < 0.02 * expect, "se {se}");
        }
    }
}

/// Direct light from a big close quad light and a small distant sphere light on a diffuse
/// floor: light sampling is poor for the big light, BSDF sampling for the small one.
fn two_lights(seed: u64) -> Scene {
    let json = format!(
        r#"{{"camera": {{"position": [0, 2.5, 4], "look_at": [0, 0, 0], "fov_y": 50,
          "width": 32, "height": 24}},
          "materials": {{"floor": {{"diffuse": [0.7, 0.7, 0.7]}},
            "big": {{"emission": [0.8, 0.8, 0.8]}}, "small": {{"emission": [12, 12, 12]}}}},
          "objects": [
            {{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}},
            {{"type": "quad", "name": "big", "corner": [-3, 0.6, -3], "edge_u": [6, 0, 0], "edge_v": [0, 0, 2], "material": "big"}},
            {{"type": "sphere", "name": "small", "center": [1.5, 3, 1], "radius": 0.25, "material": "small"}}],
          "settings": {{"integrator": "path", "spp": 4, "max_depth": 0, "seed": {seed}}}}}"#
    );
    Scene::from_json(&json).unwrap()
}

/// Block means (8x8 pixel blocks) of one image.
fn blocks(img: &[Rgb], w: usize, h: usize) -> Vec<f64> {
    let mut out = Vec::new();
    for by in (0..h).step_by(8) {
        for bx in (0..w).step_by(8) {
            let mut s = 0.0;
            for y in by..by + 8 {
                for x in bx..bx + 8 {
                    s += lum(img[y * w + x]);
                }
            }
            out.push(s / 64.0);
        }
    }
    out
}

/// Per strategy and seed, the block means; returns `[block][seed]`.
fn block_samples(strategy: PathStrategy, seeds: u64) -> (Vec<Vec<f64>>, f64) {
    let mut per_block: Vec<Vec<f64>> = Vec::new();
    let mut pixel_var = 0.0;
    let mut images = Vec::new();
    for seed in 1..=seeds {
        let scene = two_lights(seed);
        let img = path_image(&scene, strategy);
        for (i, b) in blocks(&img, 32, 24).into_iter().enumerate() {
            if per_block.len() <= i {
                per_block.push(Vec::new());
            }
            per_block[i].push(b);
        }
        images.push(img);
    }
    // Pixel variance across seeds, summed over pixels: the estimator's variance.
    for p in 0..images[0].len() {
        let v: Vec<f64> = images.iter().map(|img| lum(img[p])).collect();
        pixel_var += mean_var(&v).1;
    }
    (per_block, pixel_var)
}

/// Light sampling only, BSDF sampling only and MIS agree (Welch's t below 5 on every block and
/// pair), and MIS has the lowest summed pixel variance.
#[test]
fn strategies_agree_and_mis_has_the_lowest_variance() {
    let seeds = 24;
    let (mis, var_mis) = block_samples(PathStrategy::Mis, seeds);
    let (light, var_light) = block_samples(PathStrategy::LightOnly, seeds);
    let (bsdf, var_bsdf) = block_samples(PathStrategy::BsdfOnly, seeds);
    eprintln!("summed pixel variance: mis {var_mis:.4e} light {var_light:.4e} bsdf {var_bsdf:.4e}");
    let mut worst: f64 = 0.0;
    for (a, b) in [(&mis, &light), (&mis, &bsdf), (&light, &bsdf)] {
        for (xa, xb) in a.iter().zip(b.iter()) {
            let (ma, va) = mean_var(xa);
            let (mb, vb) = mean_var(xb);
            let t = (ma - mb) / ((va + vb) / xa.len() as f64).sqrt();
            worst = worst.max(t.abs());
            assert!(t.abs() < 5.0, "t = {t}: {ma} vs {mb}");
        }
    }
    eprintln!("largest |t| {worst:.2}");
    assert!(var_mis < var_light && var_mis < var_bsdf);
}

/// Independent uniform samples for every dimension, the film offset included (the default
/// sampler stratifies the film offset, which converges faster than N^-1/2 on edges).
#[derive(Clone, Copy, Debug)]
struct Independent {
    seed: u64,
    state: u64,
}

impl PixelSampler for Independent {
    fn start_sample(&mut self, (x, y): (u32, u32), s: u32) {
        self.state =
            splitmix64(splitmix64(self.seed ^ (u64::from(y) << 32 | u64::from(x))) ^ u64::from(s));
    }
    fn next_1d(&mut self) -> f64 {
        self.state = splitmix64(self.state);
        unit(self.state)
    }
    fn next_2d(&mut self) -> (f64, f64) {
        (self.next_1d(), self.next_1d())
    }
}

/// RMSE against a high-spp render (4096 spp) falls as N^-1/2: the log-log slope over
/// N = 4..256 is -0.5 +/- 0.1 (Cornell box, 16x16 pixels, max depth 3, independent samples;
/// the squared error averaged over 32, 16, 8, 4 seeds).
#[test]
fn rmse_falls_as_one_over_sqrt_n() {
    let text = std::fs::read_to_string("fixtures/cornell-box.json").unwrap();
    let mut base = Scene::from_json(&text).unwrap();
    base.camera = base.camera.with_size(16, 16);
    base.settings.max_depth = 3;
    let render_at = |spp: u32, seed: u64| {
        let mut s = base.clone();
        s.settings.spp = spp;
        let pt = PathTracer::new(&s);
        let sampler = Independent { seed, state: 0 };
        render(&pt, &RenderOptions::new().with_sampler(sampler), &|_| {})
            .image
            .pixels
    };
    let reference = render_at(4096, 99);
    let mut pts = Vec::new();
    for (i, n) in [4u32, 16, 64, 256].into_iter().enumerate() {
        // Average the squared error over independent seeds (fewer at higher N).
        let reps = 32 >> i;
        let mut se = 0.0;
        for r in 0..reps {
            let img = render_at(n, 1000 + r);
            se += img
                .iter()
                .zip(&reference)
                .map(|(a, b)| (lum(*a) - lum(*b)).powi(2))
                .sum::<f64>()
                / img.len() as f64;
        }
        let rmse = (se / f64::from(reps as u32)).sqrt();
        eprintln!("spp {n}: rmse {rmse:.5}");
        pts.push((f64::from(n).ln(), rmse.ln()));
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    eprintln!("log-log slope {slope:.3}");
    assert!((slope + 0.5).abs() < 0.1, "slope {slope}");
}

/// Per 8x8 block, the mean over seeds of (path - Whitted) is 0 within 5 standard errors; both
/// integrators see the same film positions (same sampler, seed and spp). The scenes set
/// `min_weight` 0: Whitted's automatic cut is a (small) bias the path tracer does not have.
fn converges_to_whitted(json: &str, w: usize, h: usize, seeds: u64) -> f64 {
    let mut diffs: Vec<Vec<f64>> = Vec::new();
    for seed in 1..=seeds {
        let mut scene = Scene::from_json(json).unwrap();
        scene.settings.seed = seed;
        scene.settings.integrator = IntegratorKind::Whitted;
        let sampler = StratifiedJitter::for_settings(&scene.settings);
        let whitted = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new().with_sampler(sampler),
            &|_| {},
        )
        .image;
        scene.settings.integrator = IntegratorKind::Path;
        let path = path_image(&scene, PathStrategy::Mis);
        let d: Vec<Rgb> = path
            .iter()
            .zip(&whitted.pixels)
            .map(|(p, w)| *p - *w)
            .collect();
        for (i, b) in blocks(&d, w, h).into_iter().enumerate() {
            if diffs.len() <= i {
                diffs.push(Vec::new());
            }
            diffs[i].push(b);
        }
    }
    let mut worst: f64 = 0.0;
    for d in &diffs {
        let (m, v) = mean_var(d);
        if v == 0.0 {
            assert!(m.abs() < 1e-12, "{m}");
            continue;
        }
        let t = m / (v / d.len() as f64).sqrt();
        worst = worst.max(t.abs());
        assert!(t.abs() < 5.0, "block mean difference {m}, t {t}");
    }
    worst
}

/// Delta lights (a point and a directional light, so light selection picks one of two) on a
/// diffuse floor, black background. (No specular objects here: a floor that sees itself in a
/// mirror or through glass has diffuse interreflection, which Whitted lacks: measured, a
/// mirror and a glass ball on this floor make the path image brighter by 2e-4 on a block, 6
/// standard errors.)
#[test]
fn delta_lights_on_a_diffuse_floor_converge_to_whitted() {
    let json = r#"{"camera": {"position": [0, 1.5, 5], "look_at": [0, 0.6, 0], "fov_y": 45,
      "width": 32, "height": 24},
      "materials": {"floor": {"diffuse": {"checker": {"even": [0.8, 0.8, 0.8], "odd": [0.2, 0.3, 0.6], "size": 0.5}}}},
      "objects": [
        {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}],
      "lights": [{"type": "point", "position": [2, 4, 3], "intensity": [30, 30, 30]},
        {"type": "directional", "direction": [-1, -2, -0.5], "irradiance": [0.5, 0.4, 0.3]}],
      "settings": {"integrator": "path", "spp": 4, "max_depth": 8, "rr_depth": 1024, "min_weight": 0}}"#;
    let worst = converges_to_whitted(json, 32, 24, 16);
    eprintln!("largest |t| {worst:.2}");
}

/// Specular chains ending on an emitter (a mirror and an absorbing glass ball in front of an
/// emissive quad, the background behind; no diffuse surface), and direct light of an area light
/// on a diffuse plane (Whitted's light_samples).
#[test]
fn specular_chains_to_emitters_and_area_direct_light_converge_to_whitted() {
    let chains = r#"{"camera": {"position": [0, 0.5, 5], "look_at": [0, 0.5, 0], "fov_y": 45,
      "width": 32, "height": 24}, "background": [0.1, 0.2, 0.3],
      "materials": {"mirror": {"reflectivity": [0.9, 0.9, 0.9]},
        "glass": {"transmissivity": [1, 1, 1], "ior": 1.5, "absorption": [0.3, 0.1, 0.05]},
        "lamp": {"emission": [4, 3, 2]}},
      "objects": [
        {"type": "sphere", "name": "mirror", "center": [-0.8, 0.6, 0], "radius": 0.6, "material": "mirror"},
        {"type": "sphere", "name": "glass", "center": [0.8, 0.6, 0.5], "radius": 0.6, "material": "glass"},
        {"type": "quad", "name": "lamp", "corner": [-2, -1, -2], "edge_u": [4, 0, 0], "edge_v": [0, 2.5, 0], "material": "lamp"}],
      "settings": {"integrator": "path", "spp": 4, "max_depth": 8, "rr_depth": 1024, "min_weight": 0}}"#;
    let w1 = converges_to_whitted(chains, 32, 24, 16);
    let area = r#"{"camera": {"position": [0, 2.5, 4], "look_at": [0, 0, 0], "fov_y": 50,
      "width": 32, "height": 24},
      "materials": {"floor": {"diffuse": [0.7, 0.6, 0.5]}, "lamp": {"emission": [5, 5, 5]}},
      "objects": [
        {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
        {"type": "quad", "name": "lamp", "corner": [-0.5, 1.5, -0.5], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "material": "lamp"}],
      "settings": {"integrator": "path", "spp": 4, "max_depth": 4, "light_samples": 1, "min_weight": 0}}"#;
    let w2 = converges_to_whitted(area, 32, 24, 16);
    eprintln!("largest |t| {w1:.2}, {w2:.2}");
}
