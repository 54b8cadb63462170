//! Adaptive antialiasing (`settings.adaptive`, and `settings.antialiasing: "auto"`) in the
//! render and in one pixel.
//!
//! A pixel's first pass is its first `plan.first` samples (`spp` under `settings.adaptive`;
//! automatic antialiasing, a probe through the centre, is in `src/render_auto.rs`). It takes a second pass
//! of samples `first..total` (drawn from a copy of the sampler after
//! [`PixelSampler::refine`]: on their own complete stratified grid, or the Sobol sequence
//! continued) when the contrast ([`Spread::contrast`]) of its own first-pass samples together
//! with the first-pass means of its 8 neighbours exceeds the threshold; its value is the mean
//! of all its samples. The neighbours catch the edge that crosses a pixel between its first
//! samples (all on one side): without them, on `benches/mitsuba-scenes/glass-emitters.json` at
//! 4 spp, 83% of the remaining error sat in unrefined pixels beside refined ones; with them a
//! first pass of one sample per pixel finds the edges.
//!
//! The render computes every pixel's first pass, then decides and traces the second passes
//! ([`rows`]); one pixel alone ([`pixel`], and so `render_pixel_counted` and `raytree trace`)
//! traces the neighbours' first passes without recording, so it makes the same decision from
//! the same bits and records exactly the samples the render used. Both hand every sample of the
//! pixel to the loop's [`SampleSink`] in the same order (first pass, then second pass), so the
//! AOV render and the denoiser's gather take the render's samples.

use super::pixel_loop::{Beauty, Camera, PixelOut, SampleSink, SinkRow, diag, one_sample};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, Spread};
use crate::scene::{AUTO_THRESHOLD, Antialiasing};
use crate::trace::{Integrator, NoopRecorder, RayCounts, Recorder};
use rayon::prelude::*;

/// Which samples the pixels of a render take when some take more than others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptivePlan {
    /// Samples of every pixel's first pass.
    pub first: u32,
    /// Samples of a refined pixel in all (first pass included).
    pub total: u32,
    /// Contrast above which a pixel is refined.
    pub threshold: f64,
    /// Automatic antialiasing (`src/render_auto.rs`): the first pass is one probe through the
    /// pixel centre, a refined pixel's value the mean of `total` samples at its Sobol points
    /// (the probe not among them); the scene's sampler is not used.
    pub auto: bool,
}

/// The plan of a render by `integrator`: `settings.adaptive` when set (first pass `spp`,
/// refined to its `max_spp`); otherwise, under `settings.antialiasing: "auto"`, automatic
/// antialiasing (a probe through the centre, refined to `spp` samples, contrast above
/// [`AUTO_THRESHOLD`]) when
/// `spp >= 2`, no `settings.sampler` is chosen and the radiance of a camera sample is a
/// function of its film position alone ([`Integrator::film_only`]); `None`: every pixel takes
/// `spp` samples.
#[must_use]
pub fn adaptive_plan<I: Integrator>(integrator: &I) -> Option<AdaptivePlan> {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    if let Some(a) = settings.adaptive {
        return Some(AdaptivePlan {
            first: spp,
            total: a.max_spp(spp).max(spp),
            threshold: a.threshold,
            auto: false,
        });
    }
    let auto = settings.antialiasing == Antialiasing::Auto
        && spp >= 2
        && settings.sampler.is_none()
        && integrator.film_only();
    auto.then_some(AdaptivePlan {
        first: 1,
        total: spp,
        threshold: AUTO_THRESHOLD,
        auto: true,
    })
}

