//! SVG back-end: hand-written XML with vector paths and real `<text>` (escaped).

use super::font::SVG_FONT_FAMILY;
use super::model::{Anchor, Diagram, Point};
use super::paint::{Prim, Rgba, Style, display_list};
use std::fmt::Write;

/// Escape text for XML content and attribute values.
#[must_use]
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => out.push(c),
        }
    }
    out
}

fn color(c: Rgba) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn opacity(c: Rgba) -> f64 {
    f64::from(c.3) / 255.0
}

fn points(p: &[Point]) -> String {
    let mut s = String::new();
    for (i, q) in p.iter().enumerate() {
        let _ = write!(s, "{}{:.2},{:.2}", if i == 0 { "" } else { " " }, q.x, q.y);
    }
    s
}

/// Every number of `p` is finite (SVG has no way to write NaN or infinity).
fn finite(p: &Prim) -> bool {
    let pt = |q: &Point| q.x.is_finite() && q.y.is_finite();
    match p {
        Prim::Fill { points, .. } => points.iter().all(pt),
        Prim::Stroke {
            points,
            width,
            dash,
            ..
        } => {
            points.iter().all(pt)
                && width.is_finite()
                && dash.is_none_or(|d| d.iter().all(|v| v.is_finite()))
        }
        Prim::Circle {
            center,
            radius,
            stroke,
            ..
        } => pt(center) && radius.is_finite() && stroke.is_none_or(|(_, w)| w.is_finite()),
        Prim::Text { pos, size, .. } => pt(pos) && size.is_finite(),
    }
}

/// The diagram as a standalone SVG document; shapes with a non-finite number are left out
/// ([`to_svg_counting`] says how many).
#[must_use]
pub fn to_svg(d: &Diagram, style: &Style) -> String {
    to_svg_counting(d, style).0
}

/// [`to_svg`] and the number of shapes left out because a coordinate, radius or size was NaN
/// or infinite (a sphere of radius 1e300 projects to an infinite circle): no `r="inf"` or
/// `x="NaN"` is ever written.
#[must_use]
pub fn to_svg_counting(d: &Diagram, style: &Style) -> (String, usize) {
    let mut dropped = 0;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{f}">"#,
        w = d.width,
        h = d.height,
        f = escape(SVG_FONT_FAMILY)
    );
    for p in display_list(d, style) {
        if !finite(&p) {
            dropped += 1;
            continue;
        }
        write_prim(&mut s, p);
    }
    s.push_str("</svg>\n");
    (s, dropped)
}

/// One SVG element for `p` (all of whose numbers are finite), on a line of its own.
fn write_prim(s: &mut String, p: Prim) {
    match p {
        Prim::Fill {
            points: pts,
            color: c,
        } => {
            let _ = writeln!(
                s,
                r#"<polygon points="{}" fill="{}" fill-opacity="{:.3}"/>"#,
                points(&pts),
                color(c),
                opacity(c)
            );
        }
        Prim::Stroke {
            points: pts,
            color: c,
            width,
            dash,
            closed,
        } => write_stroke(s, &pts, c, width, dash, closed),
        Prim::Circle {
            center,
            radius,
            fill,
            stroke,
        } => write_circle(s, center, radius, fill, stroke),
        Prim::Text {
            pos,
            text,
            size,
            color: c,
            anchor,
            halo,
        } => write_text(s, pos, &text, size, c, anchor, halo),
    }
}

/// A polyline (or a closed polygon) stroked `width` wide, dashed if `dash` is given.
fn write_stroke(
    s: &mut String,
    pts: &[Point],
    c: Rgba,
    width: f64,
    dash: Option<[f64; 2]>,
    closed: bool,
) {
    let tag = if closed { "polygon" } else { "polyline" };
    let dash = dash.map_or(String::new(), |[a, b]| {
        format!(r#" stroke-dasharray="{a:.2} {b:.2}""#)
    });
    let _ = writeln!(
        s,
        r#"<{tag} points="{}" fill="none" stroke="{}" stroke-opacity="{:.3}" stroke-width="{width:.2}" stroke-linecap="round" stroke-linejoin="round"{dash}/>"#,
        points(pts),
        color(c),
        opacity(c)
    );
}

/// A circle, filled and stroked as given.
fn write_circle(
    s: &mut String,
    center: Point,
    radius: f64,
    fill: Option<Rgba>,
    stroke: Option<(Rgba, f64)>,
) {
    let f = fill.map_or("fill=\"none\"".to_string(), |c| {
        format!(r#"fill="{}" fill-opacity="{:.3}""#, color(c), opacity(c))
    });
    let st = stroke.map_or(String::new(), |(c, w)| {
        format!(
            r#" stroke="{}" stroke-opacity="{:.3}" stroke-width="{w:.2}""#,
            color(c),
            opacity(c)
        )
    });
    let _ = writeln!(
        s,
        r#"<circle cx="{:.2}" cy="{:.2}" r="{radius:.2}" {f}{st}/>"#,
        center.x, center.y
    );
}

/// A text (escaped) at `pos`, with a halo of colour `halo` if given.
fn write_text(
    s: &mut String,
    pos: Point,
    text: &str,
    size: f64,
    c: Rgba,
    anchor: Anchor,
    halo: Option<Rgba>,
) {
    let anchor = match anchor {
        Anchor::Start => "start",
        Anchor::Middle => "middle",
        Anchor::End => "end",
    };
    let halo = halo.map_or(String::new(), |h| {
        format!(
            r#" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round" paint-order="stroke""#,
            color(h),
            size * 0.22
        )
    });
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-size="{size:.2}" fill="{}" text-anchor="{anchor}"{halo}>{}</text>"#,
        pos.x,
        pos.y,
        color(c),
        escape(text)
    );
}

#[cfg(test)]
mod tests {
    use super::{Point, Prim, escape, finite};
    use crate::diagram::paint::Rgba;

    #[test]
    fn non_finite_shapes_are_recognised() {
        let c = |r: f64, x: f64| Prim::Circle {
            center: Point::new(x, 1.0),
            radius: r,
            fill: Some(Rgba(0, 0, 0, 255)),
            stroke: None,
        };
        assert!(finite(&c(2.0, 1.0)));
        assert!(!finite(&c(f64::INFINITY, 1.0)));
        assert!(!finite(&c(2.0, f64::NAN)));
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(
            escape(r#"a<b & "c" 'd'>"#),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;"
        );
        assert_eq!(escape("θi = 41.8°"), "θi = 41.8°");
    }
}
