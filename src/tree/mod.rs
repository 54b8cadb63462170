//! The recorded ray tree of one pixel: plain data, serializable (`raytree.tree/2`, or
//! `raytree.tree/3` when it holds light-subpath splats; `/1` trees, written before the path
//! integrator, and `/2` trees are read as they are: every field added since has a default).
//!
//! Nodes live in one arena (`RayTree::nodes`) and refer to each other by [`NodeId`]. Every view
//! (text, JSON, diagram, inspector) reads this structure; keep it stable.

use crate::bvh::TraversalCost;
use crate::math::Rgb;
use crate::scene::Settings;
use glam::DVec3;
use serde::{Deserialize, Serialize};

mod info;
mod path;
#[cfg(test)]
mod tests;

pub use info::{
    AreaSample, Attenuation, Blocker, GlossyLobe, GlossySample, HitInfo, Interface, Leak,
    ShadowInfo, SplitRoulette,
};
pub use path::{DeltaTag, PathInfo, Pdf, Roulette};

/// The JSON schema tag of a serialized tree traced from the camera only.
pub const TREE_SCHEMA: &str = "raytree.tree/2";

/// The schema tag of a tree that holds light-subpath splats ([`RayTree::splats`], the `light`
/// integrator; `docs/bidirectional.md`): `/2` plus the splats and the `light` and `connection`
/// ray kinds.
pub const TREE_SCHEMA_SPLATS: &str = "raytree.tree/3";

/// The schema tags a reader accepts: `/3`, `/2` and `raytree.tree/1` (no path-tracing fields).
pub const TREE_SCHEMAS_READ: [&str; 3] = [TREE_SCHEMA_SPLATS, TREE_SCHEMA, "raytree.tree/1"];

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
    /// A ray of a light subpath: leaving an emitter, or scattered along the path from it
    /// (light tracing; its throughput is flux, not importance).
    Light,
    /// The connection of a light-subpath vertex to the camera (light tracing): a visibility
    /// ray whose contribution is splatted to the pixel it lands in.
    Connection,
}

impl RayKind {
    /// Number of kinds.
    pub const COUNT: usize = 7;

    /// All kinds, in display order.
    pub const ALL: [RayKind; Self::COUNT] = [
        RayKind::Camera,
        RayKind::Reflected,
        RayKind::Refracted,
        RayKind::Shadow,
        RayKind::Diffuse,
        RayKind::Light,
        RayKind::Connection,
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
            RayKind::Light => "light",
            RayKind::Connection => "connection",
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
    /// Settings used, as a flat record ([`crate::scene::desc::SettingsRecord`]).
    #[serde(with = "crate::scene::desc::flat_settings")]
    pub settings: Settings,
    /// Pixel radiance: the mean of the samples (equals the rendered pixel bit for bit).
    pub radiance: Rgb,
    /// Samples.
    pub samples: Vec<SampleRecord>,
    /// All nodes.
    pub nodes: Vec<RayNode>,
    /// Under automatic antialiasing (`settings.antialiasing: "auto"` where it applies): whether
    /// the pixel was on an edge (`spp` samples at its Sobol points) or not (its first pass
    /// only: its first `max(2, spp / 16)` Sobol points). Absent otherwise (every pixel took `spp`, or `settings.adaptive` decided),
    /// and in files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<bool>,
    /// Light tracing: every light-subpath contribution that landed in this pixel during the
    /// render, in the order the render added them (by light path, then along it). The pixel
    /// radiance is the sample mean plus their sum divided by `splat_divisor`. Empty for
    /// integrators that trace from the camera only (and absent from their files).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub splats: Vec<SplatRecord>,
    /// What the splat sum is divided by: the light paths started per pixel (`spp`); 0 when
    /// there are no splats.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub splat_divisor: u32,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

/// One light-subpath contribution splatted into a pixel (light tracing, `docs/bidirectional.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplatRecord {
    /// The light path's index in the pass (`(y * width + x) * spp + s` of the pixel sample that
    /// seeds it; the path itself starts on a light, anywhere).
    pub path: u64,
    /// The pixel and sample index that seed the light path.
    pub seed: [u32; 3],
    /// The strategy: `s` vertices on the light subpath (the emitter's counted), `t` on the
    /// camera subpath (1: the camera itself).
    pub strategy: [u32; 2],
    /// Film position where the connection lands, in pixels.
    pub film: [f64; 2],
    /// The light path's first ray (its root node, kind `light`).
    pub root: NodeId,
    /// The connection to the camera (kind `connection`).
    pub connection: NodeId,
    /// Unweighted contribution (what the splat adds before the division by `splat_divisor`).
    pub contribution: Rgb,
    /// MIS weight of the strategy (1: light tracing is the only strategy for these paths).
    pub mis_weight: f64,
    /// The light path expression, read from the camera (`C<RD><TS><TS>L`).
    pub lpe: String,
}

impl RayTree {
    /// The node with id `id`.
    #[must_use]
    pub fn node(&self, id: NodeId) -> &RayNode {
        &self.nodes[id.index()]
    }

    /// Per node (by index), whether it adds to this pixel: it is under one of the pixel's
    /// camera samples, or it is the connection of a splat that landed here. A light path
    /// recorded for its splats here also holds the connections it splatted to other pixels;
    /// those are marked `false`.
    #[must_use]
    pub fn pixel_nodes(&self) -> Vec<bool> {
        let mut mark = vec![false; self.nodes.len()];
        for s in &self.samples {
            for id in self.depth_first(s.root) {
                mark[id.index()] = true;
            }
        }
        for s in &self.splats {
            if let Some(m) = mark.get_mut(s.connection.index()) {
                *m = true;
            }
        }
        mark
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
