//! Light path expression AOVs and Monte Carlo statistics per pixel (issue 16).
//!
//! [`render_aovs`] renders the beauty image and, for each expression, the image of the
//! contributions whose recorded path (`C<RD><TS><TS>L`, see [`crate::lpe`]) matches it: the pixel
//! mean over samples of the sum of those contributions. The beauty image is bit for bit
//! [`crate::render()`]'s: the same pixel loop ([`crate::render::pixel_loop`], with adaptive
//! antialiasing's two passes when the scene has them) with the AOV sink, so the same samples
//! in the same order; expressions that partition the complete paths sum to it within float
//! rounding. In the same pass it gathers per pixel the
//! samples' luminance spread, path lengths, Russian-roulette terminations and dropped samples
//! ([`McPixel`]) for the debug views ([`McView`]). The recorder ([`AovRecorder`]) keeps no
//! tree: only each contribution's path string, matched once per distinct string.
//!
//! Whitted records no light path expressions: [`render_aovs`] refuses expressions under it
//! ([`AovError::Whitted`]); its statistics (noise, samples) are still gathered.

mod classes;
mod mc;
mod nodes;
mod pair;
mod recorder;
mod sink;
mod spec;
#[cfg(test)]
mod tests;
mod versus;

pub use classes::{CLASSES, Class, standard_classes};
pub use mc::{McPixel, McView, ramp, spread};
pub use nodes::{classify, pixel_from_nodes};
pub use pair::{Pair, PairSteps, Side, pair, signed_rgb8};
pub use recorder::{AovRecorder, MAX_AOVS};
pub use spec::{Aov, AovSpecError, parse_aovs};
pub use versus::{ClassShare, Versus, VersusSteps, versus};

use crate::integrator::Integrator;
use crate::lpe::Lpe;
use crate::math::Rgb;
use crate::render::steps::Steps;
use crate::render::{Image, RenderStats, pixel_loop};
use crate::sampling::SceneSampler;
use crate::scene::IntegratorKind;
use sink::AovSink;

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
    check(integrator, lpes)?;
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let sampler = SceneSampler::for_settings(&scene.settings);
    // A sink per rayon work split, so each distinct path string is matched a few times per
    // thread, not once per row.
    let rows = pixel_loop::rows(integrator, &sampler, || AovSink::new(lpes), progress);
    let first = crate::render::first_spp(integrator);
    let (beauty, stats, _, outs) = pixel_loop::assemble((w, h), first, false, rows);
    Ok(aov_render(
        integrator.kind(),
        lpes.len(),
        beauty,
        stats,
        outs,
    ))
}

/// Whether [`render_aovs`] can render `lpes` under `integrator`.
fn check<I: Integrator>(integrator: &I, lpes: &[Lpe]) -> Result<(), AovError> {
    if !lpes.is_empty() && integrator.kind() == IntegratorKind::Whitted {
        return Err(AovError::Whitted);
    }
    if lpes.len() > MAX_AOVS {
        return Err(AovError::TooMany);
    }
    Ok(())
}

/// The AOV render of `k` expressions from the assembled beauty, counts and per-pixel sinks'
/// results (non-finite AOV values written black).
fn aov_render(
    integrator: IntegratorKind,
    k: usize,
    beauty: Image,
    stats: RenderStats,
    outs: Vec<(Vec<Rgb>, McPixel)>,
) -> AovRender {
    let (w, h) = (beauty.width, beauty.height);
    let n = (w * h) as usize;
    let mut aovs = vec![Vec::with_capacity(n); k];
    let mut mc = Vec::with_capacity(n);
    for (aov, st) in outs {
        for (i, a) in aov.into_iter().enumerate() {
            aovs[i].push(if a.is_finite() { a } else { Rgb::ZERO });
        }
        mc.push(st);
    }
    let image = |pixels| Image {
        width: w,
        height: h,
        pixels,
    };
    AovRender {
        beauty,
        aovs: aovs.into_iter().map(image).collect(),
        stats,
        mc,
        integrator,
    }
}

/// [`render_aovs`] a piece at a time ([`crate::render::steps`]): the same render, bit for bit.
pub struct AovSteps {
    steps: Steps<(Vec<Rgb>, McPixel)>,
    lpes: Vec<Lpe>,
    kind: IntegratorKind,
}

impl AovSteps {
    /// An AOV render of `lpes` by `integrator`.
    ///
    /// # Errors
    /// As [`render_aovs`].
    pub fn new<I: Integrator>(integrator: &I, lpes: Vec<Lpe>) -> Result<Self, AovError> {
        check(integrator, &lpes)?;
        Ok(Self {
            steps: Steps::new(integrator, false).camera_only(),
            lpes,
            kind: integrator.kind(),
        })
    }

    /// Trace pixels by `integrator` (the same scene as [`AovSteps::new`]'s) while `more_time`
    /// says so, at least one; returns whether more is to come.
    pub fn step<I: Integrator>(&mut self, integrator: &I, more_time: &dyn Fn() -> bool) -> bool {
        let sampler = SceneSampler::for_settings(&integrator.scene().settings);
        let lpes = &self.lpes;
        self.steps
            .step(integrator, &sampler, &|| AovSink::new(lpes), more_time)
    }

    /// The finished render.
    #[must_use]
    pub fn finish(self) -> AovRender {
        let k = self.lpes.len();
        let (beauty, stats, _, outs) = self.steps.finish();
        aov_render(self.kind, k, beauty, stats, outs)
    }
}
