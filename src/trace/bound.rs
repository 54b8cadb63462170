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
//!   cut compares the throughput of one sample's estimate, `trace::glossy`).
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
    // A rough lobe's reflection lit by a point or directional light: `f cos_i = weight D G F /
    // (4 cos_o) <= weight D_max G1(wo) / (4 cos_o)`, with `D_max = 1 / (pi a^2)` and
    // `G1(wo) / cos_o = 2 / (cos_o + sqrt(cos_o^2 + a^2 sin_o^2)) <= 2 / a` (the denominator
    // grows with cos_o from a), so at most `weight / (2 pi a^3)` (Walter et al. 2007 eq. 20,
    // 33, 34). Strict, and large for small alpha.
    let glossy = used()
        .filter(|m| m.is_rough())
        .map(|m| {
            let a = m.roughness;
            max(m.reflectivity + m.transmissivity) / (2.0 * std::f64::consts::PI * a * a * a)
        })
        .fold(0.0, f64::max);
    let direct = if irradiance > 0.0 {
        (albedo * std::f64::consts::FRAC_1_PI + specular + glossy) * irradiance
    } else {
        0.0
    };
    // Area lights (emissive objects sampled for direct light, on with `light_samples`): the
    // radiance arriving over the hemisphere is at most `max(emission)` (shadow rays stop at the
    // first emitter), so their expected direct light is at most `(albedo / pi + specular) x pi x
    // max(emission)`. A single sample's estimate can exceed its expectation (`f cos L / pdf`):
    // like a point light near a surface, this part of the bound is not strict per sample.
    let area = if scene.settings.light_samples.is_some() && emission > 0.0 {
        (albedo + std::f64::consts::PI * specular) * emission
    } else {
        0.0
    };
    let local = emission + max(scene.ambient) * albedo + direct + area;
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

    /// Sampled area lights add their expected direct light to the bound:
    /// `(max albedo + pi max specular) x max emission` (pbrt's `E <= pi L_max` over the hemisphere).
    #[test]
    fn sampled_area_lights_raise_the_bound_by_their_direct_light() {
        let src = include_str!("../../fixtures/soft-shadows.json");
        let mut s = Scene::from_json(src).unwrap();
        assert!(s.settings.light_samples.is_some());
        let on = radiance_bound(&s, 0, ShadowMode::Opaque);
        s.settings.light_samples = None;
        let off = radiance_bound(&s, 0, ShadowMode::Opaque);
        // The fixture: emission 10 (max channel), albedo 0.8, specular 0.3.
        let expect = (0.8 + std::f64::consts::PI * 0.3) * 10.0;
        assert!((on - off - expect).abs() < 1e-9 * on, "on {on}, off {off}");
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

    #[test]
    fn the_ray_budget_cuts_each_sample_and_keeps_the_tree_whole() {
        use crate::render::{render_pixel, trace_pixel};
        use crate::trace::{NoopRecorder, RayCounts};
        use crate::tree::EndReason;
        let mut s =
            scene(r#", "settings": {"max_depth": 40, "min_weight": 0, "max_rays": 50, "spp": 2}"#);
        s.camera = s.camera.with_size(8, 6);
        let mut cut_trees = 0;
        for (x, y) in [(4, 3), (3, 2), (0, 0)] {
            let t = trace_pixel(&s, x, y).unwrap();
            assert!(crate::analysis::invariants::tree_violations(&t, s.background).is_empty());
            let cut = t
                .nodes
                .iter()
                .filter(|n| n.end == EndReason::RayBudget)
                .count();
            cut_trees += usize::from(cut > 0);
            // Per sample: at most the budget, plus the last ray's shadow rays.
            assert!(
                t.nodes.len() <= 2 * (50 + s.lights.len() + 1),
                "{}",
                t.nodes.len()
            );
            let mut counts = RayCounts::default();
            let l = render_pixel(&s, x, y, &mut NoopRecorder, &mut counts, |_| {});
            assert_eq!(l, t.radiance);
            assert_eq!(counts.budget_samples > 0, cut > 0);
        }
        assert!(cut_trees > 0);
    }

    mod nested_dielectrics {
        //! Random nested-dielectric scenes: the automatic cut changes each pixel by no more than
        //! its cut branches could carry (strict), and by at most one 8-bit sRGB step.
        use super::super::*;
        use crate::analysis::invariants::tree_violations;
        use crate::math::linear_to_srgb;
        use crate::render::trace_pixel;
        use crate::tree::EndReason;
        use proptest::prelude::*;

        fn scene(ior: (f64, f64), t: (f64, f64), r: f64, depth: u32) -> Scene {
            let src = format!(
                r#"{{"camera": {{"position": [0,1,5], "look_at": [0,0.6,0], "fov_y": 35,
                     "width": 12, "height": 8}},
                   "background": [0.35, 0.55, 0.85], "ambient": [0.05, 0.05, 0.05],
                   "materials": {{
                     "floor": {{"diffuse": {{"checker": {{"even": [0.9,0.1,0.1],
                                "odd": [0.9,0.9,0.2], "size": 0.5}}}}}},
                     "outer": {{"transmissivity": [{t0},{t0},{t0}], "ior": {i0},
                                "specular": [0.5,0.5,0.5], "shininess": 100}},
                     "inner": {{"transmissivity": [{t1},{t1},{t1}], "ior": {i1},
                                "reflectivity": [{r},{r},{r}]}}}},
                   "objects": [
                     {{"type": "plane", "point": [0,-0.4,0], "normal": [0,1,0],
                       "material": "floor"}},
                     {{"type": "sphere", "center": [0,0.6,0], "radius": 1,
                       "material": "outer"}},
                     {{"type": "sphere", "center": [0.1,0.6,0.1], "radius": 0.5,
                       "material": "inner"}}],
                   "lights": [{{"type": "point", "position": [3,5,4],
                                "intensity": [60,60,60]}}],
                   "settings": {{"max_depth": {depth}}}}}"#,
                i0 = ior.0,
                i1 = ior.1,
                t0 = t.0,
                t1 = t.1,
            );
            Scene::from_json(&src).unwrap()
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(24))]
            #[test]
            fn the_cut_changes_pixels_by_less_than_its_bound(
                ior in (1.05f64..2.4, 1.05f64..2.4),
                t in (0.5f64..1.0, 0.3f64..0.9),
                r in 0.0f64..0.1,
                depth in 4u32..14,
            ) {
                let cut = scene(ior, t, r, depth);
                let mut full = cut.clone();
                full.settings.min_weight = Some(0.0);
                let bound = radiance_bound(&cut, depth, cut.settings.shadows);
                let w = effective_min_weight(&cut);
                prop_assert!(w > 0.0);
                for y in 0..8 {
                    for x in 0..12 {
                        let a = trace_pixel(&cut, x, y).unwrap();
                        let b = trace_pixel(&full, x, y).unwrap();
                        prop_assert!(tree_violations(&a, cut.background).is_empty());
                        // What the cut branches could have carried: their throughput (at most
                        // the parent's times the weight cut) times the radiance bound.
                        let mut could = 0.0;
                        for n in a.nodes.iter().filter(|n| n.end == EndReason::MinWeight) {
                            could += (n.throughput * n.truncated).max_element() * bound;
                        }
                        let diff = (a.radiance - b.radiance).abs().max_element();
                        prop_assert!(diff <= could * (1.0 + 1e-9) + 1e-15,
                            "pixel {x},{y}: {diff} > {could}");
                        let enc = |c: Rgb| c.to_array().map(linear_to_srgb);
                        let (ea, eb) = (enc(a.radiance), enc(b.radiance));
                        for k in 0..3 {
                            prop_assert!((ea[k] - eb[k]).abs() <= 1.0 / 255.0,
                                "pixel {x},{y}: {ea:?} vs {eb:?}");
                        }
                    }
                }
            }
        }
    }
}
