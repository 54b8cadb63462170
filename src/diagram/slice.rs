//! Exact cross-sections of shapes with the diagram plane, in plane coordinates (world units):
//! a sphere gives a circle, a box a convex polygon, a triangle a segment, a plane a half-plane,
//! a mesh one segment per triangle it cuts.

use super::plane::PlaneFrame;
use crate::geometry::Shape;
use glam::{DVec2, DVec3};

/// A cross-section in plane coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneSlice {
    /// Sphere slice.
    Circle {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
    },
    /// Convex polygon (a box slice, or a triangle lying in the plane), counter-clockwise.
    Polygon(Vec<DVec2>),
    /// A triangle crossing the plane.
    Segment(DVec2, DVec2),
    /// A mesh's outline: one segment per triangle crossing the plane.
    Segments(Vec<(DVec2, DVec2)>),
    /// A plane's inside: points `q` with `normal . q + offset < 0`.
    HalfPlane {
        /// In-plane normal (not normalized).
        normal: DVec2,
        /// Offset.
        offset: f64,
    },
}

/// Relative tolerance for points on the plane.
const ON_PLANE: f64 = 1e-9;

/// The slice of `shape` with the plane of `frame`, if any.
#[must_use]
pub fn slice(shape: &Shape, frame: &PlaneFrame) -> Option<PlaneSlice> {
    match *shape {
        Shape::Sphere { center, radius } => {
            let d = frame.distance(center);
            let r2 = radius * radius - d * d;
            (r2 > 0.0).then(|| PlaneSlice::Circle {
                center: frame.plane_coords(center),
                radius: r2.sqrt(),
            })
        }
        Shape::Plane { point, normal } => {
            let n2 = DVec2::new(normal.dot(frame.u), normal.dot(frame.v));
            if n2.length() < 1e-9 {
                return None; // parallel to the diagram plane: no line to draw
            }
            Some(PlaneSlice::HalfPlane {
                normal: n2,
                offset: (frame.origin - point).dot(normal),
            })
        }
        Shape::Triangle { vertices, .. } => {
            let pts = cut_edges(&vertices, &[(0, 1), (1, 2), (2, 0)], frame);
            match pts.len() {
                0 | 1 => None,
                2 => Some(PlaneSlice::Segment(pts[0], pts[1])),
                _ => Some(PlaneSlice::Polygon(convex_order(pts))),
            }
        }
        Shape::Quad { vertices, .. } => {
            let pts = cut_edges(&vertices, &[(0, 1), (1, 2), (2, 3), (3, 0)], frame);
            match pts.len() {
                0 | 1 => None,
                2 => Some(PlaneSlice::Segment(pts[0], pts[1])),
                _ => Some(PlaneSlice::Polygon(convex_order(pts))),
            }
        }
        Shape::Box { min, max } => {
            let corner = |i: usize| {
                DVec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                )
            };
            let corners: Vec<DVec3> = (0..8).map(corner).collect();
            let mut edges = Vec::new();
            for i in 0..8 {
                for bit in [1, 2, 4] {
                    if i & bit == 0 {
                        edges.push((i, i | bit));
                    }
                }
            }
            let pts = cut_edges(&corners, &edges, frame);
            (pts.len() >= 3).then(|| PlaneSlice::Polygon(convex_order(pts)))
        }
        Shape::Mesh(ref m) => {
            let segments: Vec<(DVec2, DVec2)> = m
                .slice(frame.origin, frame.normal)
                .into_iter()
                .map(|[a, b]| (frame.plane_coords(a), frame.plane_coords(b)))
                .collect();
            (!segments.is_empty()).then_some(PlaneSlice::Segments(segments))
        }
    }
}

/// Where the edges `(i, j)` between `verts` cross the plane (vertices on it count once).
pub(super) fn cut_edges(
    verts: &[DVec3],
    edges: &[(usize, usize)],
    frame: &PlaneFrame,
) -> Vec<DVec2> {
    let scale = verts
        .iter()
        .map(|v| (*v - frame.origin).abs().max_element())
        .fold(1.0, f64::max);
    let tol = ON_PLANE * scale;
    let dist: Vec<f64> = verts.iter().map(|v| frame.distance(*v)).collect();
    let mut pts: Vec<DVec2> = Vec::new();
    let mut push = |p: DVec3| {
        let q = frame.plane_coords(p);
        if !pts.iter().any(|o| (*o - q).length() <= tol) {
            pts.push(q);
        }
    };
    for (i, v) in verts.iter().enumerate() {
        if dist[i].abs() <= tol {
            push(*v);
        }
    }
    for &(i, j) in edges {
        let (a, b) = (dist[i], dist[j]);
        if (a > tol && b < -tol) || (a < -tol && b > tol) {
            let t = a / (a - b);
            push(verts[i] + t * (verts[j] - verts[i]));
        }
    }
    pts
}

/// Sort points of a convex set counter-clockwise around their centroid.
fn convex_order(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    let c = pts.iter().copied().sum::<DVec2>() / pts.len() as f64;
    pts.sort_by(|a, b| {
        let (aa, ab) = ((*a - c).to_angle(), (*b - c).to_angle());
        aa.total_cmp(&ab)
    });
    pts
}

/// Clip a convex polygon to the half-plane `normal . q + offset <= 0` (Sutherland-Hodgman).
#[must_use]
pub fn clip_half_plane(poly: &[DVec2], normal: DVec2, offset: f64) -> Vec<DVec2> {
    let f = |q: DVec2| normal.dot(q) + offset;
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fa, fb) = (f(a), f(b));
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            out.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    out
}

