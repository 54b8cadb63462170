//! Automatic antialiasing (`settings.antialiasing: "auto"`, [`AdaptivePlan::auto`]) in the
//! render and in one pixel.
//!
//! Every pixel is first probed by one camera ray through its centre. A pixel whose probe and
//! its 8 neighbours' probes differ by a contrast ([`Spread::contrast`]) above the plan's
//! threshold is on an edge: its value is the mean of `spp` samples at its Owen-scrambled Sobol
//! points `0..spp` (the probe does not enter it). Any other pixel's value is its probe.
//!
//! Why these two: the image is a function of the film position alone here
//! ([`Integrator::film_only`]), so a pixel without an edge is smooth, and for a smooth pixel
//! the centre is the best single position (the midpoint rule: exact for a linear gradient,
//! where a random position errs by the gradient times its offset). A refined pixel's first
//! `2^m` Sobol points are stratified in every elementary interval of area `2^-m` (a
//! (0, 2)-sequence: Sobol 1967, Owen 1995), so an edge of any orientation is resolved at about
//! `N^-3/4`, and their mean is unbiased. Measured on
//! `benches/mitsuba-scenes/glass-emitters.json`, 320x180, against Mitsuba's 4096-spp reference
//! (docs/cost.md): 16 uniform samples per pixel give rel-RMSE 0.0069 at Sobol points and 0.0111
//! on jittered 4x4 strata; one sample 0.047 at the centre and 0.076 at a random position.
//!
//! The probe is traced without recording. A sink that takes samples (a recorded tree, the AOV
//! render, the denoiser's gather) gets the probe of an unrefined pixel traced again into it as
//! its sample 0 (the same bits: the image depends on the film position alone); its rays are
//! not counted twice, so every sink's render reports the render's ray counts.

use super::AdaptivePlan;
use super::pixel_loop::{Beauty, Camera, PixelOut, SampleSink, SinkRow, diag, one_sample};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, SobolSampler, Spread};
use crate::trace::{Integrator, NoopRecorder, RayCounts, Recorder};
use rayon::prelude::*;

/// The probe's film position: the pixel centre (and 0.5 for any further dimension, which a
/// film-only integrator does not draw).
#[derive(Clone, Copy, Debug)]
struct Centre;

impl PixelSampler for Centre {
    #[inline]
    fn start_sample(&mut self, _: (u32, u32), _: u32) {}
    #[inline]
    fn next_1d(&mut self) -> f64 {
        0.5
    }
    #[inline]
    fn next_2d(&mut self) -> (f64, f64) {
        (0.5, 0.5)
    }
}

/// The neighbours whose probes enter a pixel's decision.
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

/// Pixel (x, y)'s probe: its centre's radiance as it would enter the pixel (a dropped sample is
/// black), traced without recording.
fn probe<I: Integrator>(integrator: &I, (x, y): (u32, u32), counts: &mut RayCounts) -> Rgb {
    let cam = Camera::new(integrator);
    let mut quiet = Beauty(NoopRecorder);
    let (l, kept) = one_sample(
        integrator,
        cam,
        &mut Centre,
        (x, y, 0),
        &mut quiet,
        &mut (),
        counts,
    );
    if kept { l } else { Rgb::ZERO }
}

/// Whether a pixel with probe `own` and its neighbours' probes `others` is on an edge.
fn on_edge(plan: AdaptivePlan, own: Rgb, others: impl Iterator<Item = Rgb>) -> bool {
    let mut spread = Spread::default();
    spread.add(own);
    for l in others {
        spread.add(l);
    }
    spread.contrast() > plan.threshold
}

