//! From the diagram model to a flat display list of filled/stroked paths and text, shared by
//! the SVG and PNG back-ends (and usable by any painter, e.g. egui).

use super::model::{
    Anchor, Diagram, Fill, Inset, LabelRole, LegendKey, Point, RayEnd, RaySegment, SliceShape,
};
use super::slice::clip_half_plane;
use crate::tree::RayKind;
use glam::DVec2;

/// An sRGB colour with straight alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgba(pub u8, pub u8, pub u8, pub u8);

impl Rgba {
    /// The same colour with alpha multiplied by `f` (clamped to [0, 1]).
    #[must_use]
    pub fn fade(self, f: f64) -> Self {
        Self(
            self.0,
            self.1,
            self.2,
            (f64::from(self.3) * f.clamp(0.0, 1.0)).round() as u8,
        )
    }
}

/// Colour theme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Theme {
    /// Dark on white (slides, print).
    #[default]
    Light,
    /// Light on near-black.
    Dark,
}

/// Colours and the theme they come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Canvas background.
    pub background: Rgba,
    /// Text and outlines.
    pub ink: Rgba,
    /// Normals and secondary lines.
    pub muted: Rgba,
    /// Ray colours in [`RayKind::ALL`] order.
    pub rays: [Rgba; 4],
    /// Diffuse fill.
    pub diffuse: Rgba,
    /// Glass fill (before the absorption tint).
    pub glass: Rgba,
    /// Mirror fill.
    pub mirror: Rgba,
    /// Highlighted node underlay.
    pub highlight: Rgba,
}

impl Style {
    /// The colours of `theme`.
    #[must_use]
    pub fn new(theme: Theme) -> Self {
        match theme {
            Theme::Light => Self {
                background: Rgba(255, 255, 255, 255),
                ink: Rgba(26, 26, 26, 255),
                muted: Rgba(110, 110, 110, 255),
                rays: [
                    Rgba(40, 40, 40, 255),
                    Rgba(214, 39, 40, 255),
                    Rgba(20, 110, 200, 255),
                    Rgba(225, 150, 0, 255),
                ],
                diffuse: Rgba(215, 215, 215, 255),
                glass: Rgba(150, 205, 235, 110),
                mirror: Rgba(225, 228, 232, 255),
                highlight: Rgba(255, 0, 200, 110),
            },
            Theme::Dark => Self {
                background: Rgba(21, 23, 28, 255),
                ink: Rgba(232, 232, 232, 255),
                muted: Rgba(150, 150, 150, 255),
                rays: [
                    Rgba(235, 235, 235, 255),
                    Rgba(255, 107, 107, 255),
                    Rgba(77, 171, 247, 255),
                    Rgba(255, 212, 59, 255),
                ],
                diffuse: Rgba(62, 65, 72, 255),
                glass: Rgba(80, 160, 220, 90),
                mirror: Rgba(80, 84, 92, 255),
                highlight: Rgba(255, 60, 220, 120),
            },
        }
    }

    /// The colour of rays of `kind`.
    #[must_use]
    pub fn ray(&self, kind: RayKind) -> Rgba {
        self.rays[RayKind::ALL.iter().position(|k| *k == kind).unwrap_or(0)]
    }
}

impl Default for Style {
    fn default() -> Self {
        Self::new(Theme::Light)
    }
}

/// One drawing primitive, in canvas pixels.
#[derive(Clone, Debug, PartialEq)]
pub enum Prim {
    /// A filled closed polygon.
    Fill {
        /// Vertices.
        points: Vec<Point>,
        /// Colour.
        color: Rgba,
    },
    /// A stroked polyline.
    Stroke {
        /// Vertices.
        points: Vec<Point>,
        /// Colour.
        color: Rgba,
        /// Width in pixels.
        width: f64,
        /// Dash and gap lengths.
        dash: Option<[f64; 2]>,
        /// Close the polyline.
        closed: bool,
    },
    /// A circle.
    Circle {
        /// Centre.
        center: Point,
        /// Radius.
        radius: f64,
        /// Fill colour.
        fill: Option<Rgba>,
        /// Stroke colour and width.
        stroke: Option<(Rgba, f64)>,
    },
    /// Text on a baseline, with a halo of the background colour for legibility.
    Text {
        /// Baseline anchor point.
        pos: Point,
        /// The text.
        text: String,
        /// Size in pixels per em.
        size: f64,
        /// Colour.
        color: Rgba,
        /// Horizontal anchor.
        anchor: Anchor,
        /// Halo colour.
        halo: Option<Rgba>,
    },
}

