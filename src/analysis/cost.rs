//! What accuracy costs in time: error metrics, the settings sweep against a reference, and the
//! Pareto front of error versus time. Pure apart from reading the clock.

use crate::math::FresnelModel;
use crate::math::{Rgb, linear_to_srgb};
use crate::render::{Image, render};
use crate::scene::{OffsetStrategy, Scene, Settings};
use crate::trace::RayCounts;
use crate::trace::bound::auto_min_weight;
use serde::Serialize;
use std::time::Instant;

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

/// The sweep: which values each axis takes.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// Max depths.
    pub depths: Vec<u32>,
    /// Fresnel models.
    pub fresnels: Vec<FresnelModel>,
    /// Samples per pixel.
    pub spps: Vec<u32>,
    /// Offset strategies.
    pub offsets: Vec<OffsetStrategy>,
    /// Min weights; `None` is the automatic cut (the default, `crate::trace::bound`).
    pub min_weights: Vec<Option<f64>>,
    /// Reference max depth.
    pub reference_depth: u32,
    /// Reference samples per pixel (for the spp axis).
    pub reference_spp: u32,
    /// Timed repeats per setting (median reported).
    pub repeats: u32,
}

impl Sweep {
    /// The full sweep of the issue: depth 0..16, every Fresnel model, 1/4/16 spp, every offset
    /// strategy, and min_weight from off to coarse with the automatic cut beside them.
    #[must_use]
    pub fn full() -> Self {
        Self {
            depths: vec![0, 1, 2, 4, 8, 16],
            fresnels: vec![
                FresnelModel::None,
                FresnelModel::Schlick,
                FresnelModel::Exact,
            ],
            spps: vec![1, 4, 16],
            offsets: OffsetStrategy::ALL.to_vec(),
            // 1 / (255 * 12.92): the smallest linear step visible in 8-bit sRGB near black.
            min_weights: vec![
                Some(0.0),
                None,
                Some(3.0e-4),
                Some(1.0e-3),
                Some(1.0e-2),
                Some(5.0e-2),
            ],
            reference_depth: 32,
            reference_spp: 64,
            repeats: 5,
        }
    }

    /// A small sweep for a quick look.
    #[must_use]
    pub fn quick() -> Self {
        Self {
            depths: vec![0, 1, 4, 16],
            spps: vec![1, 4],
            min_weights: vec![Some(0.0), None, Some(1.0e-2)],
            reference_spp: 16,
            repeats: 3,
            ..Self::full()
        }
    }

