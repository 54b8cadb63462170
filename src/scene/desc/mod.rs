//! The serde mirror of the scene JSON (documented in `docs/scene-format.md`).
//!
//! Plain data with defaults and `deny_unknown_fields`; it becomes a [`crate::Scene`] only
//! through validation (`scene::validate`).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
    /// Microfacet alpha of the `reflectivity` (or `conductor`) and `transmissivity` lobes, in
    /// [0, 1]; 0 (the default) is smooth. With `roughness_v` it is the alpha along the first
    /// tangent (`alpha_u`).
    #[serde(skip_serializing_if = "is_zero")]
    pub roughness: f64,
    /// Alpha along the second tangent (`alpha_v`), in [0, 1]: an anisotropic lobe; absent, the
    /// lobe is isotropic (`roughness` both ways).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roughness_v: Option<f64>,
    /// The world direction the first tangent (`alpha_u`) follows on an anisotropic surface,
    /// projected into the tangent plane; default `[1, 0, 0]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangent: Option<Triple>,
    /// The microfacet distribution of the rough lobes: `"ggx"` (default) or `"beckmann"`.
    #[serde(skip_serializing_if = "is_ggx")]
    pub distribution: crate::bsdf::Distribution,
    /// A conductor: the mirror lobe's reflectance is the Fresnel of a complex index of
    /// refraction per channel (instead of the constant `reflectivity`, which must then be
    /// absent).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conductor: Option<ConductorDesc>,
    /// A dielectric coating over the diffuse base (plastic, Mitsuba 3 `plastic` /
    /// `roughplastic`): its Fresnel reflection (rough with `roughness`) over the base seen
    /// through it. `reflectivity` must then be absent (tint the coating with `coating.scale`)
    /// and so must `transmissivity`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coating: Option<CoatingDesc>,
    /// A thin dielectric sheet (a window pane, a soap film): `transmissivity` is then the
    /// sheet's weight, light is reflected by the sheet's total Fresnel `2R / (1 + R)` and the
    /// rest passes straight through. `ior` and `absorption` must then be absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thin: Option<ThinDesc>,
}

/// A thin dielectric sheet: its index.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThinDesc {
    /// Index of refraction of the sheet over the medium around it (> 0; Mitsuba's default
    /// 1.5046, BK7).
    pub ior: f64,
}

/// A dielectric coating: its index and tint.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoatingDesc {
    /// Index of refraction of the coating over the outside medium (> 0; Mitsuba's default
    /// 1.49, polypropylene).
    pub ior: f64,
    /// Tint on the coating's reflection (Mitsuba's `specular_reflectance`), default
    /// `[1, 1, 1]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Triple>,
    /// Tint the inter-reflections between base and coating by the base (Mitsuba's
    /// `nonlinear`, pbrt's layered walk): a coloured base looks deeper. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub nonlinear: bool,
}

fn is_ggx(d: &crate::bsdf::Distribution) -> bool {
    *d == crate::bsdf::Distribution::Ggx
}

/// A conductor's complex index of refraction: a named metal or `eta` and `k` per channel.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ConductorDesc {
    /// A named metal: `"Cu"`, `"Au"`, `"Ag"` or `"Al"` (RGB from pbrt-v4's spectra).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metal: Option<String>,
    /// Real part of the index per channel (> 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eta: Option<Triple>,
    /// Imaginary part (extinction) per channel (>= 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k: Option<Triple>,
    /// Tint on the Fresnel reflectance (Mitsuba's `specular_reflectance`), default `[1, 1, 1]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<Triple>,
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
    /// A triangle mesh given inline in world space (what `raytree convert` writes for meshes
    /// of other formats, so a converted scene is self-contained).
    Trimesh {
        /// Vertex positions.
        positions: Vec<Triple>,
        /// Triangles as three 0-based indices into `positions`; the front of each is where
        /// `(b - a) x (c - a)` points, unless `normals` say otherwise.
        indices: Vec<[u32; 3]>,
        /// Per-vertex shading normals, one per position (absent: flat).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        normals: Option<Vec<Triple>>,
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
            | ObjectDesc::Mesh { material, .. }
            | ObjectDesc::Trimesh { material, .. } => material,
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
            | ObjectDesc::Mesh { name, .. }
            | ObjectDesc::Trimesh { name, .. } => name.as_deref(),
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
            ObjectDesc::Trimesh { .. } => "trimesh",
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
    /// Spot light: a point light whose intensity falls off within a cone about `direction`
    /// (or towards `look_at`): full intensity within `falloff_angle` of the axis, nothing beyond
    /// `cone_angle`, the `profile` curve between (`docs/scene-format.md`).
    Spot {
        /// Position.
        position: Triple,
        /// The axis, the direction the light points in (give it or `look_at`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        direction: Option<Triple>,
        /// A point on the axis (instead of `direction`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        look_at: Option<Triple>,
        /// Radiant intensity per channel on the axis.
        intensity: Triple,
        /// Half-angle of the cone in degrees, in (0, 180): nothing is emitted outside it.
        cone_angle: f64,
        /// Half-angle in degrees within which the full intensity is emitted, in [0,
        /// `cone_angle`]; defaults to `cone_angle` (a hard edge).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        falloff_angle: Option<f64>,
        /// The falloff curve: `smoothstep` (pbrt-v4, the default), `linear` (in the angle,
        /// Mitsuba 3) or `gltf` (KHR_lights_punctual).
        #[serde(default)]
        profile: crate::lights::SpotProfile,
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

mod antialias;
mod integrator;
mod record;
mod settings;
mod spelling;
pub use antialias::{ADAPTIVE_FACTOR, AUTO_THRESHOLD, AdaptiveDesc, Antialiasing};
pub use integrator::{
    DEFAULT_RR_DEPTH, DEFAULT_TOLERANCE, IntegratorKind, MisHeuristic, PathSettings, ShadowMode,
    WhittedSettings,
};
pub use record::{SettingsRecord, flat_settings};
pub use settings::{
    DEFAULT_MAX_DEPTH, DEFAULT_MAX_RAYS, FilterDesc, GAUSSIAN_RADIUS_SIGMAS, OffsetDesc,
    OffsetStrategy, SamplerKind, Settings,
};
pub use spelling::{
    BdptDesc, IntegratorDesc, RouletteDesc, WhittedDesc, new_spelling, old_spelling,
};
