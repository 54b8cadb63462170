//! Veach's per-strategy images (issue 30, `raytree strategies`; Veach 1997, figure 10.3): a
//! bidirectional render split by the strategy `(s, t)` that made each contribution, weighted
//! (they add up to the render) and unweighted (each strategy alone, MIS off: an unbiased
//! estimate of its path length wherever the strategy can make the path).
//!
//! One pass over the same samples as the render: every camera sample through
//! [`Bdpt::trace_camera_observed`] (the same random numbers, the same NaN rule), every light
//! subpath through the render's light pass, its `t = 1` splats kept apart by `s`. So the
//! weighted images plus the background and the longer paths sum to the rendered image up to
//! the order of the additions.

use crate::integrator::{Bdpt, Integrator, NoopRecorder, RayCounts, StrategyPart};
use crate::math::Rgb;
use crate::render::pixel_loop::Camera;
use crate::render::splat::light_rounds;
use crate::sampling::SceneSampler;
use crate::scene::Scene;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// What a part of the image is: a strategy, the background the camera saw, or a strategy of a
/// path longer than the split keeps apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Part {
    /// The background (or environment) a camera subpath escaped to.
    Background,
    /// Strategy `(s, t)`: `s` light-subpath and `t` camera-subpath vertices.
    Strategy {
        /// Light-subpath vertices (the emitter's counted).
        s: u32,
        /// Camera-subpath vertices (the lens counted).
        t: u32,
    },
    /// Every strategy of a path with more than the split's bounces, together.
    Longer,
}

impl Part {
    /// Bounces of the strategy's path (`s + t - 2` scattering vertices; 0 = an emitter the
    /// camera sees).
    #[must_use]
    pub fn bounces(self) -> Option<u32> {
        match self {
            Self::Strategy { s, t } => Some(s + t - 2),
            _ => None,
        }
    }

    /// `s=1 t=2`, `background` or `longer`.
    #[must_use]
    pub fn label(self) -> String {
        match self {
            Self::Background => "background".to_string(),
            Self::Strategy { s, t } => format!("s={s} t={t}"),
            Self::Longer => "longer".to_string(),
        }
    }

    /// A file stem: `s1-t2`, `background`, `longer`.
    #[must_use]
    pub fn stem(self) -> String {
        match self {
            Self::Strategy { s, t } => format!("s{s}-t{t}"),
            p => p.label(),
        }
    }
}

/// One part's images (row-major linear radiance, the render's size).
#[derive(Clone, Debug, PartialEq)]
pub struct PartImage {
    /// Which part.
    pub part: Part,
    /// Its MIS-weighted contributions, as they enter the render.
    pub weighted: Vec<Rgb>,
    /// The same contributions before their MIS weights (the background's are its own).
    pub unweighted: Vec<Rgb>,
    /// Contributions it made (non-zero), over the whole image.
    pub contributions: u64,
}

/// A render split by strategy.
#[derive(Clone, Debug)]
pub struct Split {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Strategies of paths with up to this many bounces have their own part.
    pub max_bounces: u32,
    /// The parts that contributed, in [`Part`] order (background, strategies by `(s, t)`,
    /// longer).
    pub parts: Vec<PartImage>,
    /// Camera samples dropped because their sum was not finite (as the render drops them).
    pub dropped: u64,
    /// Rays traced.
    pub rays: RayCounts,
}

impl Split {
    /// The sum of the weighted parts: the rendered image up to rounding.
    #[must_use]
    pub fn total(&self) -> Vec<Rgb> {
        let mut sum = vec![Rgb::ZERO; (self.width * self.height) as usize];
        for p in &self.parts {
            for (a, b) in sum.iter_mut().zip(&p.weighted) {
                *a += *b;
            }
        }
        sum
    }

    /// Each part's share of the image's luminance (weighted; the shares sum to 1 when the
    /// image is not black, otherwise all are 0).
    #[must_use]
    pub fn shares(&self) -> Vec<(Part, f64)> {
        let sums: Vec<f64> = self
            .parts
            .iter()
            .map(|p| p.weighted.iter().map(|&c| crate::bsdf::luminance(c)).sum())
            .collect();
        let total: f64 = sums.iter().sum();
        self.parts
            .iter()
            .zip(sums)
            .map(|(p, s)| {
                let share = if total > 0.0 && total.is_finite() {
                    s / total
                } else {
                    0.0
                };
                (p.part, share)
            })
            .collect()
    }
}

/// Per-part sums of one row or of the whole image: weighted, unweighted, contributions.
type Sums = BTreeMap<Part, (Vec<Rgb>, Vec<Rgb>, u64)>;

/// `part`'s sums in images of `n` pixels, black where it is new.
fn entry(sums: &mut Sums, n: usize, part: Part) -> &mut (Vec<Rgb>, Vec<Rgb>, u64) {
    sums.entry(part)
        .or_insert_with(|| (vec![Rgb::ZERO; n], vec![Rgb::ZERO; n], 0))
}

