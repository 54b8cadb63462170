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
            dist: frame.distance(a.point),
        });
    }
    let light = scene.lights.get(info.light)?;
    let (point, directional, dist) = match light.kind {
        LightKind::Point { position, .. } => {
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
        dist,
    })
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
