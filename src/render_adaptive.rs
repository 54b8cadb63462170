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
//! The render computes every pixel's first pass, then decides and traces the second passes;
//! [`render_pixel_counted`] (and so `raytree trace`) traces the neighbours' first passes
//! without recording, so it makes the same decision from the same bits and records exactly the
//! samples the render used.

use super::{Row, camera_sample};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, Spread};
use crate::scene::{AdaptiveDesc, IntegratorKind};
use crate::trace::{Integrator, NoopRecorder, RayCounts, Recorder};
use crate::tree::SampleRecord;
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

/// Trace every sample of pixel (x, y) into `rec`; returns the pixel radiance (the mean of its
/// samples) and how many samples it took: `spp`, or with `settings.adaptive` `max_spp` where
/// the pixel is refined (see the module documentation).
pub fn render_pixel_counted<I: Integrator, S: PixelSampler, R: Recorder>(
    integrator: &I,
    sampler: &mut S,
    x: u32,
    y: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    mut on_sample: impl FnMut(SampleRecord),
) -> (Rgb, u32) {
    let scene = integrator.scene();
    let spp = scene.settings.spp.max(1);
    let Some(a) = scene.settings.adaptive else {
        // The loop as it was before adaptive antialiasing, filter and film hoisted.
        let filter = scene.settings.filter.filter();
        let film = integrator.film();
        let mut sum = Rgb::ZERO;
        for s in 0..spp {
            let ((fx, fy), ray) = camera_sample(film, filter, sampler, x, y, s);
            let (l, root) = integrator.camera_radiance(ray, sampler, rec, counts);
            if counts.keep_sample(l, integrator.kind() == IntegratorKind::Whitted, (x, y, s)) {
                sum += l;
            }
            if let Some(root) = root {
                on_sample(SampleRecord {
                    index: s,
                    film: [fx, fy],
                    root,
                    radiance: l,
                });
            }
        }
        return (sum / f64::from(spp), spp);
    };
    let first = first_pass(integrator, sampler, x, y, rec, counts, &mut on_sample);
    let total = a.max_spp(spp);
    if total <= spp {
        return (first.sum / f64::from(spp), spp);
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut scratch = RayCounts::default();
    let mut other = sampler.clone();
    let means = NEIGHBOURS.iter().filter_map(|&(dx, dy)| {
        let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
        let inside = (0..i64::from(w)).contains(&nx) && (0..i64::from(h)).contains(&ny);
        inside.then(|| {
            let (nx, ny) = (nx as u32, ny as u32);
            let rec = &mut NoopRecorder;
            let f = first_pass(
                integrator,
                &mut other,
                nx,
                ny,
                rec,
                &mut scratch,
                &mut |_| {},
            );
            f.sum / f64::from(spp)
        })
    });
    if !refines(&a, &first, means) {
        return (first.sum / f64::from(spp), spp);
    }
    let sum = second_pass(
        integrator,
        sampler,
        x,
        y,
        first.sum,
        rec,
        counts,
        &mut on_sample,
    );
    (sum / f64::from(total), total)
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
fn first_pass<I: Integrator, S: PixelSampler, R: Recorder>(
    integrator: &I,
    sampler: &mut S,
    x: u32,
    y: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    on_sample: &mut impl FnMut(SampleRecord),
) -> First {
    let mut f = First::default();
    for s in 0..integrator.scene().settings.spp.max(1) {
        let l = one_sample(integrator, sampler, x, y, s, rec, counts, on_sample);
        f.sum += l;
        f.spread.add(l);
    }
    f
}

/// Samples `spp..max_spp` of pixel (x, y) added to `sum` (the first pass's) in order, from a
/// copy of `sampler` refined for the pass.
#[allow(clippy::too_many_arguments)]
fn second_pass<I: Integrator, S: PixelSampler, R: Recorder>(
    integrator: &I,
    sampler: &S,
    x: u32,
    y: u32,
    mut sum: Rgb,
    rec: &mut R,
    counts: &mut RayCounts,
    on_sample: &mut impl FnMut(SampleRecord),
) -> Rgb {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    let total = settings.adaptive.map_or(spp, |a| a.max_spp(spp));
    let mut second = sampler.clone();
    second.refine(spp, total - spp);
    for s in spp..total {
        sum += one_sample(integrator, &mut second, x, y, s, rec, counts, on_sample);
    }
    sum
}

/// Sample `s` of pixel (x, y): its radiance as it enters the pixel's sum (a non-finite path
/// sample is dropped, counted and enters as black), recorded through `on_sample`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn one_sample<I: Integrator, S: PixelSampler, R: Recorder>(
    integrator: &I,
    sampler: &mut S,
    x: u32,
    y: u32,
    s: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    on_sample: &mut impl FnMut(SampleRecord),
) -> Rgb {
    let filter = integrator.scene().settings.filter.filter();
    let ((fx, fy), ray) = camera_sample(integrator.film(), filter, sampler, x, y, s);
    let (l, root) = integrator.camera_radiance(ray, sampler, rec, counts);
    let whitted = integrator.kind() == IntegratorKind::Whitted;
    let kept = if counts.keep_sample(l, whitted, (x, y, s)) {
        l
    } else {
        Rgb::ZERO
    };
    if let Some(root) = root {
        on_sample(SampleRecord {
            index: s,
            film: [fx, fy],
            root,
            radiance: l,
        });
    }
    kept
}

/// The rows of an adaptive render (recorder `R`, rows in parallel): every pixel's first pass,
/// then each pixel's decision and second pass; `progress` is called as second-pass rows finish.
pub(super) fn rows<R: Recorder + Default, I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    a: AdaptiveDesc,
    progress: &(dyn Fn() + Sync),
) -> Vec<Row> {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let total = a.max_spp(spp);
    let diag = |before: &RayCounts, after: &RayCounts| {
        (
            (after.self_hits - before.self_hits) as u32,
            (after.leaks - before.leaks) as u32,
        )
    };
    type FirstRow = (Vec<First>, Vec<(u32, u32)>, RayCounts);
    let first: Vec<FirstRow> = (0..h)
        .into_par_iter()
        .map(|y| {
            let (mut counts, mut rec, mut sampler) =
                (RayCounts::default(), R::default(), sampler.clone());
            let mut d = Vec::new();
            let row = (0..w)
                .map(|x| {
                    let before = counts;
                    let f = first_pass(
                        integrator,
                        &mut sampler,
                        x,
                        y,
                        &mut rec,
                        &mut counts,
                        &mut |_| {},
                    );
                    if R::DIAGNOSE {
                        d.push(diag(&before, &counts));
                    }
                    f
                })
                .collect();
            (row, d, counts)
        })
        .collect();
    let mean = |x: i64, y: i64| -> Option<Rgb> {
        let row = &first.get(usize::try_from(y).ok()?)?.0;
        Some(row.get(usize::try_from(x).ok()?)?.sum / f64::from(spp))
    };
    (0..h)
        .into_par_iter()
        .map(|y| {
            let (frow, fdiag, mut counts) = first[y as usize].clone();
            let mut rec = R::default();
            let mut d = Vec::new();
            let mut taken = Vec::with_capacity(w as usize);
            let pixels = (0..w)
                .map(|x| {
                    let f = frow[x as usize];
                    let (cx, cy) = (i64::from(x), i64::from(y));
                    let means = NEIGHBOURS
                        .iter()
                        .filter_map(|&(dx, dy)| mean(cx + dx, cy + dy));
                    let before = counts;
                    let (l, n) = if total > spp && refines(&a, &f, means) {
                        let (rec, c) = (&mut rec, &mut counts);
                        let sum =
                            second_pass(integrator, sampler, x, y, f.sum, rec, c, &mut |_| {});
                        (sum / f64::from(total), total)
                    } else {
                        (f.sum / f64::from(spp), spp)
                    };
                    if R::DIAGNOSE {
                        let (s, l) = diag(&before, &counts);
                        let (s0, l0) = fdiag[x as usize];
                        d.push((s0 + s, l0 + l));
                    }
                    taken.push(n);
                    l
                })
                .collect();
            progress();
            (pixels, d, taken, counts)
        })
        .collect()
}
