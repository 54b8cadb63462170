//! Where a secondary ray starts: the offset strategies of [`OffsetStrategy`].
//!
//! A hit point computed in floating point lies off the true surface by a rounding error that
//! grows with the magnitude of the coordinates. A ray spawned from it may meet the surface it
//! just left (self-intersection: "shadow acne"); an offset that is too large skips geometry
//! close to the surface (leaks, detached contact shadows). See `docs/numerics.md`.

use crate::geometry::Shape;
use crate::math::Ray;
use crate::scene::{OffsetDesc, OffsetStrategy};
use glam::DVec3;
use std::borrow::Cow;

/// The effective epsilon of the `scaled` strategy: `eps * max(1, max_i |p_i|)`, i.e. absolute
/// near the origin and relative to the coordinates' magnitude (and so to their rounding error)
/// far from it.
#[must_use]
pub fn scaled_epsilon(eps: f64, p: DVec3) -> f64 {
    eps * p.abs().max_element().max(1.0)
}

/// The ray from surface point `p` along `direction`, on the side of the unit vector `side` (the
/// normal, flipped towards where the ray goes). `shape` gives the surface `p` lies on; only the
/// robust strategy needs it, so the others never look it up.
#[must_use]
#[inline]
pub fn spawn<'s>(
    offset: OffsetDesc,
    shape: impl FnOnce() -> Cow<'s, Shape>,
    p: DVec3,
    side: DVec3,
    direction: DVec3,
) -> Ray {
    let eps = offset.epsilon;
    match offset.strategy {
        OffsetStrategy::Normal => Ray::new(p + eps * side, direction, 0.0),
        OffsetStrategy::Ray => Ray::new(p, direction, eps),
        OffsetStrategy::Scaled => Ray::new(p + scaled_epsilon(eps, p) * side, direction, 0.0),
        OffsetStrategy::Robust => Ray::new(robust_origin(&shape(), p, side), direction, 0.0),
    }
}

/// pbrt-v4's `OffsetRayOrigin` (PBR 4th ed., section 6.8.6) in `f64`: reproject `p` onto the
/// surface, bound its remaining error `e` per component ([`Shape::surface_point`]), move it
/// `d = |n| . e` along the normal to the ray's side (the smallest move that clears the error
/// box), then round each moved coordinate one more ULP away from the surface, so the rounding of
/// the addition itself cannot pull the origin back. No tuning constant.
#[must_use]
pub fn robust_origin(shape: &Shape, p: DVec3, side: DVec3) -> DVec3 {
    let outward = if side.dot(side) > 0.0 { side } else { DVec3::Z };
    let (q, err) = shape.surface_point(p, outward);
    let d = outward.abs().dot(err);
    let mut o = q + d * outward;
    for i in 0..3 {
        if outward[i] > 0.0 {
            o[i] = o[i].next_up();
        } else if outward[i] < 0.0 {
            o[i] = o[i].next_down();
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_is_absolute_near_origin_and_relative_far() {
        assert_eq!(scaled_epsilon(1e-4, DVec3::new(0.5, -0.2, 0.1)), 1e-4);
        assert_eq!(scaled_epsilon(1e-4, DVec3::new(0.0, -1e6, 3.0)), 1e-4 * 1e6);
    }

    #[test]
    fn robust_moves_a_few_ulps_off_a_box_face() {
        let b = Shape::Box {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        };
        let o = robust_origin(&b, DVec3::new(1.0, 0.3, 0.2), DVec3::X);
        assert_eq!(o.x, 1.0f64.next_up());
        let o = robust_origin(&b, DVec3::new(1.0, 0.3, 0.2), -DVec3::X);
        assert_eq!(o.x, 1.0f64.next_down());
    }

    #[test]
    fn robust_clears_the_sphere_far_from_origin() {
        let center = DVec3::new(1e6, -2e6, 5e5);
        let s = Shape::Sphere {
            center,
            radius: 1e-2,
        };
        let n = DVec3::new(1.0, 2.0, -2.0) / 3.0;
        let p = center + 1e-2 * n;
        let out = robust_origin(&s, p, n);
        let inn = robust_origin(&s, p, -n);
        assert!((out - center).length() > 1e-2 && (inn - center).length() < 1e-2);
        // Tiny compared with the scene: far below any epsilon a user would choose.
        assert!((out - p).length() < 1e-8 && (inn - p).length() < 1e-8);
    }
}