/// How the pixels of a render by `integrator` are sampled, in words (`raytree effects`): the
/// plan ([`adaptive_plan`]) and, for a uniform render of more than one sample, why automatic
/// antialiasing does not apply.
#[must_use]
pub fn antialiasing_note<I: Integrator>(integrator: &I) -> String {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    match adaptive_plan(integrator) {
        Some(p) if p.auto => format!(
            "spp {spp}, automatic antialiasing: one probe through each pixel centre, {} samples \
             where a pixel's probe and its 8 neighbours' differ (contrast > {}); \
             settings.antialiasing \"uniform\" for {spp} everywhere",
            p.total, p.threshold
        ),
        Some(p) => format!(
            "spp {spp}, adaptive: {} samples where a pixel's first {} and its neighbours' \
             differ (contrast > {})",
            p.total, p.first, p.threshold
        ),
        None if spp == 1 => "spp 1".to_string(),
        None => {
            let why = if settings.antialiasing == Antialiasing::Uniform {
                "settings.antialiasing uniform"
            } else if settings.sampler.is_some() {
                "settings.sampler chosen"
            } else if integrator.kind() != crate::scene::IntegratorKind::Whitted {
                "the path integrator's samples all differ"
            } else if !integrator.traces_packets() {
                "area lights or rough lobes make every sample differ"
            } else if integrator.film().has_lens() {
                "the lens makes every sample differ"
            } else {
                "the dielectric roulette makes every sample differ"
            };
            format!("spp {spp} in every pixel ({why})")
        }
    }
}

/// The neighbours whose first-pass means enter a pixel's decision.
const NEIGHBOURS: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// A pixel's first pass: the sum of its samples (as they enter the pixel) and their spread.
#[derive(Clone, Copy, Debug, Default)]
struct First {
    sum: Rgb,
    spread: Spread,
}

/// Every sample of pixel (x, y) into `sink` under `plan` (see the module documentation): the
/// pixel radiance (the mean of its samples), how many samples it took and the sink's result.
/// Automatic antialiasing is [`super::auto::pixel`].
pub(super) fn pixel<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    plan: AdaptivePlan,
    xy: (u32, u32),
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    if plan.auto {
        super::auto::pixel(integrator, plan, xy, sink, counts)
    } else {
        pixel_from(integrator, sampler, plan, xy, sink, counts)
    }
}

/// [`pixel`] with its film positions from `sampler`.
fn pixel_from<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    let scene = integrator.scene();
    let first_n = plan.first;
    let mut px = K::Pixel::default();
    let first = first_pass(integrator, sampler, plan, (x, y), sink, &mut px, counts);
    let unrefined = |sink: &mut K, px| {
        (
            first.sum / f64::from(first_n),
            first_n,
            sink.finish(px, first_n),
        )
    };
    if plan.total <= first_n {
        return unrefined(sink, px);
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut scratch = RayCounts::default();
    let mut other = sampler.clone();
    let mut quiet = Beauty(NoopRecorder);
    let means = NEIGHBOURS.iter().filter_map(|&(dx, dy)| {
        let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
        let inside = (0..i64::from(w)).contains(&nx) && (0..i64::from(h)).contains(&ny);
        inside.then(|| {
            let n = (nx as u32, ny as u32);
            let f = first_pass(
                integrator,
                &mut other,
                plan,
                n,
                &mut quiet,
                &mut (),
                &mut scratch,
            );
            f.sum / f64::from(first_n)
        })
    });
    if !refines(plan, &first, means) {
        return unrefined(sink, px);
    }
    let sum = second_pass(
        integrator,
        sampler,
        plan,
        (x, y),
        first.sum,
        sink,
        &mut px,
        counts,
    );
    let total = plan.total;
    (sum / f64::from(total), total, sink.finish(px, total))
}

/// Whether a pixel with first pass `own` and neighbours' first-pass `means` is refined.
fn refines(plan: AdaptivePlan, own: &First, means: impl Iterator<Item = Rgb>) -> bool {
    let mut spread = own.spread;
    for m in means {
        spread.add(m);
    }
    spread.contrast() > plan.threshold
}

/// Samples `0..plan.first` of pixel (x, y).
fn first_pass<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> First {
    let cam = Camera::new(integrator);
    let mut f = First::default();
    for s in 0..plan.first {
        let l = kept(one_sample(
            integrator,
            cam,
            sampler,
            (x, y, s),
            sink,
            px,
            counts,
        ));
        f.sum += l;
        f.spread.add(l);
    }
    f
}

/// A sample's radiance as it enters the pixel's sum: a dropped sample enters as black.
#[inline(always)]
fn kept((l, kept): (Rgb, bool)) -> Rgb {
    if kept { l } else { Rgb::ZERO }
}

