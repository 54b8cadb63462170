//! The light-sampling kernel: one [`LightSample`] per light and shading point, produced by one
//! function per light kind, and the unshadowed contribution every light loop of the tracer
//! (the recursion's shadow rays in `local.rs`, the direct-only single rays and packets in
//! `direct_only.rs`) computes from it. Adding a light kind (area lights) means adding one arm to
//! [`Light::sample`].
//!
//! The estimator of one light's direct light at a point is `f * L * cos / pdf` (the lecture's
//! local term for delta lights, where `pdf` is the formal 1 and `L` is the irradiance `E`
//! arriving on a surface facing the light: the Dirac delta of a point or directional light
//! cancels in the integral, pbrt-v4 section 12.1).

use super::local::cos_to_light;
use super::{RayCounts, Tracer};
use crate::interaction::SurfaceInteraction;
use crate::math::{Ray, Rgb};
use crate::sampling::PixelSampler;
use crate::scene::{Light, LightKind, OffsetStrategy};
use glam::DVec3;

pub use crate::lights::LightSample;

impl Light {
    /// Sample this light from shading point `p`; `u` is a 2D sample in `[0, 1)^2` (unused by the
    /// delta lights, which have one direction each).
    #[inline(always)]
    #[must_use]
    pub fn sample(&self, p: DVec3, u: (f64, f64)) -> LightSample {
        let _ = u;
        match self.kind {
            LightKind::Point {
                position,
                intensity,
            } => crate::lights::sample_point_light(p, position, intensity),
            LightKind::Directional {
                direction,
                irradiance,
            } => crate::lights::sample_directional_light(direction, irradiance),
        }
    }
}

/// The 2D sample the Whitted integrator passes to [`Light::sample`]: it has only delta lights,
/// which ignore it. (Area lights will take theirs from the pixel sampler.)
pub(super) const DELTA_U: (f64, f64) = (0.5, 0.5);

/// The sampler of camera rays traced without one (packets, which run only when the plan has
/// no area lights): it is never drawn from, and would give the square's centre if it were.
#[derive(Clone, Copy, Debug)]
pub(super) struct NoSamples;

impl PixelSampler for NoSamples {
    fn start_sample(&mut self, _: (u32, u32), _: u32) {}
    fn next_1d(&mut self) -> f64 {
        0.5
    }
    fn next_2d(&mut self) -> (f64, f64) {
        DELTA_U
    }
}

/// A light's shadow ray from a surface it faces, and the light's sample.
pub(super) struct Unshadowed {
    /// The shadow ray (offset by the configured strategy).
    pub ray: Ray,
    /// How far it may go.
    pub seg: f64,
    /// The light's sample.
    pub ls: LightSample,
    /// The cosine at which the surface sees it (> 0).
    pub cos: f64,
}

impl Tracer<'_> {
    /// The lights the plan keeps, with their indices: the loop of every light loop.
    #[inline(always)]
    pub(super) fn lights_on(&self) -> impl Iterator<Item = (usize, &Light)> + '_ {
        let plan = &self.plan;
        self.scene
            .lights
            .iter()
            .enumerate()
            .filter(move |(i, _)| plan.light_on(*i))
    }

    /// Sample `light` from `si` and the cosine at which the surface sees the sample
    /// ([`cos_to_light`]).
    #[inline(always)]
    pub(super) fn sample_light(
        &self,
        light: &Light,
        si: &SurfaceInteraction,
    ) -> (LightSample, f64) {
        let ls = light.sample(si.p, DELTA_U);
        let cos = cos_to_light(si.n, si.ns, ls.direction);
        (ls, cos)
    }

    /// The unrecorded light-loop body shared by the direct-only single rays and packets: the
    /// light sampled from `si`, and unless it is behind the surface its shadow ray (counted).
    /// `strategy` is a constant in the callers' loops.
    #[inline(always)]
    pub(super) fn unshadowed(
        &self,
        strategy: OffsetStrategy,
        si: &SurfaceInteraction,
        light: &Light,
        counts: &mut RayCounts,
    ) -> Option<Unshadowed> {
        let (ls, cos) = self.sample_light(light, si);
        if cos <= 0.0 {
            return None;
        }
        counts.shadow += 1;
        let from = (si.object, si.triangle);
        let (ray, seg) = self.shadow_ray(strategy, from, si.p, si.n, ls.direction, ls.distance);
        Some(Unshadowed { ray, seg, ls, cos })
    }

    /// What an unblocked [`Unshadowed`] adds at `si` (diffuse albedo `albedo`):
    /// `brdf * cos * value`, the recorded path's `weight * (value * Rgb::ONE)` bit for bit.
    #[inline(always)]
    pub(super) fn unshadowed_add<const SPECULAR: bool>(
        si: &SurfaceInteraction,
        albedo: Rgb,
        u: &Unshadowed,
    ) -> Rgb {
        let wi = u.ls.direction;
        let (_, weight) =
            Self::light_weight(SPECULAR, si.material, albedo, si.ns, (wi, si.wo), u.cos);
        weight * u.ls.value()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: LightKind) -> Light {
        Light {
            name: "l".into(),
            kind,
        }
    }

    #[test]
    fn point_light_sample_is_the_inverse_square_law() {
        let l = light(LightKind::Point {
            position: DVec3::new(1.0, 4.0, -2.0),
            intensity: Rgb::new(8.0, 16.0, 32.0),
        });
        let p = DVec3::new(1.0, 0.0, 1.0);
        let ls = l.sample(p, DELTA_U);
        // |(0, 4, -3)| = 5.
        assert_eq!(ls.distance, 5.0);
        assert!((ls.direction - DVec3::new(0.0, 0.8, -0.6)).length() < 1e-15);
        assert_eq!(ls.radiance, Rgb::new(8.0, 16.0, 32.0) / 25.0);
        assert!(ls.delta && ls.pdf == 1.0);
        assert_eq!(ls.value(), ls.radiance);
        // Delta lights ignore the 2D sample.
        assert_eq!(l.sample(p, (0.0, 0.999)), ls);
    }

    #[test]
    fn directional_light_sample_points_against_travel() {
        let l = light(LightKind::Directional {
            direction: DVec3::new(0.0, -1.0, 0.0),
            irradiance: Rgb::splat(2.0),
        });
        let ls = l.sample(DVec3::new(3.0, 1.0, 7.0), DELTA_U);
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
