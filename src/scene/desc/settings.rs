//! The `settings` block and its parts (offsets, shadows, integrator, pixel filter) of the scene
//! JSON: the serde mirror, documented in `docs/scene-format.md`.

use super::antialias::{AdaptiveDesc, Antialiasing};
use crate::math::FresnelModel;
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

/// How shadow rays treat transmissive blockers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShadowMode {
    /// Any blocker stops the shadow ray.
    #[default]
    Opaque,
    /// Each blocker passes transmissivity x Beer's attenuation over its chord (no caustics).
    Translucent,
}

/// Which integrator computes a camera ray's radiance (`settings.integrator`).
///
/// `"whitted"` is the lecture's recursion, `"path"` the Monte Carlo path tracer
/// ([`crate::integrator::PathTracer`], `docs/path-tracing.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", try_from = "String")]
pub enum IntegratorKind {
    /// The lecture's recursion ([`crate::integrator::Whitted`]).
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation, MIS and Russian roulette
    /// ([`crate::integrator::PathTracer`]).
    Path,
    /// Light tracing (particle tracing): paths start on the lights and every non-specular
    /// vertex connects to the camera ([`crate::integrator::LightTracer`],
    /// `docs/bidirectional.md`).
    Light,
    /// Bidirectional path tracing: every strategy (s, t) joining a camera and a light subpath,
    /// weighted by MIS ([`crate::integrator::Bdpt`], `docs/bidirectional.md`).
    Bdpt,
}

impl IntegratorKind {
    /// Every integrator, in documentation order.
    pub const ALL: [IntegratorKind; 4] = [
        IntegratorKind::Whitted,
        IntegratorKind::Path,
        IntegratorKind::Light,
        IntegratorKind::Bdpt,
    ];

    /// The settings (field names) only the Whitted integrator reads: the path integrator
    /// ignores them ([`IntegratorKind::WHITTED_ONLY_WHY`]). `raytree cost` leaves out their axes
    /// under the path integrator and the CLI names them when they are given for it.
    pub const WHITTED_ONLY: [&'static str; 8] = [
        "fresnel",
        "shadows",
        "min_weight",
        "tolerance",
        "light_samples",
        "glossy_samples",
        "dielectric_roulette",
        "roulette_below",
    ];

    /// Whether the integrator splats light paths into other pixels (light tracing, BDPT): its
    /// pixels are not sums of their own samples alone, so per-pixel refinement (progressive
    /// passes, adaptive sampling) does not apply.
    #[must_use]
    pub fn splats(self) -> bool {
        matches!(self, IntegratorKind::Light | IntegratorKind::Bdpt)
    }

    /// Why the path integrator ignores [`IntegratorKind::WHITTED_ONLY`], in one clause.
    pub const WHITTED_ONLY_WHY: &'static str = "it always uses exact Fresnel, its shadow rays \
        are visibility tests, so light through glass arrives by BSDF sampling, it takes one \
        light sample and one BSDF sample per bounce, and Russian roulette ends its paths instead of a \
        cut";

    /// The name used in JSON and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
            IntegratorKind::Light => "light",
            IntegratorKind::Bdpt => "bdpt",
        }
    }

    /// The integrator named `name`, or why there is none.
    ///
    /// # Errors
    /// A message for unknown names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "whitted" => Ok(IntegratorKind::Whitted),
            "path" => Ok(IntegratorKind::Path),
            "light" => Ok(IntegratorKind::Light),
            "bdpt" => Ok(IntegratorKind::Bdpt),
            _ => Err(format!(
                "unknown integrator {name:?}, expected \"whitted\", \"path\", \"light\" or \"bdpt\""
            )),
        }
    }
}

impl TryFrom<String> for IntegratorKind {
    type Error = String;

