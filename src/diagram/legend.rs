//! The legend strip at the bottom of a figure: a swatch for each ray kind drawn, the notes
//! (rays left out, the plane, what widths and labels show), flowed into rows.

use super::DiagramOptions;
use super::font::text_width;
use super::layout::{Pending, percent, plural};
use super::model::{Anchor, LabelRole, LegendEntry, LegendKey, Rect};
use super::plane::PlaneFrame;
use super::segments::{Seg3, is_off};
use super::share::Kept;
use crate::tree::RayKind;
use glam::DVec2;

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
