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
//!   `pdf_dir = 1 / (4 pi)`; what leaves is `I`.
//! - directional light (irradiance `E`, direction `d`): direction `d` (delta); origin uniform on
//!   a disc of radius `R` (the scene's bounding radius) perpendicular to `d`, `R` behind the
//!   scene's centre, `pdf_pos = 1 / (pi R^2)`; what leaves is `E`.
//! - area light (a sphere, quad, triangle or mesh of radiance `L`, emitting from its outer
//!   side): origin uniform over its area, `pdf_pos = 1 / A`; direction cosine-weighted about the
//!   outward normal, `pdf_dir = cos / pi`; what leaves is `L`.
//!
//! With these, `le |cos| / (pdf_pos pdf_dir)` of every sample is the light's flux `Phi` (for a
//! point light `4 pi I`, directional `pi R^2 E`, area `pi A L`): the powers by which light
//! sampling chooses lights (`trace::path::lights`), which the tests check.

use crate::math::Rgb;
use crate::sampling::warp::{
    orthonormal_basis, square_to_concentric_disk, square_to_cosine_hemisphere,
    square_to_uniform_sphere,
};
use crate::scene::AreaEmitter;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// A light as a source of emitted rays.
#[derive(Clone, Copy, Debug)]
pub enum Emitter<'a> {
    /// A point light of intensity `intensity`.
    Point {
        /// Position.
        position: DVec3,
        /// Radiant intensity.
        intensity: Rgb,
    },
    /// A directional light over a scene of bounding sphere (`center`, `radius`).
    Directional {
        /// Unit direction of travel.
        direction: DVec3,
        /// Irradiance on a surface facing the light.
        irradiance: Rgb,
        /// Centre of the scene's bounding sphere.
        center: DVec3,
        /// Its radius (> 0).
        radius: f64,
    },
    /// An emissive object of radiance `emission` on its outer side.
    Area {
        /// Its shape.
        shape: AreaEmitter<'a>,
        /// Emitted radiance.
        emission: Rgb,
    },
}

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
fn sample_area(shape: &AreaEmitter<'_>, u: DVec2) -> Option<(DVec3, DVec3, f64)> {
    match *shape {
        AreaEmitter::Sphere { center, radius } => {
            let n = square_to_uniform_sphere(u);
            Some((center + radius * n, n, 4.0 * PI * radius * radius))
        }
        AreaEmitter::Planar(e) => Some((e.sample_point(u), e.normal()?, e.area())),
        AreaEmitter::Mesh(m) => {
            let (p, n) = m.sample_point(u)?;
            Some((p, n, m.area()))
        }
    }
}

/// The outward normal of `shape` at `p` (on it), for [`Emitter::pdf_le`].
fn normal_at(shape: &AreaEmitter<'_>, p: DVec3, hint: Option<DVec3>) -> Option<DVec3> {
    match *shape {
        AreaEmitter::Sphere { center, .. } => hint.or_else(|| (p - center).try_normalize()),
        AreaEmitter::Planar(e) => e.normal(),
        AreaEmitter::Mesh(_) => hint,
    }
}

