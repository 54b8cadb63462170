//! Object slices on the canvas: shapes, fills by material, name labels.

use super::layout::Pending;
use super::model::{Anchor, Fill, LabelRole, ObjectSlice, Point, Rect, SliceShape};
use super::plane::PlaneFrame;
use super::slice::{PlaneSlice, clip_half_plane, cut_edges, line_in_polygon, slice};
use crate::scene::{Material, Scene};
use glam::{DVec2, DVec3};

/// How a material is drawn.
#[must_use]
pub fn fill_of(m: &Material) -> Fill {
    let tint = (-m.absorption).exp().to_array();
    if m.emission.max_element() > 0.0 {
        Fill::Emitter
    } else if m.is_transmissive() {
        match m.ior {
            Some(ior) => Fill::Glass { ior, tint },
            None => Fill::Absorbing { tint },
        }
    } else if m.absorption != DVec3::ZERO {
        Fill::Absorbing { tint }
    } else if m.reflectivity.max_element() > 0.0 {
        Fill::Mirror
    } else {
        Fill::Diffuse
    }
}

/// The slice of the quadrilateral `q` (e.g. the image plane) as the segment between its two
/// farthest crossing points, in plane coordinates.
#[must_use]
pub(super) fn cut_quad(q: &[DVec3; 4], frame: &PlaneFrame) -> Option<(DVec2, DVec2)> {
    let pts = cut_edges(q, &[(0, 1), (1, 2), (2, 3), (3, 0)], frame);
    let mut best: Option<(DVec2, DVec2)> = None;
    for (i, a) in pts.iter().enumerate() {
        for b in &pts[i + 1..] {
            if best.is_none_or(|(p, q)| (*a - *b).length() > (p - q).length()) {
                best = Some((*a, *b));
            }
        }
    }
    best
}

fn bbox(pts: &[Point]) -> Rect {
    let (lo, hi) = pts
        .iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    Rect::new(lo, hi)
}

/// Every object cut by the plane, mapped to the canvas, with its name label.
pub(super) fn slices(
    scene: &Scene,
    frame: &PlaneFrame,
    view: &Rect,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> Vec<ObjectSlice> {
    let mut out = Vec::new();
    let view_plane: Vec<DVec2> = [
        view.min,
        DVec2::new(view.max.x, view.min.y),
        view.max,
        DVec2::new(view.min.x, view.max.y),
    ]
    .iter()
    .map(|c| frame.canvas_to_plane(*c))
    .collect();
    for (i, o) in scene.objects.iter().enumerate() {
        let Some(s) = slice(&o.shape, frame) else {
            continue;
        };
        let m = scene.material_of(i);
        let fill = fill_of(m);
        let c = |q: DVec2| frame.plane_to_canvas(q);
        let (shape, edge) = match s {
            PlaneSlice::Circle { center, radius } => (
                SliceShape::Circle {
                    center: c(center),
                    radius: radius * frame.scale,
                },
                None,
            ),
            PlaneSlice::Polygon(p) => (SliceShape::Polygon(p.into_iter().map(c).collect()), None),
            PlaneSlice::Segment(a, b) => (SliceShape::Segment(c(a), c(b)), None),
            PlaneSlice::Segments(s) => (
                SliceShape::Segments(s.into_iter().map(|(a, b)| (c(a), c(b))).collect()),
                None,
            ),
            PlaneSlice::HalfPlane { normal, offset } => {
                let inside = clip_half_plane(&view_plane, normal, offset);
                if inside.len() < 3 {
                    continue;
                }
                let edge = line_in_polygon(&view_plane, normal, offset).map(|(a, b)| (c(a), c(b)));
                (
                    SliceShape::Polygon(inside.into_iter().map(c).collect()),
                    edge,
                )
            }
        };
        let (bounds, cands) = label_spots(&shape, edge, fs);
        if !bounds.overlaps(view) {
            continue;
        }
        let mut text = o.name.clone();
        if let Fill::Glass { ior, .. } = fill {
            text = format!("{text} (n = {ior:.2})");
        }
        pending.push(Pending::new(cands, &text, fs, LabelRole::Object, 0));
        out.push(ObjectSlice {
            object: i,
            name: o.name.clone(),
            fill,
            shape,
            edge,
        });
    }
    out
}

/// The canvas bounds of a slice and candidate spots for its name.
fn label_spots(
    shape: &SliceShape,
    edge: Option<(Point, Point)>,
    fs: f64,
) -> (Rect, Vec<(Point, Anchor)>) {
    match (shape, edge) {
        (SliceShape::Polygon(p), Some((a, b))) => {
            let (l, r) = if a.x <= b.x { (a, b) } else { (b, a) };
            let centroid = p.iter().copied().sum::<DVec2>() / p.len() as f64;
            let along = |t: f64| l + (r - l) * t;
            let inward = |q: Point| q + (centroid - q).normalize_or_zero() * 1.6 * fs;
            (
                bbox(p),
                vec![
                    (inward(along(0.97)), Anchor::End),
                    (inward(along(0.03)), Anchor::Start),
                    (inward(along(0.5)), Anchor::Middle),
                ],
            )
        }
        (SliceShape::Circle { center, radius }, _) => {
            let d = radius * std::f64::consts::FRAC_1_SQRT_2;
            let b = Rect::new(*center - *radius, *center + *radius);
            (
                b,
                vec![
                    (
                        *center + DVec2::new(d + 0.3 * fs, -d - 0.3 * fs),
                        Anchor::Start,
                    ),
                    (
                        *center + DVec2::new(-d - 0.3 * fs, -d - 0.3 * fs),
                        Anchor::End,
                    ),
                    (
                        *center + DVec2::new(0.0, -radius - 0.5 * fs),
                        Anchor::Middle,
                    ),
                    (*center + DVec2::new(0.0, radius + 1.3 * fs), Anchor::Middle),
                    (*center, Anchor::Middle),
                ],
            )
        }
        (SliceShape::Segments(s), _) => {
            let pts: Vec<Point> = s.iter().flat_map(|(a, b)| [*a, *b]).collect();
            polygon_spots(bbox(&pts), fs)
        }
        (SliceShape::Polygon(p), None) => polygon_spots(bbox(p), fs),
        (SliceShape::Segment(a, b), _) => {
            let m = (*a + *b) * 0.5;
            (
                bbox(&[*a, *b]),
                vec![
                    (m + DVec2::new(0.5 * fs, -0.5 * fs), Anchor::Start),
                    (m + DVec2::new(-0.5 * fs, 1.2 * fs), Anchor::End),
                ],
            )
        }
    }
}

/// Label spots around the bounds `b` of a slice: above its corners, below, at its centre.
fn polygon_spots(b: Rect, fs: f64) -> (Rect, Vec<(Point, Anchor)>) {
    (
        b,
        vec![
            (DVec2::new(b.min.x, b.min.y - 0.4 * fs), Anchor::Start),
            (DVec2::new(b.max.x, b.min.y - 0.4 * fs), Anchor::End),
            (DVec2::new(b.min.x, b.max.y + 1.2 * fs), Anchor::Start),
            ((b.min + b.max) * 0.5, Anchor::Middle),
        ],
    )
}
