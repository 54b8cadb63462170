//! What an integrator knows at a surface hit, in one value instead of 7-10 arguments: built
//! once per hit by the tracer, read by local shading, the light loops, the dielectric split,
//! the recorder and the BSDFs ([`crate::bsdf::Bsdf::at`]).

use crate::bsdf::{Bsdf, Frame, Material};
use crate::media::MediaStack;
use glam::DVec3;

/// A surface a ray leaves or hits: an object and, for a mesh, its stored triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceId {
    /// Object index.
    pub object: usize,
    /// For meshes: the stored triangle (`None` for other shapes).
    pub triangle: Option<u32>,
}

/// A hit as shading sees it, built once per hit (`Shading::surface`) and passed to local
/// shading, the light loops, the dielectric split and the recorder.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction<'a> {
    /// The hit point.
    pub p: DVec3,
    /// Unit direction back along the incoming ray (towards its origin).
    pub wo: DVec3,
    /// The ray arrives on the outward side of the surface.
    pub entering: bool,
    /// Geometric normal on the incident side: decides sides and offsets.
    pub n: DVec3,
    /// Shading normal on the incident side: lighting, mirror and Snell (mesh::shading rule).
    pub ns: DVec3,
    /// The interpolated normal of a smooth mesh, as stored (`None` for flat surfaces).
    pub smooth: Option<DVec3>,
    /// Cosine of the incidence angle against `ns`.
    pub cos_i: f64,
    /// Index into [`crate::Scene::objects`] of the surface hit.
    pub object: usize,
    /// For meshes: the stored triangle hit.
    pub triangle: Option<u32>,
    /// The surface's material.
    pub material: &'a Material,
    /// The media the incoming ray travels through (innermost on top).
    pub media: &'a MediaStack,
}

impl SurfaceInteraction<'_> {
    /// The surface as the offset strategies name it: object and stored triangle.
    #[inline(always)]
    #[must_use]
    pub fn from(&self) -> SurfaceId {
        SurfaceId {
            object: self.object,
            triangle: self.triangle,
        }
    }

    /// The shading normal on the outward side of the surface.
    #[must_use]
    pub fn outward_shading_normal(&self) -> DVec3 {
        if self.entering { self.ns } else { -self.ns }
    }

    /// The local shading frame (`z` = outward shading normal), as the BSDFs take it.
    #[must_use]
    pub fn frame(&self) -> Frame {
        let n = self.outward_shading_normal();
        if self.material.is_anisotropic() {
            // The first tangent (alpha_u) follows the material's tangent direction.
            Frame::from_normal_tangent(n, self.material.tangent)
        } else {
            Frame::from_normal(n)
        }
    }

    /// `n_inside / n_outside` as the Whitted tracer's interface computes n1 and n2: the outside
    /// is the medium around the object (the media stack without it), the inside the material's
    /// ior (index-matched when it has none).
    #[must_use]
    pub fn eta(&self) -> f64 {
        let outside = if self.entering {
            self.media.ior()
        } else {
            self.media.ior_outside(self.object)
        };
        self.material.ior.unwrap_or(outside) / outside
    }
}

/// The BSDF at a surface interaction (here, so that the BSDFs do not depend on the
/// interaction).
impl Bsdf {
    /// The BSDF of `m` at `p` as the Whitted tracer reads the material: Lambert (diffuse),
    /// mirror (`reflectivity`), dielectric (`transmissivity`, `eta = n_inside / n_outside`), the
    /// last two GGX-rough when `roughness >= SMOOTH_ALPHA`. Index-matched transmission
    /// (`eta = 1`) stays a smooth pass-through whatever the roughness (every microfacet sends
    /// light straight on). The Blinn-Phong `specular` term has no lobe here.
    /// (Built from a surface interaction: its material, point, outward shading frame and eta;
    /// eta, which reads the media stack, only for a transmissive material, the only lobe that
    /// uses it.)
    #[must_use]
    pub fn at(si: &SurfaceInteraction, roughness: f64) -> Self {
        let mut out = Bsdf::empty(si.frame());
        out.reset_at(si, roughness);
        out
    }

    /// Makes this the BSDF [`Bsdf::at`] builds, in place: a loop that keeps one `Bsdf` and
    /// resets it at every hit writes only the lobes the material has (building a 300-byte
    /// `Bsdf` by value and moving it was a `memcpy` per hit, 2% of a path-traced render).
    #[inline(always)]
    pub fn reset_at(&mut self, si: &SurfaceInteraction, roughness: f64) {
        let m = si.material;
        let eta = if m.is_transmissive() { si.eta() } else { 1.0 };
        self.reset_with(si.frame(), m, si.p, roughness, eta);
    }
}
