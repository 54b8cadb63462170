//! What accuracy costs in time: error metrics, the settings sweep against a reference, and the
//! Pareto front of error versus time. Pure apart from reading the clock.

use crate::integrator::RayCounts;
use crate::integrator::bound::auto_min_weight;
use crate::math::FresnelModel;
use crate::math::{Rgb, linear_to_srgb};
use crate::render::{Image, render};
use crate::scene::{OffsetStrategy, Scene, Settings, WhittedSettings};
use serde::Serialize;
use web_time::Instant;

mod sweep;
pub use sweep::Sweep;

/// Error of an image against a reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ErrorMetrics {
    /// Root mean square of the linear per-channel differences.
    pub rmse: f64,
    /// Largest linear per-channel difference.
    pub max: f64,
    /// Share of pixels where some sRGB-encoded channel differs by more than 1/255.
    pub off_8bit: f64,
}

/// Error metrics of `a` against `b`; `None` if the sizes differ.
#[must_use]
pub fn compare(a: &Image, b: &Image) -> Option<ErrorMetrics> {
    if (a.width, a.height) != (b.width, b.height) || a.pixels.is_empty() {
        return None;
    }
    let (mut sq, mut max, mut off) = (0.0, 0.0f64, 0usize);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (*p - *q).abs();
        sq += d.length_squared();
        max = max.max(d.max_element());
        let enc = |c: Rgb| c.to_array().map(linear_to_srgb);
        let (ep, eq) = (enc(*p), enc(*q));
        if ep.iter().zip(eq).any(|(x, y)| (x - y).abs() > 1.0 / 255.0) {
            off += 1;
        }
    }
    let n = a.pixels.len() as f64;
    Some(ErrorMetrics {
        rmse: (sq / (3.0 * n)).sqrt(),
        max,
        off_8bit: off as f64 / n,
    })
}

/// Per-pixel error (largest channel difference) for a false-colour map.
#[must_use]
pub fn error_map(a: &Image, b: &Image) -> Option<Vec<f64>> {
    ((a.width, a.height) == (b.width, b.height)).then(|| {
        a.pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| (*p - *q).abs().max_element())
            .collect()
    })
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CostRow {
    /// The swept axis.
    pub axis: String,
    /// Its value.
    pub value: String,
    /// Full settings used.
    #[serde(with = "crate::scene::desc::flat_settings")]
    pub settings: Settings,
    /// Median render time in milliseconds.
    pub median_ms: f64,
    /// Rays traced by kind.
    pub rays: RaysByKind,
    /// Error against the reference.
    pub error: ErrorMetrics,
    /// Whether no other row is both faster and more accurate (RMSE).
    pub pareto: bool,
}

/// Serializable ray counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct RaysByKind {
    /// Camera rays.
    pub camera: u64,
    /// Reflected rays.
    pub reflected: u64,
    /// Refracted rays.
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Diffuse bounces (path integrator).
    pub diffuse: u64,
    /// All rays.
    pub total: u64,
}

impl From<RayCounts> for RaysByKind {
    fn from(c: RayCounts) -> Self {
        Self {
            camera: c.camera,
            reflected: c.reflected,
            refracted: c.refracted,
            shadow: c.shadow,
            diffuse: c.diffuse,
            total: c.total(),
        }
    }
}

/// The whole report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CostReport {
    /// Image size.
    pub size: [u32; 2],
    /// Settings of the spp = 1 reference (every axis but spp is compared with it).
    #[serde(with = "crate::scene::desc::flat_settings")]
    pub reference: Settings,
    /// Reference samples per pixel for the spp and filter axes.
    pub reference_spp: u32,
    /// Reference light samples for the light-samples axis.
    pub reference_light_samples: u32,
    /// Reference glossy samples for the glossy-samples axis.
    pub reference_glossy_samples: u32,
    /// The base every row changes one setting of (min_weight `None`: the automatic cut).
    #[serde(with = "crate::scene::desc::flat_settings")]
    pub base: Settings,
    /// The automatic cut at the base settings.
    pub base_min_weight: f64,
    /// Rows in sweep order.
    pub rows: Vec<CostRow>,
}

