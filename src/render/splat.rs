//! Light tracing's splats in the render ([`Integrator::splats`]): one light path per pixel
//! sample, seeded by it (sample `s` of pixel (x, y) seeds path `(y w + x) spp + s`, which
//! starts on a light, anywhere), every contribution added to the sum of the pixel it lands
//! in, in path order. A pixel is then `camera mean + splat sum / spp`, both here and in its
//! recorded tree ([`pixel_splats`]), so the two agree bit for bit and neither depends on the
//! thread count.

use crate::integrator::light::LIGHT_SEED;
use crate::integrator::{Integrator, NoopRecorder, RayCounts, Recorder, Splat};
use crate::math::Rgb;
use crate::sampling::SceneSampler;
use crate::tree::SplatRecord;
use rayon::prelude::*;

/// Rows of seeding pixels traced per parallel round: a round's splats are added to the film
/// in order before the next starts, so memory stays bounded by one round's splats.
const ROUND_ROWS: u32 = 16;

/// The sampler of the light paths: the scene's kind and `spp`, its seed mixed with
/// [`LIGHT_SEED`].
pub(crate) fn light_sampler<I: Integrator>(integrator: &I) -> SceneSampler {
    let s = &integrator.scene().settings;
    SceneSampler::new(s.sampler_kind(), s.spp, s.seed ^ LIGHT_SEED)
}

/// The light paths seeded by row `y`, in order, each splat handed to `f` with its path index.
fn light_row<I: Integrator, R: Recorder, F: FnMut(u64, Splat)>(
    integrator: &I,
    y: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    mut f: F,
) {
    let mut sampler = light_sampler(integrator);
    for x in 0..integrator.scene().camera.width {
        light_pixel(integrator, (x, y), &mut sampler, rec, counts, &mut f);
    }
}

/// The light paths seeded by pixel `(x, y)` (one per sample), drawing from `sampler` (a
/// [`light_sampler`]), each splat handed to `f` with its path index.
pub(crate) fn light_pixel<I: Integrator, R: Recorder, F: FnMut(u64, Splat)>(
    integrator: &I,
    (x, y): (u32, u32),
    sampler: &mut SceneSampler,
    rec: &mut R,
    counts: &mut RayCounts,
    mut f: F,
) {
    let scene = integrator.scene();
    let (w, spp) = (scene.camera.width, scene.settings.spp.max(1));
    for s in 0..spp {
        let k = (u64::from(y) * u64::from(w) + u64::from(x)) * u64::from(spp) + u64::from(s);
        let mut sink = |sp: Splat| f(k, sp);
        integrator.trace_light_path((x, y, s), sampler, rec, counts, &mut sink);
    }
}

/// The light pass: every light path, its splats summed per pixel in path order. Returns the
/// sums (row-major; a pixel adds `sum / spp`) and the rays traced; `progress` gets the number
/// of seeding rows finished.
pub fn light_pass<I: Integrator>(
    integrator: &I,
    progress: &(dyn Fn(u32) + Sync),
) -> (Vec<Rgb>, RayCounts) {
    let scene = integrator.scene();
    let mut sums = vec![Rgb::ZERO; scene.camera.width as usize * scene.camera.height as usize];
    let counts = light_rounds(
        integrator,
        |i, sp| (i, sp.contribution),
        |(i, v)| sums[i] += v,
        progress,
    );
    (sums, counts)
}

/// Every light path, unrecorded, in rounds of [`ROUND_ROWS`] seeding rows traced in parallel:
/// each splat is reduced by `keep` (with the row-major index of the pixel it lands in) to what
/// the caller adds, and handed to `add` in path order, so the result does not depend on the
/// thread count. Returns the rays traced; `progress` gets the seeding rows finished.
pub(crate) fn light_rounds<I: Integrator, T: Send>(
    integrator: &I,
    keep: impl Fn(usize, Splat) -> T + Sync,
    mut add: impl FnMut(T),
    progress: &(dyn Fn(u32) + Sync),
) -> RayCounts {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut counts = RayCounts::default();
    let mut y0 = 0;
    while y0 < h {
        let rows = y0..(y0 + ROUND_ROWS).min(h);
        let parts: Vec<(Vec<T>, RayCounts)> = rows
            .into_par_iter()
            .map(|y| {
                let mut c = RayCounts::default();
                let mut out = Vec::new();
                light_row(integrator, y, &mut NoopRecorder, &mut c, |_, sp| {
                    let (px, py) = sp.pixel;
                    out.push(keep(py as usize * w as usize + px as usize, sp));
                });
                (out, c)
            })
            .collect();
        for (splats, c) in parts {
            splats.into_iter().for_each(&mut add);
            counts += c;
        }
        y0 = (y0 + ROUND_ROWS).min(h);
        progress(y0);
    }
    counts
}

