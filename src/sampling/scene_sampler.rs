//! The sampler a scene asks for (`settings.sampler`, [`crate::scene::SamplerKind`]): one type
//! behind the [`PixelSampler`] seam for every place that renders or re-traces a pixel, so the
//! tree of a pixel draws exactly the numbers its render drew.

use super::{PixelSampler, SobolSampler, StratifiedJitter};
use serde::{Deserialize, Serialize};

/// [`StratifiedJitter`] or [`SobolSampler`], chosen at run time from the settings
/// (`Settings::sampler_kind`: Sobol for the path integrator, stratified for Whitted unless
/// the scene or `--sampler` says otherwise).
///
/// The Sobol variant is large (its per-pixel seed cache, about 400 bytes): a render holds one
/// sampler per pixel loop and draws from it by reference, and boxing it would put an
/// indirection on every draw.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub enum SceneSampler {
    /// Stratified film offsets, hashed independent values after them.
    Stratified(StratifiedJitter),
    /// Owen-scrambled Sobol points.
    Sobol(SobolSampler),
}

impl SceneSampler {
    /// A sampler of `kind` for `spp` samples per pixel and `seed`.
    #[must_use]
    pub fn new(kind: SamplerKind, spp: u32, seed: u64) -> Self {
        match kind {
            SamplerKind::Stratified => Self::Stratified(StratifiedJitter::new(spp, seed)),
            SamplerKind::Sobol => Self::Sobol(SobolSampler::new(seed, (0, 0), 0)),
        }
    }

    /// Which sampler this is.
    #[must_use]
    pub fn kind(&self) -> SamplerKind {
        match self {
            Self::Stratified(_) => SamplerKind::Stratified,
            Self::Sobol(_) => SamplerKind::Sobol,
        }
    }
}

impl PixelSampler for SceneSampler {
    #[inline]
    fn start_sample(&mut self, pixel: (u32, u32), index: u32) {
        match self {
            Self::Stratified(s) => s.start_sample(pixel, index),
            Self::Sobol(s) => PixelSampler::start_sample(s, pixel, index),
        }
    }

    #[inline]
    fn next_1d(&mut self) -> f64 {
        match self {
            Self::Stratified(s) => s.next_1d(),
            Self::Sobol(s) => PixelSampler::next_1d(s),
        }
    }

    #[inline]
    fn next_2d(&mut self) -> (f64, f64) {
        match self {
            Self::Stratified(s) => s.next_2d(),
            Self::Sobol(s) => PixelSampler::next_2d(s),
        }
    }

    /// Stratified: the second pass on its own complete grid; Sobol: the sequence continues
    /// (its first `2^m` points of a pixel are a net, so a pass of the next indices fills the
    /// gaps of the first).
    fn refine(&mut self, first: u32, count: u32) {
        match self {
            Self::Stratified(s) => s.refine(first, count),
            Self::Sobol(s) => PixelSampler::refine(s, first, count),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::IntegratorKind;
    use crate::scene::Settings;

    fn draws<S: PixelSampler>(mut s: S) -> Vec<u64> {
        let mut out = Vec::new();
        for (pixel, index) in [((3, 4), 0), ((3, 4), 5), ((200, 7), 63)] {
            s.start_sample(pixel, index);
            let (a, b) = s.next_2d();
            let c = s.next_1d();
            let (d, e) = s.next_2d();
            out.extend([a, b, c, d, e].map(f64::to_bits));
        }
        out
    }

    /// Each variant draws exactly what the sampler it wraps draws (Whitted's images stay bit
    /// for bit), and the default follows the integrator.
    #[test]
    fn variants_draw_what_they_wrap_and_the_default_follows_the_integrator() {
        let strat = SceneSampler::new(SamplerKind::Stratified, 16, 9);
        assert_eq!(draws(strat), draws(StratifiedJitter::new(16, 9)));
        let sobol = SceneSampler::new(SamplerKind::Sobol, 16, 9);
        assert_eq!(draws(sobol), draws(SobolSampler::new(9, (0, 0), 0)));
        assert_ne!(draws(strat), draws(sobol));
        let mut s = Settings::default();
        assert_eq!(
            SceneSampler::for_settings(&s).kind(),
            SamplerKind::Stratified
        );
        s.integrator = IntegratorKind::Path;
        assert_eq!(SceneSampler::for_settings(&s).kind(), SamplerKind::Sobol);
        s.sampler = Some(SamplerKind::Stratified);
        assert_eq!(
            SceneSampler::for_settings(&s).kind(),
            SamplerKind::Stratified
        );
    }
}

/// Where a path's random numbers come from (`settings.sampler`, `--sampler`).
///
/// Absent from the scene: [`SamplerKind::Sobol`] under the path integrator,
/// [`SamplerKind::Stratified`] under Whitted (`crate::scene::Settings::sampler_kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", try_from = "String")]
pub enum SamplerKind {
    /// Stratified jittered film offsets, independent hashed values for the other dimensions
    /// ([`crate::sampling::StratifiedJitter`]).
    Stratified,
    /// Owen-scrambled Sobol points, one scrambled 2D pair per draw (Burley 2020;
    /// [`crate::sampling::SobolSampler`]).
    Sobol,
}

impl SamplerKind {
    /// Every sampler, in documentation order.
    pub const ALL: [SamplerKind; 2] = [SamplerKind::Stratified, SamplerKind::Sobol];

    /// The name used in JSON and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Stratified => "stratified",
            SamplerKind::Sobol => "sobol",
        }
    }

    /// The sampler named `name`, or why there is none.
    ///
    /// # Errors
    /// A message for unknown names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "stratified" => Ok(SamplerKind::Stratified),
            "sobol" => Ok(SamplerKind::Sobol),
            _ => Err(format!(
                "unknown sampler {name:?}, expected \"stratified\" or \"sobol\""
            )),
        }
    }
}

impl TryFrom<String> for SamplerKind {
    type Error = String;

    fn try_from(name: String) -> Result<Self, String> {
        Self::from_name(&name)
    }
}
