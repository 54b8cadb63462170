//! The embedded label font (egui's default proportional face, Ubuntu Light, from
//! `epaint_default_fonts`, so nothing is committed and the GUI measures text the same way):
//! advance widths for layout and glyph outlines for the PNG back-end.

use ab_glyph::{Font, FontRef, GlyphId, OutlineCurve};
use std::collections::HashMap;
use std::sync::{Arc, LazyLock, Mutex};

/// The font's bytes.
pub const FONT_BYTES: &[u8] = epaint_default_fonts::UBUNTU_LIGHT;

/// The family name to ask for in SVG (with fallbacks).
pub const SVG_FONT_FAMILY: &str = "Ubuntu, 'DejaVu Sans', 'Helvetica Neue', Arial, sans-serif";

static FONT: LazyLock<FontRef<'static>> =
    LazyLock::new(|| FontRef::try_from_slice(FONT_BYTES).expect("the embedded font parses"));

fn units_per_em() -> f64 {
    f64::from(FONT.units_per_em().unwrap_or(1000.0))
}

/// Glyph outlines, parsed once per glyph.
fn outline(id: GlyphId) -> Option<std::sync::Arc<ab_glyph::Outline>> {
    static CACHE: LazyLock<Mutex<HashMap<GlyphId, Option<Arc<ab_glyph::Outline>>>>> =
        LazyLock::new(|| Mutex::new(HashMap::new()));
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    cache
        .entry(id)
        .or_insert_with(|| FONT.outline(id).map(Arc::new))
        .clone()
}

/// Glyph ids of `text` with their x offsets in font units, and the total advance.
fn layout(text: &str) -> (Vec<(GlyphId, f64)>, f64) {
    let mut x = 0.0;
    let mut prev: Option<GlyphId> = None;
    let mut out = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = FONT.glyph_id(c);
        if let Some(p) = prev {
            x += f64::from(FONT.kern_unscaled(p, id));
        }
        out.push((id, x));
        x += f64::from(FONT.h_advance_unscaled(id));
        prev = Some(id);
    }
    (out, x)
}

/// Width of `text` at font size `size` (pixels per em).
#[must_use]
pub fn text_width(text: &str, size: f64) -> f64 {
    layout(text).1 * size / units_per_em()
}

/// One outline command in pixels, relative to the baseline start, y down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathCmd {
    /// Start a contour.
    MoveTo(f32, f32),
    /// Straight line.
    LineTo(f32, f32),
    /// Quadratic curve (control, end).
    QuadTo(f32, f32, f32, f32),
    /// Cubic curve (control 1, control 2, end).
    CubicTo(f32, f32, f32, f32, f32, f32),
    /// Close the contour.
    Close,
}

/// The outlines of `text` at `size`, starting at x = 0 on the baseline y = 0.
#[must_use]
pub fn text_outline(text: &str, size: f64) -> Vec<PathCmd> {
    let k = (size / units_per_em()) as f32;
    let (glyphs, _) = layout(text);
    let mut cmds = Vec::new();
    for (id, x0) in glyphs {
        let Some(outline) = outline(id) else {
            continue;
        };
        let x0 = x0 as f32;
        let p = |pt: ab_glyph::Point| ((x0 + pt.x) * k, -pt.y * k);
        let mut last: Option<(f32, f32)> = None;
        for curve in &outline.curves {
            let (start, end) = match *curve {
                OutlineCurve::Line(a, b) => (a, b),
                OutlineCurve::Quad(a, _, c) => (a, c),
                OutlineCurve::Cubic(a, _, _, d) => (a, d),
            };
            let s = p(start);
            if last != Some(s) {
                if last.is_some() {
                    cmds.push(PathCmd::Close);
                }
                cmds.push(PathCmd::MoveTo(s.0, s.1));
            }
            match *curve {
                OutlineCurve::Line(_, b) => {
                    let b = p(b);
                    cmds.push(PathCmd::LineTo(b.0, b.1));
                }
                OutlineCurve::Quad(_, b, c) => {
                    let (b, c) = (p(b), p(c));
                    cmds.push(PathCmd::QuadTo(b.0, b.1, c.0, c.1));
                }
                OutlineCurve::Cubic(_, b, c, d) => {
                    let (b, c, d) = (p(b), p(c), p(d));
                    cmds.push(PathCmd::CubicTo(b.0, b.1, c.0, c.1, d.0, d.1));
                }
            }
            last = Some(p(end));
        }
        if last.is_some() {
            cmds.push(PathCmd::Close);
        }
    }
    cmds
}

/// A glyph's anti-aliased coverage at one size and sub-pixel phase.
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphMask {
    /// Left edge relative to the pen position (pixels).
    pub left: i32,
    /// Top edge relative to the baseline (pixels, y down).
    pub top: i32,
    /// Width.
    pub width: usize,
    /// Height.
    pub height: usize,
    /// Coverage, row-major, 0..=255.
    pub coverage: Vec<u8>,
}

/// Sub-pixel phases per pixel for glyph masks.
const PHASES: f64 = 4.0;

fn glyph_mask(id: GlyphId, size: f64, phase: u8) -> Option<Arc<GlyphMask>> {
    type Key = (GlyphId, u64, u8);
    static CACHE: LazyLock<Mutex<HashMap<Key, Option<Arc<GlyphMask>>>>> =
        LazyLock::new(|| Mutex::new(HashMap::new()));
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    cache
        .entry((id, size.to_bits(), phase))
        .or_insert_with(|| {
            let px = (size * f64::from(FONT.height_unscaled()) / units_per_em()) as f32;
            let g = id.with_scale_and_position(
                px,
                ab_glyph::point(f32::from(phase) / PHASES as f32, 0.0),
            );
            let og = FONT.outline_glyph(g)?;
            let b = og.px_bounds();
            let (width, height) = (b.width() as usize, b.height() as usize);
            let mut coverage = vec![0u8; width * height];
            og.draw(|x, y, c| {
                if let Some(v) = coverage.get_mut(y as usize * width + x as usize) {
                    *v = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                }
            });
            Some(Arc::new(GlyphMask {
                left: b.min.x as i32,
                top: b.min.y as i32,
                width,
                height,
                coverage,
            }))
        })
        .clone()
}

/// Glyph masks of `text` at `size` with their integer pen positions, starting at `x0` on the
/// baseline (masks are cached per glyph, size and quarter-pixel phase).
#[must_use]
pub fn text_masks(text: &str, size: f64, x0: f64) -> Vec<(i32, Arc<GlyphMask>)> {
    let k = size / units_per_em();
    let (glyphs, _) = layout(text);
    glyphs
        .into_iter()
        .filter_map(|(id, x)| {
            let pen = x0 + x * k;
            let whole = pen.floor();
            let phase = (((pen - whole) * PHASES).floor() as u8).min(PHASES as u8 - 1);
            glyph_mask(id, size, phase).map(|m| (whole as i32, m))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_scale_with_size_and_length() {
        let w = text_width("refracted", 16.0);
        assert!(w > 30.0 && w < 120.0, "{w}");
        assert!((text_width("refracted", 32.0) - 2.0 * w).abs() < 1e-9);
        assert!(text_width("θi = 41.8°", 16.0) > text_width("θi", 16.0));
        assert!(!text_outline("n1", 16.0).is_empty());
    }
}
