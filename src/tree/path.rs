//! What the path integrator records on a node ([`crate::tree::RayNode::path`]).

use crate::math::Rgb;
use serde::{Deserialize, Serialize};

/// A solid-angle pdf, or `"delta"` for a specular event or a point/directional light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Pdf {
    /// Solid-angle density (sr^-1).
    Density(f64),
    /// A delta distribution (written `"delta"`).
    Delta(DeltaTag),
}

/// The JSON word `"delta"` of [`Pdf::Delta`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum DeltaTag {
    /// `"delta"`.
    #[serde(rename = "delta")]
    Delta,
}

/// A Russian-roulette decision (path integrator).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Roulette {
    /// Survival probability `min(1, max component of the throughput)`.
    pub probability: f64,
    /// Whether the path went on (its continuation was divided by `probability`).
    pub survived: bool,
}

/// What the path integrator records on a node (`RayNode::path`); see `docs/path-tracing.md`.
///
/// For a continuation ray (`camera`, `diffuse`, `reflected`, `refracted`): the lobe sampled at
/// its origin, its pdf, `bsdf_cos_pdf = f |cos| / pdf` (the node's `weight` is that divided by
/// the roulette probability), and at its hit the MIS weight of the emission it found. For a
/// shadow ray (next-event estimation): the lobe class that scatters the light, the light pdf
/// (selection x solid angle) and the MIS weight of the light sample. `contribution` is what
/// this node adds to the sample's radiance (throughput x Beer x weighted emission for a ray,
/// throughput x Beer x weight x radiance for a shadow ray): a sample's radiance is the sum of
/// its nodes' contributions in depth-first order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathInfo {
    /// The sampled lobe (absent for camera rays).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lobe: Option<crate::bsdf::LobeKind>,
    /// Solid-angle pdf of this ray's direction (BSDF pdf for continuations, light pdf for
    /// shadow rays), or delta.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pdf: Option<Pdf>,
    /// `f |cos| / pdf` of the sampled direction (continuations) or `f |cos|` (shadow rays).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bsdf_cos_pdf: Option<crate::math::Rgb>,
    /// MIS weight (power heuristic) of this light sample, or of the emission this ray found.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mis_weight: Option<f64>,
    /// The Russian-roulette decision taken at this ray's hit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roulette: Option<Roulette>,
    /// Bidirectional strategies (`bdpt`, and light tracing's connections): `[s, t]`, the
    /// vertices taken from the light subpath and from the camera subpath.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strategy: Option<[u32; 2]>,
    /// The strategy's contribution before its MIS weight (`contribution / mis_weight`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unweighted: Option<Rgb>,
    /// What this node adds to the sample's radiance.
    pub contribution: Rgb,
    /// Light path expression (OSL alphabet) of the path to this node; ends in `L` or `B` when
    /// the node contributes light.
    pub lpe: String,
}
