//! Adaptive antialiasing (`settings.adaptive`, and `settings.antialiasing: "auto"`, which
//! draws its own Sobol points) in the render and in one pixel.
//!
//! A pixel's first pass is its first `plan.first` samples. It takes a second pass of samples
//! `first..total` (a copy of the sampler after [`PixelSampler::refine`]: its own complete
//! stratified grid, or the Sobol sequence continued) when the contrast ([`Spread::contrast`])
//! of its first-pass samples and its 8 neighbours' first-pass means exceeds the threshold; its
//! value is the mean of all its samples. The neighbours catch the edge that crosses a pixel
//! between its first samples: without them, on `benches/mitsuba-scenes/glass-emitters.json` at
//! 4 spp, 83% of the remaining error sat in unrefined pixels beside refined ones.
//!
//! The render computes every pixel's first pass, then decides and traces the second passes
//! ([`rows`]); one pixel alone ([`pixel`], so `render_pixel` and `raytree trace`)
//! traces the neighbours' first passes without recording, so it makes the same decision from
//! the same bits and records exactly the samples the render used, in the same order (first
//! pass, then second pass) for every [`SampleSink`].

use super::AdaptivePlan;
use super::pixel_loop::{Beauty, Camera, PixelOut, SampleSink, SinkRow, diag, one_sample};
use crate::integrator::{Integrator, NoopRecorder, RayCounts, Recorder};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, SobolSampler, Spread};
use rayon::prelude::*;

/// Automatic antialiasing's sampler: the pixel's Owen-scrambled
/// Sobol points under the scene's seed (the first pass points `0..first`, the second pass the
/// sequence continued).
fn auto_sobol<I: Integrator>(integrator: &I) -> SobolSampler {
    SobolSampler::new(integrator.scene().settings.seed, (0, 0), 0)
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
    sum: crate::math::PixelSum,
    spread: Spread,
}

/// Every sample of pixel (x, y) into `sink` under `plan` (see the module documentation): the
/// pixel radiance (the mean of its samples), how many samples it took and the sink's result.
/// Automatic antialiasing draws from [`auto_sobol`], not `sampler`.
pub(super) fn pixel<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    plan: AdaptivePlan,
    xy: (u32, u32),
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    if plan.auto {
        let mut sobol = auto_sobol(integrator);
        pixel_from(integrator, &mut sobol, plan, xy, sink, counts)
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
// The pixel loop's own arguments (integrator, sampler, sink, counts) plus the plan, the pixel and its first-pass sum.
#[allow(clippy::too_many_arguments)]
fn second_pass<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    mut sum: crate::math::PixelSum,
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> crate::math::PixelSum {
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

/// Rows `rows` of the image under `plan` without recording (the inspector's bands,
/// `render_rows`): the first passes of those rows and of the rows beside them, then each
/// pixel's decision and second pass; the render's pixels, and its rays except the first passes
/// of the rows beside the band.
pub(super) fn band<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    rows: std::ops::Range<u32>,
) -> Vec<(Vec<Rgb>, RayCounts)> {
    let (w, h) = (
        integrator.scene().camera.width,
        integrator.scene().camera.height,
    );
    let y0 = rows.start.saturating_sub(1);
    let y1 = (rows.end + 1).min(h);
    let firsts: Vec<(Vec<First>, RayCounts)> = (y0..y1)
        .into_par_iter()
        .map(|y| {
            let (mut counts, mut sampler) = (RayCounts::default(), sampler.clone());
            let mut quiet = Beauty(NoopRecorder);
            let row = (0..w)
                .map(|x| {
                    let (s, c) = (&mut sampler, &mut counts);
                    first_pass(integrator, s, plan, (x, y), &mut quiet, &mut (), c)
                })
                .collect();
            (row, counts)
        })
        .collect();
    let mean = |x: i64, y: i64| -> Option<Rgb> {
        let row = &firsts.get(usize::try_from(y - i64::from(y0)).ok()?)?.0;
        Some(row.get(usize::try_from(x).ok()?)?.sum / f64::from(plan.first))
    };
    rows.into_par_iter()
        .map(|y| {
            let (frow, mut counts) = firsts[(y - y0) as usize].clone();
            let mut quiet = Beauty(NoopRecorder);
            let values = (0..w)
                .map(|x| {
                    let f = frow[x as usize];
                    let (cx, cy) = (i64::from(x), i64::from(y));
                    let means = NEIGHBOURS
                        .iter()
                        .filter_map(|&(dx, dy)| mean(cx + dx, cy + dy));
                    if plan.total > plan.first && refines(plan, &f, means) {
                        let (q, c) = (&mut quiet, &mut counts);
                        let sum =
                            second_pass(integrator, sampler, plan, (x, y), f.sum, q, &mut (), c);
                        sum / f64::from(plan.total)
                    } else {
                        f.sum / f64::from(plan.first)
                    }
                })
                .collect();
            (values, counts)
        })
        .collect()
}

/// [`band`] with automatic antialiasing's own positions when `plan.auto`.
pub(super) fn band_for<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    plan: AdaptivePlan,
    rows: std::ops::Range<u32>,
) -> Vec<(Vec<Rgb>, RayCounts)> {
    if plan.auto {
        band(integrator, &auto_sobol(integrator), plan, rows)
    } else {
        band(integrator, sampler, plan, rows)
    }
}

/// The rows of an adaptive render through sinks from `make` (rows in parallel): every pixel's
/// first pass, then each pixel's decision and second pass; `progress` is called as
/// second-pass rows finish. Automatic antialiasing draws from [`auto_sobol`].
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
        rows_from(integrator, &auto_sobol(integrator), plan, make, progress)
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
