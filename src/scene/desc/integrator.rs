//! The integrators' own settings: which integrator ([`IntegratorKind`]) and what each reads
//! ([`WhittedSettings`], [`PathSettings`]), spelled in the scene JSON as a tagged value,
//! `"integrator": {"type": "whitted", "fresnel": "schlick"}` (`docs/scene-format.md`; the
//! spelling itself is in `spelling.rs`).

use crate::math::FresnelModel;
use serde::{Deserialize, Serialize};

/// Which integrator computes a camera ray's radiance (`settings.integrator`'s `type`).
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

    /// Whether the integrator splats light paths into other pixels (light tracing, BDPT): its
    /// pixels are not sums of their own samples alone, so per-pixel refinement (progressive
    /// passes, adaptive sampling) does not apply.
    #[must_use]
    pub fn splats(self) -> bool {
        matches!(self, IntegratorKind::Light | IntegratorKind::Bdpt)
    }

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

/// What the Whitted integrator alone reads (`settings.integrator` of type `"whitted"`). The
/// Monte Carlo integrators ignore it: [`WhittedSettings::WHY_OTHERS_IGNORE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WhittedSettings {
    /// Fresnel model.
    pub fresnel: FresnelModel,
    /// Shadow-ray mode.
    pub shadows: ShadowMode,
    /// Throughput below which recursion stops (`0` = the exhaustive tree); absent (`None`):
    /// chosen from `tolerance` and the scene ([`crate::integrator::bound`]).
    pub min_weight: Option<f64>,
    /// What one cut branch may still add to a pixel, in display units (sRGB-encoded, 0..1);
    /// decides the automatic `min_weight`. Default half an 8-bit step, 1/510.
    pub tolerance: f64,
    /// Shadow rays per area light (emissive sphere, quad or triangle) per diffuse hit (soft
    /// shadows). Absent: emissive objects are only seen (by camera, mirror and refracted
    /// rays), not sampled as lights, as before area lights existed.
    pub light_samples: Option<u32>,
    /// Rays sampled per rough (`roughness > 0`) reflection or refraction lobe, at the first
    /// rough hit of a path (below a sampled ray, one per lobe).
    pub glossy_samples: u32,
    /// From this depth on (0 = the camera ray's hit), a smooth dielectric hit follows one of
    /// reflection and refraction, chosen by Russian roulette with probability proportional to
    /// their weights, instead of both ([`crate::integrator::roulette`]); absent: always both.
    pub dielectric_roulette: Option<u32>,
    /// A smooth dielectric hit whose throughput (max channel) is below this weight follows one
    /// of reflection and refraction, chosen by Russian roulette, instead of both (`0`: always
    /// both); absent: chosen from the scene ([`crate::integrator::roulette`]'s automatic
    /// weight, off for an explicit `min_weight` or a tolerance of 0).
    pub roulette_below: Option<f64>,
}

impl WhittedSettings {
    /// Why the Monte Carlo integrators ignore these settings, in one clause.
    pub const WHY_OTHERS_IGNORE: &'static str = "it always uses exact Fresnel, its shadow rays \
        are visibility tests, so light through glass arrives by BSDF sampling, it takes one \
        light sample and one BSDF sample per bounce, and Russian roulette ends its paths instead of a \
        cut";
}

/// Default [`WhittedSettings::tolerance`]: half an 8-bit display step.
pub const DEFAULT_TOLERANCE: f64 = 1.0 / 510.0;

impl Default for WhittedSettings {
    fn default() -> Self {
        Self {
            fresnel: FresnelModel::Exact,
            shadows: ShadowMode::Opaque,
            min_weight: None,
            tolerance: DEFAULT_TOLERANCE,
            light_samples: None,
            glossy_samples: 1,
            dielectric_roulette: None,
            roulette_below: None,
        }
    }
}

/// What the Monte Carlo integrators read (`"path"`, `"light"` and `"bdpt"` share it, so that
/// comparing them compares estimators, not settings).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSettings {
    /// Russian roulette from this bounce on (the first bounce is 1; 0 plays from the first
    /// bounce too), survival probability min(1, max component of the throughput).
    pub rr_depth: u32,
    /// Bidirectional path tracing: the MIS heuristic over its strategies (default balance).
    /// Read by `bdpt` alone.
    pub mis: MisHeuristic,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            rr_depth: DEFAULT_RR_DEPTH,
            mis: MisHeuristic::Balance,
        }
    }
}

/// The multiple-importance-sampling heuristic bidirectional path tracing weighs its strategies
/// (s, t) by (`settings.path.mis`; Veach 1997, section 9.2.2): the path tracer always combines its
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
}

impl TryFrom<String> for MisHeuristic {
    type Error = String;

    fn try_from(s: String) -> Result<Self, String> {
        Self::from_name(&s)
    }
}

/// Default [`PathSettings::rr_depth`].
pub const DEFAULT_RR_DEPTH: u32 = 5;
