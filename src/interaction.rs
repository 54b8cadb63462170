//! What an integrator knows at a surface hit, in one value instead of 7-10 arguments: built
//! once per hit by the tracer, read by local shading, the light loops, the dielectric split,
//! the recorder and the BSDFs ([`crate::bsdf::Bsdf::at`]).

use crate::bsdf::Frame;
use crate::media::MediaStack;
use crate::scene::Material;
use glam::DVec3;

/// A surface a ray leaves or hits: an object and, for a mesh, its stored triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceId {
    /// Object index.
    pub object: usize,
    /// For meshes: the stored triangle (`None` for other shapes).
    pub triangle: Option<u32>,
}

/// A hit as shading sees it, built once per hit ([`crate::integrator::Shading::surface`]) and passed to local
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
