//! The one light type both integrators (and light tracing) reach every light through:
//! [`Light`], a point, directional or area light, with the two directions of sampling a light
//! needs (after pbrt-v4's `Light` interface, Pharr, Jakob, Humphreys, *Physically Based
//! Rendering*, 4th ed., chapter 12):
//!
//! - towards a point: [`Light::sample_li`] (a direction from a shading point, with its
//!   solid-angle pdf) and [`Light::pdf_li`] (that pdf for a given direction, for MIS);
//! - from the light: [`Light::sample_le`] and [`Light::pdf_le`] (an emitted ray, with the
//!   densities of its origin and direction; `emit.rs`);
//! - [`Light::power`], the flux light selection weighs it by ([`super::LightSampler`]).
//!
//! The scene hands its lights out in this form (`crate::Scene::light_list`,
//! `crate::Scene::area_light`); nothing here depends on the scene.

use super::{LightSample, PlanarEmitter, PreparedPlanar, Spot, sample_sphere, sphere_pdf};
use crate::math::Rgb;
use crate::mesh::Mesh;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// The shape of an area light, prepared for many samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AreaShape<'a> {
    /// A sphere, sampled uniformly in the cone it subtends (towards a point).
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
    /// A quad or triangle, sampled uniformly by area, its constants computed once.
    Planar(PreparedPlanar),
    /// A triangle mesh, sampled uniformly over its whole area (`super::mesh`).
    Mesh(&'a Mesh),
}

impl<'a> AreaShape<'a> {
    /// A quad or triangle.
    #[must_use]
    pub fn planar(e: PlanarEmitter) -> Self {
        Self::Planar(PreparedPlanar::new(e))
    }

    /// Surface area.
    #[must_use]
    pub fn area(&self) -> f64 {
        match *self {
            AreaShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            AreaShape::Planar(e) => e.area(),
            AreaShape::Mesh(m) => m.area(),
        }
    }

    /// A [`LightSample`] towards this shape (radiance `emission`) from `p`, `None` where `p`
    /// cannot see its outer side.
    #[inline(always)]
    #[must_use]
    pub fn sample(&self, p: DVec3, emission: Rgb, u: (f64, f64)) -> Option<LightSample> {
        let u = DVec2::new(u.0, u.1);
        // By reference: a prepared quad is 150 bytes, copied per sample by a `match *self`.
        match self {
            AreaShape::Sphere { center, radius } => sample_sphere(p, *center, *radius, emission, u),
            AreaShape::Planar(e) => e.sample(p, emission, u),
            AreaShape::Mesh(m) => super::mesh::sample(m, p, emission, u),
        }
    }

    /// The solid-angle pdf of [`Self::sample`] for direction `wi` from `p` (0 where the ray
    /// misses the outer side).
    #[inline(always)]
    #[must_use]
    pub fn pdf(&self, p: DVec3, wi: DVec3) -> f64 {
        match self {
            AreaShape::Sphere { center, radius } => sphere_pdf(p, *center, *radius, wi),
            AreaShape::Planar(e) => e.pdf(p, wi),
            AreaShape::Mesh(m) => super::mesh::pdf(m, p, wi),
        }
    }
}

/// A light: what every light loop, light sampler and light tracer sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light<'a> {
    /// A point light of radiant intensity `intensity`, in every direction or, as a spot
    /// light, falling off within a cone.
    Point {
        /// Position.
        position: DVec3,
        /// Radiant intensity (irradiance = intensity / r^2); a spot light's, on its axis.
        intensity: Rgb,
        /// The cone of a spot light; `None` for a light that shines in every direction.
        spot: Option<Spot>,
    },
    /// A directional light, over a scene of bounding sphere (`center`, `radius`).
    Directional {
        /// Unit direction of travel.
        direction: DVec3,
        /// Irradiance on a surface facing the light.
        irradiance: Rgb,
        /// Centre of the scene's bounding sphere (where emitted rays start from).
        center: DVec3,
        /// Its radius (> 0): the disc the light's flux is counted over.
        radius: f64,
    },
    /// An emissive object of radiance `emission` on its outer side.
    Area {
        /// The object's index in the scene.
        object: usize,
        /// Its shape.
        shape: AreaShape<'a>,
        /// Emitted radiance.
        emission: Rgb,
    },
}

