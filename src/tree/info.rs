//! What a node records about its hit, the interface it crossed, attenuation, shadows and
//! stochastic samples ([`crate::tree::RayNode`]'s parts).

use crate::math::{Fresnel, Rgb};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The surface a ray hit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HitInfo {
    /// Ray parameter.
    pub t: f64,
    /// World-space hit point.
    pub point: DVec3,
    /// Outward unit geometric normal.
    pub normal: DVec3,
    /// Object index.
    pub object: usize,
    /// Object name.
    pub object_name: String,
    /// Material name.
    pub material: String,
    /// Whether the ray arrived from the outer side.
    pub entering: bool,
    /// Cosine between the reversed ray and the normal on the incident side.
    pub cos_i: f64,
    /// For meshes: the triangle hit (face index in the OBJ file, polygons fan-triangulated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub triangle: Option<u32>,
    /// For smooth meshes: the outward shading normal used (the geometric `normal` where the
    /// shading normal failed the consistency rule of `mesh::shading`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading_normal: Option<DVec3>,
}

/// A dielectric interface event (only where the material transmits).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Interface {
    /// Index on the incident side.
    pub n1: f64,
    /// Index on the far side.
    pub n2: f64,
    /// Incident cosine.
    pub cos_i: f64,
    /// Transmitted cosine (`None` under total internal reflection).
    pub cos_t: Option<f64>,
    /// Reflected and transmitted fractions.
    pub fresnel: Fresnel,
    /// Total internal reflection happened.
    pub tir: bool,
    /// Russian roulette followed one of the reflected and refracted rays instead of both
    /// (`settings.roulette_below` or `settings.dielectric_roulette`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roulette: Option<SplitRoulette>,
}

/// A Russian-roulette choice between a dielectric hit's reflected and refracted rays: the ray
/// followed and the probability it had; its weight was divided by that probability.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplitRoulette {
    /// Whether the reflected ray was followed (else the refracted one).
    pub reflected: bool,
    /// The probability of that choice.
    pub probability: f64,
}

impl SplitRoulette {
    /// "reflected" or "refracted": the ray followed.
    #[must_use]
    pub fn ray(&self) -> &'static str {
        if self.reflected {
            "reflected"
        } else {
            "refracted"
        }
    }
}

/// Beer's law on the segment of this ray.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Attenuation {
    /// The absorbing object the segment lies in.
    pub medium: usize,
    /// Distance travelled inside it (infinite for a miss: `null` in JSON).
    #[serde(with = "infinite_as_null")]
    pub distance: f64,
    /// Absorption coefficients.
    pub absorption: Rgb,
    /// `exp(-absorption * distance)`.
    pub factor: Rgb,
}

/// An object a shadow ray passed through.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Blocker {
    /// Object index.
    pub object: usize,
    /// Object name.
    pub object_name: String,
    /// Ray parameter of the first crossing.
    pub t: f64,
    /// Length of the ray inside it.
    pub chord: f64,
    /// Light passed: transmissivity x Beer (zero when opaque).
    pub factor: Rgb,
}

/// A surface the spawn offset skipped (see `integrator::diagnose`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Leak {
    /// Object index.
    pub object: usize,
    /// Object name.
    pub object_name: String,
    /// Distance of the skipped crossing from the spawn point.
    pub distance: f64,
}

/// Shadow-ray details.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShadowInfo {
    /// Light index.
    pub light: usize,
    /// Light name.
    pub light_name: String,
    /// Distance to the light (infinite for directional: `null` in JSON).
    #[serde(with = "infinite_as_null")]
    pub distance: f64,
    /// `N.L` at the shaded point.
    pub cos_theta: f64,
    /// BRDF value (diffuse/pi + Blinn-Phong, + the rough lobes' GGX reflection for point and
    /// directional lights).
    pub brdf: Rgb,
    /// Unshadowed irradiance on a surface facing the light.
    pub irradiance: Rgb,
    /// Everything between the point and the light.
    pub blockers: Vec<Blocker>,
    /// Product of the blockers' factors.
    pub transmittance: Rgb,
    /// For a shadow ray towards an area light (an emissive object): the sampled point and its
    /// pdf. Absent for point and directional lights (and in trees written before area lights).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub area: Option<AreaSample>,
}

/// One shadow ray's sample of an area light (`ShadowInfo::area`). For such a ray
/// `ShadowInfo::light` is `scene.lights.len() + object` (no index of `scene.lights`),
/// `light_name` the object's name, `irradiance` the estimator's `radiance / pdf`, and the
/// node's `weight` is `brdf * cos / light_samples`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AreaSample {
    /// The emissive object (index into the scene's objects).
    pub object: usize,
    /// The sampled point on it.
    pub point: DVec3,
    /// Unit direction from the shaded point to `point`.
    pub direction: DVec3,
    /// Solid-angle pdf of `direction`.
    pub pdf: f64,
    /// Emitted radiance arriving along `direction` when unoccluded.
    pub radiance: Rgb,
    /// Which of the `light_samples` samples of this light at this hit (from 0).
    pub sample: u32,
}

/// Which rough lobe a sampled ray was drawn from (`GlossySample::lobe`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GlossyLobe {
    /// The GGX rough mirror of `reflectivity` (no Fresnel).
    RoughMirror,
    /// The GGX rough dielectric of `transmissivity` (exact Fresnel per microfacet).
    RoughDielectric,
    /// The rough conductor of `reflectivity` with a `conductor` (conductor Fresnel per
    /// microfacet and channel).
    RoughConductor,
    /// The rough dielectric coating of a plastic, its reflection alone (`reflectivity` times
    /// the coating's Fresnel per microfacet; the base is lit by the light loop).
    RoughCoating,
}

impl GlossyLobe {
    /// Words for the text tree.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::RoughMirror => "rough mirror",
            Self::RoughDielectric => "rough dielectric",
            Self::RoughConductor => "rough conductor",
            Self::RoughCoating => "rough coating",
        }
    }
}

/// A reflected or refracted ray sampled from a rough lobe (`RayNode::glossy`). Its node's
/// `weight` is `bsdf * cos / pdf / count`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GlossySample {
    /// The lobe it was drawn from.
    pub lobe: GlossyLobe,
    /// Which of the `count` samples of this lobe at this hit (from 0). A sample whose
    /// direction carries nothing (below the surface) is not traced, so indices may skip.
    pub sample: u32,
    /// Samples drawn from this lobe at this hit (`settings.glossy_samples` at a path's first
    /// rough hit, 1 below a sampled ray).
    pub count: u32,
    /// Solid-angle pdf of the direction.
    pub pdf: f64,
    /// The lobe's BSDF value `f(wo, wi)` (no cosine).
    pub bsdf: Rgb,
    /// `abs(cos)` of the direction against the shading normal.
    pub cos: f64,
    /// The direction crosses the surface (refraction through the sampled microfacet).
    pub transmitted: bool,
}

/// An `f64` that may be `+infinity` by design (a directional light's distance, a miss inside an
/// absorbing medium), written as JSON `null` and read back as infinity; NaN and `-infinity`
/// stay numbers, which `crate::finite::first_nonfinite` still refuses to write.
mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if *v == f64::INFINITY {
            s.serialize_none()
        } else {
            s.serialize_f64(*v)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}