    /// The settings of every row, as `(axis, value label, settings)`, from `base`. The
    /// automatic min_weight row is labelled `auto (w)` with the cut it takes on `scene`.
    #[must_use]
    pub fn settings(&self, scene: &Scene, base: &Settings) -> Vec<(String, String, Settings)> {
        let mut out = Vec::new();
        let mut push =
            |axis: &str, value: String, s: Settings| out.push((axis.to_string(), value, s));
        for &d in &self.depths {
            push(
                "max_depth",
                d.to_string(),
                Settings {
                    max_depth: d,
                    ..*base
                },
            );
        }
        for &f in &self.fresnels {
            push(
                "fresnel",
                format!("{f:?}").to_lowercase(),
                Settings {
                    fresnel: f,
                    ..*base
                },
            );
        }
        for &n in &self.spps {
            push("spp", n.to_string(), Settings { spp: n, ..*base });
        }
        for &o in &self.offsets {
            let mut s = *base;
            s.offset.strategy = o;
            push("offset", o.name().to_string(), s);
        }
        for &w in &self.min_weights {
            let s = Settings {
                min_weight: w,
                ..*base
            };
            let label = match w {
                Some(w) => format!("{w:e}"),
                None => format!("auto ({:.1e})", auto_min_weight(scene, &s)),
            };
            push("min_weight", label, s);
        }
        out
    }
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CostRow {
    /// The swept axis.
    pub axis: String,
    /// Its value.
    pub value: String,
    /// Full settings used.
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
    pub reference: Settings,
    /// Reference samples per pixel for the spp axis.
    pub reference_spp: u32,
    /// The base every row changes one setting of (min_weight `None`: the automatic cut).
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
        fresnel: FresnelModel::Exact,
        min_weight: Some(0.0),
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
    // The base is the default (the automatic min_weight) at depth 16; it differs from the
    // exhaustive reference in depth and the cut, so each axis shows its own error (the offset
    // axis keeps the scene's epsilon for the strategies that use one).
    let mut base = Settings {
        max_depth: 16,
        fresnel: FresnelModel::Exact,
        spp: 1,
        min_weight: None,
        ..scene.settings
    };
    base.offset.strategy = OffsetStrategy::Robust;
    let configs = sweep.settings(scene, &base);
    let repeats = sweep.repeats.max(1) as usize;
    let total = 2 + configs.len() * repeats;
    let mut done = 0;
    let reference = reference_settings(&base, sweep);
    // The first render also warms the thread pool and caches before anything is timed.
    let ref1 = render(&with_settings(scene, reference), &|_| {}).0;
    done += 1;
    progress(done, total);
    let ref_many = render(
        &with_settings(
            scene,
            Settings {
                spp: sweep.reference_spp,
                ..reference
            },
        ),
        &|_| {},
    )
    .0;
    done += 1;
    progress(done, total);
    let mut rows = Vec::new();
    for (axis, value, settings) in configs {
        let s = with_settings(scene, settings);
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..repeats {
            let start = Instant::now();
            let r = render(&s, &|_| {});
            times.push(start.elapsed().as_secs_f64() * 1e3);
            last = Some(r);
            done += 1;
            progress(done, total);
        }
        let (image, stats) = last.expect("at least one repeat");
        let reference = if axis == "spp" { &ref_many } else { &ref1 };
        rows.push(CostRow {
            axis,
            value,
            settings,
            median_ms: median(times),
            rays: stats.rays.into(),
            error: compare(&image, reference).expect("same size"),
            pareto: false,
        });
    }
    mark_pareto(&mut rows);
    CostReport {
        size: [scene.camera.width, scene.camera.height],
        reference,
        reference_spp: sweep.reference_spp,
        base,
        base_min_weight: auto_min_weight(scene, &base),
        rows,
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
mod tests {
    use super::*;

    fn img(p: &[Rgb]) -> Image {
        Image {
            width: p.len() as u32,
            height: 1,
            pixels: p.to_vec(),
        }
    }

    #[test]
    fn metrics_closed_form() {
        let a = img(&[Rgb::ZERO, Rgb::splat(0.5)]);
        assert_eq!(compare(&a, &a).unwrap(), ErrorMetrics::default());
        let b = img(&[Rgb::new(0.3, 0.0, 0.0), Rgb::splat(0.5)]);
        let m = compare(&a, &b).unwrap();
        assert!((m.rmse - (0.09f64 / 6.0).sqrt()).abs() < 1e-15);
        assert_eq!(m.max, 0.3);
        assert_eq!(m.off_8bit, 0.5);
        assert!(compare(&a, &img(&[Rgb::ZERO])).is_none());
    }

    #[test]
    fn the_sweep_has_an_auto_min_weight_row_and_an_exhaustive_reference() {
        let mut scene = Scene::default_scene();
        scene.camera = scene.camera.with_size(32, 18);
        let sweep = Sweep {
            depths: vec![],
            fresnels: vec![],
            spps: vec![],
            offsets: vec![],
            repeats: 1,
            reference_spp: 1,
            ..Sweep::quick()
        };
        let r = run(&scene, &sweep, &|_, _| {});
        assert_eq!(r.reference.min_weight, Some(0.0));
        assert_eq!(r.base.min_weight, None);
        let auto = crate::trace::bound::auto_min_weight(&scene, &r.base);
        assert!(auto > 0.0 && auto == r.base_min_weight);
        let values: Vec<&str> = r.rows.iter().map(|row| row.value.as_str()).collect();
        assert_eq!(values, ["0e0", &format!("auto ({auto:.1e})"), "1e-2"]);
        let [exhaustive, auto_row, coarse] = &r.rows[..] else {
            unreachable!()
        };
        assert_eq!(auto_row.settings.min_weight, None);
        // The cut traces fewer rays than the exhaustive tree at depth 16, more than 1e-2.
        assert!(auto_row.rays.total < exhaustive.rays.total, "{r:?}");
        assert!(auto_row.rays.total > coarse.rays.total, "{r:?}");
    }

    #[test]
    fn pareto_front() {
        let row = |t: f64, e: f64| CostRow {
            axis: String::new(),
            value: String::new(),
            settings: Settings::default(),
            median_ms: t,
            rays: RaysByKind::default(),
            error: ErrorMetrics {
                rmse: e,
                ..ErrorMetrics::default()
            },
            pareto: false,
        };
        let mut rows = vec![row(1.0, 0.5), row(2.0, 0.1), row(3.0, 0.2), row(4.0, 0.0)];
        mark_pareto(&mut rows);
        let front: Vec<bool> = rows.iter().map(|r| r.pareto).collect();
        assert_eq!(front, [true, true, false, true]);
    }
}