/// Add `part` at pixel `i` of an image of `n` pixels.
fn add(sums: &mut Sums, n: usize, part: Part, i: usize, unweighted: Rgb, weight: f64) {
    let e = entry(sums, n, part);
    e.0[i] += unweighted * weight;
    e.1[i] += unweighted;
    if unweighted != Rgb::ZERO {
        e.2 += 1;
    }
}

/// The part of strategy `[s, t]` (or the background) under a split at `max_bounces`.
fn part_of(strategy: Option<[u32; 2]>, max_bounces: u32) -> Part {
    match strategy {
        None => Part::Background,
        Some([s, t]) if s + t - 2 <= max_bounces => Part::Strategy { s, t },
        Some(_) => Part::Longer,
    }
}

/// Split `scene`'s bidirectional render (its settings, whatever `settings.integrator` says) by
/// strategy, keeping strategies of paths with up to `max_bounces` bounces apart. `progress`
/// gets the rows finished (camera pass, then light pass: `2 * height` in all).
#[must_use]
pub fn split(scene: &Scene, max_bounces: u32, progress: &(dyn Fn(u32) + Sync)) -> Split {
    let bdpt = Bdpt::new(scene);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let done = std::sync::atomic::AtomicU32::new(0);
    let tick = || progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
    let rows: Vec<(Sums, RayCounts)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let row = camera_row(&bdpt, y, max_bounces);
            tick();
            row
        })
        .collect();
    let n = (w * h) as usize;
    let mut sums = Sums::new();
    let mut rays = RayCounts::default();
    for (y, (row, c)) in rows.into_iter().enumerate() {
        for (part, (wt, un, k)) in row {
            let e = entry(&mut sums, n, part);
            let at = y * w as usize;
            for x in 0..w as usize {
                e.0[at + x] += wt[x];
                e.1[at + x] += un[x];
            }
            e.2 += k;
        }
        rays += c;
    }
    let dropped = rays.dropped_samples;
    rays += light_rows(&bdpt, max_bounces, &mut sums, &|rows| progress(h + rows));
    let parts = sums
        .into_iter()
        .filter(|(_, (_, _, contributions))| *contributions > 0)
        .map(|(part, (wt, un, contributions))| PartImage {
            part,
            weighted: wt.into_iter().map(|c| c / f64::from(spp)).collect(),
            unweighted: un.into_iter().map(|c| c / f64::from(spp)).collect(),
            contributions,
        })
        .collect();
    Split {
        width: w,
        height: h,
        spp,
        max_bounces,
        parts,
        dropped,
        rays,
    }
}

/// Row `y`'s camera samples, split: the render's sampler and film positions, a sample whose
/// sum is not finite dropped whole (as the render's pixel loop drops it).
fn camera_row(bdpt: &Bdpt<'_>, y: u32, max_bounces: u32) -> (Sums, RayCounts) {
    let scene = Integrator::scene(bdpt);
    let (w, spp) = (scene.camera.width, scene.settings.spp.max(1));
    let mut sampler = SceneSampler::for_settings(&scene.settings);
    let cam = Camera::new(bdpt);
    let mut sums = Sums::new();
    let mut counts = RayCounts::default();
    let mut parts: Vec<StrategyPart> = Vec::new();
    for x in 0..w {
        for s in 0..spp {
            let (_, ray) = cam.sample(&mut sampler, x, y, s);
            parts.clear();
            let (l, _) = bdpt.trace_camera_observed(
                ray,
                &mut sampler,
                &mut NoopRecorder,
                &mut counts,
                |p| {
                    parts.push(p);
                },
            );
            if !counts.keep_sample(l, false, (x, y, s)) {
                continue;
            }
            for p in &parts {
                let part = part_of(p.strategy, max_bounces);
                add(
                    &mut sums,
                    w as usize,
                    part,
                    x as usize,
                    p.unweighted,
                    p.weight,
                );
            }
        }
    }
    (sums, counts)
}

/// A splat as the split keeps it: pixel index, part, unweighted value, MIS weight.
type SplitSplat = (usize, Part, Rgb, f64);

/// The light pass ([`light_rounds`], as the render's), its `t = 1` splats added to `sums` by
/// strategy, in path order; `progress` gets the seeding rows finished.
fn light_rows(
    bdpt: &Bdpt<'_>,
    max_bounces: u32,
    sums: &mut Sums,
    progress: &(dyn Fn(u32) + Sync),
) -> RayCounts {
    let scene = Integrator::scene(bdpt);
    let n = (scene.camera.width * scene.camera.height) as usize;
    light_rounds(
        bdpt,
        |i, sp| -> SplitSplat {
            let part = part_of(Some([sp.vertices, 1]), max_bounces);
            (i, part, sp.unweighted, sp.mis_weight)
        },
        |(i, part, un, weight)| add(sums, n, part, i, un, weight),
        progress,
    )
}
