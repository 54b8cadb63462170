//! The drawing primitive [`Prim`] and small builders of common shapes (strokes, arrow
//! heads, crosses, rectangles).

use super::Rgba;
use crate::diagram::model::{Anchor, Point};
use glam::DVec2;

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

pub(super) fn stroke(points: Vec<Point>, color: Rgba, width: f64, dash: Option<[f64; 2]>) -> Prim {
    Prim::Stroke {
        points,
        color,
        width,
        dash,
        closed: false,
    }
}

/// A filled disc without outline (hit points, spawn points, the eye).
pub(super) fn dot(center: Point, radius: f64, color: Rgba) -> Prim {
    Prim::Circle {
        center,
        radius,
        fill: Some(color),
        stroke: None,
    }
}

pub(super) fn arrow_head(to: Point, dir: Point, len: f64, color: Rgba) -> Option<Prim> {
    let d = dir.try_normalize()?;
    let n = DVec2::new(-d.y, d.x);
    let base = to - d * len;
    Some(Prim::Fill {
        points: vec![to, base + n * len * 0.38, base - n * len * 0.38],
        color,
    })
}

pub(super) fn rect_points(min: Point, max: Point) -> Vec<Point> {
    vec![min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)]
}

pub(super) fn cross(at: Point, s: f64, color: Rgba, width: f64, out: &mut Vec<Prim>) {
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
