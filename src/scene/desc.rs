//! The serde mirror of the scene JSON (documented in `docs/scene-format.md`).
//!
//! Plain data with defaults and `deny_unknown_fields`; it becomes a [`crate::Scene`] only
//! through validation (`scene::validate`).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

use crate::math::FresnelModel;
pub use crate::mesh::MeshNormals;

/// An `[x, y, z]` or `[r, g, b]` triple as written in JSON.
pub type Triple = [f64; 3];

/// The whole scene file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// The pinhole camera and image size.
    pub camera: CameraDesc,
    /// Radiance of rays that miss everything.
    #[serde(default)]
    pub background: Triple,
    /// The lecture's ambient term (times the diffuse albedo).
    #[serde(default)]
    pub ambient: Triple,
    /// Named materials.
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialDesc>,
    /// The geometry.
    #[serde(default)]
    pub objects: Vec<ObjectDesc>,
    /// Point and directional lights.
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    /// Tracer settings (each overridable on the command line).
    #[serde(default)]
    pub settings: Settings,
}

/// A pinhole camera.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub position: Triple,
    /// A point the camera looks at.
    pub look_at: Triple,
    /// Up hint (need not be orthogonal to the view direction).
    #[serde(default = "default_up")]
    pub up: Triple,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Thin-lens radius in world units (>= 0; 0, the default, is the pinhole).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub aperture_radius: f64,
    /// Distance of the plane in focus along the view direction (> 0; default
    /// `|look_at - position|`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<f64>,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn default_up() -> Triple {
    [0.0, 1.0, 0.0]
}

/// A diffuse albedo: a constant or a world-space checkerboard.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TextureDesc {
    /// Constant rgb.
    Solid(Triple),
    /// `{"checker": {...}}`.
    Checker {
        /// The checker parameters.
        checker: CheckerDesc,
    },
}

/// A 3D checkerboard: cell `(floor(x/s) + floor(y/s) + floor(z/s))` even or odd.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerDesc {
    /// Colour of even cells.
    pub even: Triple,
    /// Colour of odd cells.
    pub odd: Triple,
    /// Cell size in world units (> 0).
    pub size: f64,
}

/// The lecture's general material; every part defaults to zero / absent.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MaterialDesc {
    /// Diffuse albedo (Lambertian BRDF albedo / pi).
    pub diffuse: Option<TextureDesc>,
    /// Blinn-Phong specular colour.
    pub specular: Triple,
    /// Blinn-Phong exponent.
    pub shininess: f64,
    /// Mirror reflectivity.
    pub reflectivity: Triple,
    /// Transmissivity (refraction where `ior` is set).
    pub transmissivity: Triple,
    /// Index of refraction (> 0).
    pub ior: Option<f64>,
    /// Beer's law coefficients per unit length inside the object.
    pub absorption: Triple,
    /// Emitted radiance from the outer side.
    pub emission: Triple,
    /// GGX (Trowbridge-Reitz) alpha of the `reflectivity` and `transmissivity` lobes, in
    /// [0, 1]; 0 (the default) is smooth.
    #[serde(skip_serializing_if = "is_zero")]
    pub roughness: f64,
}

