//! From the diagram model to a flat display list of filled/stroked paths and text, shared by
//! the SVG and PNG back-ends (and usable by any painter, e.g. egui).

mod hatch;
mod prim;
mod rays;
mod style;

pub use prim::Prim;
pub use style::{Rgba, Style, Theme};

use super::model::{Diagram, Fill, LabelRole, LegendKey, RaySegment, SliceShape};
use crate::tree::RayKind;
use glam::DVec2;
use hatch::hatch;
use prim::{arrow_head, cross, dot, rect_points, stroke};
use rays::{inset_prims, ray_prims};
use style::mix;

/// The display list of `d` in `style`: back to front.
#[must_use]
pub fn display_list(d: &Diagram, style: &Style) -> Vec<Prim> {
    let fs = d
        .labels
        .iter()
        .find(|l| l.role == LabelRole::Legend)
        .map_or(17.0, |l| l.size / 0.9);
    let ws = (fs / 17.0).max(0.7);
    let mut out = vec![Prim::Fill {
        points: vec![
            DVec2::ZERO,
            DVec2::new(d.width, 0.0),
            DVec2::new(d.width, d.height),
            DVec2::new(0.0, d.height),
        ],
        color: style.background,
    }];
    for o in &d.objects {
        let (fill, outline) = match o.fill {
            Fill::Glass { tint, .. } | Fill::Absorbing { tint } => {
                let g = style.glass;
                let t = |c: u8, k: f64| ((f64::from(c)) * k.clamp(0.25, 1.0)) as u8;
                (
                    Rgba(t(g.0, tint[0]), t(g.1, tint[1]), t(g.2, tint[2]), g.3),
                    style.rays[2].fade(0.8),
                )
            }
            Fill::Mirror => (style.mirror, style.ink),
            Fill::Diffuse => (style.diffuse, style.muted),
            Fill::Emitter => (style.rays[3].fade(0.85), style.rays[3]),
        };
        if o.fill == Fill::Emitter {
            lamp_glow(&o.shape, style.rays[3].fade(0.35), 9.0 * ws, &mut out);
        }
        match &o.shape {
            SliceShape::Circle { center, radius } => out.push(Prim::Circle {
                center: *center,
                radius: *radius,
                fill: Some(fill),
                stroke: Some((outline, 1.6 * ws)),
            }),
            SliceShape::Polygon(p) => {
                out.push(Prim::Fill {
                    points: p.clone(),
                    color: fill,
                });
                if o.edge.is_none() {
                    out.push(Prim::Stroke {
                        points: p.clone(),
                        color: outline,
                        width: 1.6 * ws,
                        dash: None,
                        closed: true,
                    });
                }
            }
            SliceShape::Segment(a, b) => out.push(stroke(vec![*a, *b], outline, 4.0 * ws, None)),
            SliceShape::Segments(s) => {
                for (a, b) in s {
                    out.push(stroke(vec![*a, *b], outline, 2.0 * ws, None));
                }
            }
        }
        if o.fill == Fill::Mirror {
            for (a, b) in hatch(&o.shape, 9.0 * ws) {
                out.push(stroke(vec![a, b], style.muted.fade(0.7), 1.0 * ws, None));
            }
        }
        if let Some((a, b)) = o.edge {
            out.push(stroke(vec![a, b], outline, 2.0 * ws, None));
        }
    }
    if let Some((a, b)) = d.camera.as_ref().and_then(|c| c.image_plane) {
        out.push(stroke(vec![a, b], style.muted, 2.0 * ws, None));
    }
    for h in &d.hits {
        if h.normal != DVec2::ZERO {
            let a = h.point - h.normal * h.normal_len;
            let b = h.point + h.normal * h.normal_len;
            out.push(stroke(
                vec![a, b],
                style.muted.fade(h.fade),
                1.3 * ws,
                Some([5.0 * ws, 4.0 * ws]),
            ));
        }
    }
    let mut order: Vec<&RaySegment> = d.rays.iter().collect();
    order.sort_by_key(|r| std::cmp::Reverse(r.depth));
    for r in order {
        ray_prims(r, style, fs, ws, &mut out);
    }
    for h in &d.hits {
        for a in &h.arcs {
            out.push(stroke(
                a.points(24),
                style.ink.fade(0.8 * h.fade),
                1.4 * ws,
                None,
            ));
        }
        out.push(dot(h.point, 3.0 * ws, style.ink.fade(h.fade)));
        if h.tir {
            out.push(Prim::Circle {
                center: h.point,
                radius: 0.42 * fs,
                fill: None,
                stroke: Some((style.rays[1].fade(h.fade), 1.6 * ws)),
            });
        }
        if h.truncated {
            let s = 0.35 * fs;
            out.push(Prim::Stroke {
                points: vec![
                    h.point + DVec2::new(-s, -s),
                    h.point + DVec2::new(s, -s),
                    h.point + DVec2::new(s, s),
                    h.point + DVec2::new(-s, s),
                ],
                color: style.muted,
                width: 1.5 * ws,
                dash: None,
                closed: true,
            });
        }
    }
    for l in &d.lights {
        let c = style.rays[3].fade(l.fade);
        match l.directional {
            None if l.area => {
                // Where rays meet a lamp: a small lamp glyph (the lamp itself is drawn where
                // the plane cuts it).
                out.push(Prim::Circle {
                    center: l.point,
                    radius: 0.3 * fs,
                    fill: Some(c),
                    stroke: Some((style.ink.fade(l.fade), 1.0 * ws)),
                });
                for k in 0..4 {
                    let a =
                        f64::from(k) * std::f64::consts::FRAC_PI_2 + std::f64::consts::FRAC_PI_4;
                    let v = DVec2::new(a.cos(), a.sin());
                    out.push(stroke(
                        vec![l.point + v * 0.4 * fs, l.point + v * 0.7 * fs],
                        c,
                        1.6 * ws,
                        None,
                    ));
                }
            }
            None => {
                // A spot light: its cone's edges in the plane, dashed.
                for e in l.cone.iter().flatten() {
                    out.push(stroke(
                        vec![l.point + *e * 0.9 * fs, l.point + *e * 10.0 * fs],
                        c,
                        1.4 * ws,
                        Some([0.5 * fs, 0.35 * fs]),
                    ));
                }
                for k in 0..8 {
                    let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
                    let v = DVec2::new(a.cos(), a.sin());
                    out.push(stroke(
                        vec![l.point + v * 0.55 * fs, l.point + v * 0.9 * fs],
                        c,
                        2.0 * ws,
                        None,
                    ));
                }
                out.push(Prim::Circle {
                    center: l.point,
                    radius: 0.42 * fs,
                    fill: Some(c),
                    stroke: Some((style.ink.fade(l.fade), 1.0 * ws)),
                });
            }
            Some(dir) => {
                let from = l.point - dir * 2.2 * fs;
                out.push(stroke(vec![from, l.point], c, 3.0 * ws, None));
                out.extend(arrow_head(l.point + dir * 0.4 * fs, dir, 0.9 * fs, c));
            }
        }
    }
    if let Some(c) = &d.camera {
        if let Some((a, b)) = c.pixel_span {
            let mid = (a + b) * 0.5;
            let half = ((b - a) * 0.5).try_normalize().unwrap_or(DVec2::X)
                * ((b - a).length() * 0.5).max(0.35 * fs);
            out.push(stroke(
                vec![mid - half, mid + half],
                style.rays[1],
                5.0 * ws,
                None,
            ));
        }
        out.push(dot(c.pixel, 3.5 * ws, style.ink));
        out.push(dot(c.eye, 0.35 * fs, style.ink));
    }
    for i in &d.insets {
        inset_prims(i, style, ws, fs, &mut out);
    }
    let r = d.legend_rect;
    out.push(Prim::Fill {
        points: rect_points(r.min, r.max),
        color: style.background.fade(0.94),
    });
    out.push(Prim::Stroke {
        points: rect_points(r.min, r.max),
        color: style.muted.fade(0.6),
        width: 1.0,
        dash: None,
        closed: true,
    });
    for e in &d.legend {
        let (a, b) = (e.pos, e.pos + DVec2::new(2.0 * fs, 0.0));
        match e.key {
            LegendKey::Ray(kind) => {
                let dash = (kind == RayKind::Shadow).then_some([8.0 * ws, 5.0 * ws]);
                out.push(stroke(vec![a, b], style.ray(kind), 2.6 * ws, dash));
                out.extend(arrow_head(b, b - a, 0.6 * fs, style.ray(kind)));
            }
            LegendKey::OffPlane => out.push(stroke(
                vec![a, b],
                style.rays[1].fade(0.5),
                2.6 * ws,
                Some([2.0 * ws, 4.0 * ws]),
            )),
            LegendKey::Normal => out.push(stroke(
                vec![a, b],
                style.muted,
                1.3 * ws,
                Some([5.0 * ws, 4.0 * ws]),
            )),
            LegendKey::Blocked => cross(
                a + DVec2::new(fs, 0.0),
                0.4 * fs,
                style.rays[3],
                2.5 * ws,
                &mut out,
            ),
            LegendKey::Note => {}
        }
    }
    for l in &d.labels {
        let color = match l.role {
            LabelRole::Attenuation | LabelRole::Angle => {
                l.kind.map_or(style.ink, |k| mix(style.ray(k), style.ink))
            }
            _ => style.ink,
        };
        out.push(Prim::Text {
            pos: l.pos,
            text: l.text.clone(),
            size: l.size,
            color,
            anchor: l.anchor,
            halo: Some(style.background),
        });
    }
    out
}

/// A wide translucent stroke around a lamp's slice: its glow.
fn lamp_glow(shape: &SliceShape, color: Rgba, width: f64, out: &mut Vec<Prim>) {
    match shape {
        SliceShape::Circle { center, radius } => out.push(Prim::Circle {
            center: *center,
            radius: *radius + 0.5 * width,
            fill: None,
            stroke: Some((color, width)),
        }),
        SliceShape::Polygon(p) => out.push(Prim::Stroke {
            points: p.clone(),
            color,
            width,
            dash: None,
            closed: true,
        }),
        SliceShape::Segment(a, b) => out.push(stroke(vec![*a, *b], color, 2.0 * width, None)),
        SliceShape::Segments(s) => {
            for (a, b) in s {
                out.push(stroke(vec![*a, *b], color, 2.0 * width, None));
            }
        }
    }
}
