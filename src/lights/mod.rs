//! Light sampling, pure geometry: a [`LightSample`] towards a spherical, quad or triangle
//! emitter (emission from the outer side only) or a delta light, as seen from a point `p`.
//!
//! Sources: the sphere by the cone it subtends (pbrt-v4 `Sphere::Sample(ctx, u)`, Shirley et
//! al. 1996 "Monte Carlo Techniques for Direct Lighting Calculations"); quads and triangles
//! uniformly by area, the area pdf converted to solid angle by `pdf_area dist^2 / |cos_light|`
//! (pbrt-v4 `Shape::PDF(ctx, wi)` default; Veach's thesis eq. 8.10). See `docs/monte-carlo.md`.

mod emit;
mod light;
pub mod mesh;
mod prepared;
mod sampler;
mod spot;
#[cfg(test)]
mod tests;

pub use emit::EmittedRay;
pub use light::{AreaShape, Light};
pub use prepared::PreparedPlanar;
pub use sampler::LightSampler;
pub use spot::{Spot, SpotProfile};

use crate::math::Rgb;
use crate::sampling::warp::{
    orthonormal_basis, square_to_triangle_barycentrics, square_to_uniform_cone, uniform_cone_pdf,
};
use glam::{DVec2, DVec3};

/// A direction towards a light and what arrives along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub direction: DVec3,
    /// Distance to the sampled point (infinite for a directional light): the shadow ray's length.
    pub distance: f64,
    /// Emitted radiance arriving along `direction`; for a delta light the irradiance at normal
    /// incidence it delivers (intensity / r^2, or the directional irradiance).
    pub radiance: Rgb,
    /// Solid-angle pdf of `direction`; 1 for a delta light.
    pub pdf: f64,
    /// A delta light (point or directional): no other strategy can find it.
    pub delta: bool,
}

impl LightSample {
    /// What the sample adds before the BSDF and cosine, as the tracer's light loops use it:
    /// the irradiance itself for a delta light (no division, so the delta lights' bits are the
    /// historical ones), otherwise [`LightSample::weight`].
    #[inline(always)]
    #[must_use]
    pub fn value(&self) -> Rgb {
        if self.delta {
            self.radiance
        } else {
            self.weight()
        }
    }

    /// The direct-light estimator's factor `radiance / pdf` (the light's irradiance for a delta
    /// light); multiply by `f |cos|` and visibility.
    #[inline(always)]
    #[must_use]
    pub fn weight(&self) -> Rgb {
        if self.pdf > 0.0 {
            self.radiance / self.pdf
        } else {
            Rgb::ZERO
        }
    }
}

/// The cone `(axis, distance to centre, cos_max, sin2_max)` a sphere subtends from `p`, or `None`
/// when `p` is inside or on it (the outer side cannot be seen).
fn sphere_cone(p: DVec3, center: DVec3, radius: f64) -> Option<(DVec3, f64, f64, f64)> {
    let to = center - p;
    let d2 = to.length_squared();
    let r2 = radius * radius;
    if d2 <= r2 {
        return None;
    }
    let d = d2.sqrt();
    let sin2_max = r2 / d2;
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    Some((to / d, d, cos_max, sin2_max))
}

/// A direction uniform in the cone the sphere subtends from `p` (half-angle `asin(r/d)`),
/// solid-angle pdf `1 / (2 pi (1 - cos_max))`; `None` from inside the sphere.
#[must_use]
pub fn sample_sphere(
    p: DVec3,
    center: DVec3,
    radius: f64,
    radiance: Rgb,
    u: DVec2,
) -> Option<LightSample> {
    let (axis, d, cos_max, sin2_max) = sphere_cone(p, center, radius)?;
    let local = square_to_uniform_cone(u, cos_max, sin2_max);
    let (s, t) = orthonormal_basis(axis);
    let direction = (local.x * s + local.y * t + local.z * axis).normalize();
    // The near intersection along `direction`: b - sqrt(r^2 - d^2 sin^2), clamped at the
    // silhouette where rounding makes the discriminant slightly negative.
    let b = d * local.z;
    let disc = (radius * radius - d * d * (1.0 - local.z * local.z)).max(0.0);
    let distance = (b - disc.sqrt()).max(0.0);
    Some(LightSample {
        direction,
        distance,
        radiance,
        pdf: uniform_cone_pdf(local, cos_max, sin2_max),
        delta: false,
    })
}

/// The solid-angle pdf of [`sample_sphere`] for direction `wi` from `p`.
#[must_use]
pub fn sphere_pdf(p: DVec3, center: DVec3, radius: f64, wi: DVec3) -> f64 {
    sphere_cone(p, center, radius).map_or(0.0, |(axis, _, cos_max, sin2_max)| {
        uniform_cone_pdf(DVec3::new(0.0, 0.0, wi.dot(axis)), cos_max, sin2_max)
    })
}

/// A planar emitter: the parallelogram `corner + s edge_u + t edge_v` (`s, t` in `[0, 1]`) or
/// the triangle `corner, corner + edge_u, corner + edge_v`; its outer side is where
/// `edge_u x edge_v` points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarEmitter {
    /// First vertex.
    pub corner: DVec3,
    /// First edge.
    pub edge_u: DVec3,
    /// Second edge.
    pub edge_v: DVec3,
    /// A triangle (half the parallelogram) rather than a quad.
    pub triangle: bool,
}

impl PlanarEmitter {
    /// The quad `corner + s u + t v`.
    #[must_use]
    pub fn quad(corner: DVec3, edge_u: DVec3, edge_v: DVec3) -> Self {
        Self {
            corner,
            edge_u,
            edge_v,
            triangle: false,
        }
    }

