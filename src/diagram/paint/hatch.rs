//! Mirror hatching: diagonal lines clipped to a circle or convex polygon.

use crate::diagram::model::{Point, SliceShape};
use glam::DVec2;

/// Clip the line through `p` along `d` to a convex polygon (either orientation).
fn clip_line_convex(poly: &[Point], p: Point, d: Point) -> Option<(Point, Point)> {
    let area: f64 = (0..poly.len())
        .map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()]))
        .sum();
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let e = b - a;
        // Inside is where sign(area) * e x (q - a) >= 0.
        let num = area.signum() * e.perp_dot(p - a);
        let den = area.signum() * e.perp_dot(d);
        if den.abs() < 1e-12 {
            if num < 0.0 {
                return None;
            }
        } else if den > 0.0 {
            t0 = t0.max(-num / den);
        } else {
            t1 = t1.min(-num / den);
        }
    }
    (t0 < t1 && t0.is_finite() && t1.is_finite()).then(|| (p + d * t0, p + d * t1))
}

/// Diagonal hatch lines across a circle or convex polygon.
pub(super) fn hatch(shape: &SliceShape, spacing: f64) -> Vec<(Point, Point)> {
    let d = DVec2::new(1.0, -1.0).normalize();
    let n = DVec2::new(d.y, -d.x) * -1.0;
    let mut out = Vec::new();
    match shape {
        SliceShape::Circle { center, radius } => {
            // At most 4001 lines, as for polygons: a huge (1e300) or non-finite radius must not
            // allocate without bound (f64::min also maps NaN to the cap).
            let k = (radius / spacing).floor().min(2000.0) as i64;
            for i in -k..=k {
                let off = i as f64 * spacing;
                let half = (radius * radius - off * off).max(0.0).sqrt();
                let m = *center + n * off;
                out.push((m - d * half, m + d * half));
            }
        }
        SliceShape::Polygon(p) if p.len() >= 3 => {
            let proj: Vec<f64> = p.iter().map(|q| q.dot(n)).collect();
            let lo = proj.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = proj.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mut s = (lo / spacing).ceil() * spacing;
            while s < hi && out.len() < 4000 {
                if let Some(seg) = clip_line_convex(p, n * s, d) {
                    out.push(seg);
                }
                s += spacing;
            }
        }
        _ => {}
    }
    out
}