impl Emitter<'_> {
    /// An emitted ray from `u_pos` (the origin) and `u_dir` (the direction); `None` for a
    /// degenerate light (zero area).
    #[must_use]
    pub fn sample_le(&self, u_pos: DVec2, u_dir: DVec2) -> Option<EmittedRay> {
        match *self {
            Emitter::Point {
                position,
                intensity,
            } => Some(EmittedRay {
                origin: position,
                direction: square_to_uniform_sphere(u_dir),
                normal: None,
                le: intensity,
                pdf_pos: 1.0,
                pdf_dir: 1.0 / (4.0 * PI),
                delta_pos: true,
                delta_dir: false,
            }),
            Emitter::Directional {
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
            Emitter::Area { shape, emission } => {
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

    /// The densities `(pdf_pos, pdf_dir)` with which [`Emitter::sample_le`] draws a ray from
    /// `origin` (on the light; for a mesh, with its outward `normal` there) along `direction`:
    /// for delta parts the other density alone (the delta's own is 1), zero where the light
    /// cannot emit that ray (behind an area light's outer side).
    #[must_use]
    pub fn pdf_le(&self, origin: DVec3, normal: Option<DVec3>, direction: DVec3) -> (f64, f64) {
        match *self {
            Emitter::Point { .. } => (1.0, 1.0 / (4.0 * PI)),
            Emitter::Directional { radius, .. } => (1.0 / (PI * radius * radius), 1.0),
            Emitter::Area { shape, .. } => {
                let area = match shape {
                    AreaEmitter::Sphere { radius, .. } => 4.0 * PI * radius * radius,
                    AreaEmitter::Planar(e) => e.area(),
                    AreaEmitter::Mesh(m) => m.area(),
                };
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

/// The sphere around every bounded object of `scene` (centre, radius; radius 1 about the
/// origin when there is none, or when it is not finite): the disc over which a directional
/// light's flux is counted and from which its emitted rays start.
#[must_use]
pub fn bounding_sphere(scene: &crate::Scene) -> (DVec3, f64) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for o in &scene.objects {
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

/// Every light of `scene` as an [`Emitter`]: its point and directional lights in order, then
/// its area lights in object order (as light sampling numbers them), each with its name.
#[must_use]
pub fn emitters(scene: &crate::Scene) -> Vec<(String, Emitter<'_>)> {
    use crate::scene::LightKind;
    let (center, radius) = bounding_sphere(scene);
    let delta = scene.lights.iter().map(|l| {
        let e = match l.kind {
            LightKind::Point {
                position,
                intensity,
            } => Emitter::Point {
                position,
                intensity,
            },
            LightKind::Directional {
                direction,
                irradiance,
            } => Emitter::Directional {
                direction,
                irradiance,
                center,
                radius,
            },
        };
        (l.name.clone(), e)
    });
    let area = (0..scene.objects.len()).filter_map(|i| {
        let (shape, emission) = scene.area_light(i)?;
        Some((
            scene.objects[i].name.clone(),
            Emitter::Area { shape, emission },
        ))
    });
    delta.chain(area).collect()
}

/// Emitted rays a probe of [`dark_emitters`] traces per area light (an 8 x 8 grid of origins,
/// each with its own direction).
pub const DARK_PROBE: u32 = 64;

/// The names of the area lights of `scene` that light nothing: none of [`DARK_PROBE`] emitted
/// rays (origins stratified over the light, cosine-weighted directions from its emitting side)
/// meets a surface. Such a lamp faces away from everything (issue 32: an area light whose
/// emitting side sees no surface got no warning; only its directly seen face shows).
#[must_use]
pub fn dark_emitters(scene: &crate::Scene) -> Vec<String> {
    let side = f64::from(DARK_PROBE).sqrt() as u32;
    emitters(scene)
        .into_iter()
        .filter(|(_, e)| matches!(e, Emitter::Area { .. }))
        .filter(|(_, e)| {
            !(0..DARK_PROBE).any(|k| {
                let cell = DVec2::new(f64::from(k % side), f64::from(k / side));
                let u_pos = (cell + 0.5) / f64::from(side);
                // A second, shuffled grid for the directions (golden-ratio steps).
                let u_dir = DVec2::new(
                    (f64::from(k) * 0.618_033_988_749_895 + 0.25).fract(),
                    (f64::from(k) + 0.5) / f64::from(DARK_PROBE),
                );
                e.sample_le(u_pos, u_dir).is_some_and(|r| {
                    let t_min = 1e-7 * (1.0 + r.origin.abs().max_element());
                    let ray = crate::math::Ray::new(r.origin, r.direction, t_min);
                    scene.intersect(&ray, f64::INFINITY).is_some()
                })
            })
        })
        .map(|(name, _)| name)
        .collect()
}

#[cfg(test)]
mod tests;
