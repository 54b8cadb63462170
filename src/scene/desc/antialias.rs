//! How many samples each pixel takes: `settings.antialiasing` and `settings.adaptive`.

use serde::{Deserialize, Serialize};

/// What `spp` means when `settings.adaptive` is absent (`settings.antialiasing`,
/// `--antialiasing`).
///
/// `auto` (the default): where the image is a function of the film position alone (the
/// Whitted integrator without area lights, rough lobes, a lens or the dielectric roulette, and
/// no `settings.sampler` chosen), every pixel first takes `max(2, spp / 16)` samples at its
/// Owen-scrambled Sobol points, and only pixels on an edge (their samples and their 8
/// neighbours' means differ by a contrast above [`AUTO_THRESHOLD`]) go on to `spp`; elsewhere,
/// and always at `spp` 1, it is `uniform`. `uniform`: every pixel takes `spp` samples. The rule
/// and its measured cost are in `docs/cost.md` (automatic antialiasing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Antialiasing {
    /// Edge pixels take `spp` samples, the others a first pass of `max(2, spp / 16)`, where
    /// the image allows it.
    #[default]
    Auto,
    /// Every pixel takes `spp` samples.
    Uniform,
}

impl Antialiasing {
    /// Both, in documentation order.
    pub const ALL: [Antialiasing; 2] = [Antialiasing::Auto, Antialiasing::Uniform];

    /// The name used in JSON and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Antialiasing::Auto => "auto",
            Antialiasing::Uniform => "uniform",
        }
    }

    /// Whether this is the default (`auto`).
    #[must_use]
    pub fn is_auto(&self) -> bool {
        *self == Antialiasing::Auto
    }
}

/// The contrast above which automatic antialiasing refines a pixel. Chosen on
/// `benches/mitsuba-scenes/glass-emitters.json` at 320x180 (docs/cost.md), measured with a
/// one-sample first pass: 0.02, 0.05, 0.1 and 0.2 gave rel-RMSE 0.0071-0.0091 at 16 spp, 0.05
/// the lowest error before the refined pixels grow faster than the error falls; with the
/// two-point Sobol first pass 0.05 gives 0.0070.
pub const AUTO_THRESHOLD: f64 = 0.05;

/// Adaptive antialiasing (`settings.adaptive`, after Whitted 1980 and Mitchell 1987): a pixel's
/// first pass is its `spp` samples; if in any channel the contrast
/// `(max - min) / (max + min + 0.01)` of those samples together with the first-pass means of
/// its 8 neighbours exceeds `threshold`, the pixel takes a second pass of `max_spp - spp`
/// samples (stratified on their own complete grid, or the Sobol sequence continued), and its
/// value is the mean of all `max_spp` samples. `raytree trace` re-traces the neighbours' first
/// passes, so it makes the render's decision ([`crate::sampling::contrast`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveDesc {
    /// Contrast above which a pixel is refined (>= 0; 0 refines every pixel whose samples
    /// differ at all).
    pub threshold: f64,
    /// Samples of a refined pixel in all (first pass included); absent:
    /// [`ADAPTIVE_FACTOR`] times `spp` (at most 65536).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_spp: Option<u32>,
}

/// A refined pixel's samples per first-pass sample when `adaptive.max_spp` is absent.
pub const ADAPTIVE_FACTOR: u32 = 16;

impl AdaptiveDesc {
    /// The samples of a refined pixel when the first pass has `spp` samples.
    #[must_use]
    pub fn max_spp(&self, spp: u32) -> u32 {
        self.max_spp
            .unwrap_or_else(|| spp.saturating_mul(ADAPTIVE_FACTOR).min(65_536))
    }
}
