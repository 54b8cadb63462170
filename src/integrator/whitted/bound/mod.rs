//! The bounded-error cut (issue 18): the automatic `min_weight`, chosen so that a branch is cut
//! only when what it could still add to a pixel is below `settings.tolerance` in display units.
//!
//! A secondary ray of throughput `tau` (the product of the weights and Beer factors above it)
//! adds `tau * L` to its sample's radiance, where `L` is the radiance it carries. `L` is bounded
//! from the scene, per colour channel, following the recursion of the lecture's `trace`:
//!
//! - a miss carries at most the background, `L <= max(background)` (Beer factors are <= 1);
//! - a hit carries its local term plus its weighted secondary rays. The local term is at most
//!   `B = max(emission) + max(ambient) max(albedo) + (max(albedo) / pi + max(specular)) sum_l E_l`
//!   (plus `(max(albedo) + pi max(specular)) max(emission)` when area lights are sampled),
//!   since Lambert's `albedo / pi`, the Blinn-Phong `specular (N.H)^n <= specular`, `cos <= 1`,
//!   a shadow ray's transmission `<= 1`, and `E_l` bounds light `l`'s irradiance on any surface:
//!   the irradiance of a directional light, or `I / d^2` of a point light with `d` the least
//!   distance from the light to any surface (a lower bound on it: the sphere's, plane's or box's
//!   distance, a triangle's plane and box, a mesh's box, or its triangles' when the light is
//!   inside the box); a rough (GGX) lobe adds at most `weight / (2 pi alpha^3)` to the
//!   BRDF x cosine of a point or directional light (see `radiance_bound`). The weights of a
//!   hit's secondary rays sum to `reflectivity + transmissivity (R + T) = reflectivity +
//!   transmissivity <= s` per channel; a ray sampled from a rough lobe (visible normals) has
//!   `f cos / pdf = weight G1(wi) <= weight`, so one sample's estimate obeys the same sum (the
//!   cut compares the throughput of one sample's estimate, `integrator::whitted::glossy`).
//!
//! So a ray with `k` bounces left carries at most `max(background, B) (1 + s + ... + s^k)`, and
//! `max_depth` bounds `k`. A pixel's 8-bit sRGB value moves at most 12.92 times its linear
//! change (the curve's steepest slope, at black), so a branch with
//! `max(tau) < tolerance / (12.92 L_max)` changes the displayed pixel by less than `tolerance`.
//!
//! Where the bound is not strict: the bound is per cut branch, and the cut branches of one pixel
//! add up (the tree records each cut weight); a point light on a surface (`d = 0`) has no
//! bounded irradiance, and translucent shadows through materials with transmissivity above 1
//! can grow: both give an infinite bound, so the cut is 0 (the exhaustive tree, bounded by
//! `settings.max_rays`).
//!
//! [`carried`] bounds the same radiance material by material (tighter: between lamps, mirrors
//! and clear glass it does not grow with depth) and sets the automatic weight below which glass
//! hits play Russian roulette instead of splitting. The cut keeps this shared bound: with the
//! carried one as its per-branch threshold, the cut branches of a pixel added up to more than
//! half an 8-bit step (0.066% of the mirror corridor's pixels off by more than 1/255).

use crate::geometry::Shape;
use crate::math::Rgb;
use crate::scene::{LightKind, Material, Scene, Settings, ShadowMode, Texture};
use glam::DVec3;

/// The steepest slope of the linear-to-sRGB curve (its linear segment at black).
pub const SRGB_MAX_SLOPE: f64 = 12.92;

/// The `min_weight` the tracer uses: the setting when given, else [`auto_min_weight`].
#[must_use]
pub fn effective_min_weight(scene: &Scene) -> f64 {
    scene
        .settings
        .whitted
        .min_weight
        .unwrap_or_else(|| auto_min_weight(scene, &scene.settings))
}

/// The automatic cut for `settings` (tolerance and max depth) on `scene`: in `[0, 1]`, 0 when
/// the tolerance is 0 or the scene's radiance has no finite bound.
#[must_use]
pub fn auto_min_weight(scene: &Scene, settings: &Settings) -> f64 {
    let bound = radiance_bound(scene, settings.max_depth, settings.whitted.shadows);
    let tol = settings.whitted.tolerance;
    if tol <= 0.0 || !bound.is_finite() {
        return 0.0;
    }
    if bound <= 0.0 {
        return 1.0; // nothing can be added: cut every branch that carries less than all
    }
    (tol / (SRGB_MAX_SLOPE * bound)).clamp(0.0, 1.0)
}

