//! The `settings` block and its parts (offsets, shadows, integrator, pixel filter) of the scene
//! JSON: the serde mirror, documented in `docs/scene-format.md`.

use super::antialias::{AdaptiveDesc, Antialiasing};
use super::integrator::{IntegratorKind, PathSettings, WhittedSettings};
pub use crate::sampling::SamplerKind;
use serde::{Deserialize, Serialize};

/// Where secondary rays start: the lecture's normal offset or a `t_min` along the ray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OffsetStrategy {
    /// `P +/- eps N` (lecture slides "Reflected Rays", "Transmitted Ray").
    #[default]
    Normal,
    /// Start at `P` and accept hits only beyond `t = eps`.
    Ray,
    /// `P +/- eps' N` with `eps' = eps * max(1, max_i |P_i|)`: relative to the magnitude of the
    /// hit point's coordinates, whose rounding error grows with them.
    Scaled,
    /// No tuning constant: pbrt-v4's conservative error bounds (`OffsetRayOrigin`, Pharr, Jakob,
    /// Humphreys, *Physically Based Rendering*, 4th ed., section 6.8.6); `epsilon` is ignored.
    Robust,
}

impl OffsetStrategy {
    /// Every strategy, in documentation order.
    pub const ALL: [OffsetStrategy; 4] = [
        OffsetStrategy::Normal,
        OffsetStrategy::Ray,
        OffsetStrategy::Scaled,
        OffsetStrategy::Robust,
    ];

    /// The name used in JSON and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            OffsetStrategy::Normal => "normal",
            OffsetStrategy::Ray => "ray",
            OffsetStrategy::Scaled => "scaled",
            OffsetStrategy::Robust => "robust",
        }
    }

    /// Whether the strategy uses `epsilon` at all.
    #[must_use]
    pub fn uses_epsilon(self) -> bool {
        self != OffsetStrategy::Robust
    }
}

/// Offset strategy and its epsilon.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OffsetDesc {
    /// Strategy.
    pub strategy: OffsetStrategy,
    /// Epsilon in world units (>= 0).
    pub epsilon: f64,
}

impl Default for OffsetDesc {
    fn default() -> Self {
        Self {
            strategy: OffsetStrategy::Normal,
            epsilon: 1e-4,
        }
    }
}

/// The sampler of these settings: its kind, `spp` and `seed` (here, so that sampling does
/// not depend on the scene).
impl crate::sampling::SceneSampler {
    /// The sampler of `settings`: its kind, `spp` and `seed`.
    #[must_use]
    pub fn for_settings(settings: &Settings) -> Self {
        Self::new(settings.sampler_kind(), settings.spp, settings.seed)
    }
}

/// The pixel filter (`settings.filter`), importance-sampled: the camera ray's offset from the
/// pixel centre is drawn from it ([`crate::sampling::PixelFilter`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum FilterDesc {
    /// Uniform over the pixel (today's positions, bit for bit). A struct variant, empty, so
    /// that `deny_unknown_fields` refuses `{"type": "box", "radius": -5}` (serde lets a unit
    /// variant of an internally tagged enum take any fields).
    Box {},
    /// Separable tent of `radius` pixels.
    Tent {
        /// Half-width in pixels (> 0).
        radius: f64,
    },
    /// Separable Gaussian of standard deviation `sigma` pixels, truncated at `radius` pixels.
    Gaussian {
        /// Standard deviation in pixels (> 0).
        sigma: f64,
        /// Truncation radius in pixels (> 0); default [`GAUSSIAN_RADIUS_SIGMAS`] `sigma`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius: Option<f64>,
    },
}

impl Default for FilterDesc {
    fn default() -> Self {
        FilterDesc::Box {}
    }
}

/// A Gaussian filter without a `radius` is truncated at this many `sigma`.
pub const GAUSSIAN_RADIUS_SIGMAS: f64 = 3.0;

impl FilterDesc {
    /// The sampling filter.
    #[must_use]
    pub fn filter(&self) -> crate::sampling::PixelFilter {
        use crate::sampling::PixelFilter;
        match *self {
            FilterDesc::Box {} => PixelFilter::Box,
            FilterDesc::Tent { radius } => PixelFilter::Tent { radius },
            FilterDesc::Gaussian { sigma, radius } => PixelFilter::Gaussian {
                sigma,
                radius: radius.unwrap_or(GAUSSIAN_RADIUS_SIGMAS * sigma),
            },
        }
    }

    /// Whether this is the default box.
    #[must_use]
    pub fn is_box(&self) -> bool {
        matches!(self, FilterDesc::Box {})
    }