    /// The triangle `a, b, c` (front where `(b - a) x (c - a)` points).
    #[must_use]
    pub fn triangle(a: DVec3, b: DVec3, c: DVec3) -> Self {
        Self {
            corner: a,
            edge_u: b - a,
            edge_v: c - a,
            triangle: true,
        }
    }

    /// Area (0 for degenerate edges).
    #[must_use]
    pub fn area(&self) -> f64 {
        let a = self.edge_u.cross(self.edge_v).length();
        if self.triangle { 0.5 * a } else { a }
    }

    /// Unit normal on the outer side (`None` when degenerate).
    #[must_use]
    pub fn normal(&self) -> Option<DVec3> {
        self.edge_u.cross(self.edge_v).try_normalize()
    }

    /// A point uniform in area.
    #[must_use]
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        if self.triangle {
            let b = square_to_triangle_barycentrics(u);
            self.corner + b.y * self.edge_u + b.z * self.edge_v
        } else {
            self.corner + u.x * self.edge_u + u.y * self.edge_v
        }
    }

    /// A direction from `p` towards a point uniform in area, its pdf converted to solid angle;
    /// `None` when `p` is not on the outer side or the emitter is degenerate.
    #[must_use]
    pub fn sample(&self, p: DVec3, radiance: Rgb, u: DVec2) -> Option<LightSample> {
        let n = self.normal()?;
        self.sample_given(n, || self.area(), p, radiance, u)
    }

    /// [`Self::sample`] with the unit normal `n` and the area (asked for only when a sample
    /// is made) given, so that a light can compute them once ([`PreparedPlanar`]).
    #[inline]
    pub(crate) fn sample_given(
        &self,
        n: DVec3,
        area: impl FnOnce() -> f64,
        p: DVec3,
        radiance: Rgb,
        u: DVec2,
    ) -> Option<LightSample> {
        if (p - self.corner).dot(n) <= 0.0 {
            return None;
        }
        let to = self.sample_point(u) - p;
        let dist2 = to.length_squared();
        let distance = dist2.sqrt();
        let direction = to / distance;
        let cos_light = -direction.dot(n);
        if cos_light <= 0.0 || !direction.is_finite() {
            return None;
        }
        Some(LightSample {
            direction,
            distance,
            radiance,
            pdf: dist2 / (area() * cos_light),
            delta: false,
        })
    }

    /// The solid-angle pdf of [`Self::sample`] for direction `wi` from `p` (0 when the ray
    /// misses the emitter or arrives at its back).
    #[must_use]
    pub fn pdf(&self, p: DVec3, wi: DVec3) -> f64 {
        let Some(n) = self.normal() else {
            return 0.0;
        };
        let c = self.edge_u.cross(self.edge_v);
        self.pdf_given(n, (c, c.length_squared()), || self.area(), p, wi)
    }

    /// [`Self::pdf`] with the unit normal `n`, `edge_u x edge_v` and its squared length, and
    /// the area given ([`PreparedPlanar`]).
    #[inline]
    pub(crate) fn pdf_given(
        &self,
        n: DVec3,
        (c, c2): (DVec3, f64),
        area: impl FnOnce() -> f64,
        p: DVec3,
        wi: DVec3,
    ) -> f64 {
        let cos_light = -wi.dot(n);
        if cos_light <= 0.0 || (p - self.corner).dot(n) <= 0.0 {
            return 0.0;
        }
        let t = (self.corner - p).dot(n) / wi.dot(n);
        if !(t > 0.0 && t.is_finite()) {
            return 0.0;
        }
        // Coordinates of the hit in the (edge_u, edge_v) basis, by the dual basis.
        let q = p + t * wi - self.corner;
        let s = q.cross(self.edge_v).dot(c) / c2;
        let r = self.edge_u.cross(q).dot(c) / c2;
        let inside = s >= 0.0
            && r >= 0.0
            && if self.triangle {
                s + r <= 1.0
            } else {
                s <= 1.0 && r <= 1.0
            };
        if inside {
            t * t / (area() * cos_light)
        } else {
            0.0
        }
    }
}

/// A point light as a delta sample: irradiance `intensity / r^2` along the direction to it.
#[inline(always)]
#[must_use]
pub fn sample_point_light(p: DVec3, position: DVec3, intensity: Rgb) -> LightSample {
    let to = position - p;
    let r2 = to.length_squared();
    let r = r2.sqrt();
    LightSample {
        direction: to / r,
        distance: r,
        radiance: intensity / r2,
        pdf: 1.0,
        delta: true,
    }
}

/// A directional light (travelling along `direction`) as a delta sample.
#[inline(always)]
#[must_use]
pub fn sample_directional_light(direction: DVec3, irradiance: Rgb) -> LightSample {
    LightSample {
        direction: -direction,
        distance: f64::INFINITY,
        radiance: irradiance,
        pdf: 1.0,
        delta: true,
    }
}

/// Lambert's closed form for the irradiance at `p` (unit normal `n`) from a uniform polygon of
/// radiance `l` wholly above the horizon of `(p, n)`:
/// `E = l/2 |sum_i theta_i (n . unit(v_i x v_i+1))|` (Lambert 1760; Arvo 1994, "The Irradiance
/// Jacobian for Partially Occluded Polyhedral Sources", eq. 1). The reference the area-light
/// samplers are tested against.
#[must_use]
pub fn polygon_irradiance(p: DVec3, n: DVec3, verts: &[DVec3], l: f64) -> f64 {
    let v: Vec<DVec3> = verts.iter().map(|&q| (q - p).normalize()).collect();
    let mut sum = 0.0;
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
        let theta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += theta * n.dot(a.cross(b).normalize());
    }
    0.5 * l * sum.abs()
}
