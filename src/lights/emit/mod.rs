//! Emitted rays: light leaving a light, sampled from the light's side, for light tracing and
//! bidirectional estimators (issue 30; the interface issue 28 asks of one light type).
//!
//! `sample_le` draws a ray leaving a light with the density of its origin (per unit area, or a
//! delta position) and of its direction (per unit solid angle, or a delta direction), and the
//! radiance it carries; `pdf_le` gives both densities for a given ray. The conventions are
//! pbrt-v4's `Light::SampleLe` / `Light::PDF_Le` (Pharr, Jakob, Humphreys, *Physically Based
//! Rendering*, 4th ed., section 12.x and 16.3; Veach 1997, section 10.2):
//!
//! - point light (intensity `I`): origin the light (delta), direction uniform over the sphere,
//!   `pdf_dir = 1 / (4 pi)`; what leaves is `I`. A spot light draws its direction uniformly in
//!   its cone, `pdf_dir = 1 / (2 pi (1 - cos theta_cone))`, and what leaves is `I` times its
//!   falloff ([`super::Spot`]).
//! - directional light (irradiance `E`, direction `d`): direction `d` (delta); origin uniform on
//!   a disc of radius `R` (the scene's bounding radius) perpendicular to `d`, `R` behind the
//!   scene's centre, `pdf_pos = 1 / (pi R^2)`; what leaves is `E`.
//! - area light (a sphere, quad, triangle or mesh of radiance `L`, emitting from its outer
//!   side): origin uniform over its area, `pdf_pos = 1 / A`; direction cosine-weighted about the
//!   outward normal, `pdf_dir = cos / pi`; what leaves is `L`.
//!
//! With these, `le |cos| / (pdf_pos pdf_dir)` of every sample is the light's flux `Phi` (for a
//! point light `4 pi I`, spot `I` times its falloff's solid angle, directional `pi R^2 E`, area `pi A L`): the powers by which light
//! sampling chooses lights (`super::LightSampler`), which the tests check.

use super::{AreaShape, Light};
use crate::math::Rgb;
use crate::sampling::warp::{
    orthonormal_basis, square_to_concentric_disk, square_to_cosine_hemisphere,
    square_to_uniform_sphere,
};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// A ray leaving a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmittedRay {
    /// Origin, on the light.
    pub origin: DVec3,
    /// Unit direction of travel.
    pub direction: DVec3,
    /// The light's outward normal at `origin` (area lights; `None` for point and directional).
    pub normal: Option<DVec3>,
    /// What leaves: radiance (area), intensity (point) or irradiance (directional).
    pub le: Rgb,
    /// Density of `origin` per unit area (1 for a delta position).
    pub pdf_pos: f64,
    /// Density of `direction` per unit solid angle (1 for a delta direction).
    pub pdf_dir: f64,
    /// The origin is a delta (point light).
    pub delta_pos: bool,
    /// The direction is a delta (directional light).
    pub delta_dir: bool,
}

impl EmittedRay {
    /// `le |cos| / (pdf_pos pdf_dir)`: the flux a light path starting with this ray carries
    /// (before the light's selection probability); zero for a zero density.
    #[must_use]
    pub fn weight(&self) -> Rgb {
        let cos = self.normal.map_or(1.0, |n| n.dot(self.direction).abs());
        let pdf = self.pdf_pos * self.pdf_dir;
        if pdf > 0.0 {
            self.le * (cos / pdf)
        } else {
            Rgb::ZERO
        }
    }
}

/// A point uniform over `shape`'s area and the outward normal there, with the area.
fn sample_area(shape: &AreaShape<'_>, u: DVec2) -> Option<(DVec3, DVec3, f64)> {
    match *shape {
        AreaShape::Sphere { center, radius } => {
            let n = square_to_uniform_sphere(u);
            Some((center + radius * n, n, 4.0 * PI * radius * radius))
        }
        AreaShape::Planar(e) => Some((e.sample_point(u), e.normal()?, e.area())),
        AreaShape::Mesh(m) => {
            let (p, n) = super::mesh::sample_point(m, u)?;
            Some((p, n, m.area()))
        }
    }
}