/// One object: a shape, its material and an optional name.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ObjectDesc {
    /// A sphere.
    Sphere {
        /// Centre.
        center: Triple,
        /// Radius.
        radius: f64,
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// An infinite plane; its inside is behind the normal.
    Plane {
        /// A point on the plane.
        point: Triple,
        /// Outward normal.
        normal: Triple,
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// A triangle; its front is where `(b-a) x (c-a)` points.
    Triangle {
        /// `[a, b, c]`.
        vertices: [Triple; 3],
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// A parallelogram `corner + s edge_u + t edge_v`, `s, t` in `[0, 1]`; its front (outer
    /// side, where emission leaves) is where `edge_u x edge_v` points.
    Quad {
        /// First corner.
        corner: Triple,
        /// First edge.
        edge_u: Triple,
        /// Second edge (not parallel to `edge_u`).
        edge_v: Triple,
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: Triple,
        /// Upper corner.
        max: Triple,
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// A triangle mesh read from a Wavefront OBJ file, placed by scale, rotation, translation.
    Mesh {
        /// OBJ file; a relative path is resolved against the scene file's directory.
        file: String,
        /// Translation.
        #[serde(default)]
        translate: Triple,
        /// Rotation in degrees about X, then Y, then Z (extrinsic XYZ Euler angles).
        #[serde(default)]
        rotate: Triple,
        /// Uniform scale or per-axis `[sx, sy, sz]` (non-zero).
        #[serde(default)]
        scale: ScaleDesc,
        /// Shading normals: `file` (default), `flat` or `smooth`.
        #[serde(default)]
        normals: MeshNormals,
        /// Material name.
        material: String,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
}

/// A mesh's scale: one number or one per axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ScaleDesc {
    /// The same factor on every axis.
    Uniform(f64),
    /// `[sx, sy, sz]`.
    Axes(Triple),
}

impl Default for ScaleDesc {
    fn default() -> Self {
        ScaleDesc::Uniform(1.0)
    }
}

impl ObjectDesc {
    /// The material name.
    #[must_use]
    pub fn material(&self) -> &str {
        match self {
            ObjectDesc::Sphere { material, .. }
            | ObjectDesc::Plane { material, .. }
            | ObjectDesc::Triangle { material, .. }
            | ObjectDesc::Quad { material, .. }
            | ObjectDesc::Box { material, .. }
            | ObjectDesc::Mesh { material, .. } => material,
        }
    }

    /// The optional display name.
    #[must_use]
    pub fn name(&self) -> Option<&str> {
        match self {
            ObjectDesc::Sphere { name, .. }
            | ObjectDesc::Plane { name, .. }
            | ObjectDesc::Triangle { name, .. }
            | ObjectDesc::Quad { name, .. }
            | ObjectDesc::Box { name, .. }
            | ObjectDesc::Mesh { name, .. } => name.as_deref(),
        }
    }

    /// The `type` tag.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            ObjectDesc::Sphere { .. } => "sphere",
            ObjectDesc::Plane { .. } => "plane",
            ObjectDesc::Triangle { .. } => "triangle",
            ObjectDesc::Quad { .. } => "quad",
            ObjectDesc::Box { .. } => "box",
            ObjectDesc::Mesh { .. } => "mesh",
        }
    }
}

/// A light source.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum LightDesc {
    /// Point light: irradiance `intensity / r^2` at distance r.
    Point {
        /// Position.
        position: Triple,
        /// Radiant intensity per channel.
        intensity: Triple,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
    /// Directional light: constant irradiance arriving along `direction`.
    Directional {
        /// Direction the light travels (from the light into the scene).
        direction: Triple,
        /// Irradiance on a surface facing the light.
        irradiance: Triple,
        /// Display name.
        #[serde(default)]
        name: Option<String>,
    },
}

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
/// ([`crate::trace::PathTracer`], `docs/path-tracing.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", try_from = "String")]
pub enum IntegratorKind {
    /// The lecture's recursion ([`crate::trace::Whitted`]).
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation, MIS and Russian roulette
    /// ([`crate::trace::PathTracer`]).
    Path,
}

impl IntegratorKind {
    /// Every integrator, in documentation order.
    pub const ALL: [IntegratorKind; 2] = [IntegratorKind::Whitted, IntegratorKind::Path];

    /// The name used in JSON and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
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
            _ => Err(format!(
                "unknown integrator {name:?}, expected \"whitted\" or \"path\""
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

/// The pixel filter (`settings.filter`), importance-sampled: the camera ray's offset from the
/// pixel centre is drawn from it ([`crate::sampling::PixelFilter`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum FilterDesc {
    /// Uniform over the pixel (today's positions, bit for bit).
    #[default]
    Box,
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

/// A Gaussian filter without a `radius` is truncated at this many `sigma`.
pub const GAUSSIAN_RADIUS_SIGMAS: f64 = 3.0;

impl FilterDesc {
    /// The sampling filter.
    #[must_use]
    pub fn filter(&self) -> crate::sampling::PixelFilter {
        use crate::sampling::PixelFilter;
        match *self {
            FilterDesc::Box => PixelFilter::Box,
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
        *self == FilterDesc::Box
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
            "box" if arg.is_none() => Ok(FilterDesc::Box),
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
    /// chosen from `tolerance` and the scene ([`crate::trace::bound`]).
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
            filter: FilterDesc::Box,
            offset: OffsetDesc::default(),
            fresnel: FresnelModel::Exact,
            shadows: ShadowMode::Opaque,
            min_weight: None,
            tolerance: DEFAULT_TOLERANCE,
            max_rays: DEFAULT_MAX_RAYS,
            light_samples: None,
            rr_depth: DEFAULT_RR_DEPTH,
            glossy_samples: 1,
        }
    }
}
