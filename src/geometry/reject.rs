//! Cheap, conservative rejections before the watertight test of a flat shape: they answer
//! "surely missed" only where the exact test cannot accept the hit, so every hit it finds is
//! still found, bit for bit (`.ci/fixcheck`), and most misses skip its shear and edge functions.

use crate::math::Ray;
use glam::DVec3;

/// Whether the plane of a flat shape (through `p` with unit `normal`) is crossed so far outside
/// `(t_min, t_max)` along `ray` that the exact test cannot accept its hit: a cheap rejection
/// before the watertight test. The margin (a millionth of the distance scale `|p - o| / |cos|`
/// plus of `t` itself) is far above the rounding that separates this plane distance from the
/// watertight test's, so no hit the exact test would accept is rejected.
#[inline]
pub(super) fn plane_out_of_range(p: DVec3, normal: DVec3, ray: &Ray, t_max: f64) -> bool {
    let denom = normal.dot(ray.direction);
    let to = p - ray.origin;
    let t = to.dot(normal) / denom;
    if !t.is_finite() {
        return false;
    }
    let margin = 1e-6 * (to.length() / denom.abs() + t.abs());
    t > t_max + margin || t < ray.t_min - margin
}

/// [`plane_out_of_range`] (with a wider margin: the 1-norm of `p - o`), or else whether the
/// plane is crossed clearly outside the parallelogram `v` (corners `v0, v0 + e1, v0 + e1 + e2, v0 + e2`).
///
/// The crossing `q = o + t d - v0` has the coordinates `alpha = (q x e2) . c / |c|^2`,
/// `beta = (e1 x q) . c / |c|^2` with `c = e1 x e2`; it is inside for both in `[0, 1]`. The
/// test rejects only beyond a margin of `1e-6` plus `1e-9 L max|e| / |c|` in those coordinates
/// (`L` a bound on the lengths that enter `q`: `|t d| + |to| + |to| |d| / |cos|`), about a
/// million times the rounding of `q` and of the watertight test's edge functions; a grazing
/// ray (tiny `cos`) gets a huge margin and goes to the exact test. Compared without divisions
/// (multiplied through by `|c|^2`, with 1-norms and max-norms as bounds of the 2-norms, which
/// only widen the margin); a NaN anywhere compares false and rejects nothing.
#[inline]
pub(super) fn quad_surely_missed(v: &[DVec3; 4], normal: DVec3, ray: &Ray, t_max: f64) -> bool {
    QuadFrame::new(v).surely_missed(v[0], normal, ray, t_max)
}

/// The per-quad part of [`quad_surely_missed`]: edges, `c = e1 x e2`, `|c|^2` and the margin's
/// edge scale `max(|e1|_1, |e2|_1) max|c|`, computed once per quad by a prepared scene
/// ([`super::Prepared`]); the same values, so the same answers, as computing them per ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct QuadFrame {
    e1: DVec3,
    e2: DVec3,
    c: DVec3,
    area2: f64,
    scale: f64,
}

fn l1(x: DVec3) -> f64 {
    x.abs().element_sum()
}

impl QuadFrame {
    /// The frame of the parallelogram `v`.
    #[inline]
    pub(crate) fn new(v: &[DVec3; 4]) -> Self {
        let (e1, e2) = (v[1] - v[0], v[3] - v[0]);
        let c = e1.cross(e2);
        Self {
            e1,
            e2,
            c,
            area2: c.dot(c),
            scale: l1(e1).max(l1(e2)) * c.abs().max_element(),
        }
    }

    /// [`quad_surely_missed`] of the parallelogram with first corner `v0` and this frame.
    #[inline]
    pub(crate) fn surely_missed(&self, v0: DVec3, normal: DVec3, ray: &Ray, t_max: f64) -> bool {
        let d = ray.direction;
        let inv = 1.0 / normal.dot(d);
        let to = v0 - ray.origin;
        // One division; `t` within an ulp of `plane_out_of_range`'s, `dist` its bound with the
        // 1-norm (no square root): both far inside the margin.
        let t = to.dot(normal) * inv;
        if !t.is_finite() {
            return false;
        }
        let dist = l1(to) * inv.abs();
        let margin = 1e-6 * (dist + t.abs());
        if t > t_max + margin || t < ray.t_min - margin {
            return true;
        }
        let q = t * d - to;
        let (c, area2) = (self.c, self.area2);
        let a = q.cross(self.e2).dot(c);
        let b = self.e1.cross(q).dot(c);
        let d1 = l1(d);
        let len = t.abs() * d1 + l1(to) + dist * d1 + l1(q);
        let m = 1e-6 * area2 + 3e-9 * len * self.scale;
        a < -m || b < -m || a > area2 + m || b > area2 + m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rays through a grid of points on and around a skewed parallelogram, from many origins:
    /// whenever the exact watertight test hits, the rejection says "maybe"; and points well
    /// outside are rejected (the shortcut works).
    #[test]
    fn rejects_only_what_the_exact_test_misses() {
        let v0 = DVec3::new(0.3, -0.2, 1.0);
        let (e1, e2) = (DVec3::new(2.0, 0.1, 0.3), DVec3::new(0.7, 1.5, -0.4));
        let v = [v0, v0 + e1, v0 + e1 + e2, v0 + e2];
        let normal = e1.cross(e2).normalize();
        let mut rejected = 0;
        for o in [
            DVec3::new(0.0, 0.0, 6.0),
            DVec3::new(5.0, -3.0, -4.0),
            DVec3::new(1e4, 2e4, 3e3),
            DVec3::new(-0.2, 0.1, 1.1),
        ] {
            for i in -20..=120 {
                for j in -20..=120 {
                    let (s, u) = (f64::from(i) / 100.0, f64::from(j) / 100.0);
                    // Also the edges exactly, and a hair outside them.
                    for (s, u) in [
                        (s, u),
                        (s.clamp(0.0, 1.0), u),
                        (-1e-13, u),
                        (s, 1.0 + 1e-13),
                    ] {
                        let target = v0 + s * e1 + u * e2;
                        let ray = Ray::new(o, target - o, 1e-9);
                        let exact = super::super::quad_t(&v, &ray)
                            .filter(|&t| t > ray.t_min && t < f64::INFINITY);
                        let missed = quad_surely_missed(&v, normal, &ray, f64::INFINITY);
                        assert!(!(missed && exact.is_some()), "{o} {s} {u}");
                        rejected += u32::from(missed);
                    }
                }
            }
        }
        assert!(rejected > 100_000, "{rejected}");
    }
}
