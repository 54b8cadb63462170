//! Rays as 3D segments, their projection onto the canvas (clipped to the view), and how far
//! off the plane a segment runs.

use super::DiagramOptions;
use super::model::{Point, RayEnd, RaySegment, Rect};
use super::plane;
use crate::scene::{LightKind, Scene};
use crate::tree::{EndReason, RayKind, RayNode};
use glam::{DVec2, DVec3};

/// A ray as a 3D segment before projection.
pub(super) struct Seg3<'a> {
    pub node: &'a RayNode,
    pub start: DVec3,
    /// Finite end point, `None` for rays that leave the scene.
    pub end: Option<DVec3>,
    pub end_kind: RayEnd,
}

pub(super) fn seg3<'a>(scene: &Scene, n: &'a RayNode) -> Seg3<'a> {
    let start = if n.kind == RayKind::Camera {
        n.origin
    } else {
        n.spawn_point
    };
    let (end, end_kind) = match (&n.shadow, &n.hit) {
        (Some(s), _) => match n.end {
            EndReason::LightBehind => (None, RayEnd::LightBehind),
            EndReason::Blocked => {
                let b = s
                    .blockers
                    .iter()
                    .find(|b| b.factor == DVec3::ZERO)
                    .or(s.blockers.first());
                let t = b.map_or(0.0, |b| b.t);
                (Some(n.origin + t * n.direction), RayEnd::Blocked)
            }
            // An area light's shadow ray ends on the lamp, at its sampled point.
            _ => match (&s.area, scene.lights.get(s.light).map(|l| &l.kind)) {
                (Some(a), _) => (Some(a.point), RayEnd::Light),
                (None, Some(LightKind::Point { position, .. })) => (Some(*position), RayEnd::Light),
                _ => (None, RayEnd::Light),
            },
        },
        (None, Some(h)) => (Some(h.point), RayEnd::Hit),
        (None, None) => (None, RayEnd::Miss),
    };
    Seg3 {
        node: n,
        start,
        end,
        end_kind,
    }
}

/// The ray parameter where the canvas ray `from + t * dir` leaves `rect` (`t >= 0`).
pub(super) fn exit_param(from: Point, dir: Point, rect: &Rect) -> f64 {
    let mut t = f64::INFINITY;
    for (p, d, lo, hi) in [
        (from.x, dir.x, rect.min.x, rect.max.x),
        (from.y, dir.y, rect.min.y, rect.max.y),
    ] {
        if d > 0.0 {
            t = t.min((hi - p) / d);
        } else if d < 0.0 {
            t = t.min((lo - p) / d);
        }
    }
    if t.is_finite() { t.max(0.0) } else { 0.0 }
}

/// Whether a 3D distance from the plane counts as "off the plane": more than 1/1000 of the
/// figure's extent (about a pixel at 1280 wide), so rounding and near-planar bounces stay solid.
pub(super) fn is_off(d: f64, extent3: f64) -> bool {
    d.abs() > 1e-3 * extent3
}

/// Opacity for a distance from the plane: 1 on it, fading to 0.3.
pub(super) fn fade(d: f64, extent3: f64) -> f64 {
    if is_off(d, extent3) {
        (0.85 - 1.5 * d.abs() / extent3).max(0.3)
    } else {
        1.0
    }
}

pub(super) fn project(
    s: &Seg3,
    frame: &plane::PlaneFrame,
    view: &Rect,
    extent3: f64,
    fs: f64,
    opts: &DiagramOptions,
) -> RaySegment {
    let n = s.node;
    let from = frame.to_canvas(s.start);
    let dc = frame.dir_to_canvas(n.direction) * frame.scale;
    let (to, end3) = match s.end {
        Some(e) => (frame.to_canvas(e), e),
        None if s.end_kind == RayEnd::LightBehind => {
            let d = dc.try_normalize().unwrap_or(DVec2::ZERO) * 1.5 * fs;
            (from + d, s.start + n.direction * (1.5 * fs / frame.scale))
        }
        None => {
            if dc.length() * 1e6 < frame.scale {
                (from, s.start)
            } else {
                let t = exit_param(from, dc, view);
                (from + t * dc, s.start + t * n.direction)
            }
        }
    };
    let d = [frame.distance(s.start), frame.distance(end3)];
    let far = if d[0].abs() > d[1].abs() { d[0] } else { d[1] };
    let throughput = if n.kind == RayKind::Shadow {
        // Shadow rays carry the throughput of the surface they leave.
        n.parent.map_or(1.0, |_| n.throughput.max_element())
    } else {
        n.throughput.max_element()
    };
    RaySegment {
        node: n.id,
        kind: n.kind,
        depth: n.depth,
        from,
        to,
        end: s.end_kind,
        throughput: throughput.clamp(0.0, 1.0),
        plane_distance: d,
        off_plane: is_off(far, extent3),
        fade: fade(far, extent3),
        tir: false,
        highlighted: opts.highlight == Some(n.id),
    }
}

/// Clip a segment to `rect` (Liang-Barsky); a segment entirely outside keeps zero length at
/// its start so it still appears once in the model.
pub(super) fn clip_to(r: &mut RaySegment, rect: &Rect) {
    let d = r.to - r.from;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, r.from.x - rect.min.x),
        (d.x, rect.max.x - r.from.x),
        (-d.y, r.from.y - rect.min.y),
        (d.y, rect.max.y - r.from.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                t1 = -1.0;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    if t0 > t1 {
        r.to = r.from;
        return;
    }
    let from = r.from + d * t0;
    r.to = r.from + d * t1;
    r.from = from;
}