/// The most linear radiance (any channel) a ray can carry with up to `max_depth` bounces left
/// (see the module notes); may be infinite. One bound for every hit: the largest of each
/// material quantity, whichever materials they come from ([`carried::carried_bound`] bounds
/// each material's hits apart, tighter).
#[must_use]
pub fn radiance_bound(scene: &Scene, max_depth: u32, shadows: ShadowMode) -> f64 {
    let Some(irradiance) = light_irradiance(scene, shadows) else {
        return f64::INFINITY;
    };
    let terms: Vec<Terms> = scene.used_materials().map(Terms::of).collect();
    let most = |f: fn(&Terms) -> f64| terms.iter().map(f).fold(0.0, f64::max);
    let all = Terms {
        albedo: Rgb::splat(most(|t| t.albedo.max_element())),
        specular: Rgb::splat(most(|t| t.specular.max_element())),
        glossy: most(|t| t.glossy),
        emission: Rgb::splat(most(|t| t.emission.max_element())),
        split: Rgb::splat(most(|t| t.split.max_element())),
    };
    let ambient = Rgb::splat(scene.ambient.max_element().max(0.0));
    let local = all.local(ambient, irradiance, area_emission(scene)).x;
    let one = local.max(scene.background.max_element().max(0.0));
    one * geometric_sum(all.split.x, max_depth)
}

/// The brightest emission (max channel) when area lights are sampled (`light_samples`).
fn area_emission(scene: &Scene) -> Option<f64> {
    let emission = scene
        .used_materials()
        .map(|m| m.emission.max_element().max(0.0))
        .fold(0.0, f64::max);
    (scene.settings.whitted.light_samples.is_some() && emission > 0.0).then_some(emission)
}

/// The point and directional lights' irradiance bound `sum_l E_l` (max channels; infinite for a
/// point light on a surface); `None` when translucent shadows through materials with
/// transmissivity above 1 leave the radiance unbounded.
fn light_irradiance(scene: &Scene, shadows: ShadowMode) -> Option<f64> {
    let max = |c: Rgb| c.max_element().max(0.0);
    let through = scene
        .used_materials()
        .map(|m| max(m.transmissivity))
        .fold(0.0, f64::max);
    if shadows == ShadowMode::Translucent && through > 1.0 {
        return None;
    }
    Some(
        scene
            .lights
            .iter()
            .map(|l| match l.kind {
                LightKind::Directional { irradiance, .. } => max(irradiance),
                // A spot light's falloff is at most 1: its axis intensity bounds it.
                LightKind::Point {
                    position,
                    intensity,
                    ..
                } => {
                    let d = surface_distance(scene, position);
                    if d > 0.0 {
                        max(intensity) / (d * d)
                    } else {
                        f64::INFINITY
                    }
                }
            })
            .sum(),
    )
}

/// One material's quantities in the bound, per channel and clamped at 0.
#[derive(Clone, Copy, Debug)]
struct Terms {
    albedo: Rgb,
    specular: Rgb,
    /// The rough lobe's highlight bound `weight / (2 pi a^3)` (0 for smooth materials).
    glossy: f64,
    emission: Rgb,
    /// `reflectivity + transmissivity`: the secondary rays' weights sum to at most this.
    split: Rgb,
}

impl Terms {
    fn of(m: &Material) -> Self {
        let pos = |c: Rgb| c.max(Rgb::ZERO);
        // A rough lobe's reflection lit by a point or directional light: `f cos_i = weight D G
        // F / (4 cos_o) <= weight D_max G1(wo) / (4 cos_o)`, with `D_max = 1 / (pi a^2)` and
        // `G1(wo) / cos_o = 2 / (cos_o + sqrt(cos_o^2 + a^2 sin_o^2)) <= 2 / a` (the
        // denominator grows with cos_o from a), so at most `weight / (2 pi a^3)` (Walter et
        // al. 2007 eq. 20, 33, 34). Strict, and large for small alpha. Anisotropic or
        // Beckmann: `D_max = 1 / (pi a_u a_v) <= 1 / (pi a^2)` with `a` the smaller alpha, and
        // `G1 / cos <= c 2 / a` with `c = 1` (GGX) or `sqrt(pi)` (Beckmann;
        // `Microfacet::g1_over_cos_max`). A conductor's Fresnel is at most 1.
        let glossy = if m.is_rough() {
            let dist = m.microfacet();
            let a = dist.alpha_x.min(dist.alpha_y);
            let c = match dist.kind {
                crate::bsdf::Distribution::Ggx => 1.0,
                crate::bsdf::Distribution::Beckmann => std::f64::consts::PI.sqrt(),
            };
            (m.reflectivity + m.transmissivity).max_element().max(0.0)
                / (2.0 * std::f64::consts::PI * a * a * a)
                * c
        } else {
            0.0
        };
        // A coating shows the base through `t_i t_o / (eta^2 (1 - F_dr,int))` with `t <= 1`
        // (and a nonlinear coating's effective albedo is at most `rho`): at most
        // `base_scale`, which exceeds 1 slightly (1.10 at eta 1.5; the factor itself reaches
        // 1.016 at normal incidence).
        let coat = m.coating.map_or(1.0, |c| c.base_scale().max(1.0));
        Self {
            albedo: match m.diffuse {
                Texture::Solid(c) => pos(c),
                Texture::Checker { even, odd, .. } => pos(even).max(pos(odd)),
            } * coat,
            specular: pos(m.specular),
            glossy,
            emission: pos(m.emission),
            split: pos(m.reflectivity + m.transmissivity),
        }
    }

