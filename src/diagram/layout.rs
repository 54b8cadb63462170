//! Text layout: greedy collision-free label placement and the legend strip.
//!
//! Labels come with candidate positions and a priority (0 = must show: object names, lights,
//! camera). They are placed in priority order; a label whose every candidate overlaps an
//! already placed label, the legend or an inset is dropped. This keeps deep trees readable.

use super::DiagramOptions;
use super::font::text_width;
use super::model::{Anchor, Label, LabelRole, LegendEntry, LegendKey, Point, Rect};
use super::plane::PlaneFrame;
use super::segments::{Seg3, is_off};
use super::share::Kept;
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

/// What the legend describes: the drawn segments of the chosen sample, their plane, the size of
/// the scene they touch, the plane's description, the note on other samples left out, the
/// kept set and the options.
pub(super) struct LegendSource<'a> {
    pub segs: &'a [Seg3<'a>],
    pub frame: &'a PlaneFrame,
    pub extent3: f64,
    pub plane_text: &'a str,
    pub others_note: Option<&'a str>,
    pub kept: &'a Kept,
    pub opts: &'a DiagramOptions,
}

/// The legend strip: its labels (to place with the others), its entries and its box.
pub(super) struct Legend {
    pub pending: Vec<Pending>,
    pub entries: Vec<LegendEntry>,
    pub rect: Rect,
}

/// One item of the legend: a swatch (or none, for a note) and its text.
struct LegendItem {
    key: LegendKey,
    text: String,
}

impl LegendItem {
    fn note(text: String) -> Self {
        Self {
            key: LegendKey::Note,
            text,
        }
    }
}

/// An item flowed into a row, `x` from the row's start.
struct RowItem {
    key: LegendKey,
    text: String,
    x: f64,
}

/// The legend strip at the bottom of a `w` x `h` canvas with font size `fs`: its labels,
/// swatches and box.
pub(super) fn legend(source: &LegendSource, (w, h, fs): (f64, f64, f64)) -> Legend {
    let mut items = swatch_items(source.segs);
    items.extend(off_plane_item(source.segs, source.frame, source.extent3));
    items.extend(note_items(source));
    let rows = flow_rows(items, w, fs);
    lay_out_rows(rows, w, h, fs)
}

/// A swatch for each ray kind drawn, the normal, and the blocked shadow ray's cross if one is
/// drawn.
fn swatch_items(segs: &[Seg3]) -> Vec<LegendItem> {
    let mut items: Vec<LegendItem> = Vec::new();
    for kind in RayKind::ALL {
        if segs.iter().any(|s| s.node.kind == kind) {
            let text = if kind == RayKind::Shadow {
                "shadow (to light)"
            } else {
                kind.name()
            };
            items.push(LegendItem {
                key: LegendKey::Ray(kind),
                text: text.to_string(),
            });
        }
    }
    items.push(LegendItem {
        key: LegendKey::Normal,
        text: "normal".to_string(),
    });
    if segs
        .iter()
        .any(|s| s.end_kind == super::model::RayEnd::Blocked)
    {
        items.push(LegendItem {
            key: LegendKey::Blocked,
            text: "blocked shadow ray".to_string(),
        });
    }
    items
}

/// How many rays leave the plane (and how far the farthest does), if any do.
fn off_plane_item(segs: &[Seg3], frame: &PlaneFrame, extent3: f64) -> Option<LegendItem> {
    let mut off = 0;
    let mut max_d: f64 = 0.0;
    for s in segs {
        let end = s.end.unwrap_or(s.start + s.node.direction * extent3);
        let d = frame.distance(s.start).abs().max(frame.distance(end).abs());
        if is_off(d, extent3) {
            off += 1;
            max_d = max_d.max(d);
        }
    }
    (off > 0).then(|| LegendItem {
        key: LegendKey::OffPlane,
        text: format!("{off} ray{} leave{} the plane: projected, dotted, fainter with distance (up to {max_d:.2})", plural(off), if off == 1 { "s" } else { "" }),
    })
}

