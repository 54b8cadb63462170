//! The scene's lights in the one form every integrator uses ([`crate::lights::Light`]): its
//! point and directional lights, and every emissive object that can be sampled as an area
//! light.

use super::{LightKind, Scene};
use crate::geometry::Shape;
use crate::lights::{AreaShape, Light, LightSampler, PlanarEmitter};
use glam::DVec3;

impl Scene {
    /// Object `i` as an area light, when its material emits and its shape can be sampled
    /// (sphere by its cone, quad, triangle and mesh by area; boxes and planes are not sampled),
    /// and it is not a bit-identical copy of an earlier object (issue 27: copies are one light).
    #[must_use]
    pub fn area_light(&self, i: usize) -> Option<Light<'_>> {
        let emission = self.material_of(i).emission;
        if emission.max_element() <= 0.0 || self.accel.is_coincident_copy(i, self.objects.len()) {
            return None;
        }
        let shape = match self.objects[i].shape {
            Shape::Sphere { center, radius } => AreaShape::Sphere { center, radius },
            Shape::Quad {
                vertices: [a, b, _, d],
                ..
            } => AreaShape::planar(PlanarEmitter::quad(a, b - a, d - a)),
            Shape::Triangle {
                vertices: [a, b, c],
                ..
            } => AreaShape::planar(PlanarEmitter::triangle(a, b, c)),
            Shape::Mesh(ref m) => AreaShape::Mesh(m),
            _ => return None,
        };
        Some(Light::Area {
            object: i,
            shape,
            emission,
        })
    }

    /// Point or directional light `k` ([`Scene::lights`]) as a [`Light`]; a directional light
    /// carries the scene's bounding sphere `bounds` ([`Scene::bounding_sphere`]).
    #[must_use]
    pub fn delta_light(&self, k: usize, (center, radius): (DVec3, f64)) -> Light<'static> {
        match self.lights[k].kind {
            LightKind::Point {
                position,
                intensity,
                spot,
            } => Light::Point {
                position,
                intensity,
                spot,
            },
            LightKind::Directional {
                direction,
                irradiance,
            } => Light::Directional {
                direction,
                irradiance,
                center,
                radius,
            },
        }
    }

    /// Every light: the point and directional lights in order, then the area lights in object
    /// order (as light sampling numbers them; a recorded shadow ray's `light` index is `k` for
    /// `lights[k]` and `lights.len() + object` for an area light).
    #[must_use]
    pub fn light_list(&self) -> Vec<Light<'_>> {
        let bounds = self.bounding_sphere();
        let delta = (0..self.lights.len()).map(|k| self.delta_light(k, bounds));
        let area = (0..self.objects.len()).filter_map(|i| self.area_light(i));
        delta.chain(area).collect()
    }

    /// The light sampler over [`Scene::light_list`], in proportion to power.
    #[must_use]
    pub fn light_sampler(&self) -> LightSampler<'_> {
        LightSampler::new(self.light_list(), self.objects.len())
    }

    /// The name of `light` (an entry of [`Scene::light_list`] whose delta lights are
    /// `lights[k]` for index `k` < `lights.len()`).
    #[must_use]
    pub fn light_name(&self, index: usize, light: &Light<'_>) -> &str {
        match light.object() {
            Some(o) => &self.objects[o].name,
            None => &self.lights[index].name,
        }
    }

    /// The names of the lights (point, directional, emissive objects) whose flux overflows a
    /// 64-bit float, so that light sampling chooses them by a clamped power.
    #[must_use]
    pub fn overflowing_lights(&self) -> Vec<String> {
        let sampler = self.light_sampler();
        sampler
            .overflowing()
            .into_iter()
            .map(|i| self.light_name(i, &sampler.lights()[i]).to_string())
            .collect()
    }

    /// The sphere around every bounded object (centre, radius; radius 1 about the origin when
    /// there is none, or when it is not finite): the disc over which a directional light's flux
    /// is counted and from which its emitted rays start.
    #[must_use]
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for o in &self.objects {
            if let Some((a, b)) = o.shape.bounds() {
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        let r = 0.5 * (hi - lo).length();
        if r.is_finite() && r > 0.0 {
            (0.5 * lo + 0.5 * hi, r)
        } else {
            (DVec3::ZERO, 1.0)
        }
    }
}
