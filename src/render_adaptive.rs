//! Adaptive antialiasing (`settings.adaptive`) in the render and in one pixel.
//!
//! A pixel's first pass is its `spp` samples. It takes a second pass of `max_spp - spp` samples
//! (drawn from a copy of the sampler after [`PixelSampler::refine`]: sample indices
//! `spp..max_spp` on their own complete stratified grid) when the contrast
//! ([`Spread::contrast`]) of its own first-pass samples together with the first-pass means of
//! its 8 neighbours exceeds the threshold; its value is the mean of all its samples. The
//! neighbours catch the edge that crosses a pixel between its first samples (all on one side):
//! without them, on `benches/mitsuba-scenes/glass-emitters.json` at 4 spp, 83% of the remaining
//! error sat in unrefined pixels beside refined ones.
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
use crate::scene::AdaptiveDesc;
use crate::trace::{Integrator, NoopRecorder, RayCounts, Recorder};
use rayon::prelude::*;

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

/// Every sample of pixel (x, y) into `sink` under `settings.adaptive` (see the module
/// documentation): the pixel radiance (the mean of its samples), how many samples it took and
/// the sink's result.
pub(super) fn pixel<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    a: AdaptiveDesc,
    (x, y): (u32, u32),
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    let scene = integrator.scene();
    let spp = scene.settings.spp.max(1);
    let mut px = K::Pixel::default();
    let first = first_pass(integrator, sampler, x, y, sink, &mut px, counts);
    let total = a.max_spp(spp);
    let unrefined = |sink: &mut K, px| (first.sum / f64::from(spp), spp, sink.finish(px, spp));
    if total <= spp {
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
            let (nx, ny) = (nx as u32, ny as u32);
            let f = first_pass(
                integrator,
                &mut other,
                nx,
                ny,
                &mut quiet,
                &mut (),
                &mut scratch,
            );
            f.sum / f64::from(spp)
        })
    });
    if !refines(&a, &first, means) {
        return unrefined(sink, px);
    }
    let sum = second_pass(integrator, sampler, x, y, first.sum, sink, &mut px, counts);
    (sum / f64::from(total), total, sink.finish(px, total))
}

/// Whether a pixel with first pass `own` and neighbours' first-pass `means` is refined.
fn refines(a: &AdaptiveDesc, own: &First, means: impl Iterator<Item = Rgb>) -> bool {
    let mut spread = own.spread;
    for m in means {
        spread.add(m);
    }
    spread.contrast() > a.threshold
}

/// Samples `0..spp` of pixel (x, y).
fn first_pass<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    x: u32,
    y: u32,
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> First {
    let cam = Camera::new(integrator);
    let mut f = First::default();
    for s in 0..integrator.scene().settings.spp.max(1) {
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

/// Samples `spp..max_spp` of pixel (x, y) added to `sum` (the first pass's) in order, from a
/// copy of `sampler` refined for the pass.
#[allow(clippy::too_many_arguments)]
fn second_pass<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &S,
    x: u32,
    y: u32,
    mut sum: Rgb,
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> Rgb {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    let total = settings.adaptive.map_or(spp, |a| a.max_spp(spp));
    let cam = Camera::new(integrator);
    let mut second = sampler.clone();
    second.refine(spp, total - spp);
    for s in spp..total {
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
/// second-pass rows finish.
pub(super) fn rows<I, S, K, F>(
    integrator: &I,
    sampler: &S,
    a: AdaptiveDesc,
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
    let spp = scene.settings.spp.max(1);
    let total = a.max_spp(spp);
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
                    let f = first_pass(integrator, &mut sampler, x, y, sink, &mut px, &mut counts);
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
        Some(row.get(usize::try_from(x).ok()?)?.sum / f64::from(spp))
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
                    let (value, taken) = if total > spp && refines(&a, &f, means) {
                        let c = &mut counts;
                        let sum = second_pass(integrator, sampler, x, y, f.sum, sink, &mut px, c);
                        (sum / f64::from(total), total)
                    } else {
                        (f.sum / f64::from(spp), spp)
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