impl Light<'_> {
    /// A point or directional light: one direction from each point, found by no other
    /// strategy than light sampling.
    #[inline]
    #[must_use]
    pub fn is_delta(&self) -> bool {
        !matches!(self, Light::Area { .. })
    }

    /// The object of an area light.
    #[inline]
    #[must_use]
    pub fn object(&self) -> Option<usize> {
        match self {
            Light::Area { object, .. } => Some(*object),
            _ => None,
        }
    }

    /// A direction from shading point `p` towards the light, what arrives along it and its
    /// solid-angle pdf; `u` is a 2D sample in `[0, 1)^2`, unused by the delta lights (one
    /// direction each: always `Some`). `None` where `p` cannot see an area light's outer side.
    #[inline(always)]
    #[must_use]
    pub fn sample_li(&self, p: DVec3, u: (f64, f64)) -> Option<LightSample> {
        match self {
            Light::Point {
                position,
                intensity,
                spot,
            } => {
                let ls = super::sample_point_light(p, *position, *intensity);
                match spot {
                    None => Some(ls),
                    // Outside the cone nothing arrives: no sample, as pbrt-v4's `SampleLi`
                    // returns none where the intensity is zero.
                    Some(cone) => {
                        let f = cone.falloff(-ls.direction);
                        (f > 0.0).then(|| LightSample {
                            radiance: ls.radiance * f,
                            ..ls
                        })
                    }
                }
            }
            Light::Directional {
                direction,
                irradiance,
                ..
            } => Some(super::sample_directional_light(*direction, *irradiance)),
            Light::Area {
                shape, emission, ..
            } => shape.sample(p, *emission, u),
        }
    }

    /// The solid-angle pdf with which [`Self::sample_li`] from `p` draws direction `wi`: 0 for
    /// a delta light (no direction has a density) and where `wi` misses an area light.
    #[inline]
    #[must_use]
    pub fn pdf_li(&self, p: DVec3, wi: DVec3) -> f64 {
        match self {
            Light::Area { shape, .. } => shape.pdf(p, wi),
            _ => 0.0,
        }
    }

    /// The flux `Phi` averaged over RGB (pbrt-v4 `Light::Phi`, `SampledSpectrum::Average`):
    /// `4 pi I` for a point light, `I` times the integral of its falloff for a spot light
    /// ([`Spot::solid_angle`], pbrt-v4 `SpotLight::Phi`), `pi r^2 E` for a directional light over the disc of the
    /// scene's bounding sphere (`DistantLight::Phi`), `pi A Le` for a one-sided diffuse
    /// emitter of area `A` (`DiffuseAreaLight::Phi`). Infinite when it overflows.
    #[must_use]
    pub fn power(&self) -> f64 {
        let mean = |c: Rgb| (c.x + c.y + c.z) / 3.0;
        match *self {
            Light::Point {
                intensity, spot, ..
            } => spot.map_or(4.0 * PI, |s| s.solid_angle()) * mean(intensity),
            Light::Directional {
                irradiance, radius, ..
            } => PI * radius * radius * mean(irradiance),
            Light::Area {
                shape, emission, ..
            } => PI * shape.area() * mean(emission),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DELTA_U: (f64, f64) = (0.5, 0.5);

    #[test]
    fn point_light_sample_is_the_inverse_square_law() {
        let l = Light::Point {
            position: DVec3::new(1.0, 4.0, -2.0),
            intensity: Rgb::new(8.0, 16.0, 32.0),
            spot: None,
        };
        let p = DVec3::new(1.0, 0.0, 1.0);
        let ls = l.sample_li(p, DELTA_U).unwrap();
        // |(0, 4, -3)| = 5.
        assert_eq!(ls.distance, 5.0);
        assert!((ls.direction - DVec3::new(0.0, 0.8, -0.6)).length() < 1e-15);
        assert_eq!(ls.radiance, Rgb::new(8.0, 16.0, 32.0) / 25.0);
        assert!(ls.delta && ls.pdf == 1.0);
        assert_eq!(ls.value(), ls.radiance);
        // Delta lights ignore the 2D sample.
        assert_eq!(l.sample_li(p, (0.0, 0.999)).unwrap(), ls);
    }

    #[test]
    fn directional_light_sample_points_against_travel() {
        let l = Light::Directional {
            direction: DVec3::new(0.0, -1.0, 0.0),
            irradiance: Rgb::splat(2.0),
            center: DVec3::ZERO,
            radius: 1.0,
        };
        let ls = l.sample_li(DVec3::new(3.0, 1.0, 7.0), DELTA_U).unwrap();
        assert_eq!(ls.direction, DVec3::Y);
        assert!(ls.distance.is_infinite() && ls.delta);
        assert_eq!(ls.value(), Rgb::splat(2.0));
    }

    /// A non-delta sample's value is radiance over pdf (the Monte Carlo estimator's weight).
    #[test]
    fn area_sample_value_divides_by_the_pdf() {
        let ls = LightSample {
            direction: DVec3::Z,
            distance: 2.0,
            radiance: Rgb::splat(3.0),
            pdf: 4.0,
            delta: false,
        };
        assert_eq!(ls.value(), Rgb::splat(0.75));
    }
}