/// The value, samples and sink result of pixel (x, y) once decided: an edge pixel's `plan.total`
/// Sobol samples into `sink`; otherwise the probe `own`, handed to a sink that takes samples as
/// its sample 0 (its rays counted in a scratch count).
#[allow(clippy::too_many_arguments)]
fn finish<I: Integrator, K: SampleSink>(
    integrator: &I,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    own: Rgb,
    edge: bool,
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    let cam = Camera::new(integrator);
    let mut px = K::Pixel::default();
    if !edge {
        if K::TAKES_SAMPLES {
            let mut scratch = RayCounts::default();
            let c = &mut scratch;
            one_sample(integrator, cam, &mut Centre, (x, y, 0), sink, &mut px, c);
        }
        return (own, 1, sink.finish(px, 1));
    }
    let mut sobol = SobolSampler::new(integrator.scene().settings.seed, (x, y), 0);
    let mut sum = Rgb::ZERO;
    for s in 0..plan.total {
        let (l, kept) = one_sample(
            integrator,
            cam,
            &mut sobol,
            (x, y, s),
            sink,
            &mut px,
            counts,
        );
        if kept {
            sum += l;
        }
    }
    (
        sum / f64::from(plan.total),
        plan.total,
        sink.finish(px, plan.total),
    )
}

/// Pixel (x, y) alone: its probe and its neighbours' (traced again, as the render traced
/// them), the decision, and its samples into `sink`.
pub(super) fn pixel<I: Integrator, K: SampleSink>(
    integrator: &I,
    plan: AdaptivePlan,
    (x, y): (u32, u32),
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let own = probe(integrator, (x, y), counts);
    let mut scratch = RayCounts::default();
    let others = NEIGHBOURS.iter().filter_map(|&(dx, dy)| {
        let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
        let inside = (0..i64::from(w)).contains(&nx) && (0..i64::from(h)).contains(&ny);
        inside.then(|| probe(integrator, (nx as u32, ny as u32), &mut scratch))
    });
    let edge = on_edge(plan, own, others);
    finish(integrator, plan, (x, y), own, edge, sink, counts)
}

/// Rows `rows` of the render through sinks from `make`: the probes of those rows and of the
/// rows beside them (rows in parallel), then each pixel's decision and samples; `progress` is
/// called as rows finish. The probes of the rows beside the range are traced for the decisions
/// at its edges and counted in no row.
pub(super) fn rows<I, K, F>(
    integrator: &I,
    plan: AdaptivePlan,
    rows: std::ops::Range<u32>,
    make: F,
    progress: &(dyn Fn() + Sync),
) -> Vec<SinkRow<K::Out>>
where
    I: Integrator,
    K: SampleSink,
    F: Fn() -> K + Sync + Send,
{
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let diagnose = K::Rec::DIAGNOSE;
    // Probed rows: the range and one row on each side (inside the image).
    let y0 = rows.start.saturating_sub(1);
    let y1 = (rows.end + 1).min(h);
    type ProbeRow = (Vec<Rgb>, Vec<(u32, u32)>, RayCounts);
    let probes: Vec<ProbeRow> = (y0..y1)
        .into_par_iter()
        .map(|y| {
            let mut counts = RayCounts::default();
            let mut d = Vec::new();
            let row = (0..w)
                .map(|x| {
                    let before = counts;
                    let l = probe(integrator, (x, y), &mut counts);
                    if diagnose {
                        d.push(diag(&before, &counts));
                    }
                    l
                })
                .collect();
            (row, d, counts)
        })
        .collect();
    let at = |x: i64, y: i64| -> Option<Rgb> {
        let row = &probes.get(usize::try_from(y - i64::from(y0)).ok()?)?.0;
        row.get(usize::try_from(x).ok()?).copied()
    };
    rows.into_par_iter()
        .map_init(&make, |sink, y| {
            let (prow, pdiag, mut counts) = probes[(y - y0) as usize].clone();
            let pixels = (0..w)
                .map(|x| {
                    let (cx, cy) = (i64::from(x), i64::from(y));
                    let others = NEIGHBOURS
                        .iter()
                        .filter_map(|&(dx, dy)| at(cx + dx, cy + dy));
                    let own = prow[x as usize];
                    let edge = on_edge(plan, own, others);
                    let before = counts;
                    let (value, taken, out) =
                        finish(integrator, plan, (x, y), own, edge, sink, &mut counts);
                    let diag = if diagnose {
                        let (s, l) = diag(&before, &counts);
                        let (s0, l0) = pdiag[x as usize];
                        (s0 + s, l0 + l)
                    } else {
                        (0, 0)
                    };
                    PixelOut {
                        value,
                        taken,
                        diag,
                        out,
                    }
                })
                .collect();
            progress();
            (pixels, counts)
        })
        .collect()
}
