//! Projecting the selected pixel's ray tree onto the image: world points to film coordinates
//! through the scene's pinhole camera, with segments clipped at a near plane.

use crate::scene::Camera;
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};
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
    /// A shadow ray stopped by an opaque blocker: the segment ends at the blocker.
    pub blocked: bool,
}

/// Where node `n`'s ray is drawn to: its hit; for a shadow ray the light, or the first blocker
/// when an opaque one stops it; a long way out for a miss.
#[must_use]
pub fn segment_end(n: &RayNode) -> (DVec3, bool) {
    match (&n.hit, &n.shadow) {
        (Some(h), _) => (h.point, false),
        (None, Some(s)) if n.end == EndReason::Blocked && !s.blockers.is_empty() => {
            (n.origin + n.direction * s.blockers[0].t, true)
        }
        (None, Some(s)) if s.distance.is_finite() => (n.origin + n.direction * s.distance, false),
        _ => (n.origin + n.direction * MISS_LENGTH, false),
    }
}

/// Node `n` as a film-space segment, or `None` when it lies behind the camera.
#[must_use]
pub fn node_segment(camera: &Camera, n: &RayNode) -> Option<PathSegment> {
    let (end, blocked) = segment_end(n);
    let film = film_segment(camera, n.spawn_point, end)?;
    Some(PathSegment {
        node: n.id,
        kind: n.kind,
        film,
        blocked,
    })
}

/// Every ray of `tree` as a film-space segment (see [`node_segment`]).
#[must_use]
pub fn path_segments(camera: &Camera, tree: &RayTree) -> Vec<PathSegment> {
    tree.nodes
        .iter()
        .filter_map(|n| node_segment(camera, n))
        .collect()
}

/// The rays of one sample (the sample whose tree holds `node`, else the first) as segments.
#[must_use]
pub fn sample_segments(camera: &Camera, tree: &RayTree, node: Option<NodeId>) -> Vec<PathSegment> {
    let Some(root) = sample_root(tree, node) else {
        return Vec::new();
    };
    tree.depth_first(root)
        .into_iter()
        .filter_map(|id| node_segment(camera, tree.node(id)))
        .collect()
}

/// The camera ray at the root of `node`'s sample (the first sample's without a node).
#[must_use]
pub fn sample_root(tree: &RayTree, node: Option<NodeId>) -> Option<NodeId> {
    let Some(mut id) = node.filter(|id| id.index() < tree.nodes.len()) else {
        return tree.samples.first().map(|s| s.root);
    };
    while let Some(p) = tree.node(id).parent {
        id = p;
    }
    Some(id)
}

/// The part of film segment `a -> b` inside `[0, w] x [0, h]` (Liang-Barsky), or `None`.
#[must_use]
pub fn clip_to_film(seg: [[f64; 2]; 2], w: f64, h: f64) -> Option<[[f64; 2]; 2]> {
    let [a, b] = seg;
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-d[0], a[0]),
        (d[0], w - a[0]),
        (-d[1], a[1]),
        (d[1], h - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| {
        let at = |t: f64| [a[0] + d[0] * t, a[1] + d[1] * t];
        [at(t0), at(t1)]
    })
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
    fn clipping_keeps_the_part_inside_the_film() {
        let c = |s| clip_to_film(s, 10.0, 5.0);
        assert_eq!(c([[1.0, 1.0], [2.0, 2.0]]), Some([[1.0, 1.0], [2.0, 2.0]]));
        assert_eq!(
            c([[-10.0, 1.0], [20.0, 1.0]]),
            Some([[0.0, 1.0], [10.0, 1.0]])
        );
        assert_eq!(c([[-1.0, -1.0], [-5.0, 3.0]]), None);
        assert_eq!(c([[5.0, 2.0], [5.0, 50.0]]), Some([[5.0, 2.0], [5.0, 5.0]]));
    }

    #[test]
    fn a_blocked_shadow_ray_ends_at_its_blocker() {
        // Pixel 400,200 of the classic scene: shadow #4 from inside the glass ball is blocked
        // by the ball itself.
        let scene = Scene::default_scene();
        let tree = crate::trace_pixel(&scene, 400, 200).unwrap();
        let n = tree
            .nodes
            .iter()
            .find(|n| n.end == EndReason::Blocked)
            .expect("a blocked shadow ray");
        let (end, blocked) = segment_end(n);
        assert!(blocked);
        let s = n.shadow.as_ref().unwrap();
        assert!((end - n.origin).length() < s.distance);
        assert!(((end - n.origin).length() - s.blockers[0].t).abs() < 1e-9);
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