/// The outward normal of `shape` at `p` (on it), for [`Light::pdf_le`].
fn normal_at(shape: &AreaShape<'_>, p: DVec3, hint: Option<DVec3>) -> Option<DVec3> {
    match *shape {
        AreaShape::Sphere { center, .. } => hint.or_else(|| (p - center).try_normalize()),
        AreaShape::Planar(e) => e.normal(),
        AreaShape::Mesh(_) => hint,
    }
}

impl Light<'_> {
    /// An emitted ray from `u_pos` (the origin) and `u_dir` (the direction); `None` for a
    /// degenerate light (zero area).
    #[must_use]
    pub fn sample_le(&self, u_pos: DVec2, u_dir: DVec2) -> Option<EmittedRay> {
        match *self {
            Light::Point {
                position,
                intensity,
                spot,
            } => {
                // A spot light draws uniformly in its cone (pbrt-v4 `SpotLight::SampleLe`).
                let (direction, le, pdf_dir) = match spot {
                    None => (square_to_uniform_sphere(u_dir), intensity, 1.0 / (4.0 * PI)),
                    Some(cone) => {
                        let (w, pdf) = cone.sample(u_dir);
                        (w, intensity * cone.falloff(w), pdf)
                    }
                };
                Some(EmittedRay {
                    origin: position,
                    direction,
                    normal: None,
                    le,
                    pdf_pos: 1.0,
                    pdf_dir,
                    delta_pos: true,
                    delta_dir: false,
                })
            }
            Light::Directional {
                direction,
                irradiance,
                center,
                radius,
            } => {
                let (t, b) = orthonormal_basis(direction);
                let d = square_to_concentric_disk(u_pos) * radius;
                Some(EmittedRay {
                    origin: center - radius * direction + d.x * t + d.y * b,
                    direction,
                    normal: None,
                    le: irradiance,
                    pdf_pos: 1.0 / (PI * radius * radius),
                    pdf_dir: 1.0,
                    delta_pos: false,
                    delta_dir: true,
                })
            }
            Light::Area {
                shape, emission, ..
            } => {
                let (origin, n, area) = sample_area(&shape, u_pos)?;
                if !(area > 0.0 && area.is_finite()) {
                    return None;
                }
                let local = square_to_cosine_hemisphere(u_dir);
                let (t, b) = orthonormal_basis(n);
                let direction = (local.x * t + local.y * b + local.z * n).normalize();
                Some(EmittedRay {
                    origin,
                    direction,
                    normal: Some(n),
                    le: emission,
                    pdf_pos: 1.0 / area,
                    // From the direction as made, so that `pdf_le` gives back the same bits.
                    pdf_dir: n.dot(direction).max(0.0) / PI,
                    delta_pos: false,
                    delta_dir: false,
                })
            }
        }
    }

    /// The densities `(pdf_pos, pdf_dir)` with which [`Light::sample_le`] draws a ray from
    /// `origin` (on the light; for a mesh, with its outward `normal` there) along `direction`:
    /// for delta parts the other density alone (the delta's own is 1), zero where the light
    /// cannot emit that ray (behind an area light's outer side).
    #[must_use]
    pub fn pdf_le(&self, origin: DVec3, normal: Option<DVec3>, direction: DVec3) -> (f64, f64) {
        match *self {
            Light::Point { spot: None, .. } => (1.0, 1.0 / (4.0 * PI)),
            Light::Point {
                spot: Some(cone), ..
            } => (1.0, cone.pdf(direction)),
            Light::Directional { radius, .. } => (1.0 / (PI * radius * radius), 1.0),
            Light::Area { shape, .. } => {
                let area = shape.area();
                let Some(n) = normal_at(&shape, origin, normal) else {
                    return (0.0, 0.0);
                };
                let cos = n.dot(direction);
                if area.is_nan() || area <= 0.0 || cos <= 0.0 {
                    return (0.0, 0.0);
                }
                (1.0 / area, cos / PI)
            }
        }
    }
}

#[cfg(test)]
mod tests;
