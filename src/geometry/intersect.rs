//! Per-shape intersection helpers behind [`Shape::intersect`](super::Shape::intersect) and
//! [`Shape::inside_interval`](super::Shape::inside_interval): the stable sphere quadratic and the
//! box slab test.

use super::ShapeHit;
use crate::math::Ray;
use glam::DVec3;

pub(super) fn accept(t: f64, t_min: f64, t_max: f64) -> bool {
    t > t_min && t < t_max
}

/// The nearer of a solid's entry and exit `(t0, t1)` (`t0 <= t1`) inside `(ray.t_min, t_max)`:
/// the entry, else the exit (the ray starts inside).
#[inline(always)]
pub(super) fn nearest_crossing((t0, t1): (f64, f64), ray: &Ray, t_max: f64) -> Option<f64> {
    if accept(t0, ray.t_min, t_max) {
        Some(t0)
    } else {
        accept(t1, ray.t_min, t_max).then_some(t1)
    }
}

/// Both roots of the ray-sphere quadratic, in the numerically stable form of Haines et al.,
/// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7, eq. 10-14):
/// the discriminant is computed from the perpendicular distance, and the second root from
/// `c / q` to avoid cancellation.
pub(super) fn sphere_roots(center: DVec3, radius: f64, ray: &Ray) -> Option<(f64, f64)> {
    let f = ray.origin - center;
    let d = ray.direction;
    let a = d.dot(d);
    let b = -f.dot(d);
    let perp = f + (b / a) * d;
    let disc = radius * radius - perp.dot(perp);
    if disc < 0.0 {
        return None;
    }
    let c = f.dot(f) - radius * radius;
    let q = b + b.signum_or_one() * (a * disc).sqrt();
    let (r0, r1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q / a) };
    Some((r0.min(r1), r0.max(r1)))
}

trait SignumOrOne {
    fn signum_or_one(self) -> f64;
}

impl SignumOrOne for f64 {
    fn signum_or_one(self) -> f64 {
        if self < 0.0 { -1.0 } else { 1.0 }
    }
}

#[inline]
pub(super) fn sphere_hit(center: DVec3, radius: f64, ray: &Ray, t_max: f64) -> Option<ShapeHit> {
    let t = nearest_crossing(sphere_roots(center, radius, ray)?, ray, t_max)?;
    let normal = ((ray.at(t) - center) / radius).normalize();
    Some(ShapeHit { t, normal })
}

/// Slab test (Kay & Kajiya 1986): the line's parameter interval inside the box.
pub(super) fn slab_interval(min: DVec3, max: DVec3, ray: &Ray) -> Option<(f64, f64)> {
    let inv = ray.direction.recip();
    let a = (min - ray.origin) * inv;
    let b = (max - ray.origin) * inv;
    // NaN (0 * inf on a face plane) is dropped by f64::min/max, keeping the other axes.
    let t0 = a.x.min(b.x).max(a.y.min(b.y)).max(a.z.min(b.z));
    let t1 = a.x.max(b.x).min(a.y.max(b.y)).min(a.z.max(b.z));
    (t0 <= t1).then_some((t0, t1))
}

/// The outward normal of the box face nearest to `p`.
pub(super) fn box_normal(min: DVec3, max: DVec3, p: DVec3) -> DVec3 {
    let size = (max - min).max(DVec3::splat(f64::MIN_POSITIVE));
    let lo = (p - min) / size;
    let hi = (max - p) / size;
    let mut best = (lo.x, -DVec3::X);
    for (d, n) in [
        (hi.x, DVec3::X),
        (lo.y, -DVec3::Y),
        (hi.y, DVec3::Y),
        (lo.z, -DVec3::Z),
        (hi.z, DVec3::Z),
    ] {
        if d.abs() < best.0.abs() {
            best = (d, n);
        }
    }
    best.1
}