/// The notes: Russian roulette at glass, the rays and samples left out, the plane, and what
/// widths and labels show.
fn note_items(source: &LegendSource) -> Vec<LegendItem> {
    let mut items = Vec::new();
    let rouletted = source
        .segs
        .iter()
        .filter(|s| (s.node.interface.as_ref()).is_some_and(|i| i.roulette.is_some()))
        .count();
    if rouletted > 0 {
        items.push(LegendItem::note(format!(
            "{rouletted} weak glass hit{} followed one ray (Russian roulette, weight / probability).",
            if rouletted == 1 { "" } else { "s" }
        )));
    }
    let kept = source.kept;
    if kept.dropped > 0 {
        items.push(LegendItem::note(format!(
            "{} ray{} under {} of the pixel each left out ({} of it in all).",
            kept.dropped,
            plural(kept.dropped),
            percent(kept.min_share),
            percent(kept.dropped_share)
        )));
    }
    if let Some(note) = source.others_note {
        items.push(LegendItem::note(note.to_string()));
    }
    items.push(LegendItem::note(format!("Plane: {}.", source.plane_text)));
    items.push(LegendItem::note(format!(
        "Width ~ throughput; angles, n, R/T, Beer shown to depth {}.",
        source.opts.label_depth
    )));
    items
}

/// The legend's text size for font size `fs`.
fn legend_text_size(fs: f64) -> f64 {
    fs * 0.9
}

/// The items flowed into rows that fit a `w` wide canvas; a note wider than the strip is
/// broken at spaces into lines that fit.
fn flow_rows(items: Vec<LegendItem>, w: f64, fs: f64) -> Vec<Vec<RowItem>> {
    let size = legend_text_size(fs);
    let swatch = 2.0 * fs;
    let gap = 0.4 * fs;
    let spacing = 1.3 * fs;
    let avail = w - 2.0 * fs;
    let mut rows: Vec<Vec<RowItem>> = vec![Vec::new()];
    let mut x = 0.0;
    let items = items.into_iter().flat_map(|LegendItem { key, text }| {
        let lines = if key == LegendKey::Note && text_width(&text, size) > avail {
            wrap_words(&text, avail, |t| text_width(t, size))
        } else {
            vec![text]
        };
        lines.into_iter().map(move |t| (key.clone(), t))
    });
    for (key, text) in items {
        let lead = if key == LegendKey::Note {
            0.0
        } else {
            swatch + gap
        };
        let iw = lead + text_width(&text, size);
        if x > 0.0 && x + iw > avail {
            rows.push(Vec::new());
            x = 0.0;
        }
        rows.last_mut()
            .expect("one row")
            .push(RowItem { key, text, x });
        x += iw + spacing;
    }
    rows
}

/// The legend's box at the bottom of the `w` x `h` canvas, holding `rows`, and each item's
/// label and entry.
fn lay_out_rows(rows: Vec<Vec<RowItem>>, w: f64, h: f64, fs: f64) -> Legend {
    let size = legend_text_size(fs);
    let swatch = 2.0 * fs;
    let gap = 0.4 * fs;
    let line = 1.45 * fs;
    let height = rows.len() as f64 * line + 0.5 * fs;
    let rect = Rect::new(
        DVec2::new(fs * 0.5, h - fs * 0.4 - height),
        DVec2::new(w - fs * 0.5, h - fs * 0.4),
    );
    let mut pending = Vec::new();
    let mut entries = Vec::new();
    for (r, row) in rows.into_iter().enumerate() {
        let baseline = rect.min.y + 0.25 * fs + (r as f64 + 1.0) * line - 0.45 * fs;
        for RowItem { key, text, x } in row {
            let x0 = fs + x;
            let tx = if key == LegendKey::Note {
                x0
            } else {
                x0 + swatch + gap
            };
            pending.push(Pending::fixed(
                DVec2::new(tx, baseline),
                Anchor::Start,
                &text,
                size,
                LabelRole::Legend,
            ));
            entries.push(LegendEntry {
                key,
                pos: DVec2::new(x0, baseline - 0.3 * size),
                text,
            });
        }
    }
    Legend {
        pending,
        entries,
        rect,
    }
}

/// `text` broken at spaces into lines no wider than `avail` by `width` (a word wider than
/// `avail` keeps a line of its own).
fn wrap_words(text: &str, avail: f64, width: impl Fn(&str) -> f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if !line.is_empty() && width(&candidate) > avail {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    lines.push(line);
    lines
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

#[cfg(test)]
mod tests {
    use super::wrap_words;

    #[test]
    fn a_long_note_breaks_at_spaces_into_lines_that_fit() {
        let width = |t: &str| t.chars().count() as f64;
        let text = "Plane: through the connection ray #6 and its parent #0, chosen over the plane";
        let lines = wrap_words(text, 20.0, width);
        assert!(lines.len() > 3, "{lines:?}");
        assert!(lines.iter().all(|l| width(l) <= 20.0), "{lines:?}");
        assert_eq!(lines.join(" "), text);
        let long = wrap_words("a incomprehensibilities b", 5.0, width);
        assert_eq!(long, ["a", "incomprehensibilities", "b"]);
        assert_eq!(wrap_words("short", 20.0, width), ["short"]);
    }
}