/// The part of the line `normal . q + offset = 0` inside the convex polygon `poly`.
#[must_use]
pub fn line_in_polygon(poly: &[DVec2], normal: DVec2, offset: f64) -> Option<(DVec2, DVec2)> {
    let f = |q: DVec2| normal.dot(q) + offset;
    let mut pts = Vec::new();
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fa, fb) = (f(a), f(b));
        if (fa <= 0.0 && fb > 0.0) || (fa > 0.0 && fb <= 0.0) {
            pts.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    (pts.len() >= 2).then(|| (pts[0], pts[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(origin: DVec3, normal: DVec3) -> PlaneFrame {
        PlaneFrame::new(origin, normal, DVec3::Y, DVec3::X)
    }

    #[test]
    fn sphere_gives_circle_with_pythagorean_radius() {
        let f = frame(DVec3::new(0.0, 0.0, 0.6), DVec3::Z);
        let s = Shape::Sphere {
            center: DVec3::new(2.0, 3.0, 0.0),
            radius: 1.0,
        };
        let Some(PlaneSlice::Circle { center, radius }) = slice(&s, &f) else {
            panic!("expected a circle");
        };
        assert!((radius - 0.8).abs() < 1e-12, "{radius}");
        assert!((center - f.plane_coords(DVec3::new(2.0, 3.0, 0.6))).length() < 1e-12);
        let far = frame(DVec3::new(0.0, 0.0, 1.5), DVec3::Z);
        assert_eq!(slice(&s, &far), None);
    }

    #[test]
    fn box_cut_diagonally_gives_rectangle() {
        // The plane x = y cuts the unit cube in a rectangle sqrt(2) x 1.
        let f = frame(DVec3::ZERO, DVec3::new(1.0, -1.0, 0.0).normalize());
        let b = Shape::Box {
            min: DVec3::ZERO,
            max: DVec3::ONE,
        };
        let Some(PlaneSlice::Polygon(p)) = slice(&b, &f) else {
            panic!("expected a polygon");
        };
        assert_eq!(p.len(), 4);
        let mut sides: Vec<f64> = (0..4).map(|i| (p[(i + 1) % 4] - p[i]).length()).collect();
        sides.sort_by(f64::total_cmp);
        for (s, want) in sides.iter().zip([1.0, 1.0, 2f64.sqrt(), 2f64.sqrt()]) {
            assert!((s - want).abs() < 1e-12, "{sides:?}");
        }
        // Counter-clockwise: positive signed area sqrt(2).
        let area: f64 = (0..4).map(|i| p[i].perp_dot(p[(i + 1) % 4])).sum::<f64>() / 2.0;
        assert!((area - 2f64.sqrt()).abs() < 1e-12, "{area}");
    }

    #[test]
    fn box_cut_by_its_face_plane_and_by_a_corner_plane() {
        let b = Shape::Box {
            min: DVec3::ZERO,
            max: DVec3::ONE,
        };
        // z = 0.5 through the middle: unit square.
        let Some(PlaneSlice::Polygon(p)) = slice(&b, &frame(DVec3::splat(0.5), DVec3::Z)) else {
            panic!()
        };
        assert_eq!(p.len(), 4);
        // x + y + z = 1.5 cuts a regular hexagon.
        let n = DVec3::ONE.normalize();
        let Some(PlaneSlice::Polygon(h)) = slice(&b, &frame(DVec3::splat(0.5), n)) else {
            panic!()
        };
        assert_eq!(h.len(), 6);
        for i in 0..6 {
            assert!(((h[(i + 1) % 6] - h[i]).length() - 0.5f64.sqrt()).abs() < 1e-12);
        }
    }

    #[test]
    fn triangle_gives_segment_and_plane_gives_half_plane() {
        let t = Shape::Triangle {
            vertices: [
                DVec3::new(-1.0, 0.0, -1.0),
                DVec3::new(1.0, 0.0, -1.0),
                DVec3::new(0.0, 0.0, 1.0),
            ],
            normal: DVec3::Y,
        };
        let f = frame(DVec3::ZERO, DVec3::Z);
        let Some(PlaneSlice::Segment(a, b)) = slice(&t, &f) else {
            panic!()
        };
        assert!(((a - b).length() - 1.0).abs() < 1e-12);
        let floor = Shape::Plane {
            point: DVec3::new(0.0, -1.0, 0.0),
            normal: DVec3::Y,
        };
        let Some(PlaneSlice::HalfPlane { normal, offset }) = slice(&floor, &f) else {
            panic!()
        };
        // Below y = -1 is inside.
        assert!(normal.dot(DVec2::new(0.0, -2.0)) + offset < 0.0);
        assert!(normal.dot(DVec2::new(5.0, 0.0)) + offset > 0.0);
        let square = [
            DVec2::new(-2.0, -2.0),
            DVec2::new(2.0, -2.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(-2.0, 2.0),
        ];
        let inside = clip_half_plane(&square, normal, offset);
        let area: f64 = (0..inside.len())
            .map(|i| inside[i].perp_dot(inside[(i + 1) % inside.len()]))
            .sum::<f64>()
            / 2.0;
        assert!((area - 4.0).abs() < 1e-12, "{area}");
        let (p, q) = line_in_polygon(&square, normal, offset).unwrap();
        assert!((p.y + 1.0).abs() < 1e-12 && (q.y + 1.0).abs() < 1e-12);
    }
}
