//! From the diagram model to a flat display list of filled/stroked paths and text, shared by
//! the SVG and PNG back-ends (and usable by any painter, e.g. egui).

mod hatch;
mod prim;
mod rays;
mod style;

pub use prim::Prim;
pub use style::{Rgba, Style, Theme};

use super::model::{
    CameraMark, Diagram, Fill, HitMark, Label, LabelRole, LegendKey, LightMark, ObjectSlice,
    RaySegment, SliceShape,
};
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
    let mut p = Painter {
        style,
        fs,
        ws: (fs / 17.0).max(0.7),
        out: Vec::new(),
    };
    p.background(d);
    for o in &d.objects {
        p.object(o);
    }
    if let Some((a, b)) = d.camera.as_ref().and_then(|c| c.image_plane) {
        p.out
            .push(stroke(vec![a, b], style.muted, 2.0 * p.ws, None));
    }
    for h in &d.hits {
        p.normal(h);
    }
    let mut order: Vec<&RaySegment> = d.rays.iter().collect();
    order.sort_by_key(|r| std::cmp::Reverse(r.depth));
    for r in order {
        ray_prims(r, style, p.fs, p.ws, &mut p.out);
    }
    for h in &d.hits {
        p.hit_marks(h);
    }
    for l in &d.lights {
        p.light(l);
    }
    if let Some(c) = &d.camera {
        p.camera(c);
    }
    for i in &d.insets {
        inset_prims(i, style, p.ws, p.fs, &mut p.out);
    }
    p.legend(d);
    for l in &d.labels {
        p.label(l);
    }
    p.out
}

/// What every layer of the display list is drawn with: the style, the legend's font size
/// `fs` (the unit of glyph sizes), the stroke width scale `ws`, and the list so far.
struct Painter<'a> {
    style: &'a Style,
    fs: f64,
    ws: f64,
    out: Vec<Prim>,
}

