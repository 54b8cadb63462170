//! The light and camera marks (and their labels) drawn where rays meet lights and the eye.

use super::layout::Pending;
use super::model::{Anchor, CameraMark, LabelRole, LightMark, RayEnd, RaySegment};
use super::segments::{Seg3, fade, is_off};
use super::{objects, plane};
use crate::scene::{LightKind, Scene};
use glam::{DVec2, DVec3};

pub(super) fn light_marks(
    scene: &Scene,
    segs: &[Seg3],
    rays: &[RaySegment],
    frame: &plane::PlaneFrame,
    extent3: f64,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> Vec<LightMark> {
    let mut out: Vec<LightMark> = Vec::new();
    for (s, r) in segs.iter().zip(rays) {
        // A ray entirely outside the view marks nothing.
        if (r.to - r.from).length() < 0.5 {
            continue;
        }
        let Some(LightAt {
            light,
            area,
            name,
            point,
            directional,
            cone,
            dist,
        }) = light_at(scene, s, r, frame)
        else {
            continue;
        };
        if out.iter().any(|m| m.light == light) {
            continue;
        }
        let f = fade(dist, extent3);
        let mut text = name;
        if is_off(dist, extent3) {
            text = format!("{text} ({dist:+.2} off plane)");
        }
        pending.push(Pending::new(
            vec![
                (point + DVec2::new(0.9 * fs, -0.6 * fs), Anchor::Start),
                (point + DVec2::new(-0.9 * fs, -0.6 * fs), Anchor::End),
                (point + DVec2::new(0.0, 1.6 * fs), Anchor::Middle),
            ],
            &text,
            fs,
            LabelRole::Light,
            0,
        ));
        out.push(LightMark {
            light,
            area,
            point,
            directional,
            cone,
            plane_distance: dist,
            fade: f,
        });
    }
    out
}

/// The light a ray meets ([`light_at`]).
struct LightAt {
    /// Its index (`scene.lights.len() + object` for an emissive object).
    light: usize,
    /// An emissive object.
    area: bool,
    name: String,
    /// The mark's canvas point.
    point: DVec2,
    /// A directional light's canvas direction of travel.
    directional: Option<DVec2>,
    /// A spot light's cone edges in the plane ([`cone_edges`]).
    cone: Option<[DVec2; 2]>,
    /// Distance from the plane.
    dist: f64,
}

/// The light a ray meets, if any. Shadow rays meet their light (an area light at its sampled
/// point); a camera, reflected, refracted or bounce ray meets an emissive object it hits on the
/// outer side.
fn light_at(scene: &Scene, s: &Seg3, r: &RaySegment, frame: &plane::PlaneFrame) -> Option<LightAt> {
    let Some(info) = &s.node.shadow else {
        let hit = s.node.hit.as_ref()?;
        let emits = scene.material_of(hit.object).emission.max_element() > 0.0;
        if !(emits && hit.entering) {
            return None;
        }
        return Some(LightAt {
            light: scene.lights.len() + hit.object,
            area: true,
            name: hit.object_name.clone(),
            point: r.to,
            directional: None,
            cone: None,
            dist: frame.distance(hit.point),
        });
    };
    if let Some(a) = &info.area {
        if s.node.end == crate::tree::EndReason::LightBehind {
            return None;
        }
        return Some(LightAt {
            light: info.light,
            area: true,
            name: info.light_name.clone(),
            point: r.to,
            directional: None,
            cone: None,
            dist: frame.distance(a.point),
        });
    }
    let light = scene.lights.get(info.light)?;
    let mut cone = None;
    let (point, directional, dist) = match light.kind {
        LightKind::Point { position, spot, .. } => {
            cone = spot.and_then(|c| cone_edges(frame, &c));
            let p = frame.to_canvas(position);
            // A light outside the frame is marked where its shadow ray leaves it.
            let p = if (p - r.to).length() > 1.0 && r.end == RayEnd::Light {
                r.to
            } else {
                p
            };
            (p, None, frame.distance(position))
        }
        LightKind::Directional { direction, .. } => {
            if !matches!(r.end, RayEnd::Light) {
                return None;
            }
            (r.to, frame.dir_to_canvas(direction).try_normalize(), 0.0)
        }
    };
    Some(LightAt {
        light: info.light,
        area: false,
        name: light.name.clone(),
        point,
        directional,
        cone,
        dist,
    })
}

/// The two lines in which the diagram plane through a spot light cuts its cone, as unit canvas
/// directions; `None` when the plane misses the cone (only the apex in common). With the axis `a` written in the plane's axes, `d(phi) = cos phi u +
/// sin phi v` lies on the cone where `a_u cos phi + a_v sin phi = cos theta_cone`, that is
/// `phi = phi_0 +- acos(cos theta_cone / |a_in_plane|)`.
fn cone_edges(frame: &plane::PlaneFrame, spot: &crate::lights::Spot) -> Option<[DVec2; 2]> {
    let (au, av) = (spot.axis.dot(frame.u), spot.axis.dot(frame.v));
    let r = au.hypot(av);
    let c = spot.cone.cos();
    if r <= 1e-9 || r < c.abs() {
        return None;
    }
    let phi0 = av.atan2(au);
    let half = (c / r).clamp(-1.0, 1.0).acos();
    let edge = |phi: f64| {
        let d = phi.cos() * frame.u + phi.sin() * frame.v;
        frame.dir_to_canvas(d).try_normalize()
    };
    Some([edge(phi0 - half)?, edge(phi0 + half)?])
}

pub(super) fn camera_mark(
    scene: &Scene,
    pixel3: DVec3,
    film: (f64, f64),
    frame: &plane::PlaneFrame,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> CameraMark {
    let cam = &scene.camera;
    let corner = |fx: f64, fy: f64| {
        let (u, v) = cam.film_to_plane(fx, fy);
        cam.position + cam.forward + u * cam.right + v * cam.up
    };
    let (w, h) = (f64::from(cam.width), f64::from(cam.height));
    let image = [
        corner(0.0, 0.0),
        corner(w, 0.0),
        corner(w, h),
        corner(0.0, h),
    ];
    let (px, py) = (film.0.floor(), film.1.floor());
    let pixel = [
        corner(px, py),
        corner(px + 1.0, py),
        corner(px + 1.0, py + 1.0),
        corner(px, py + 1.0),
    ];
    let cut = |q: &[DVec3; 4]| {
        let p = objects::cut_quad(q, frame);
        p.map(|(a, b)| (frame.plane_to_canvas(a), frame.plane_to_canvas(b)))
    };
    let eye = frame.to_canvas(cam.position);
    let p = frame.to_canvas(pixel3);
    pending.push(Pending::new(
        vec![
            (eye + DVec2::new(-0.6 * fs, 1.5 * fs), Anchor::End),
            (eye + DVec2::new(0.0, -0.9 * fs), Anchor::Middle),
            (eye + DVec2::new(0.0, 1.8 * fs), Anchor::Middle),
        ],
        "A (eye)",
        fs,
        LabelRole::Camera,
        0,
    ));
    pending.push(Pending::new(
        vec![
            (p + DVec2::new(0.5 * fs, -0.7 * fs), Anchor::Start),
            (p + DVec2::new(0.5 * fs, 1.4 * fs), Anchor::Start),
            (p + DVec2::new(-0.5 * fs, -0.7 * fs), Anchor::End),
        ],
        "P (pixel centre)",
        fs,
        LabelRole::Camera,
        0,
    ));
    CameraMark {
        eye,
        image_plane: cut(&image),
        pixel: p,
        pixel_span: cut(&pixel),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::{Spot, SpotProfile};

    /// The plane z = 0 (u = x, v = y, canvas y down): a spot pointing down -y with a 30-degree
    /// cone has its edges 30 degrees either side of straight down; tilted 20 degrees out of the
    /// plane the edges close in, exactly where the cone meets the plane; a plane across the
    /// axis (the spot pointing along the normal) cuts no edge.
    #[test]
    fn the_cone_edges_are_where_the_plane_cuts_the_cone() {
        let frame = plane::PlaneFrame::new(DVec3::ZERO, DVec3::Z, DVec3::Y, DVec3::X);
        let spot = |axis: DVec3| Spot {
            axis: axis.normalize(),
            cone: 30f64.to_radians(),
            falloff: 0.0,
            profile: SpotProfile::Smoothstep,
        };
        let s = spot(DVec3::NEG_Y);
        let [a, b] = cone_edges(&frame, &s).unwrap();
        let down = DVec2::new(0.0, 1.0);
        for e in [a, b] {
            assert!(
                (e.dot(down) - 30f64.to_radians().cos()).abs() < 1e-12,
                "{e}"
            );
        }
        assert!((a.x + b.x).abs() < 1e-12 && a.x != 0.0);
        let tilt = 20f64.to_radians();
        let s = spot(DVec3::new(0.0, -tilt.cos(), tilt.sin()));
        for e in cone_edges(&frame, &s).unwrap() {
            let w = DVec3::new(e.x, -e.y, 0.0);
            assert!((w.dot(s.axis) - s.cone.cos()).abs() < 1e-12);
        }
        assert!(cone_edges(&frame, &spot(DVec3::Z)).is_none());
    }
}
