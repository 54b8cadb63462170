//! Light path expression AOVs and Monte Carlo statistics per pixel (issue 16).
//!
//! [`render_aovs`] renders the beauty image and, for each expression, the image of the
//! contributions whose recorded path (`C<RD><TS><TS>L`, see [`crate::lpe`]) matches it: the pixel
//! mean over samples of the sum of those contributions. The beauty image is bit for bit
//! [`crate::render()`]'s (same samples in the same order); expressions that partition the
//! complete paths sum to it within float rounding. In the same pass it gathers per pixel the
//! samples' luminance spread, path lengths, Russian-roulette terminations and dropped samples
//! ([`McPixel`]) for the debug views ([`McView`]). The recorder ([`AovRecorder`]) keeps no
//! tree: only each contribution's path string, matched once per distinct string.
//!
//! Whitted records no light path expressions: [`render_aovs`] refuses expressions under it
//! ([`AovError::Whitted`]); its statistics (noise, samples) are still gathered.

mod classes;
mod mc;
mod nodes;
mod recorder;
mod spec;
#[cfg(test)]
mod tests;
mod versus;

pub use classes::{CLASSES, Class, standard_classes};
pub use mc::{McPixel, McView, ramp, spread};
pub use nodes::{classify, pixel_from_nodes};
pub use recorder::{AovRecorder, MAX_AOVS};
pub use spec::{Aov, AovSpecError, parse_aovs};
pub use versus::{ClassShare, Versus, versus};

use crate::lpe::Lpe;
use crate::math::Rgb;
use crate::render::{Image, RenderStats, camera_sample};
use crate::sampling::{PixelSampler, SceneSampler};
use crate::scene::IntegratorKind;
use crate::trace::{Integrator, RayCounts};
use rayon::prelude::*;

/// Why an AOV render cannot run.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AovError {
    /// Expressions under the Whitted integrator, which records no light paths.
    #[error(
        "light path expression AOVs need the path integrator (Whitted records no light paths): add --integrator path"
    )]
    Whitted,
    /// More expressions than the recorder's match cache holds.
    #[error("at most {MAX_AOVS} AOVs")]
    TooMany,
}

/// What [`render_aovs`] produces.
#[derive(Clone, Debug)]
pub struct AovRender {
    /// The beauty image (bit for bit [`crate::render()`]'s).
    pub beauty: Image,
    /// One image per expression, in order.
    pub aovs: Vec<Image>,
    /// The render's counts (as [`crate::render()`]'s).
    pub stats: RenderStats,
    /// Per-pixel Monte Carlo statistics, row-major.
    pub mc: Vec<McPixel>,
    /// The integrator that rendered.
    pub integrator: IntegratorKind,
}

/// One row: beauty pixels, AOV pixels (`w x k`, pixel-major), statistics, counts.
type Row = (Vec<Rgb>, Vec<Rgb>, Vec<McPixel>, RayCounts);

/// Render `integrator`'s image with one AOV per expression of `lpes`, rows in parallel over
/// rayon's pool; `progress` gets the number of rows done.
///
/// # Errors
/// [`AovError::Whitted`] for expressions under the Whitted integrator, [`AovError::TooMany`]
/// past [`MAX_AOVS`].
pub fn render_aovs<I: Integrator>(
    integrator: &I,
    lpes: &[Lpe],
    progress: &(dyn Fn(u32) + Sync),
) -> Result<AovRender, AovError> {
    if !lpes.is_empty() && integrator.kind() == IntegratorKind::Whitted {
        return Err(AovError::Whitted);
    }
    if lpes.len() > MAX_AOVS {
        return Err(AovError::TooMany);
    }
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let sampler = SceneSampler::for_settings(&scene.settings);
    let done = std::sync::atomic::AtomicU32::new(0);
    // A recorder per rayon work split (`map_init`: a few per thread), so each distinct path
    // string is matched a few times per thread, not once per row.
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map_init(
            || AovRecorder::new(lpes),
            |rec, y| {
                let mut sampler = sampler;
                let mut counts = RayCounts::default();
                let mut lums = Vec::new();
                let mut row: Row = (Vec::new(), Vec::new(), Vec::new(), RayCounts::default());
                for x in 0..w {
                    let px = pixel(
                        integrator,
                        &mut sampler,
                        rec,
                        (x, y),
                        &mut counts,
                        &mut lums,
                    );
                    row.0.push(px.0);
                    row.1.extend(px.1);
                    row.2.push(px.2);
                }
                row.3 = counts;
                progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
                row
            },
        )
        .collect();
    let k = lpes.len();
    let n = (w * h) as usize;
    let mut stats = RenderStats::default();
    let mut beauty = Vec::with_capacity(n);
    let mut aovs = vec![Vec::with_capacity(n); k];
    let mut mc = Vec::with_capacity(n);
    for (y, (row, aov, st, counts)) in rows.into_iter().enumerate() {
        stats.rays += counts;
        for (x, p) in row.into_iter().enumerate() {
            beauty.push(stats.admit_pixel(p, x, y));
        }
        for (i, a) in aov.into_iter().enumerate() {
            aovs[i % k].push(if a.is_finite() { a } else { Rgb::ZERO });
        }
        mc.extend(st);
    }
    let image = |pixels| Image {
        width: w,
        height: h,
        pixels,
    };
    Ok(AovRender {
        beauty: image(beauty),
        aovs: aovs.into_iter().map(image).collect(),
        stats,
        mc,
        integrator: integrator.kind(),
    })
}

/// One pixel: its beauty value (the mean of its samples, as [`crate::render::render_pixel`]
/// sums them), its AOV values and its statistics. `lums` is scratch space.
fn pixel<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &mut S,
    rec: &mut AovRecorder<'_>,
    (x, y): (u32, u32),
    counts: &mut RayCounts,
    lums: &mut Vec<f64>,
) -> (Rgb, Vec<Rgb>, McPixel) {
    let scene = integrator.scene();
    let spp = scene.settings.spp.max(1);
    let filter = scene.settings.filter.filter();
    let film = integrator.film();
    let whitted = integrator.kind() == IntegratorKind::Whitted;
    let mut sum = Rgb::ZERO;
    let mut aov = vec![Rgb::ZERO; rec.sample.len()];
    let mut px = McPixel {
        samples: spp,
        ..McPixel::default()
    };
    let mut segments = 0u64;
    lums.clear();
    for s in 0..spp {
        let (_, ray) = camera_sample(film, filter, sampler, x, y, s);
        rec.start_sample();
        let (l, _) = integrator.camera_radiance(ray, sampler, rec, counts);
        segments += u64::from(rec.segments);
        px.roulette += u32::from(rec.roulette);
        if counts.keep_sample(l, whitted, (x, y, s)) {
            sum += l;
            for (a, c) in aov.iter_mut().zip(&rec.sample) {
                *a += *c;
            }
            // (A non-finite Whitted sample makes a black pixel: it adds no spread.)
            lums.push(if l.is_finite() {
                crate::bsdf::luminance(l)
            } else {
                0.0
            });
        } else {
            // Dropped as the render drops it: black, counted.
            px.dropped += 1;
            lums.push(0.0);
        }
    }
    let n = f64::from(spp);
    for a in &mut aov {
        *a /= n;
    }
    px.path_length = segments as f64 / n;
    px.set_spread(lums);
    (sum / n, aov, px)
}
