//! The recorded ray tree of one pixel: plain data, serializable (`raytree.tree/2`; `/1` trees,
//! written before the path integrator, read as they are: every field added since has a default).
//!
//! Nodes live in one arena (`RayTree::nodes`) and refer to each other by [`NodeId`]. Every view
//! (text, JSON, diagram, inspector) reads this structure; keep it stable.

use crate::bvh::TraversalCost;
use crate::math::{Fresnel, Rgb};
use crate::scene::Settings;
use glam::DVec3;
use serde::{Deserialize, Serialize};

mod path;
#[cfg(test)]
mod tests;

pub use path::{DeltaTag, PathInfo, Pdf, Roulette};

/// The JSON schema tag of a serialized tree.
pub const TREE_SCHEMA: &str = "raytree.tree/2";

/// The schema tags a reader accepts: this one and `raytree.tree/1` (no path-tracing fields).
pub const TREE_SCHEMAS_READ: [&str; 2] = [TREE_SCHEMA, "raytree.tree/1"];

/// Index of a node in [`RayTree::nodes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(transparent)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The arena index.
    #[must_use]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a ray is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    /// From the eye through the pixel.
    Camera,
    /// Mirror or Fresnel reflection (including total internal reflection).
    Reflected,
    /// Snell refraction.
    Refracted,
    /// Towards a light.
    Shadow,
    /// A diffuse bounce sampled from the BSDF (path integrator).
    Diffuse,
}

impl RayKind {
    /// Number of kinds.
    pub const COUNT: usize = 5;

    /// All kinds, in display order.
    pub const ALL: [RayKind; Self::COUNT] = [
        RayKind::Camera,
        RayKind::Reflected,
        RayKind::Refracted,
        RayKind::Shadow,
        RayKind::Diffuse,
    ];

    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Camera => "camera",
            RayKind::Reflected => "reflected",
            RayKind::Refracted => "refracted",
            RayKind::Shadow => "shadow",
            RayKind::Diffuse => "diffuse",
        }
    }
}

/// Why a ray's recursion ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndReason {
    /// Not finished (only seen while tracing).
    Pending,
    /// Missed everything: background radiance.
    Miss,
    /// Hit a surface with no reflectivity or transmissivity: only local shading.
    Surface,
    /// Spawned all its secondary rays.
    Continued,
    /// Secondary rays were cut by `max_depth`.
    MaxDepth,
    /// Secondary rays were cut by `min_weight`.
    MinWeight,
    /// Secondary rays were cut because the sample reached its ray budget (`max_rays`).
    RayBudget,
    /// Shadow ray reached its light unblocked.
    Unblocked,
    /// Shadow ray passed translucent blockers with some light left.
    Attenuated,
    /// Shadow ray stopped by an opaque blocker (or all light absorbed).
    Blocked,
    /// The light is behind the surface (`N.L <= 0`): no shadow ray was cast.
    LightBehind,
    /// Path integrator: Russian roulette ended the path here.
    RussianRoulette,
    /// Path integrator: the BSDF sample carried nothing (absorbed, below the horizon, or a
    /// sampled direction on the wrong side of the geometric surface).
    Absorbed,
}

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
}

/// Beer's law on the segment of this ray.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Attenuation {
    /// The absorbing object the segment lies in.
    pub medium: usize,
    /// Distance travelled inside it (may be infinite for a miss).
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

/// A surface the spawn offset skipped (see `trace::diagnose`).
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
    /// Distance to the light (infinite for directional).
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
}

