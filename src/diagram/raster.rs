//! PNG back-end: the display list rasterized with tiny-skia; text from cached anti-aliased glyph
//! masks of the embedded font (ab_glyph's rasterizer), blended in integer arithmetic, so the
//! output is deterministic. PNG encoding uses
//! fast deflate: a figure is mostly flat colour, and the default level costs 50 ms at 1280x720.

use super::font::{text_masks, text_width};
use super::layout::label_box;
use super::model::{Anchor, Diagram, Point};
use super::paint::{Prim, Rgba, Style, display_list};
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Stroke, StrokeDash,
    Transform,
};

fn paint(c: Rgba) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(Color::from_rgba8(c.0, c.1, c.2, c.3));
    p.anti_alias = true;
    p
}

fn poly(points: &[Point], closed: bool) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let (first, rest) = points.split_first()?;
    pb.move_to(first.x as f32, first.y as f32);
    for q in rest {
        pb.line_to(q.x as f32, q.y as f32);
    }
    if closed {
        pb.close();
    }
    pb.finish()
}

fn stroke_style(width: f64, dash: Option<[f64; 2]>) -> Stroke {
    Stroke {
        width: width as f32,
        line_cap: if dash.is_some() {
            LineCap::Butt
        } else {
            LineCap::Round
        },
        line_join: LineJoin::Round,
        dash: dash.and_then(|[a, b]| StrokeDash::new(vec![a as f32, b as f32], 0.0)),
        ..Stroke::default()
    }
}

/// Blend `text` into the pixmap with cached glyph masks (source-over, premultiplied).
fn draw_text(pm: &mut Pixmap, pos: Point, text: &str, size: f64, anchor: Anchor, c: Rgba) {
    let w = text_width(text, size);
    let x0 = match anchor {
        Anchor::Start => pos.x,
        Anchor::Middle => pos.x - w * 0.5,
        Anchor::End => pos.x - w,
    };
    let baseline = pos.y.round() as i32;
    let (pw, ph) = (pm.width() as i32, pm.height() as i32);
    let pixels = pm.pixels_mut();
    for (pen, m) in text_masks(text, size, x0) {
        for row in 0..m.height {
            let y = baseline + m.top + row as i32;
            if !(0..ph).contains(&y) {
                continue;
            }
            for col in 0..m.width {
                let x = pen + m.left + col as i32;
                let cov = u32::from(m.coverage[row * m.width + col]);
                if cov == 0 || !(0..pw).contains(&x) {
                    continue;
                }
                let a = cov * u32::from(c.3) / 255;
                let dst = &mut pixels[(y * pw + x) as usize];
                let blend = |s: u8, d: u8| {
                    ((u32::from(s) * a + u32::from(d) * (255 - a) + 127) / 255) as u8
                };
                let out = tiny_skia::ColorU8::from_rgba(
                    blend(c.0, dst.red()),
                    blend(c.1, dst.green()),
                    blend(c.2, dst.blue()),
                    ((a * 255 + u32::from(dst.alpha()) * (255 - a) + 127) / 255) as u8,
                );
                // Destination is opaque (the background is), so premultiplied equals straight.
                *dst = out.premultiply();
            }
        }
    }
}

/// Draw the diagram into a new pixmap of its size.
#[must_use]
pub fn to_pixmap(d: &Diagram, style: &Style) -> Pixmap {
    let mut pm =
        Pixmap::new(d.width as u32, d.height as u32).expect("the diagram size was validated");
    let id = Transform::identity();
    for p in display_list(d, style) {
        match p {
            Prim::Fill { points, color } => {
                if let Some(path) = poly(&points, true) {
                    pm.fill_path(&path, &paint(color), FillRule::Winding, id, None);
                }
            }
            Prim::Stroke {
                points,
                color,
                width,
                dash,
                closed,
            } => {
                if let Some(path) = poly(&points, closed) {
                    pm.stroke_path(&path, &paint(color), &stroke_style(width, dash), id, None);
                }
            }
            Prim::Circle {
                center,
                radius,
                fill,
                stroke,
            } => {
                let Some(path) = PathBuilder::from_circle(
                    center.x as f32,
                    center.y as f32,
                    radius.max(0.1) as f32,
                ) else {
                    continue;
                };
                if let Some(c) = fill {
                    pm.fill_path(&path, &paint(c), FillRule::Winding, id, None);
                }
                if let Some((c, w)) = stroke {
                    pm.stroke_path(&path, &paint(c), &stroke_style(w, None), id, None);
                }
            }
            Prim::Text {
                pos,
                text,
                size,
                color,
                anchor,
                halo,
            } => {
                if let Some(h) = halo {
                    // A translucent plate rather than a stroked halo: stroking glyph outlines
                    // costs more than the rest of the figure together.
                    let b = label_box(pos, anchor, &text, size);
                    if let Some(r) = tiny_skia::Rect::from_ltrb(
                        b.min.x as f32,
                        b.min.y as f32,
                        b.max.x as f32,
                        b.max.y as f32,
                    ) {
                        pm.fill_rect(r, &paint(h.fade(0.78)), id, None);
                    }
                }
                draw_text(&mut pm, pos, &text, size, anchor, color);
            }
        }
    }
    pm
}

/// The diagram as PNG bytes (deterministic: same model, same bytes).
#[must_use]
pub fn to_png(d: &Diagram, style: &Style) -> Vec<u8> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let pm = to_pixmap(d, style);
    // The background is opaque, so premultiplied RGBA equals straight RGBA; drop alpha.
    let rgb: Vec<u8> = pm
        .data()
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Fast, FilterType::Adaptive)
        .write_image(
            &rgb,
            pm.width(),
            pm.height(),
            image::ExtendedColorType::Rgb8,
        )
        .expect("PNG encoding into memory cannot fail");
    out
}