fn stroke(points: Vec<Point>, color: Rgba, width: f64, dash: Option<[f64; 2]>) -> Prim {
    Prim::Stroke {
        points,
        color,
        width,
        dash,
        closed: false,
    }
}

/// Clip the line through `p` along `d` to a convex polygon (either orientation).
fn clip_line_convex(poly: &[Point], p: Point, d: Point) -> Option<(Point, Point)> {
    let area: f64 = (0..poly.len())
        .map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()]))
        .sum();
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let e = b - a;
        // Inside is where sign(area) * e x (q - a) >= 0.
        let num = area.signum() * e.perp_dot(p - a);
        let den = area.signum() * e.perp_dot(d);
        if den.abs() < 1e-12 {
            if num < 0.0 {
                return None;
            }
        } else if den > 0.0 {
            t0 = t0.max(-num / den);
        } else {
            t1 = t1.min(-num / den);
        }
    }
    (t0 < t1 && t0.is_finite() && t1.is_finite()).then(|| (p + d * t0, p + d * t1))
}

/// Diagonal hatch lines across a circle or convex polygon.
fn hatch(shape: &SliceShape, spacing: f64) -> Vec<(Point, Point)> {
    let d = DVec2::new(1.0, -1.0).normalize();
    let n = DVec2::new(d.y, -d.x) * -1.0;
    let mut out = Vec::new();
    match shape {
        SliceShape::Circle { center, radius } => {
            let k = (radius / spacing).floor() as i64;
            for i in -k..=k {
                let off = i as f64 * spacing;
                let half = (radius * radius - off * off).max(0.0).sqrt();
                let m = *center + n * off;
                out.push((m - d * half, m + d * half));
            }
        }
        SliceShape::Polygon(p) if p.len() >= 3 => {
            let proj: Vec<f64> = p.iter().map(|q| q.dot(n)).collect();
            let lo = proj.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = proj.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mut s = (lo / spacing).ceil() * spacing;
            while s < hi && out.len() < 4000 {
                if let Some(seg) = clip_line_convex(p, n * s, d) {
                    out.push(seg);
                }
                s += spacing;
            }
        }
        _ => {}
    }
    out
}

fn arrow_head(to: Point, dir: Point, len: f64, color: Rgba) -> Option<Prim> {
    let d = dir.try_normalize()?;
    let n = DVec2::new(-d.y, d.x);
    let base = to - d * len;
    Some(Prim::Fill {
        points: vec![to, base + n * len * 0.38, base - n * len * 0.38],
        color,
    })
}

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
        };
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
        out.push(Prim::Circle {
            center: h.point,
            radius: 3.0 * ws,
            fill: Some(style.ink.fade(h.fade)),
            stroke: None,
        });
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
            None => {
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
        out.push(Prim::Circle {
            center: c.pixel,
            radius: 3.5 * ws,
            fill: Some(style.ink),
            stroke: None,
        });
        out.push(Prim::Circle {
            center: c.eye,
            radius: 0.35 * fs,
            fill: Some(style.ink),
            stroke: None,
        });
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

fn mix(a: Rgba, b: Rgba) -> Rgba {
    let m = |x: u8, y: u8| ((u16::from(x) + u16::from(y)) / 2) as u8;
    Rgba(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2), 255)
}

fn rect_points(min: Point, max: Point) -> Vec<Point> {
    vec![min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)]
}

fn cross(at: Point, s: f64, color: Rgba, width: f64, out: &mut Vec<Prim>) {
    out.push(stroke(
        vec![at + DVec2::new(-s, -s), at + DVec2::new(s, s)],
        color,
        width,
        None,
    ));
    out.push(stroke(
        vec![at + DVec2::new(-s, s), at + DVec2::new(s, -s)],
        color,
        width,
        None,
    ));
}

fn ray_prims(r: &RaySegment, style: &Style, fs: f64, ws: f64, out: &mut Vec<Prim>) {
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

fn inset_prims(i: &Inset, style: &Style, ws: f64, fs: f64, out: &mut Vec<Prim>) {
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
        out.push(Prim::Circle {
            center: *o,
            radius: 3.5 * ws,
            fill: Some(style.ray(*kind)),
            stroke: None,
        });
    }
    out.push(Prim::Circle {
        center: i.hit,
        radius: 4.0 * ws,
        fill: Some(style.ink),
        stroke: None,
    });
    out.push(Prim::Stroke {
        points: rect_points(r.min, r.max),
        color: style.ink,
        width: 1.5 * ws,
        dash: None,
        closed: true,
    });
}