/// The most accurate settings: deep recursion, exact Fresnel, no early termination and the
/// robust offset (no self-hits and no leaks at any scale, docs/numerics.md).
#[must_use]
pub fn reference_settings(base: &Settings, sweep: &Sweep) -> Settings {
    let mut s = Settings {
        max_depth: sweep.reference_depth,
        whitted: WhittedSettings {
            fresnel: FresnelModel::Exact,
            min_weight: Some(0.0),
            ..base.whitted
        },
        spp: 1,
        ..*base
    };
    s.offset.strategy = OffsetStrategy::Robust;
    s
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn with_settings(scene: &Scene, s: Settings) -> Scene {
    Scene {
        settings: s,
        ..scene.clone()
    }
}

/// Run the sweep. `progress(done, total)` is called after each render.
pub fn run(scene: &Scene, sweep: &Sweep, progress: &dyn Fn(usize, usize)) -> CostReport {
    let base = base_settings(scene);
    let configs = sweep.settings(scene, &base);
    let repeats = sweep.repeats.max(1) as usize;
    let reference = reference_settings(&base, sweep);
    let wanted = wanted_references(sweep, &configs, reference);
    let mut renders = Renders {
        done: 0,
        total: wanted.len() + configs.len() * repeats,
        progress,
    };
    let refs: Vec<(Settings, Image)> = wanted
        .into_iter()
        .map(|r| (r, renders.render(&with_settings(scene, r)).image))
        .collect();
    let measure = Measure {
        scene,
        sweep,
        reference,
        refs: &refs,
        repeats,
    };
    let mut rows = Vec::new();
    for (axis, value, settings) in configs {
        rows.push(measure.row(axis, value, settings, &mut renders));
    }
    mark_pareto(&mut rows);
    CostReport {
        size: [scene.camera.width, scene.camera.height],
        reference,
        reference_spp: sweep.reference_spp,
        reference_light_samples: sweep.reference_light_samples,
        reference_glossy_samples: sweep.reference_glossy_samples,
        base,
        base_min_weight: auto_min_weight(scene, &base),
        rows,
    }
}

/// The base every row changes one setting of.
///
/// The base is the default (the automatic min_weight) at depth 16; it differs from the
/// exhaustive reference in depth and the cut, so each axis shows its own error (the offset
/// axis keeps the scene's epsilon for the strategies that use one).
fn base_settings(scene: &Scene) -> Settings {
    let mut base = Settings {
        max_depth: 16,
        whitted: WhittedSettings {
            fresnel: FresnelModel::Exact,
            min_weight: None,
            dielectric_roulette: None,
            ..scene.settings.whitted
        },
        spp: 1,
        adaptive: None,
        antialiasing: crate::scene::Antialiasing::Uniform,
        ..scene.settings
    };
    base.offset.strategy = OffsetStrategy::Robust;
    base
}

/// The references: the pixel-centre one and the spp one first (the first render also warms
/// the thread pool and caches before anything is timed), then those of the other
/// stochastic axes, each once.
fn wanted_references(
    sweep: &Sweep,
    configs: &[(String, String, Settings)],
    reference: Settings,
) -> Vec<Settings> {
    let mut wanted = vec![
        reference,
        Settings {
            spp: sweep.reference_spp,
            ..reference
        },
    ];
    for (axis, _, s) in configs {
        let r = sweep.reference_for(axis, s, &reference);
        if !wanted.contains(&r) {
            wanted.push(r);
        }
    }
    wanted
}

/// The sweep's renders, counted for the progress callback.
struct Renders<'a> {
    done: usize,
    total: usize,
    progress: &'a dyn Fn(usize, usize),
}

impl Renders<'_> {
    /// Render `scene` with the default options and report the progress.
    fn render(&mut self, scene: &Scene) -> crate::render::Rendered {
        let r = render(
            &crate::integrator::SceneIntegrator::new(scene),
            &crate::render::RenderOptions::new(),
            &|_| {},
        );
        self.tick();
        r
    }

    /// Count one render done and report it.
    fn tick(&mut self) {
        self.done += 1;
        (self.progress)(self.done, self.total);
    }
}

/// What measuring a row needs: the scene, the sweep and the rendered references.
struct Measure<'a> {
    scene: &'a Scene,
    sweep: &'a Sweep,
    /// The pixel-centre reference's settings.
    reference: Settings,
    /// Every reference's settings and image.
    refs: &'a [(Settings, Image)],
    repeats: usize,
}

impl Measure<'_> {
    /// Render a row `repeats` times, and its median time, rays and error against its reference.
    fn row(
        &self,
        axis: String,
        value: String,
        settings: Settings,
        renders: &mut Renders,
    ) -> CostRow {
        let s = with_settings(self.scene, settings);
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..self.repeats {
            let start = Instant::now();
            let r = render(
                &crate::integrator::SceneIntegrator::new(&s),
                &crate::render::RenderOptions::new(),
                &|_| {},
            );
            times.push(start.elapsed().as_secs_f64() * 1e3);
            last = Some(r);
            renders.tick(); // after the clock: the progress bar is not timed
        }
        let crate::render::Rendered { image, stats, .. } = last.expect("at least one repeat");
        let want = self.sweep.reference_for(&axis, &settings, &self.reference);
        let reference = &self
            .refs
            .iter()
            .find(|(r, _)| *r == want)
            .expect("every reference rendered")
            .1;
        CostRow {
            axis,
            value,
            settings,
            median_ms: median(times),
            rays: stats.rays.into(),
            error: compare(&image, reference).expect("same size"),
            pareto: false,
        }
    }
}

/// Mark rows that no other row beats on both time and RMSE.
pub fn mark_pareto(rows: &mut [CostRow]) {
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.median_ms, r.error.rmse)).collect();
    for (i, r) in rows.iter_mut().enumerate() {
        let (t, e) = pts[i];
        r.pareto = !pts
            .iter()
            .enumerate()
            .any(|(j, &(t2, e2))| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

#[cfg(test)]
mod tests;
