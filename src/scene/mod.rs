//! The validated scene: camera, materials, objects, lights and settings.

mod accel;
mod camera;
mod check;
pub mod desc;
mod error;
mod generated;
mod lights;
mod locate;
mod mesh_object;
mod packet;
mod path;
mod scan;
mod suggest;
mod transform;
mod validate;

use crate::bvh::TraversalCost;
use crate::geometry::Shape;
use crate::math::{Ray, Rgb};
use crate::mesh::MeshData;
use glam::DVec3;
use std::borrow::Cow;

pub use accel::{Accel, traversal_cost_image};
pub use camera::{Camera, Film};
pub use desc::{
    AUTO_THRESHOLD, AdaptiveDesc, Antialiasing, FilterDesc, IntegratorKind, OffsetDesc,
    OffsetStrategy, SamplerKind, SceneDesc, Settings, ShadowMode,
};
pub use error::SceneError;
pub use generated::icosphere_scene;
pub use locate::locate;
pub use transform::transformed;
pub use validate::{
    MAX_RR_DEPTH, MAX_SPP, check_aperture, check_focus, check_rr_depth, check_settings, validate,
};

/// The built-in default scene: the lecture's classic (mirror ball, glass ball, checkered floor,
/// one light). Same file as `fixtures/classic.json`.
pub const DEFAULT_SCENE_JSON: &str = include_str!("../../fixtures/classic.json");

/// A diffuse albedo.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// Constant.
    Solid(Rgb),
    /// World-space 3D checkerboard.
    Checker {
        /// Even cells.
        even: Rgb,
        /// Odd cells.
        odd: Rgb,
        /// Cell size.
        size: f64,
    },
}

impl Texture {
    /// The albedo at world point `p`.
    #[must_use]
    pub fn at(&self, p: DVec3) -> Rgb {
        match *self {
            Texture::Solid(c) => c,
            Texture::Checker { even, odd, size } => {
                // A tiny bias keeps points exactly on a cell boundary (a floor at y = 0) stable.
                let c = ((p / size) + 1e-9).floor();
                if (c.x + c.y + c.z).rem_euclid(2.0) == 0.0 {
                    even
                } else {
                    odd
                }
            }
        }
    }

    /// Whether the albedo is zero everywhere.
    #[must_use]
    pub fn is_black(&self) -> bool {
        match *self {
            Texture::Solid(c) => c == Rgb::ZERO,
            Texture::Checker { even, odd, .. } => even == Rgb::ZERO && odd == Rgb::ZERO,
        }
    }
}

/// The lecture's general material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name in the scene file.
    pub name: String,
    /// Diffuse albedo.
    pub diffuse: Texture,
    /// Blinn-Phong specular colour.
    pub specular: Rgb,
    /// Blinn-Phong exponent.
    pub shininess: f64,
    /// Mirror reflectivity.
    pub reflectivity: Rgb,
    /// Transmissivity.
    pub transmissivity: Rgb,
    /// Index of refraction; `None` means index-matched to the surrounding medium.
    pub ior: Option<f64>,
    /// Beer's law coefficients inside the object.
    pub absorption: Rgb,
    /// Emitted radiance (outer side).
    pub emission: Rgb,
    /// GGX alpha of the `reflectivity` and `transmissivity` lobes, in [0, 1] (0: smooth; below
    /// [`crate::bsdf::SMOOTH_ALPHA`] the lobes are traced as smooth).
    pub roughness: f64,
    /// Alpha along the second tangent (equal to `roughness` for an isotropic lobe).
    pub roughness_v: f64,
    /// The world direction the first tangent follows where the lobe is anisotropic.
    pub tangent: DVec3,
    /// GGX or Beckmann.
    pub distribution: crate::bsdf::Distribution,
    /// A conductor's complex index: the `reflectivity` lobe's reflectance is then
    /// `reflectivity * F_conductor(cos)` per channel (`reflectivity` is the tint, at most the
    /// reflectance, so every bound on it still holds).
    pub conductor: Option<crate::bsdf::ComplexIor>,
}

impl Material {
    /// Whether the material transmits light.
    #[must_use]
    pub fn is_transmissive(&self) -> bool {
        self.transmissivity != Rgb::ZERO
    }

    /// Whether the material has a rough (GGX) lobe: a roughness of at least
    /// [`crate::bsdf::SMOOTH_ALPHA`] on a nonzero `reflectivity` or `transmissivity`.
    #[must_use]
    pub fn is_rough(&self) -> bool {
        self.roughness.max(self.roughness_v) >= crate::bsdf::SMOOTH_ALPHA
            && (self.reflectivity != Rgb::ZERO || self.is_transmissive())
    }

    /// Whether the rough lobes are anisotropic (`roughness_v` differs from `roughness`), which
    /// makes the shading frame follow [`Material::tangent`].
    #[must_use]
    pub fn is_anisotropic(&self) -> bool {
        self.roughness_v != self.roughness
    }

    /// The microfacet distribution of the rough lobes (alphas clamped to at least
    /// [`crate::bsdf::SMOOTH_ALPHA`]).
    #[must_use]
    pub fn microfacet(&self) -> crate::bsdf::Microfacet {
        crate::bsdf::Microfacet::with(self.distribution, self.roughness, self.roughness_v)
    }

