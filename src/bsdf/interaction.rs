//! What the integrator knows at a surface hit, in one value instead of 7-10 arguments.

use super::{Bsdf, Frame};
use crate::scene::Material;
use crate::trace::MediaStack;
use glam::{DVec2, DVec3};

/// A surface hit as shading sees it.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction<'a> {
    /// The hit point.
    pub p: DVec3,
    /// Geometric normal on the outward side.
    pub n: DVec3,
    /// Shading normal on the outward side (the interpolated normal of a smooth mesh, else `n`).
    pub ns: DVec3,
    /// Surface parameters where the shape has them.
    pub uv: Option<DVec2>,
    /// The object's index.
    pub object: usize,
    /// The object's material.
    pub material: &'a Material,
    /// The ray arrived on the outward side.
    pub entering: bool,
    /// The media the arriving ray travels through.
    pub media: MediaStack,
}

impl SurfaceInteraction<'_> {
    /// The local shading frame (`z` = outward shading normal).
    #[must_use]
    pub fn frame(&self) -> Frame {
        Frame::from_normal(self.ns)
    }

    /// `n_inside / n_outside` as the Whitted tracer's interface computes n1 and n2: the outside
    /// is the medium around the object (the media stack without it), the inside the material's
    /// ior (index-matched when it has none).
    #[must_use]
    pub fn eta(&self) -> f64 {
        let outside = if self.entering {
            self.media.ior()
        } else {
            self.media.left(self.object).ior()
        };
        self.material.ior.unwrap_or(outside) / outside
    }

    /// The BSDF at this hit for GGX `roughness` (0: smooth).
    #[must_use]
    pub fn bsdf(&self, roughness: f64) -> Bsdf {
        Bsdf::from_material(self.material, self.p, self.frame(), roughness, self.eta())
    }
}
