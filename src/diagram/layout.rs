//! Text layout: greedy collision-free label placement (the legend strip is in `legend`).
//!
//! Labels come with candidate positions and a priority (0 = must show: object names, lights,
//! camera). They are placed in priority order; a label whose every candidate overlaps an
//! already placed label, the legend or an inset is dropped. This keeps deep trees readable.

use super::font::text_width;
use super::model::{Anchor, Label, LabelRole, Point, Rect};
use crate::tree::{NodeId, RayKind};
use glam::DVec2;

/// How far a label that belongs to a vertex or a segment may lie from it: the distance from
/// its box's nearest point, in font sizes (issue 32: "θi = 64.5°" of the camera ray's floor
/// hit drifted three font sizes away, into the ball beside another ray).
pub const OWNER_REACH: f64 = 2.5;

/// What a label is about, in canvas pixels: it is placed within [`OWNER_REACH`] of it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Owner {
    /// A hit: angles, n1/n2, R/T.
    Vertex(Point),
    /// A ray's drawn segment: Beer factors, shadow outcomes.
    Segment(Point, Point),
}

impl Owner {
    /// Distance from the owner to box `b` (0 when they touch).
    fn distance(&self, b: &Rect) -> f64 {
        match *self {
            Owner::Vertex(v) => rect_distance(b, v),
            Owner::Segment(a, c) => {
                if crosses(b, a, c) {
                    return 0.0;
                }
                // The nearest point is a corner of the box or an end of the segment.
                let corners = [
                    b.min,
                    b.max,
                    DVec2::new(b.min.x, b.max.y),
                    DVec2::new(b.max.x, b.min.y),
                ];
                let to_seg = |p: Point| {
                    let d = c - a;
                    let t = if d.length_squared() > 0.0 {
                        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    (a + d * t - p).length()
                };
                corners
                    .into_iter()
                    .map(to_seg)
                    .chain([rect_distance(b, a), rect_distance(b, c)])
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// The point spots are generated around: the vertex, or the segment's middle.
    fn centre(&self) -> Point {
        match *self {
            Owner::Vertex(v) => v,
            Owner::Segment(a, c) => (a + c) * 0.5,
        }
    }
}

/// Distance from point `p` to box `b` (0 inside).
fn rect_distance(b: &Rect, p: Point) -> f64 {
    (b.min - p).max(p - b.max).max(DVec2::ZERO).length()
}

/// A label waiting for a position.
#[derive(Clone, Debug)]
pub(super) struct Pending {
    cands: Vec<(Point, Anchor)>,
    text: String,
    size: f64,
    role: LabelRole,
    priority: u32,
    fixed: bool,
    node: Option<NodeId>,
    kind: Option<RayKind>,
    owner: Option<Owner>,
}

impl Pending {
    /// A label with candidate positions, tried in order.
    pub fn new(
        cands: Vec<(Point, Anchor)>,
        text: &str,
        size: f64,
        role: LabelRole,
        priority: u32,
    ) -> Self {
        Self {
            cands,
            text: text.to_string(),
            size,
            role,
            priority,
            fixed: false,
            node: None,
            kind: None,
            owner: None,
        }
    }

    /// A label placed exactly at `pos` whatever it overlaps.
    pub fn fixed(pos: Point, anchor: Anchor, text: &str, size: f64, role: LabelRole) -> Self {
        Self {
            fixed: true,
            ..Self::new(vec![(pos, anchor)], text, size, role, 0)
        }
    }

    /// Attach the ray node and its kind.
    pub fn for_node(mut self, node: NodeId, kind: RayKind) -> Self {
        self.node = Some(node);
        self.kind = Some(kind);
        self
    }

    /// Keep the label within [`OWNER_REACH`] of what it is about.
    pub fn owned_by(mut self, owner: Owner) -> Self {
        self.owner = Some(owner);
        self
    }
}

/// Spots hugging `owner`'s centre: 16 directions at three gaps, each a baseline position for
/// a centred label of `text` whose box lies `gap` beyond the centre along that direction; with
/// its preference (0 = the direction `towards`, the nearest gap), for the cost.
fn hugging(owner: &Owner, towards: Point, text: &str, size: f64) -> Vec<(Point, f64)> {
    let c = owner.centre();
    let half = DVec2::new(text_width(text, size) * 0.5 + size * 0.12, size * 0.63);
    let want = (towards - c)
        .try_normalize()
        .unwrap_or(DVec2::new(0.0, -1.0));
    let mut out = Vec::new();
    for (g, gap) in [0.4, 1.0, 1.8].into_iter().enumerate() {
        for k in 0..16 {
            let a = f64::from(k) * std::f64::consts::TAU / 16.0;
            let u = DVec2::new(a.cos(), a.sin());
            let reach = gap * size + u.x.abs() * half.x + u.y.abs() * half.y;
            // Baseline = box centre + 0.27 size (see `label_box`).
            let pos = c + u * reach + DVec2::new(0.0, 0.27 * size);
            let turn = u.dot(want).clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
            out.push((pos, 0.25 * g as f64 + 0.5 * turn));
        }
    }
    out
}

/// The box a label occupies.
#[must_use]
pub fn label_box(pos: Point, anchor: Anchor, text: &str, size: f64) -> Rect {
    let w = text_width(text, size);
    let x0 = match anchor {
        Anchor::Start => pos.x,
        Anchor::Middle => pos.x - w * 0.5,
        Anchor::End => pos.x - w,
    };
    let pad = size * 0.12;
    Rect::new(
        DVec2::new(x0 - pad, pos.y - size * 0.78 - pad),
        DVec2::new(x0 + w + pad, pos.y + size * 0.24 + pad),
    )
}

/// Whether segment `a`-`b` crosses rectangle `r` (Liang-Barsky).
fn crosses(r: &Rect, a: Point, b: Point) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - r.min.x),
        (d.x, r.max.x - a.x),
        (-d.y, a.y - r.min.y),
        (d.y, r.max.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    t0 <= t1
}

/// More spots around a label's first one, nearest first: used when the given spots are taken
/// or lie on rays.
fn ring(pos: Point, size: f64) -> Vec<Point> {
    let mut out = Vec::new();
    for step in [1.0, 2.0] {
        for (dx, dy) in [
            (0.0, -1.1),
            (0.0, 1.1),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, -1.1),
            (-1.0, -1.1),
            (1.0, 1.1),
            (-1.0, 1.1),
        ] {
            out.push(pos + DVec2::new(dx * 1.5, dy) * size * step);
        }
    }
    out
}

/// Place labels in priority order, avoiding each other and `obstacles`, inside `canvas`, and
/// preferring spots that cross none of `lines` (the rays). Each label tries its own spots
/// first, then a ring of spots around the first one; a label with no free spot is dropped,
/// except must-show ones (priority 0), which take their first spot.
pub(super) fn place(
    mut pending: Vec<Pending>,
    canvas: Rect,
    obstacles: Vec<Rect>,
    lines: &[(Point, Point)],
) -> Vec<Label> {
    pending.sort_by_key(|p| (!p.fixed, p.priority));
    let mut taken: Vec<Rect> = Vec::new();
    let mut out = Vec::new();
    for p in pending {
        let (cands, prefs) = candidates(&p);
        let boxes: Vec<Rect> = cands
            .iter()
            .map(|(pos, a)| label_box(*pos, *a, &p.text, p.size))
            .collect();
        let near = |b: &Rect| {
            p.owner
                .is_none_or(|o| o.distance(b) <= OWNER_REACH * p.size)
        };
        let free = |b: &Rect| {
            canvas.contains_rect(b)
                && near(b)
                && !taken.iter().chain(&obstacles).any(|t| t.overlaps(b))
        };
        let cost = |i: usize, b: &Rect| {
            let hits = lines.iter().filter(|(a, c)| crosses(b, *a, *c)).count();
            hits as f64 * 2.5 + prefs[i] + i as f64 * 1e-3
        };
        let chosen = if p.fixed {
            Some(0)
        } else {
            boxes
                .iter()
                .enumerate()
                .filter(|(_, b)| free(b))
                .map(|(i, b)| (cost(i, b), i))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, i)| i)
                .or((p.priority == 0).then_some(0))
        };
        let Some(i) = chosen else { continue };
        let (mut pos, anchor) = cands[i];
        let mut b = boxes[i];
        if !p.fixed {
            // Keep must-show labels inside the canvas.
            let shift = DVec2::new(
                (canvas.min.x - b.min.x).max(0.0) + (canvas.max.x - b.max.x).min(0.0),
                (canvas.min.y - b.min.y).max(0.0) + (canvas.max.y - b.max.y).min(0.0),
            );
            pos += shift;
            b = Rect::new(b.min + shift, b.max + shift);
        }
        taken.push(b);
        out.push(Label {
            pos,
            text: p.text,
            size: p.size,
            anchor,
            role: p.role,
            node: p.node,
            kind: p.kind,
        });
    }
    out
}

