//! PNG back-end: the display list rasterized with tiny-skia; text as glyph outlines of the
//! embedded font, filled by tiny-skia too (so the output is deterministic).

use super::font::{PathCmd, text_outline, text_width};
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

fn text_path(pos: Point, text: &str, size: f64, anchor: Anchor) -> Option<Path> {
    let w = text_width(text, size);
    let x0 = match anchor {
        Anchor::Start => pos.x,
        Anchor::Middle => pos.x - w * 0.5,
        Anchor::End => pos.x - w,
    } as f32;
    let y0 = pos.y as f32;
    let mut pb = PathBuilder::new();
    for c in text_outline(text, size) {
        match c {
            PathCmd::MoveTo(x, y) => pb.move_to(x0 + x, y0 + y),
            PathCmd::LineTo(x, y) => pb.line_to(x0 + x, y0 + y),
            PathCmd::QuadTo(a, b, x, y) => pb.quad_to(x0 + a, y0 + b, x0 + x, y0 + y),
            PathCmd::CubicTo(a, b, c, d, x, y) => {
                pb.cubic_to(x0 + a, y0 + b, x0 + c, y0 + d, x0 + x, y0 + y)
            }
            PathCmd::Close => pb.close(),
        }
    }
    pb.finish()
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
                let Some(path) = text_path(pos, &text, size, anchor) else {
                    continue;
                };
                if let Some(h) = halo {
                    pm.stroke_path(&path, &paint(h), &stroke_style(size * 0.22, None), id, None);
                }
                pm.fill_path(&path, &paint(color), FillRule::Winding, id, None);
            }
        }
    }
    pm
}

/// The diagram as PNG bytes (deterministic: same model, same bytes).
#[must_use]
pub fn to_png(d: &Diagram, style: &Style) -> Vec<u8> {
    to_pixmap(d, style)
        .encode_png()
        .expect("PNG encoding into memory cannot fail")
}
