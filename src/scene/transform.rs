//! Moving a whole scene: uniform scale about the origin, then a translation. Used to sweep
//! scene scales (`raytree acne`) and by the hard-case tests.

use super::{LightKind, Scene, Texture};
use crate::geometry::Shape;
use glam::DVec3;
use std::sync::Arc;

/// The scene under `x -> scale * x + translation` (`scale > 0`), looking the same.
///
/// Camera, shapes (meshes too, with their BVHs rebuilt) and point lights move; point-light
/// intensities are multiplied by `scale^2` and absorption coefficients divided by `scale`, so
/// irradiance and Beer's factors (and so the image) are unchanged; checker cells scale with the
/// scene (their pattern is fixed in world space, so a translation that is not a whole number of
/// cells shifts it). The thin lens's aperture radius and focus distance scale too. Directions, normals and the
/// field of view are invariant. The offset
/// epsilon stays absolute: an offset strategy either scales it or not, and that is what the
/// sweep measures.
#[must_use]
pub fn transformed(scene: &Scene, scale: f64, translation: DVec3) -> Scene {
    let map = |p: DVec3| scale * p + translation;
    let mut out = scene.clone();
    out.camera.position = map(scene.camera.position);
    out.camera.aperture_radius *= scale;
    out.camera.focus_distance *= scale;
    for o in &mut out.objects {
        o.shape = match o.shape {
            Shape::Sphere { center, radius } => Shape::Sphere {
                center: map(center),
                radius: scale * radius,
            },
            Shape::Plane { point, normal } => Shape::Plane {
                point: map(point),
                normal,
            },
            Shape::Triangle { vertices, normal } => Shape::Triangle {
                vertices: vertices.map(map),
                normal,
            },
            Shape::Quad { vertices, normal } => Shape::Quad {
                vertices: vertices.map(map),
                normal,
            },
            Shape::Box { min, max } => Shape::Box {
                min: map(min),
                max: map(max),
            },
            Shape::Mesh(ref m) => Shape::Mesh(Arc::new(m.scaled(scale, translation))),
        };
    }
    // The object bounds moved.
    out.rebuild_accel();
    for m in &mut out.materials {
        m.absorption /= scale;
        if let Texture::Checker { size, .. } = &mut m.diffuse {
            *size *= scale;
        }
    }
    for l in &mut out.lights {
        if let LightKind::Point {
            position,
            intensity,
            ..
        } = &mut l.kind
        {
            *position = map(*position);
            *intensity *= scale * scale;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render;

    #[test]
    fn identity_is_identity_and_scaling_keeps_the_image() {
        let mut s = Scene::default_scene();
        s.camera = s.camera.with_size(24, 18);
        // The robust offset has no absolute epsilon, which would not scale with the scene.
        s.settings.offset.strategy = crate::scene::OffsetStrategy::Robust;
        // Roulette choices hash the hit points, which the transform moves: split everywhere.
        s.settings.whitted.roulette_below = Some(0.0);
        assert_eq!(transformed(&s, 1.0, DVec3::ZERO), s);
        // Scale by a power of two and translate by whole checker cells (2 x cell size):
        // every computation scales exactly, so the image matches closely.
        let moved = transformed(&s, 4.0, DVec3::new(8.0, 0.0, -16.0));
        let (a, _, _) = render(
            &crate::integrator::SceneIntegrator::new(&s),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        let (b, _, _) = render(
            &crate::integrator::SceneIntegrator::new(&moved),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        let worst = crate::analysis::cost::compare(&a, &b)
            .expect("same size")
            .max;
        assert!(worst < 1e-6, "worst pixel difference {worst}");
    }
}