/// The splats of pixel `(x, y)`, recorded into `rec`, in the order [`light_pass`] adds them:
/// the whole pass is traced unrecorded to find the light paths that land there, then each of
/// those is traced again into `rec` (the same random numbers, so the same contributions).
/// Returns the splat records and the rays of both passes, or, when more than `max_paths` light
/// paths land there, `Err` with their number (nothing recorded).
pub fn pixel_splats<I: Integrator, R: Recorder>(
    integrator: &I,
    (x, y): (u32, u32),
    rec: &mut R,
    max_paths: u64,
) -> Result<(Vec<SplatRecord>, RayCounts), u64> {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let found: Vec<(Vec<u64>, RayCounts)> = (0..h)
        .into_par_iter()
        .map(|row| {
            let mut c = RayCounts::default();
            let mut paths: Vec<u64> = Vec::new();
            light_row(integrator, row, &mut NoopRecorder, &mut c, |k, sp| {
                if sp.pixel == (x, y) && paths.last() != Some(&k) {
                    paths.push(k);
                }
            });
            (paths, c)
        })
        .collect();
    let landing: u64 = found.iter().map(|(p, _)| p.len() as u64).sum();
    if landing > max_paths {
        return Err(landing);
    }
    let mut counts = RayCounts::default();
    let mut records = Vec::new();
    let mut sampler = light_sampler(integrator);
    for k in found.iter().flat_map(|(p, _)| p.iter().copied()) {
        let seed_pixel = k / u64::from(spp);
        let seed = (
            (seed_pixel % u64::from(w)) as u32,
            (seed_pixel / u64::from(w)) as u32,
            (k % u64::from(spp)) as u32,
        );
        let mut here = Vec::new();
        let root = integrator.trace_light_path(seed, &mut sampler, rec, &mut counts, &mut |sp| {
            if sp.pixel == (x, y) {
                here.push(sp);
            }
        });
        let Some(root) = root else { continue };
        records.extend(here.into_iter().filter_map(|sp| {
            Some(SplatRecord {
                path: k,
                seed: [seed.0, seed.1, seed.2],
                strategy: [sp.vertices, 1],
                film: [sp.film.0, sp.film.1],
                root,
                connection: sp.connection?,
                contribution: sp.contribution,
                mis_weight: sp.mis_weight,
                lpe: sp.lpe,
            })
        }));
    }
    for (_, c) in found {
        counts += c;
    }
    Ok((records, counts))
}

/// `camera + sum / spp`: a pixel's value from its camera samples' mean and its splat sum.
#[inline]
#[must_use]
pub fn with_splats(camera: Rgb, sum: Rgb, spp: u32) -> Rgb {
    camera + sum / f64::from(spp.max(1))
}

/// The splat sum of `records`, in their order (the render's).
#[must_use]
pub fn splat_sum(records: &[SplatRecord]) -> Rgb {
    records.iter().fold(Rgb::ZERO, |s, r| s + r.contribution)
}

/// Add the light pass's `sums` (row-major) to the camera pixels of `rows`
/// ([`with_splats`]) and its rays to the first row's counts.
pub(crate) fn add_to_rows<O>(
    rows: &mut [super::pixel_loop::SinkRow<O>],
    sums: &[Rgb],
    spp: u32,
    counts: RayCounts,
) {
    let mut i = 0;
    for (row, _) in rows.iter_mut() {
        for p in row.iter_mut() {
            p.value = with_splats(p.value, sums[i], spp);
            i += 1;
        }
    }
    if let Some((_, c)) = rows.first_mut() {
        *c += counts;
    }
}
