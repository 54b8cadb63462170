//! `f32` triangle packs: the vertices of up to four triangles of one BVH group, structure of
//! arrays, and a conservative `f32` version of the watertight edge test that tells which of them
//! the `f64` test ([`crate::geometry::triangle_t`]) could hit.
//!
//! The edge test is the shear-and-permute one of Woop, Benthin and Wald (JCGT 2013) with the same
//! axis choice as the `f64` test, so it is watertight on its own (shared vertices round to the
//! same `f32` values). It only *filters*: a lane is rejected only when all three edge functions
//! are provably off by more than their rounding error, so every triangle the `f64` test hits is
//! kept, including rays exactly through shared edges and vertices (edge functions 0 in `f64`).
//!
//! Error bound. Vertices and the (shifted) ray origin are stored relative to the root box's
//! centre, so with `M` their largest magnitude (`M` = half the root box, `|o|` the origin's)
//! a translated vertex `p - o` is within `2 u (M + |o|)` of exact (`u = 2^-24`: rounding of the
//! stored vertex, the origin and the subtraction) and a sheared coordinate `x - sx z` within
//! `delta = 8 u (M + |o|)` (`|sx| <= 1`; rounding of `sx`, the product and the difference).
//! The `f64` test's own rounding is `2^-53`-sized. An edge function `cx by - cy bx` is then off
//! by at most `delta (|cx| + |cy| + |bx| + |by| + 2 delta) + 3 u (|cx by| + |cy bx|)`, which is
//! at most `4 r delta + 2 delta^2 + 6 u r^2` with `r` the largest sheared coordinate of the
//! triangle: one bound for all three edges. The filter uses twice that `delta`
//! ([`crate::bvh::wide::WideRay::slack`], which also covers the `f64` shift of the origin) and
//! `8 u r^2`. `max` may drop a NaN coordinate, but a NaN also makes an edge function NaN, which
//! no comparison rejects.

use super::triangle::ShearedRay;
use crate::bvh::wide::{GROUP, WideRay, max};
use glam::DVec3;

/// Four triangles: `v[axis][corner][lane]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriPack {
    v: [[[f32; GROUP]; 3]; 3],
}

impl TriPack {
    /// Pack up to [`GROUP`] triangles relative to `center` (unused lanes are zero and masked by
    /// the caller's count).
    pub(crate) fn new(tris: &[[DVec3; 3]], center: DVec3) -> Self {
        let mut v = [[[0.0; GROUP]; 3]; 3];
        for (lane, tri) in tris.iter().take(GROUP).enumerate() {
            for (corner, p) in tri.iter().enumerate() {
                for (axis, row) in v.iter_mut().enumerate() {
                    row[corner][lane] = (p[axis] - center[axis]) as f32;
                }
            }
        }
        Self { v }
    }

    /// Prefetch the pack's lines (144 bytes: addresses at most 48 bytes apart, the last in the
    /// final word).
    #[inline(always)]
    pub(crate) fn prefetch(&self) {
        for row in &self.v {
            crate::bvh::prefetch(row);
        }
        crate::bvh::prefetch(&self.v[2][2][GROUP - 1]);
    }
}

/// Per-query constants of the `f32` edge test.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgeRay {
    /// Axis indices: sheared x, sheared y, ray axis.
    k: [usize; 3],
    sx: f32,
    sy: f32,
    /// Shifted origin, components in `k` order.
    o: [f32; 3],
    /// `4 delta`, the bound's linear factor.
    d4: f32,
    /// `2 delta^2` plus the least normal `f32` (so the bound is never 0).
    dd: f32,
    /// Keep every lane (`f32` unsafe for this query).
    all: bool,
}

type Rows = [[f32; GROUP]; 3];

/// The pack's rows of axes `k`: constant indices per permutation (one predictable jump where
/// three indexings would each be bounds checked).
#[inline(always)]
fn rows(v: &[Rows; 3], k: [usize; 3]) -> (&Rows, &Rows, &Rows) {
    match k {
        [0, 1, 2] => (&v[0], &v[1], &v[2]),
        [1, 2, 0] => (&v[1], &v[2], &v[0]),
        [2, 0, 1] => (&v[2], &v[0], &v[1]),
        [1, 0, 2] => (&v[1], &v[0], &v[2]),
        [2, 1, 0] => (&v[2], &v[1], &v[0]),
        [0, 2, 1] => (&v[0], &v[2], &v[1]),
        [kx, ky, kz] => (&v[kx], &v[ky], &v[kz]),
    }
}

const U4: f32 = 2.0 * f32::EPSILON;

impl EdgeRay {
    /// Constants for the exact test's `sheared` ray, prepared for the BVH as `w`.
    pub(crate) fn new(sheared: &ShearedRay, w: &WideRay) -> Self {
        let [kx, ky, kz] = sheared.k;
        let delta = w.slack;
        Self {
            k: sheared.k,
            sx: sheared.s[0] as f32,
            sy: sheared.s[1] as f32,
            o: [kx, ky, kz].map(|a| w.origin[a]),
            d4: 4.0 * delta,
            dd: 2.0 * delta * delta + f32::MIN_POSITIVE,
            all: w.exact() || !delta.is_finite(),
        }
    }

    /// Bit `l` set for every lane `l < count` the `f64` test might hit.
    #[inline(always)]
    pub(crate) fn candidates(&self, pack: &TriPack, count: u32) -> u32 {
        let lanes = (1u32 << count) - 1;
        if self.all {
            return lanes;
        }
        let (px, py, pz) = rows(&pack.v, self.k);
        let [ox, oy, oz] = self.o;
        let (d4, dd) = (self.d4, self.dd);
        let mut mask = 0;
        for l in 0..GROUP {
            let shear = |c: usize| {
                let z = pz[c][l] - oz;
                (px[c][l] - ox - self.sx * z, py[c][l] - oy - self.sy * z)
            };
            let ((ax, ay), (bx, by), (cx, cy)) = (shear(0), shear(1), shear(2));
            let u = cx * by - cy * bx;
            let v = ax * cy - ay * cx;
            let w = bx * ay - by * ax;
            // One bound for all three edges, from the largest sheared coordinate `r`:
            // delta * 4r + 2 delta^2 + 4u * 2r^2 (module notes).
            let r = max(
                max(max(ax.abs(), ay.abs()), max(bx.abs(), by.abs())),
                max(cx.abs(), cy.abs()),
            );
            let e = r * (d4 + 2.0 * U4 * r) + dd;
            let below = (u < -e) | (v < -e) | (w < -e);
            let above = (u > e) | (v > e) | (w > e);
            mask |= u32::from(!(below & above)) << l;
        }
        mask & lanes
    }
}
