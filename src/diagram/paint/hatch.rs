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
            // At most 4001 lines, counted as steps: a polygon more than 4000 spacings across
            // (a 1e300 box) is hatched more coarsely, and far from the origin, where adding
            // `spacing` may not move `s` at all, the step count still ends the loop.
            let spacing = spacing.max(hi / 4000.0 - lo / 4000.0);
            let mut s = (lo / spacing).ceil() * spacing;
            let mut steps = 0;
            while s < hi && steps <= 4000 {
                if let Some(seg) = clip_line_convex(p, n * s, d) {
                    out.push(seg);
                }
                s += spacing;
                steps += 1;
            }
        }
        _ => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(lo: f64, hi: f64) -> SliceShape {
        SliceShape::Polygon(vec![
            DVec2::new(lo, lo),
            DVec2::new(hi, lo),
            DVec2::new(hi, hi),
            DVec2::new(lo, hi),
        ])
    }

    /// A unit square at spacing 0.1: lines 0.1 apart across it, all inside it.
    #[test]
    fn a_square_is_hatched_inside() {
        let lines = hatch(&square(0.0, 1.0), 0.1);
        // Its projection on the hatch normal spans sqrt(2): about 14 lines.
        assert!((13..=15).contains(&lines.len()), "{}", lines.len());
        for (a, b) in lines {
            for q in [a, b] {
                assert!((-1e-9..=1.0 + 1e-9).contains(&q.x) && (-1e-9..=1.0 + 1e-9).contains(&q.y));
            }
        }
    }

    /// A 1e300 square, or a small one 1e300 from the origin (where adding the spacing does not
    /// move the line), ends with at most 4001 lines instead of looping (a hostile-input hang of
    /// `raytree diagram`, found by `tests/hostile`). A 1e300 square gets no lines: its edges'
    /// cross products overflow, so the clip finds no finite segment.
    #[test]
    fn huge_or_far_polygons_end() {
        assert!(hatch(&square(-1e300, 0.0), 0.05).len() <= 4001);
        assert_eq!(hatch(&square(-1e150, 1e150), 0.05).len(), 4001);
        assert!(hatch(&square(1e300, 1e300 + 1e290), 0.05).len() <= 4001);
        assert!(hatch(&square(-f64::MAX, f64::MAX), 0.05).len() <= 4001);
    }
}