impl GlossyLobe {
    /// Words for the text tree.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::RoughMirror => "rough mirror",
            Self::RoughDielectric => "rough dielectric",
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

/// One ray of the tree.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RayNode {
    /// This node's id.
    pub id: NodeId,
    /// What the ray is for.
    pub kind: RayKind,
    /// Recursion depth (camera = 0; a shadow ray has its surface's depth).
    pub depth: u32,
    /// The spawning ray.
    pub parent: Option<NodeId>,
    /// Spawned rays, in order.
    pub children: Vec<NodeId>,
    /// Surface point the ray was spawned from (the eye for camera rays).
    pub spawn_point: DVec3,
    /// Offset applied: `origin - spawn_point`.
    pub offset: DVec3,
    /// Ray origin.
    pub origin: DVec3,
    /// Unit direction.
    pub direction: DVec3,
    /// Smallest accepted hit distance.
    pub t_min: f64,
    /// Closest hit (none for misses and shadow rays).
    pub hit: Option<HitInfo>,
    /// Dielectric event at the hit.
    pub interface: Option<Interface>,
    /// Beer's law on this ray's segment.
    pub attenuation: Option<Attenuation>,
    /// Weight relative to the parent (reflectivity + T*R, T*(1-R), BRDF*cos for shadows, or
    /// `bsdf * cos / pdf / count` for a sampled glossy ray).
    pub weight: Rgb,
    /// Product of weights and attenuations from the camera to this ray's origin.
    pub throughput: Rgb,
    /// Emission seen at the hit.
    pub emitted: Rgb,
    /// Ambient term at the hit.
    pub ambient: Rgb,
    /// Local shading: emission + ambient + sum of shadow children's weighted radiance.
    pub local: Rgb,
    /// Radiance carried back along this ray (after attenuation).
    pub radiance: Rgb,
    /// Secondary weight that was not traced (max depth or min weight).
    pub truncated: Rgb,
    /// Why recursion ended here.
    pub end: EndReason,
    /// Shadow details (shadow rays only).
    pub shadow: Option<ShadowInfo>,
    /// Acceleration-structure work for this ray's intersection query.
    #[serde(default)]
    pub traversal: TraversalCost,
    /// The ray's first hit is the surface it was spawned from, a self-intersection (set only
    /// when diagnostics ran; always for recorded trees).
    #[serde(default)]
    pub self_hit: bool,
    /// The spawn offset skipped this surface, which a zero offset would have met.
    #[serde(default)]
    pub leak: Option<Leak>,
    /// Path integrator: the sample's estimator at this ray (absent in Whitted trees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<PathInfo>,
    /// For a reflected or refracted ray sampled from a rough lobe: the sample (absent for the
    /// smooth lobes' rays and in trees written before glossy sampling).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glossy: Option<GlossySample>,
}

impl RayNode {
    /// A fresh node; fields are filled as tracing proceeds.
    #[must_use]
    pub fn new(
        kind: RayKind,
        depth: u32,
        spawn_point: DVec3,
        origin: DVec3,
        direction: DVec3,
    ) -> Self {
        Self {
            id: NodeId(0),
            kind,
            depth,
            parent: None,
            children: Vec::new(),
            spawn_point,
            offset: origin - spawn_point,
            origin,
            direction,
            t_min: 0.0,
            hit: None,
            interface: None,
            attenuation: None,
            weight: Rgb::ONE,
            throughput: Rgb::ONE,
            emitted: Rgb::ZERO,
            ambient: Rgb::ZERO,
            local: Rgb::ZERO,
            radiance: Rgb::ZERO,
            truncated: Rgb::ZERO,
            end: EndReason::Pending,
            shadow: None,
            traversal: TraversalCost::default(),
            self_hit: false,
            leak: None,
            path: None,
            glossy: None,
        }
    }

    /// This ray's contribution to the pixel: `throughput * radiance`.
    #[must_use]
    pub fn contribution(&self) -> Rgb {
        self.throughput * self.radiance
    }
}

/// One sample of the pixel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleRecord {
    /// Sample index.
    pub index: u32,
    /// Film position in pixels.
    pub film: [f64; 2],
    /// Root (camera) node.
    pub root: NodeId,
    /// Radiance of the sample.
    pub radiance: Rgb,
}

/// The full ray tree of one pixel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RayTree {
    /// Always [`TREE_SCHEMA`].
    pub schema: String,
    /// Pixel coordinates.
    pub pixel: [u32; 2],
    /// Settings used.
    pub settings: Settings,
    /// Pixel radiance: the mean of the samples (equals the rendered pixel bit for bit).
    pub radiance: Rgb,
    /// Samples.
    pub samples: Vec<SampleRecord>,
    /// All nodes.
    pub nodes: Vec<RayNode>,
}

impl RayTree {
    /// The node with id `id`.
    #[must_use]
    pub fn node(&self, id: NodeId) -> &RayNode {
        &self.nodes[id.index()]
    }

    /// Node ids in depth-first order starting at `root`.
    #[must_use]
    pub fn depth_first(&self, root: NodeId) -> Vec<NodeId> {
        let mut out = Vec::new();
        let mut stack = vec![root];
        while let Some(id) = stack.pop() {
            out.push(id);
            stack.extend(self.node(id).children.iter().rev());
        }
        out
    }

    /// Number of nodes of each kind, in [`RayKind::ALL`] order.
    #[must_use]
    pub fn count_by_kind(&self) -> [usize; RayKind::COUNT] {
        let mut c = [0; RayKind::COUNT];
        for n in &self.nodes {
            c[RayKind::ALL.iter().position(|k| *k == n.kind).unwrap_or(0)] += 1;
        }
        c
    }
}