/// A label's spots and the preference of each (0 best): its own spots; then, for a label
/// that belongs to a vertex or a segment, spots hugging it (nearest the first own spot's
/// direction first), else a ring around its first spot.
fn candidates(p: &Pending) -> (Vec<(Point, Anchor)>, Vec<f64>) {
    let mut cands = p.cands.clone();
    let mut prefs = vec![0.0; cands.len()];
    if p.fixed {
        return (cands, prefs);
    }
    let Some(&(first, anchor)) = p.cands.first() else {
        return (cands, prefs);
    };
    match &p.owner {
        Some(o) => {
            for (pos, pref) in hugging(o, first, &p.text, p.size) {
                cands.push((pos, Anchor::Middle));
                prefs.push(0.5 + pref);
            }
        }
        None => {
            for (k, q) in ring(first, p.size).into_iter().enumerate() {
                cands.push((q, anchor));
                prefs.push(1.0 + (k / 8) as f64);
            }
        }
    }
    (cands, prefs)
}

/// `"s"` for a count other than 1 (`"1 ray"`, `"2 rays"`, `"0 rays"`).
#[must_use]
pub fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// A fraction as a percentage with as many decimals as it needs (at least two significant
/// digits below 1 %).
#[must_use]
pub fn percent(f: f64) -> String {
    let p = 100.0 * f;
    if p == 0.0 || !p.is_finite() || p >= 10.0 {
        return format!("{p:.0}%");
    }
    let digits = (1.0 - p.log10().floor()).clamp(1.0, 6.0) as usize;
    let s = format!("{p:.digits$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    format!("{s}%")
}
