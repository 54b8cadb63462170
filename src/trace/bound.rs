//! The bounded-error cut (issue 18): the automatic `min_weight`, chosen so that a branch is cut
//! only when what it could still add to a pixel is below `settings.tolerance` in display units.
//!
//! A secondary ray of throughput `tau` (the product of the weights and Beer factors above it)
//! adds `tau * L` to its sample's radiance, where `L` is the radiance it carries. `L` is bounded
//! from the scene, per colour channel, following the recursion of the lecture's `trace`:
//!
//! - a miss carries at most the background, `L <= max(background)` (Beer factors are <= 1);
//! - a hit carries its local term plus its weighted secondary rays. The local term is at most
//!   `B = max(emission) + max(ambient) max(albedo) + (max(albedo) / pi + max(specular)) sum_l E_l`,
//!   since Lambert's `albedo / pi`, the Blinn-Phong `specular (N.H)^n <= specular`, `cos <= 1`,
//!   a shadow ray's transmission `<= 1`, and `E_l` bounds light `l`'s irradiance on any surface:
//!   the irradiance of a directional light, or `I / d^2` of a point light with `d` the least
//!   distance from the light to any surface (a lower bound on it: the sphere's, plane's or box's
//!   distance, a triangle's plane and box, a mesh's box, or its triangles' when the light is
//!   inside the box). The weights of a hit's secondary rays sum to
//!   `reflectivity + transmissivity (R + T) = reflectivity + transmissivity <= s` per channel.
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

use crate::geometry::Shape;
use crate::math::Rgb;
use crate::scene::{LightKind, Scene, Settings, ShadowMode, Texture};
use glam::DVec3;

/// The steepest slope of the linear-to-sRGB curve (its linear segment at black).
pub const SRGB_MAX_SLOPE: f64 = 12.92;

/// The `min_weight` the tracer uses: the setting when given, else [`auto_min_weight`].
#[must_use]
pub fn effective_min_weight(scene: &Scene) -> f64 {
    scene
        .settings
        .min_weight
        .unwrap_or_else(|| auto_min_weight(scene, &scene.settings))
}

/// The automatic cut for `settings` (tolerance and max depth) on `scene`: in `[0, 1]`, 0 when
/// the tolerance is 0 or the scene's radiance has no finite bound.
#[must_use]
pub fn auto_min_weight(scene: &Scene, settings: &Settings) -> f64 {
    let bound = radiance_bound(scene, settings.max_depth, settings.shadows);
    let tol = settings.tolerance;
    if tol <= 0.0 || !bound.is_finite() {
        return 0.0;
    }
    if bound <= 0.0 {
        return 1.0; // nothing can be added: cut every branch that carries less than all
    }
    (tol / (SRGB_MAX_SLOPE * bound)).clamp(0.0, 1.0)
}

