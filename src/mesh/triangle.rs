//! The watertight ray-triangle test (used by meshes and by [`crate::geometry::Shape::Triangle`]), [`triangle_t`], and its per-ray part, [`ShearedRay`].

use crate::math::Ray;
use glam::DVec3;

/// Watertight ray-triangle test (Woop, Benthin, Wald, "Watertight Ray/Triangle Intersection",
/// JCGT 2(1), 2013), two-sided; returns the hit distance.
///
/// The vertices are translated to the ray origin and sheared so the ray runs along +z; the
/// three 2D edge functions are then computed per vertex with the same operations for every
/// triangle, so an edge shared by two triangles gives exactly negated values on both sides and
/// no ray passes between them. Unlike the paper's `f32` kernel no higher-precision fallback is
/// needed for the edge functions: they already are `f64`.
pub(crate) fn triangle_t(v: &[DVec3; 3], ray: &Ray) -> Option<f64> {
    ShearedRay::new(ray)?.t(v)
}

/// The per-ray part of [`triangle_t`] (axis permutation and shear), computed once for testing
/// many triangles; [`ShearedRay::t`] is then exactly `triangle_t`, bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    origin: DVec3,
    /// Axes: sheared x, sheared y, along the ray (the largest direction component).
    pub(crate) k: [usize; 3],
    /// Shear factors `d[kx] / d[kz]`, `d[ky] / d[kz]` and scale `1 / d[kz]`.
    pub(crate) s: [f64; 3],
}

impl ShearedRay {
    /// `None` for a zero or non-finite direction (no triangle is hit).
    pub(crate) fn new(ray: &Ray) -> Option<Self> {
        let d = ray.direction;
        let kz = d.abs().max_position();
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        if !(sx.is_finite() && sy.is_finite() && sz.is_finite()) {
            return None;
        }
        Some(Self {
            origin: ray.origin,
            k: [kx, ky, kz],
            s: [sx, sy, sz],
        })
    }

    /// [`triangle_t`] of `v` for this ray.
    #[inline]
    pub(crate) fn t(&self, v: &[DVec3; 3]) -> Option<f64> {
        let ([kx, ky, kz], [sx, sy, sz]) = (self.k, self.s);
        // Arrays, not `DVec3` indexing (a `match` per component); the same values.
        let [a, b, c] = v.map(|p| (p - self.origin).to_array());
        let shear = |p: [f64; 3]| (p[kx] - sx * p[kz], p[ky] - sy * p[kz]);
        let ((ax, ay), (bx, by), (cx, cy)) = (shear(a), shear(b), shear(c));
        let u = cx * by - cy * bx;
        let w_ = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || w_ < 0.0 || w < 0.0) && (u > 0.0 || w_ > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + w_ + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t_scaled = u * (sz * a[kz]) + w_ * (sz * b[kz]) + w * (sz * c[kz]);
        Some(t_scaled / det)
    }
}