    fn try_from(name: String) -> Result<Self, String> {
        Self::from_name(&name)
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

/// Tracer settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// The integrator (`"whitted"` or `"path"`).
    pub integrator: IntegratorKind,
    /// Seed of the per-pixel sample positions and random numbers (0 = the historical positions).
    pub seed: u64,
    /// Deepest recursion; 0 = camera rays and shadow rays only.
    pub max_depth: u32,
    /// Samples per pixel (stratified; positions drawn from `filter`).
    pub spp: u32,
    /// The pixel filter (default box).
    #[serde(skip_serializing_if = "FilterDesc::is_box")]
    pub filter: FilterDesc,
    /// Secondary-ray offset.
    pub offset: OffsetDesc,
    /// Fresnel model.
    pub fresnel: FresnelModel,
    /// Shadow-ray mode.
    pub shadows: ShadowMode,
    /// Throughput below which recursion stops (`0` = the exhaustive tree); absent (`None`):
    /// chosen from `tolerance` and the scene ([`crate::integrator::bound`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_weight: Option<f64>,
    /// What one cut branch may still add to a pixel, in display units (sRGB-encoded, 0..1);
    /// decides the automatic `min_weight`. Default half an 8-bit step, 1/510.
    pub tolerance: f64,
    /// Per-sample ray budget (camera, secondary and shadow rays): a sample that reaches it
    /// spawns no more secondary rays (the safety net of the exhaustive tree).
    pub max_rays: u64,
    /// Shadow rays per area light (emissive sphere, quad or triangle) per diffuse hit in the
    /// Whitted integrator (soft shadows). Absent: emissive objects are only seen (by camera,
    /// mirror and refracted rays), not sampled as lights, as before area lights existed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_samples: Option<u32>,
    /// Path integrator: Russian roulette from this bounce on (the first bounce is 1; 0 plays
    /// from the first bounce too), survival probability min(1, max component of the
    /// throughput). Ignored by the Whitted integrator.
    #[serde(skip_serializing_if = "is_default_rr_depth")]
    pub rr_depth: u32,
    /// Rays sampled per rough (`roughness > 0`) reflection or refraction lobe in the Whitted
    /// integrator, at the first rough hit of a path (below a sampled ray, one per lobe).
    #[serde(skip_serializing_if = "is_one")]
    pub glossy_samples: u32,
    /// The sampler (absent: the integrator's default, [`Settings::sampler_kind`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler: Option<SamplerKind>,
    /// What `spp` means without `adaptive`: `auto` (edge pixels take `spp` samples, the
    /// others one, where the image is a function of the film position alone) or `uniform`.
    #[serde(skip_serializing_if = "Antialiasing::is_auto")]
    pub antialiasing: Antialiasing,
    /// Adaptive antialiasing with a chosen threshold: more samples only for pixels whose
    /// first `spp` samples (and their neighbours') disagree; overrides `antialiasing`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<AdaptiveDesc>,
    /// Whitted integrator: from this depth on (0 = the camera ray's hit), a smooth dielectric
    /// hit follows one of reflection and refraction, chosen by Russian roulette with
    /// probability proportional to their weights, instead of both ([`crate::integrator::roulette`]);
    /// absent: always both.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dielectric_roulette: Option<u32>,
    /// Whitted integrator: a smooth dielectric hit whose throughput (max channel) is below this
    /// weight follows one of reflection and refraction, chosen by Russian roulette, instead of
    /// both (`0`: always both); absent: chosen from the scene ([`crate::integrator::roulette`]'s
    /// automatic weight, off for an explicit `min_weight` or a tolerance of 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roulette_below: Option<f64>,
    /// Bidirectional path tracing: the MIS heuristic over its strategies (default balance).
    /// Read by `bdpt` alone.
    #[serde(skip_serializing_if = "MisHeuristic::is_balance")]
    pub mis: MisHeuristic,
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

/// The multiple-importance-sampling heuristic bidirectional path tracing weighs its strategies
/// (s, t) by (`settings.mis`; Veach 1997, section 9.2.2): the path tracer always combines its
/// light and BSDF samples by the power heuristic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", try_from = "String")]
pub enum MisHeuristic {
    /// `w_s = p_s / sum_i p_i` (pbrt-v3 and -v4's `BDPTIntegrator`).
    #[default]
    Balance,
    /// `w_s = p_s^2 / sum_i p_i^2`, the exponent 2 Veach recommends (Mitsuba 3's `bdpt`).
    Power,
}

impl MisHeuristic {
    /// The heuristic's name in scene files and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MisHeuristic::Balance => "balance",
            MisHeuristic::Power => "power",
        }
    }

    /// From its name.
    ///
    /// # Errors
    /// Anything but `"balance"` or `"power"`.
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "balance" => Ok(MisHeuristic::Balance),
            "power" => Ok(MisHeuristic::Power),
            _ => Err(format!(
                "unknown MIS heuristic {name:?}, expected \"balance\" or \"power\""
            )),
        }
    }

    /// `ratio` (a strategy's density over the one that made the path) as it enters the
    /// weight's denominator: itself under the balance heuristic, its square under the power
    /// heuristic.
    #[inline]
    #[must_use]
    pub fn term(self, ratio: f64) -> f64 {
        match self {
            MisHeuristic::Balance => ratio,
            MisHeuristic::Power => ratio * ratio,
        }
    }

    #[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
    fn is_balance(&self) -> bool {
        *self == MisHeuristic::Balance
    }
}

impl TryFrom<String> for MisHeuristic {
    type Error = String;

    fn try_from(s: String) -> Result<Self, String> {
        Self::from_name(&s)
    }
}

/// Default [`Settings::rr_depth`].
pub const DEFAULT_RR_DEPTH: u32 = 5;

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_default_rr_depth(v: &u32) -> bool {
    *v == DEFAULT_RR_DEPTH
}

fn is_one(v: &u32) -> bool {
    *v == 1
}

/// Default [`Settings::tolerance`]: half an 8-bit display step.
pub const DEFAULT_TOLERANCE: f64 = 1.0 / 510.0;
/// Default [`Settings::max_rays`] per sample: 2^20.
pub const DEFAULT_MAX_RAYS: u64 = 1 << 20;

impl Default for Settings {
    fn default() -> Self {
        Self {
            integrator: IntegratorKind::Whitted,
            seed: 0,
            max_depth: 16,
            spp: 1,
            filter: FilterDesc::Box {},
            offset: OffsetDesc::default(),
            fresnel: FresnelModel::Exact,
            shadows: ShadowMode::Opaque,
            min_weight: None,
            tolerance: DEFAULT_TOLERANCE,
            max_rays: DEFAULT_MAX_RAYS,
            light_samples: None,
            rr_depth: DEFAULT_RR_DEPTH,
            glossy_samples: 1,
            sampler: None,
            antialiasing: Antialiasing::Auto,
            adaptive: None,
            dielectric_roulette: None,
            roulette_below: None,
            mis: MisHeuristic::Balance,
        }
    }
}