    /// The filter written `box`, `tent:R` or `gaussian:SIGMA` (the `--filter` flag), or why
    /// not. Values are checked by [`crate::scene::check_settings`].
    ///
    /// # Errors
    /// An unknown type, a missing or extra parameter, or a parameter that is not a number.
    pub fn parse(v: &str) -> Result<Self, String> {
        let (kind, arg) = match v.split_once(':') {
            Some((k, a)) => (k, Some(a)),
            None => (v, None),
        };
        let number = |a: Option<&str>, what: &str| -> Result<f64, String> {
            let a = a.ok_or_else(|| {
                format!("{kind} needs its {what}: {kind}:{}", what.to_uppercase())
            })?;
            a.trim()
                .parse::<f64>()
                .map_err(|_| format!("{what} {a:?} is not a number"))
        };
        match kind {
            "box" if arg.is_none() => Ok(FilterDesc::Box {}),
            "box" => Err("box takes no parameter".into()),
            "tent" => Ok(FilterDesc::Tent {
                radius: number(arg, "radius")?,
            }),
            "gaussian" => Ok(FilterDesc::Gaussian {
                sigma: number(arg, "sigma")?,
                radius: None,
            }),
            _ => Err(format!(
                "unknown filter {kind:?}, expected box, tent:RADIUS or gaussian:SIGMA"
            )),
        }
    }
}

/// Tracer settings: the integrator in force and every integrator's own settings (so that a
/// command that switches integrator, `--integrator`, `raytree versus` or the inspector's menu,
/// finds the scene's), and what every integrator reads (film sampling, offsets, depth).
///
/// The scene JSON spells the integrator's settings as a tagged value (`spelling.rs`,
/// `docs/scene-format.md`); a tree and a report record them flat
/// ([`crate::scene::desc::SettingsRecord`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The integrator in force.
    pub integrator: IntegratorKind,
    /// What the Whitted integrator reads.
    pub whitted: WhittedSettings,
    /// What the path, light and bdpt integrators read.
    pub path: PathSettings,
    /// Seed of the per-pixel sample positions and random numbers (0 = the historical positions).
    pub seed: u64,
    /// Deepest recursion; 0 = camera rays and shadow rays only.
    pub max_depth: u32,
    /// Samples per pixel (stratified; positions drawn from `filter`).
    pub spp: u32,
    /// The pixel filter (default box).
    pub filter: FilterDesc,
    /// Secondary-ray offset.
    pub offset: OffsetDesc,
    /// Per-sample ray budget (camera, secondary and shadow rays): a sample that reaches it
    /// spawns no more secondary rays (the safety net of the exhaustive tree).
    pub max_rays: u64,
    /// The sampler (absent: the integrator's default, [`Settings::sampler_kind`]).
    pub sampler: Option<SamplerKind>,
    /// What `spp` means without `adaptive`: `auto` (edge pixels take `spp` samples, the
    /// others one, where the image is a function of the film position alone) or `uniform`.
    pub antialiasing: Antialiasing,
    /// Adaptive antialiasing with a chosen threshold: more samples only for pixels whose
    /// first `spp` samples (and their neighbours') disagree; overrides `antialiasing`.
    pub adaptive: Option<AdaptiveDesc>,
}

impl Settings {
    /// The sampler in effect: `sampler` if set, otherwise Sobol for the path and light
    /// integrators (lower error per sample, `docs/path-tracing.md`) and stratified for Whitted
    /// (its images as they always were).
    #[must_use]
    pub fn sampler_kind(&self) -> SamplerKind {
        self.sampler.unwrap_or(match self.integrator {
            IntegratorKind::Path | IntegratorKind::Light | IntegratorKind::Bdpt => {
                SamplerKind::Sobol
            }
            IntegratorKind::Whitted => SamplerKind::Stratified,
        })
    }
}

/// Default [`Settings::max_rays`] per sample: 2^20.
pub const DEFAULT_MAX_RAYS: u64 = 1 << 20;

/// Default [`Settings::max_depth`].
pub const DEFAULT_MAX_DEPTH: u32 = 16;

impl Default for Settings {
    fn default() -> Self {
        Self {
            integrator: IntegratorKind::Whitted,
            whitted: WhittedSettings::default(),
            path: PathSettings::default(),
            seed: 0,
            max_depth: DEFAULT_MAX_DEPTH,
            spp: 1,
            filter: FilterDesc::Box {},
            offset: OffsetDesc::default(),
            max_rays: DEFAULT_MAX_RAYS,
            sampler: None,
            antialiasing: Antialiasing::Auto,
            adaptive: None,
        }
    }
}