    /// The local term's bound `B` of the module notes, per channel.
    fn local(&self, ambient: Rgb, irradiance: f64, area: Option<f64>) -> Rgb {
        let direct = if irradiance > 0.0 {
            (self.albedo * std::f64::consts::FRAC_1_PI + self.specular + Rgb::splat(self.glossy))
                * irradiance
        } else {
            Rgb::ZERO
        };
        // Area lights (emissive objects sampled for direct light, on with `light_samples`): the
        // radiance arriving over the hemisphere is at most `max(emission)` (shadow rays stop at
        // the first emitter), so their expected direct light is at most `(albedo / pi +
        // specular) x pi x max(emission)`. A single sample's estimate can exceed its
        // expectation (`f cos L / pdf`): like a point light near a surface, this part of the
        // bound is not strict per sample.
        let area = area.map_or(Rgb::ZERO, |e| {
            (self.albedo + std::f64::consts::PI * self.specular) * e
        });
        self.emission + ambient * self.albedo + direct + area
    }
}

/// `1 + s + ... + s^k`, without cancellation (infinite when it overflows).
fn geometric_sum(s: f64, k: u32) -> f64 {
    if s == 1.0 {
        return f64::from(k) + 1.0;
    }
    if s < 1.0 {
        return (1.0 - s.powf(f64::from(k) + 1.0)) / (1.0 - s);
    }
    (s.powf(f64::from(k) + 1.0) - 1.0) / (s - 1.0)
}

/// A lower bound on the distance from `p` to the nearest surface of the scene.
fn surface_distance(scene: &Scene, p: DVec3) -> f64 {
    scene
        .objects
        .iter()
        .map(|o| shape_distance(&o.shape, p))
        .fold(f64::INFINITY, f64::min)
}

fn shape_distance(shape: &Shape, p: DVec3) -> f64 {
    match shape {
        Shape::Sphere { center, radius } => ((p - *center).length() - radius).abs(),
        Shape::Plane { point, normal } => (p - *point).dot(*normal).abs(),
        Shape::Triangle { vertices, normal } => triangle_distance(vertices, *normal, p),
        Shape::Quad {
            vertices: [a, b, c, d],
            normal,
        } => triangle_distance(&[*a, *b, *c], *normal, p).min(triangle_distance(
            &[*a, *c, *d],
            *normal,
            p,
        )),
        Shape::Box { min, max } => box_surface_distance(*min, *max, p),
        Shape::Mesh(mesh) => {
            let b = mesh.bounds();
            let outside = box_distance(b.min, b.max, p);
            if outside > 0.0 {
                return outside;
            }
            (0..mesh.triangle_count())
                .map(|i| {
                    let v = mesh.triangle(i);
                    let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
                    triangle_distance(&v, n, p)
                })
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// Both the distance to the triangle's plane and to its box are at most the true distance.
fn triangle_distance(v: &[DVec3; 3], normal: DVec3, p: DVec3) -> f64 {
    let plane = (p - v[0]).dot(normal).abs();
    let lo = v[0].min(v[1]).min(v[2]);
    let hi = v[0].max(v[1]).max(v[2]);
    plane.max(box_distance(lo, hi, p))
}

/// Distance from `p` to the solid box (0 inside).
fn box_distance(min: DVec3, max: DVec3, p: DVec3) -> f64 {
    (min - p).max(p - max).max(DVec3::ZERO).length()
}

/// Distance from `p` to the box's surface (inside too).
fn box_surface_distance(min: DVec3, max: DVec3, p: DVec3) -> f64 {
    let outside = box_distance(min, max, p);
    if outside > 0.0 {
        return outside;
    }
    (p - min).min(max - p).min_element().max(0.0)
}

pub mod carried;
#[cfg(test)]
mod tests;