/// Samples `plan.first..plan.total` of pixel (x, y) added to `sum` (the first pass's) in
/// order, from a copy of `sampler` refined for the pass.
#[allow(clippy::too_many_arguments)]
fn second_pass<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    mut sum: Rgb,
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> Rgb {
    let cam = Camera::new(integrator);
    let mut second = sampler.clone();
    second.refine(plan.first, plan.total - plan.first);
    for s in plan.first..plan.total {
        sum += kept(one_sample(
            integrator,
            cam,
            &mut second,
            (x, y, s),
            sink,
            px,
            counts,
        ));
    }
    sum
}

/// The rows of an adaptive render through sinks from `make` (rows in parallel): every pixel's
/// first pass, then each pixel's decision and second pass; `progress` is called as
/// second-pass rows finish. Automatic antialiasing is [`super::auto::rows`].
pub(super) fn rows<I, S, K, F>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    make: F,
    progress: &(dyn Fn() + Sync),
) -> Vec<SinkRow<K::Out>>
where
    I: Integrator,
    S: PixelSampler,
    K: SampleSink,
    F: Fn() -> K + Sync + Send,
{
    if plan.auto {
        let h = integrator.scene().camera.height;
        super::auto::rows(integrator, plan, 0..h, make, progress)
    } else {
        rows_from(integrator, sampler, plan, make, progress)
    }
}

/// [`rows`] with film positions from copies of `sampler`.
fn rows_from<I, S, K, F>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    make: F,
    progress: &(dyn Fn() + Sync),
) -> Vec<SinkRow<K::Out>>
where
    I: Integrator,
    S: PixelSampler,
    K: SampleSink,
    F: Fn() -> K + Sync + Send,
{
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let (first_n, total) = (plan.first, plan.total);
    let diagnose = K::Rec::DIAGNOSE;
    type FirstRow = (Vec<First>, Vec<(u32, u32)>, RayCounts);
    let first: Vec<(FirstRow, Vec<K::Pixel>)> = (0..h)
        .into_par_iter()
        .map_init(&make, |sink, y| {
            let (mut counts, mut sampler) = (RayCounts::default(), sampler.clone());
            let (mut d, mut data) = (Vec::new(), Vec::with_capacity(w as usize));
            let row = (0..w)
                .map(|x| {
                    let before = counts;
                    let mut px = K::Pixel::default();
                    let (s, c) = (&mut sampler, &mut counts);
                    let f = first_pass(integrator, s, plan, (x, y), sink, &mut px, c);
                    if diagnose {
                        d.push(diag(&before, &counts));
                    }
                    data.push(px);
                    f
                })
                .collect();
            ((row, d, counts), data)
        })
        .collect();
    let (first, data): (Vec<FirstRow>, Vec<Vec<K::Pixel>>) = first.into_iter().unzip();
    let mean = |x: i64, y: i64| -> Option<Rgb> {
        let row = &first.get(usize::try_from(y).ok()?)?.0;
        Some(row.get(usize::try_from(x).ok()?)?.sum / f64::from(first_n))
    };
    data.into_par_iter()
        .enumerate()
        .map_init(&make, |sink, (y, data)| {
            let (frow, fdiag, _) = &first[y];
            let mut counts = first[y].2;
            let y = y as u32;
            let pixels = data
                .into_iter()
                .enumerate()
                .map(|(x, mut px)| {
                    let f = frow[x];
                    let (cx, cy) = (x as i64, i64::from(y));
                    let means = NEIGHBOURS
                        .iter()
                        .filter_map(|&(dx, dy)| mean(cx + dx, cy + dy));
                    let before = counts;
                    let x = x as u32;
                    let (value, taken) = if total > first_n && refines(plan, &f, means) {
                        let c = &mut counts;
                        let sum =
                            second_pass(integrator, sampler, plan, (x, y), f.sum, sink, &mut px, c);
                        (sum / f64::from(total), total)
                    } else {
                        (f.sum / f64::from(first_n), first_n)
                    };
                    let diag = if diagnose {
                        let (s, l) = diag(&before, &counts);
                        let (s0, l0) = fdiag[x as usize];
                        (s0 + s, l0 + l)
                    } else {
                        (0, 0)
                    };
                    PixelOut {
                        value,
                        taken,
                        diag,
                        out: sink.finish(px, taken),
                    }
                })
                .collect();
            progress();
            (pixels, counts)
        })
        .collect()
}
