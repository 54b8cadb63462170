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

pub use crate::bsdf::{Material, Texture};
pub use accel::{Accel, traversal_cost_image};
pub use camera::{Camera, CameraConnection, Film};
pub use desc::{
    AUTO_THRESHOLD, AdaptiveDesc, Antialiasing, FilterDesc, IntegratorKind, MisHeuristic,
    OffsetDesc, OffsetStrategy, PathSettings, SamplerKind, SceneDesc, Settings, ShadowMode,
    WhittedSettings,
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
    /// Point light with radiant intensity; with a cone, a spot light.
    Point {
        /// Position.
        position: DVec3,
        /// Intensity (irradiance = intensity / r^2); a spot light's, on its axis.
        intensity: Rgb,
        /// A spot light's cone and falloff; `None` for light in every direction.
        spot: Option<crate::lights::Spot>,
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