/// The most linear radiance (any channel) a ray can carry with up to `max_depth` bounces left
/// (see the module notes); may be infinite.
#[must_use]
pub fn radiance_bound(scene: &Scene, max_depth: u32, shadows: ShadowMode) -> f64 {
    let used = || scene.objects.iter().map(|o| &scene.materials[o.material]);
    let max = |c: Rgb| c.max_element().max(0.0);
    let albedo = used()
        .map(|m| match m.diffuse {
            Texture::Solid(c) => max(c),
            Texture::Checker { even, odd, .. } => max(even).max(max(odd)),
        })
        .fold(0.0, f64::max);
    let specular = used().map(|m| max(m.specular)).fold(0.0, f64::max);
    let emission = used().map(|m| max(m.emission)).fold(0.0, f64::max);
    let split = used()
        .map(|m| max(m.reflectivity + m.transmissivity))
        .fold(0.0, f64::max);
    let irradiance: f64 = scene
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Directional { irradiance, .. } => max(irradiance),
            LightKind::Point {
                position,
                intensity,
            } => {
                let d = surface_distance(scene, position);
                if d > 0.0 {
                    max(intensity) / (d * d)
                } else {
                    f64::INFINITY
                }
            }
        })
        .sum();
    let through = used().map(|m| max(m.transmissivity)).fold(0.0, f64::max);
    if shadows == ShadowMode::Translucent && through > 1.0 {
        return f64::INFINITY;
    }
    let direct = if irradiance > 0.0 {
        (albedo * std::f64::consts::FRAC_1_PI + specular) * irradiance
    } else {
        0.0
    };
    let local = emission + max(scene.ambient) * albedo + direct;
    let one = local.max(max(scene.background));
    one * geometric_sum(split, max_depth)
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

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(extra: &str) -> Scene {
        let src = format!(
            r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40,
                 "width": 4, "height": 3}},
               "background": [0.1, 0.1, 0.1], "ambient": [0, 0, 0],
               "materials": {{"m": {{"diffuse": [0.5, 0.5, 0.5]}},
                             "g": {{"transmissivity": [0.9, 0.9, 0.9], "ior": 1.5}}}},
               "objects": [{{"type": "plane", "point": [0,-1,0], "normal": [0,1,0],
                             "material": "m"}},
                           {{"type": "sphere", "center": [0,0,0], "radius": 1,
                             "material": "g"}}],
               "lights": [{{"type": "point", "position": [0,3,0], "intensity": [8,8,8]}}]
               {extra}}}"#
        );
        Scene::from_json(&src).unwrap()
    }

    #[test]
    fn the_bound_follows_the_closed_form() {
        let s = scene("");
        // Nearest surface to the light: the sphere, 3 - 1 = 2 away: E <= 8 / 4 = 2; local
        // <= (0.5 / pi + 0) * 2; s = 0.9; 16 bounces.
        let local = 0.5 / std::f64::consts::PI * 2.0;
        let sum = (1.0 - 0.9f64.powi(17)) / 0.1;
        let b = radiance_bound(&s, 16, ShadowMode::Opaque);
        assert!((b - local * sum).abs() < 1e-12, "{b}");
        let w = auto_min_weight(&s, &s.settings);
        assert!(
            (w - (1.0 / 510.0) / (12.92 * local * sum)).abs() < 1e-15,
            "{w}"
        );
        assert_eq!(effective_min_weight(&s), w);
    }

    #[test]
    fn exhaustive_and_unbounded_cases_cut_nothing() {
        let s = scene(r#", "settings": {"min_weight": 0}"#);
        assert_eq!(effective_min_weight(&s), 0.0);
        let s = scene(r#", "settings": {"tolerance": 0}"#);
        assert_eq!(effective_min_weight(&s), 0.0);
        // A light on the plane: irradiance without bound.
        let mut s = scene("");
        s.lights[0].kind = LightKind::Point {
            position: DVec3::new(5.0, -1.0, 0.0),
            intensity: Rgb::ONE,
        };
        assert_eq!(radiance_bound(&s, 4, ShadowMode::Opaque), f64::INFINITY);
        assert_eq!(effective_min_weight(&s), 0.0);
    }

    #[test]
    fn distances_never_exceed_the_true_distance() {
        let p = DVec3::new(0.3, 0.2, 0.1);
        assert!((box_surface_distance(DVec3::ZERO, DVec3::ONE, p) - 0.1).abs() < 1e-15);
        assert!(
            (box_surface_distance(DVec3::ZERO, DVec3::ONE, DVec3::splat(2.0)) - 3f64.sqrt()).abs()
                < 1e-12
        );
        let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
        // Above the triangle: the plane distance; beside it in its plane: the box distance.
        assert_eq!(
            triangle_distance(&v, DVec3::Z, DVec3::new(0.2, 0.2, 0.5)),
            0.5
        );
        assert_eq!(
            triangle_distance(&v, DVec3::Z, DVec3::new(3.0, 0.0, 0.0)),
            2.0
        );
        assert_eq!(geometric_sum(1.0, 3), 4.0);
        assert_eq!(geometric_sum(2.0, 3), 15.0);
        assert_eq!(geometric_sum(3.0, 1024), f64::INFINITY);
    }
}
