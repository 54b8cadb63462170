//! The GGX (Trowbridge-Reitz) microfacet distribution, isotropic, with the Smith masking
//! function and visible-normal sampling.
//!
//! Sources: Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces"
//! (D, G1: eq. 33-34); Heitz 2014, "Understanding the Masking-Shadowing Function" (Lambda);
//! Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)); pbrt-v4
//! `TrowbridgeReitzDistribution` (`src/pbrt/util/scattering.h`), whose formulas these are,
//! rewritten without `tan` so that grazing directions give 0 instead of NaN. The shadowing-masking
//! term is the separable product `G1(wo) G1(wi)` (Walter et al. 2007 eq. 23; Mitsuba 3's
//! `MicrofacetDistribution::G`).

use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Alpha below which a lobe is treated as smooth (a delta lobe; pbrt-v4 `EffectivelySmooth`).
pub const SMOOTH_ALPHA: f64 = 1e-3;

/// An isotropic GGX distribution of roughness `alpha` (> 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// The roughness (the distribution's width, `alpha = roughness` here).
    pub alpha: f64,
}

impl Ggx {
    /// The distribution of roughness `alpha`, clamped to at least [`SMOOTH_ALPHA`].
    #[must_use]
    pub fn new(alpha: f64) -> Self {
        Self {
            alpha: alpha.max(SMOOTH_ALPHA),
        }
    }

    /// `D(wm) = 1 / (pi a^2 (cos^2 + sin^2 / a^2)^2)` for `wm` in the upper hemisphere, else 0
    /// (Walter 2007 eq. 33, written as `cos^4 (1 + tan^2/a^2)^2 = (cos^2 + sin^2/a^2)^2`).
    #[must_use]
    pub fn d(&self, wm: DVec3) -> f64 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let k = wm.z * wm.z + (wm.x * wm.x + wm.y * wm.y) / a2;
        1.0 / (PI * a2 * k * k)
    }

    /// `sqrt(cos^2 + a^2 sin^2)`: the common factor of `Lambda` and `G1`.
    fn root(&self, w: DVec3) -> f64 {
        let a2 = self.alpha * self.alpha;
        (w.z * w.z + a2 * (w.x * w.x + w.y * w.y)).sqrt()
    }

    /// Smith masking `G1(w) = 1 / (1 + Lambda(w)) = 2 |cos| / (|cos| + sqrt(cos^2 + a^2 sin^2))`
    /// (Walter 2007 eq. 34); 0 at grazing.
    #[must_use]
    pub fn g1(&self, w: DVec3) -> f64 {
        let c = w.z.abs();
        let r = self.root(w);
        if r == 0.0 { 0.0 } else { 2.0 * c / (c + r) }
    }

    /// The separable shadowing-masking `G1(wo) G1(wi)`.
    #[must_use]
    pub fn g(&self, wo: DVec3, wi: DVec3) -> f64 {
        self.g1(wo) * self.g1(wi)
    }

    /// The density of visible normals seen from `w`,
    /// `D_w(wm) = G1(w) max(0, w.wm) D(wm) / |cos w|` (Heitz 2018 eq. 1), as a density of `wm`
    /// per solid angle, with `w` below the surface first mirrored to the upper side (as
    /// [`Self::sample_visible`] does). `G1 / |cos|` is evaluated as `2 / (|cos| + root)`,
    /// finite at grazing.
    #[must_use]
    pub fn d_visible(&self, w: DVec3, wm: DVec3) -> f64 {
        let denom = w.z.abs() + self.root(w);
        let facing = if w.z < 0.0 { -w.dot(wm) } else { w.dot(wm) };
        if denom == 0.0 || facing <= 0.0 {
            return 0.0;
        }
        2.0 / denom * facing * self.d(wm)
    }

    /// A microfacet normal (upper hemisphere) drawn with density [`Self::d_visible`] for the
    /// direction `w` (either hemisphere: the visible normals of `w` flipped into the upper one),
    /// by Heitz 2018's algorithm as written in pbrt-v4 `Sample_wm`.
    #[must_use]
    pub fn sample_visible(&self, w: DVec3, u: DVec2) -> DVec3 {
        let a = self.alpha;
        // Stretch to the hemisphere configuration (alpha = 1).
        let mut wh = DVec3::new(a * w.x, a * w.y, w.z).normalize_or(DVec3::Z);
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            DVec3::Z.cross(wh).normalize()
        } else {
            DVec3::X
        };
        let t2 = wh.cross(t1);
        // Uniform disk (polar), warped to the projected visible hemisphere.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let (px, py0) = (r * phi.cos(), r * phi.sin());
        let h = (1.0 - px * px).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        let py = (1.0 - s) * h + s * py0;
        let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
        let nh = px * t1 + py * t2 + pz * wh;
        // Unstretch.
        DVec3::new(a * nh.x, a * nh.y, nh.z.max(1e-6)).normalize()
    }
}
