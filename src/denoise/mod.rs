//! A denoiser for stochastic renders (issue 16): the edge-avoiding a-trous wavelet filter of
//! Dammertz et al. 2010 guided by albedo and normal buffers taken at the first non-delta hit
//! (`features`), with the per-pixel variance steering the luminance edge stopping (the SVGF
//! idea of Schied et al. 2017, for one frame) (`atrous`). [`gather`] renders the image with
//! its features: the same image, bit for bit, as [`crate::render::render`]. The filter only
//! changes the image: a pixel's recorded tree (`raytree trace`, the diagram, the inspector) is
//! always of its raw samples. See `docs/denoise.md`.

mod atrous;
mod features;
mod gather;
#[cfg(test)]
mod tests;

pub use atrous::{DenoiseParams, DenoiseSteps, denoise};
pub use features::{FeatureSample, MAX_DELTA_BOUNCES, first_non_delta};
pub use gather::{GatherSteps, gather, gather_counted, gather_sampled};

use crate::math::Rgb;
use crate::render::Image;
use glam::DVec3;

/// The guide buffers of a render, row-major like [`Image`].
#[derive(Clone, Debug, PartialEq)]
pub struct Features {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Mean albedo of the pixel's samples ([`FeatureSample::albedo`]).
    pub albedo: Vec<Rgb>,
    /// Mean shading normal of the pixel's samples (not renormalised: shorter where the
    /// samples disagree; zero where they all escape).
    pub normal: Vec<DVec3>,
    /// Variance of the pixel mean's luminance, from its samples (0 with one sample).
    pub variance: Vec<f64>,
    /// Variance of the mean albedo's luminance (the albedo is an estimate too: a lens or the
    /// pixel footprint averages several surfaces), from the samples (0 with one sample).
    pub albedo_variance: Vec<f64>,
    /// Mean emission the pixel's camera rays see directly ([`FeatureSample::emitted`]): kept
    /// out of the filter and added back after it.
    pub emitted: Vec<Rgb>,
    /// Fraction of the pixel's samples whose camera ray hits an emitter's outer side: pixels of
    /// different coverage are filtered apart (a lamp, its antialiased edge and the ceiling
    /// beside it are three classes the albedo and normal cannot separate).
    pub emitter: Vec<f64>,
    /// Samples per pixel.
    pub spp: u32,
    /// Whether the samples are random (path tracing, area lights, glossy lobes, a lens): a
    /// render of one deterministic sample per pixel has no noise and variance 0.
    pub stochastic: bool,
}

impl Features {
    /// The albedo buffer as an image (for `out.albedo.png`).
    #[must_use]
    pub fn albedo_image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self.albedo.clone(),
        }
    }

    /// The normal buffer mapped from [-1, 1] to [0, 1] per axis (for `out.normal.png`).
    #[must_use]
    pub fn normal_image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self.normal.iter().map(|n| *n * 0.5 + 0.5).collect(),
        }
    }
}
