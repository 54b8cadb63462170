//! Projecting the selected pixel's ray tree onto the image: world points to film coordinates
//! through the scene's pinhole camera, with segments clipped at a near plane.

use crate::scene::Camera;
use crate::tree::{NodeId, RayKind, RayTree};
use glam::DVec3;

/// Points closer to the eye than this (along `forward`) are clipped.
const NEAR: f64 = 1e-3;
/// How far a ray that hits nothing is drawn.
const MISS_LENGTH: f64 = 1e3;

/// Film position (pixels, (0,0) top-left) of `point_in_world`, or `None` behind the near plane.
#[must_use]
pub fn film_from_world(camera: &Camera, point_in_world: DVec3) -> Option<[f64; 2]> {
    let d = point_in_world - camera.position;
    let z = d.dot(camera.forward);
    if z < NEAR {
        return None;
    }
    let half_h = (camera.fov_y.to_radians() * 0.5).tan();
    let half_w = half_h * f64::from(camera.width) / f64::from(camera.height);
    let u = d.dot(camera.right) / z;
    let v = d.dot(camera.up) / z;
    let fx = (u / half_w + 1.0) * 0.5 * f64::from(camera.width);
    let fy = (1.0 - v / half_h) * 0.5 * f64::from(camera.height);
    Some([fx, fy])
}

/// The segment `a -> b` in film coordinates, clipped to the part in front of the camera.
#[must_use]
pub fn film_segment(camera: &Camera, a: DVec3, b: DVec3) -> Option<[[f64; 2]; 2]> {
    let za = (a - camera.position).dot(camera.forward);
    let zb = (b - camera.position).dot(camera.forward);
    if za < NEAR && zb < NEAR {
        return None;
    }
    let clip = |p: DVec3, zp: f64, q: DVec3, zq: f64| {
        // Clip a little in front of the near plane so rounding cannot push it behind.
        if zp >= NEAR {
            p
        } else {
            p + (q - p) * ((2.0 * NEAR - zp) / (zq - zp))
        }
    };
    let a2 = clip(a, za, b, zb);
    let b2 = clip(b, zb, a, za);
    Some([film_from_world(camera, a2)?, film_from_world(camera, b2)?])
}

/// One drawable segment of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSegment {
    /// The node the segment belongs to.
    pub node: NodeId,
    /// What the ray is for.
    pub kind: RayKind,
    /// Film-space end points.
    pub film: [[f64; 2]; 2],
}

/// Every ray of `tree` as a film-space segment: spawn point to hit (or to the light for shadow
/// rays, or a long way out for misses).
#[must_use]
pub fn path_segments(camera: &Camera, tree: &RayTree) -> Vec<PathSegment> {
    tree.nodes
        .iter()
        .filter_map(|n| {
            let end = match (&n.hit, &n.shadow) {
                (Some(h), _) => h.point,
                (None, Some(s)) if s.distance.is_finite() => n.origin + n.direction * s.distance,
                _ => n.origin + n.direction * MISS_LENGTH,
            };
            let film = film_segment(camera, n.spawn_point, end)?;
            Some(PathSegment {
                node: n.id,
                kind: n.kind,
                film,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn a_camera_ray_projects_back_onto_its_film_position() {
        let cam = Scene::default_scene().camera;
        for (fx, fy) in [(0.5, 0.5), (320.0, 180.0), (639.5, 10.25), (100.0, 359.0)] {
            let ray = cam.ray(fx, fy);
            for t in [0.5, 3.0, 40.0] {
                let [px, py] = film_from_world(&cam, ray.at(t)).unwrap();
                assert!(
                    (px - fx).abs() < 1e-9 && (py - fy).abs() < 1e-9,
                    "{px},{py}"
                );
            }
        }
        assert!(film_from_world(&cam, cam.position - cam.forward).is_none());
    }

    #[test]
    fn the_camera_segment_of_a_pixel_collapses_to_that_pixel() {
        let scene = Scene::default_scene();
        let tree = crate::trace_pixel(&scene, 300, 200).unwrap();
        let segs = path_segments(&scene.camera, &tree);
        assert_eq!(segs.len(), tree.nodes.len());
        let cam = segs.iter().find(|s| s.kind == RayKind::Camera).unwrap();
        // Both ends lie on the pixel's camera ray: the near-clipped eye and the hit.
        for p in cam.film {
            assert!((p[0] - 300.5).abs() < 1e-6 && (p[1] - 200.5).abs() < 1e-6);
        }
    }
}
