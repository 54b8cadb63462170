//! The primitives of one ray segment (line, dash, arrow head or end mark) and of one zoomed
//! spawn-point inset.

use super::prim::{arrow_head, cross, dot, rect_points, stroke};
use super::{Prim, Style};
use crate::diagram::model::{Inset, RayEnd, RaySegment};
use crate::diagram::slice::clip_half_plane;
use crate::tree::RayKind;
use glam::DVec2;

pub(super) fn ray_prims(r: &RaySegment, style: &Style, fs: f64, ws: f64, out: &mut Vec<Prim>) {
    let tp = r.throughput.sqrt();
    let width = (1.3 + 2.4 * tp) * ws;
    let color = style.ray(r.kind).fade(r.fade * (0.4 + 0.6 * tp));
    let dash = match (r.kind == RayKind::Shadow, r.off_plane) {
        (false, false) => None,
        (true, false) => Some([8.0 * ws, 5.0 * ws]),
        (false, true) => Some([2.0 * ws, 4.0 * ws]),
        (true, true) => Some([2.0 * ws, 7.0 * ws]),
    };
    let dir = r.to - r.from;
    if r.highlighted {
        out.push(stroke(
            vec![r.from, r.to],
            style.highlight,
            width + 7.0 * ws,
            None,
        ));
    }
    if dir.length() < 0.5 {
        // Perpendicular to the plane: a ring marks where it leaves.
        out.push(Prim::Circle {
            center: r.from,
            radius: 0.3 * fs,
            fill: None,
            stroke: Some((color, 1.5 * ws)),
        });
        return;
    }
    out.push(stroke(vec![r.from, r.to], color, width, dash));
    match r.end {
        RayEnd::Hit | RayEnd::Miss | RayEnd::Light => {
            let len = (0.55 * fs + 2.0 * width).min(dir.length() * 0.6);
            out.extend(arrow_head(r.to, dir, len, color));
        }
        RayEnd::Blocked => cross(
            r.to,
            0.4 * fs,
            style.ray(r.kind).fade(r.fade),
            2.5 * ws,
            out,
        ),
        RayEnd::LightBehind => {
            let n = DVec2::new(-dir.y, dir.x).normalize_or_zero() * 0.3 * fs;
            out.push(stroke(vec![r.to - n, r.to + n], color, 2.0 * ws, None));
        }
    }
}

pub(super) fn inset_prims(i: &Inset, style: &Style, ws: f64, fs: f64, out: &mut Vec<Prim>) {
    let r = i.rect;
    let nearest = i.anchor.clamp(r.min, r.max);
    out.push(stroke(
        vec![i.anchor, nearest],
        style.muted,
        1.0 * ws,
        Some([3.0 * ws, 3.0 * ws]),
    ));
    out.push(Prim::Fill {
        points: rect_points(r.min, r.max),
        color: style.background,
    });
    let nc = (i.hit - i.inside).normalize_or_zero();
    let solid = clip_half_plane(&rect_points(r.min, r.max), nc, -nc.dot(i.hit));
    if solid.len() >= 3 {
        out.push(Prim::Fill {
            points: solid,
            color: style.diffuse,
        });
    }
    out.push(stroke(
        vec![i.surface.0, i.surface.1],
        style.ink,
        2.0 * ws,
        None,
    ));
    for (kind, o, end) in &i.rays {
        if (*o - i.hit).length() > 1.0 {
            out.push(stroke(vec![i.hit, *o], style.highlight, 3.0 * ws, None));
        }
        out.push(stroke(vec![*o, *end], style.ray(*kind), 2.2 * ws, None));
        out.extend(arrow_head(*end, *end - *o, 0.5 * fs, style.ray(*kind)));
        out.push(dot(*o, 3.5 * ws, style.ray(*kind)));
    }
    out.push(dot(i.hit, 4.0 * ws, style.ink));
    out.push(Prim::Stroke {
        points: rect_points(r.min, r.max),
        color: style.ink,
        width: 1.5 * ws,
        dash: None,
        closed: true,
    });
}
