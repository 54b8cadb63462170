//! A mesh's area distribution, for sampling it as an area light (`crate::lights::mesh`): the
//! running sums of its triangles' areas, so a triangle is chosen in proportion to its area.

use super::Mesh;
use glam::{DVec2, DVec3};

/// The running sums of the stored triangles' areas (the last one is the mesh's area).
pub(super) fn area_cdf(tris: &[[DVec3; 3]]) -> Vec<f64> {
    let mut sum = 0.0;
    tris.iter()
        .map(|&[a, b, c]| {
            sum += 0.5 * (b - a).cross(c - a).length();
            sum
        })
        .collect()
}

impl Mesh {
    /// Total surface area.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area_cdf.last().copied().unwrap_or(0.0)
    }

    /// The stored triangle `u.x` picks in proportion to area: its vertices, its area `a`, the
    /// mesh's area and `u` with `u.x` rescaled into the triangle's own sample; `None` for a
    /// mesh of no area.
    #[must_use]
    pub fn pick_triangle(&self, u: DVec2) -> Option<([DVec3; 3], f64, f64, DVec2)> {
        let total = self.area();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let target = u.x * total;
        let i = self
            .area_cdf
            .partition_point(|&c| c <= target)
            .min(self.tris.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.area_cdf[i - 1] };
        let a = self.area_cdf[i] - lo;
        let ux = ((target - lo) / a).clamp(0.0, 1.0 - f64::EPSILON / 2.0);
        Some((self.tris[i], a, total, DVec2::new(ux, u.y)))
    }
}