impl Painter<'_> {
    /// The background: one rectangle over the whole diagram.
    fn background(&mut self, d: &Diagram) {
        self.out.push(Prim::Fill {
            points: vec![
                DVec2::ZERO,
                DVec2::new(d.width, 0.0),
                DVec2::new(d.width, d.height),
                DVec2::new(0.0, d.height),
            ],
            color: self.style.background,
        });
    }

    /// One object's slice: its glow if it is a lamp, its fill and outline, a mirror's hatching
    /// and a plane's visible boundary line.
    fn object(&mut self, o: &ObjectSlice) {
        let (style, ws) = (self.style, self.ws);
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
        let out = &mut self.out;
        if o.fill == Fill::Emitter {
            lamp_glow(&o.shape, style.rays[3].fade(0.35), 9.0 * ws, out);
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

    /// A hit's normal, dashed through the hit point (drawn under the rays).
    fn normal(&mut self, h: &HitMark) {
        if h.normal != DVec2::ZERO {
            let a = h.point - h.normal * h.normal_len;
            let b = h.point + h.normal * h.normal_len;
            self.out.push(stroke(
                vec![a, b],
                self.style.muted.fade(h.fade),
                1.3 * self.ws,
                Some([5.0 * self.ws, 4.0 * self.ws]),
            ));
        }
    }

    /// A hit's marks over the rays: its angle arcs, its dot, a ring for total internal
    /// reflection and a square where the tree was cut.
    fn hit_marks(&mut self, h: &HitMark) {
        let (style, fs, ws) = (self.style, self.fs, self.ws);
        for a in &h.arcs {
            self.out.push(stroke(
                a.points(24),
                style.ink.fade(0.8 * h.fade),
                1.4 * ws,
                None,
            ));
        }
        self.out
            .push(dot(h.point, 3.0 * ws, style.ink.fade(h.fade)));
        if h.tir {
            self.out.push(Prim::Circle {
                center: h.point,
                radius: 0.42 * fs,
                fill: None,
                stroke: Some((style.rays[1].fade(h.fade), 1.6 * ws)),
            });
        }
        if h.truncated {
            let s = 0.35 * fs;
            self.out.push(Prim::Stroke {
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

    /// A light's glyph: a lamp where rays meet an area light, a star (and its cone) for a
    /// point or spot light, an arrow for a directional one.
    fn light(&mut self, l: &LightMark) {
        let c = self.style.rays[3].fade(l.fade);
        match l.directional {
            None if l.area => self.area_lamp(l, c),
            None => self.point_light(l, c),
            Some(dir) => {
                let from = l.point - dir * 2.2 * self.fs;
                self.out
                    .push(stroke(vec![from, l.point], c, 3.0 * self.ws, None));
                self.out.extend(arrow_head(
                    l.point + dir * 0.4 * self.fs,
                    dir,
                    0.9 * self.fs,
                    c,
                ));
            }
        }
    }

    /// Where rays meet a lamp: a small lamp glyph (the lamp itself is drawn where the plane
    /// cuts it).
    fn area_lamp(&mut self, l: &LightMark, c: Rgba) {
        let (fs, ws) = (self.fs, self.ws);
        self.out.push(Prim::Circle {
            center: l.point,
            radius: 0.3 * fs,
            fill: Some(c),
            stroke: Some((self.style.ink.fade(l.fade), 1.0 * ws)),
        });
        for k in 0..4 {
            let a = f64::from(k) * std::f64::consts::FRAC_PI_2 + std::f64::consts::FRAC_PI_4;
            let v = DVec2::new(a.cos(), a.sin());
            self.out.push(stroke(
                vec![l.point + v * 0.4 * fs, l.point + v * 0.7 * fs],
                c,
                1.6 * ws,
                None,
            ));
        }
    }

    /// A point or spot light: a star, and a spot light's cone edges in the plane, dashed.
    fn point_light(&mut self, l: &LightMark, c: Rgba) {
        let (fs, ws) = (self.fs, self.ws);
        for e in l.cone.iter().flatten() {
            self.out.push(stroke(
                vec![l.point + *e * 0.9 * fs, l.point + *e * 10.0 * fs],
                c,
                1.4 * ws,
                Some([0.5 * fs, 0.35 * fs]),
            ));
        }
        for k in 0..8 {
            let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let v = DVec2::new(a.cos(), a.sin());
            self.out.push(stroke(
                vec![l.point + v * 0.55 * fs, l.point + v * 0.9 * fs],
                c,
                2.0 * ws,
                None,
            ));
        }
        self.out.push(Prim::Circle {
            center: l.point,
            radius: 0.42 * fs,
            fill: Some(c),
            stroke: Some((self.style.ink.fade(l.fade), 1.0 * ws)),
        });
    }

    /// The camera: the traced pixel's span on the image plane, the pixel and the eye.
    fn camera(&mut self, c: &CameraMark) {
        let (style, fs, ws) = (self.style, self.fs, self.ws);
        if let Some((a, b)) = c.pixel_span {
            let mid = (a + b) * 0.5;
            let half = ((b - a) * 0.5).try_normalize().unwrap_or(DVec2::X)
                * ((b - a).length() * 0.5).max(0.35 * fs);
            self.out.push(stroke(
                vec![mid - half, mid + half],
                style.rays[1],
                5.0 * ws,
                None,
            ));
        }
        self.out.push(dot(c.pixel, 3.5 * ws, style.ink));
        self.out.push(dot(c.eye, 0.35 * fs, style.ink));
    }

    /// The legend's box and the sample line (or mark) of each entry; its words are labels.
    fn legend(&mut self, d: &Diagram) {
        let (style, fs, ws) = (self.style, self.fs, self.ws);
        let r = d.legend_rect;
        self.out.push(Prim::Fill {
            points: rect_points(r.min, r.max),
            color: style.background.fade(0.94),
        });
        self.out.push(Prim::Stroke {
            points: rect_points(r.min, r.max),
            color: style.muted.fade(0.6),
            width: 1.0,
            dash: None,
            closed: true,
        });
        let out = &mut self.out;
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
                LegendKey::Blocked => {
                    cross(
                        a + DVec2::new(fs, 0.0),
                        0.4 * fs,
                        style.rays[3],
                        2.5 * ws,
                        out,
                    );
                }
                LegendKey::Note => {}
            }
        }
    }

    /// One label's text, tinted by its ray's kind for attenuations and angles.
    fn label(&mut self, l: &Label) {
        let style = self.style;
        let color = match l.role {
            LabelRole::Attenuation | LabelRole::Angle => {
                l.kind.map_or(style.ink, |k| mix(style.ray(k), style.ink))
            }
            _ => style.ink,
        };
        self.out.push(Prim::Text {
            pos: l.pos,
            text: l.text.clone(),
            size: l.size,
            color,
            anchor: l.anchor,
            halo: Some(style.background),
        });
    }
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
