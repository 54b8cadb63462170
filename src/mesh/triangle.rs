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
        // Not `v.map`: that stayed an outlined `try_map` call (4% of a render, perf).
        let (a, b, c) = (self.vertex(v[0]), self.vertex(v[1]), self.vertex(v[2]));
        Self::t_of(a, b, c, self.s[2])
    }

    /// A vertex relative to the ray origin and sheared: `(x', y', z)`, the values
    /// [`ShearedRay::t`] computes for it.
    #[inline(always)]
    fn vertex(&self, p: DVec3) -> (f64, f64, f64) {
        let ([kx, ky, kz], [sx, sy, _]) = (self.k, self.s);
        // Arrays, not `DVec3` indexing (a `match` per component); the same values.
        let p = (p - self.origin).to_array();
        (p[kx] - sx * p[kz], p[ky] - sy * p[kz], p[kz])
    }

    /// `triangle_t` of the parallelogram `v` split along `v0 v2` (the two triangles
    /// `v0 v1 v2` and `v0 v2 v3`, the first's hit if any): [`ShearedRay::t`] of each, bit for
    /// bit, with the shared corners `v0` and `v2` translated and sheared once.
    #[inline(always)]
    pub(crate) fn t_quad(&self, v: &[DVec3; 4]) -> Option<f64> {
        let (a, b, c) = (self.vertex(v[0]), self.vertex(v[1]), self.vertex(v[2]));
        let d = self.vertex(v[3]);
        Self::t_of(a, b, c, self.s[2]).or_else(|| Self::t_of(a, c, d, self.s[2]))
    }

    /// The edge functions, the two-sided inside test and the scaled distance of the sheared
    /// vertices `a`, `b`, `c` (`sz`: the shear's scale `1 / d[kz]`).
    #[inline(always)]
    fn t_of(
        (ax, ay, az): (f64, f64, f64),
        (bx, by, bz): (f64, f64, f64),
        (cx, cy, cz): (f64, f64, f64),
        sz: f64,
    ) -> Option<f64> {
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
        let t_scaled = u * (sz * az) + w_ * (sz * bz) + w * (sz * cz);
        Some(t_scaled / det)
    }
}