    /// The lobe of the `reflectivity` term: a mirror of constant weight, or a conductor with
    /// Fresnel; GGX/Beckmann-rough where `rough`.
    #[must_use]
    pub fn reflection_lobe(&self, rough: bool) -> crate::bsdf::Lobe {
        use crate::bsdf::Lobe;
        let weight = self.reflectivity;
        match (self.conductor, rough) {
            (None, false) => Lobe::Mirror { weight },
            (None, true) => Lobe::RoughMirror {
                weight,
                dist: self.microfacet(),
            },
            (Some(ior), false) => Lobe::Conductor { weight, ior },
            (Some(ior), true) => Lobe::RoughConductor {
                weight,
                ior,
                dist: self.microfacet(),
            },
        }
    }
}

/// A shape with its material and name.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Display name (`<type>#<index>` when the file gives none).
    pub name: String,
    /// Geometry.
    pub shape: Shape,
    /// Index into [`Scene::materials`].
    pub material: usize,
}

/// A light source.
#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// Point light with radiant intensity.
    Point {
        /// Position.
        position: DVec3,
        /// Intensity (irradiance = intensity / r^2).
        intensity: Rgb,
    },
    /// Directional light.
    Directional {
        /// Unit direction of travel.
        direction: DVec3,
        /// Irradiance.
        irradiance: Rgb,
    },
}

/// A named light.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Display name (`light#<index>` when the file gives none).
    pub name: String,
    /// The emitter.
    pub kind: LightKind,
}

/// A validated scene, ready to trace.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Camera.
    pub camera: Camera,
    /// Miss radiance.
    pub background: Rgb,
    /// Ambient term.
    pub ambient: Rgb,
    /// Materials, indexed by [`Object::material`].
    pub materials: Vec<Material>,
    /// Objects.
    pub objects: Vec<Object>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Tracer settings.
    pub settings: Settings,
    /// BVH over `objects`, built by validation; call [`Scene::rebuild_accel`] after editing
    /// `objects` (until then, intersection falls back to a linear scan if the count changed).
    pub accel: Accel,
}

/// A hit on the closest object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter.
    pub t: f64,
    /// Outward unit geometric normal.
    pub normal: DVec3,
    /// Index into [`Scene::objects`].
    pub object: usize,
    /// For meshes: the stored triangle (see [`crate::mesh::Mesh::source_triangle`]).
    pub triangle: Option<u32>,
}

impl Scene {
    /// Parse and validate scene JSON. Errors carry the JSON path and line:column.
    pub fn from_json(src: &str) -> Result<Self, SceneError> {
        validate::from_json(src, &mut |_| {
            Err("mesh objects need a file loader (Scene::from_json_with)".into())
        })
    }

    /// The built-in default scene.
    #[must_use]
    pub fn default_scene() -> Self {
        Self::from_json(DEFAULT_SCENE_JSON).expect("the built-in scene is valid")
    }

    /// Parse and validate scene JSON whose `mesh` objects are read by `load_mesh(file)` (the
    /// `file` string as written; the caller resolves paths and reads files). A loader error
    /// is reported at the object's `file` path.
    pub fn from_json_with(
        src: &str,
        load_mesh: &mut dyn FnMut(&str) -> Result<MeshData, String>,
    ) -> Result<Self, SceneError> {
        validate::from_json(src, load_mesh)
    }

    /// The closest hit with `t` in `(ray.t_min, t_max)`; among equal distances the lowest
    /// object index, exactly as a linear scan in object order (BVH over objects).
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<Hit> {
        self.intersect_counted(ray, t_max, &mut TraversalCost::default())
    }

    /// The outward shading normal at `p` on `hit`: interpolated vertex normals on smooth
    /// meshes, `None` where it is the geometric normal.
    #[must_use]
    pub fn shading_normal(&self, hit: &Hit, p: DVec3) -> Option<DVec3> {
        match (&self.objects[hit.object].shape, hit.triangle) {
            (Shape::Mesh(m), Some(t)) => m.shading_normal(t as usize, p),
            _ => None,
        }
    }

    /// For mesh hits, the face index in the mesh's input (OBJ order).
    #[must_use]
    pub fn source_triangle(&self, hit: &Hit) -> Option<u32> {
        match (&self.objects[hit.object].shape, hit.triangle) {
            (Shape::Mesh(m), Some(t)) => Some(m.source_triangle(t as usize)),
            _ => None,
        }
    }

    /// The surface a ray leaves from object `object`: the object's shape, or for a mesh hit
    /// on stored `triangle` that triangle alone (what the robust offset bounds its error by).
    #[must_use]
    pub fn surface_shape(&self, object: usize, triangle: Option<u32>) -> Cow<'_, Shape> {
        match (&self.objects[object].shape, triangle) {
            (Shape::Mesh(m), Some(t)) => Cow::Owned(Shape::mesh_triangle(m, t as usize)),
            (shape, _) => Cow::Borrowed(shape),
        }
    }

    /// The material of object `i`.
    #[must_use]
    pub fn material_of(&self, object: usize) -> &Material {
        &self.materials[self.objects[object].material]
    }

    /// Whether some object uses material `m` (an index into [`Scene::materials`]).
    #[must_use]
    pub fn material_used(&self, m: usize) -> bool {
        self.objects.iter().any(|o| o.material == m)
    }

    /// The materials some object uses, in table order: the ones that decide the effect plan
    /// ([`crate::effects::EffectPlan::for_scene`]).
    pub fn used_materials(&self) -> impl Iterator<Item = &Material> {
        let mut used = vec![false; self.materials.len()];
        for o in &self.objects {
            used[o.material] = true;
        }
        self.materials
            .iter()
            .zip(used)
            .filter_map(|(m, u)| u.then_some(m))
    }
}

#[cfg(test)]
mod lens_tests;
