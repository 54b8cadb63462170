//! The render's outputs: the image, what the render did, per-pixel diagnostic counts.

use crate::integrator::RayCounts;
use crate::math::Rgb;

/// A linear-radiance image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<Rgb>,
}

impl Image {
    /// The pixel at (x, y).
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[(y * self.width + x) as usize]
    }

    /// 8-bit sRGB bytes, RGB order, clamped.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.to_array().map(crate::math::linear_to_srgb8))
            .collect()
    }
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced by kind.
    pub rays: RayCounts,
    /// Pixels whose value was not finite (replaced by black).
    pub nonfinite_pixels: u64,
    /// The first such pixel, in scan order.
    pub first_nonfinite: Option<(u32, u32)>,
    /// Pixels with at least one self-hit ray (diagnosed renders only; see `integrator::diagnose`).
    pub self_hit_pixels: u64,
    /// Pixels with at least one leaking ray (diagnosed renders only).
    pub leak_pixels: u64,
    /// Camera samples taken (`width * height * spp` without adaptive antialiasing).
    pub samples: u64,
    /// Pixels adaptive antialiasing refined (took more than `spp` samples).
    pub refined_pixels: u64,
}

impl RenderStats {
    /// Pixel (x, y) as it enters the image: itself when finite; otherwise black, counted in
    /// [`RenderStats::nonfinite_pixels`] and the first named in
    /// [`RenderStats::first_nonfinite`], so no NaN reaches an image.
    #[inline]
    pub fn admit_pixel(&mut self, p: Rgb, x: usize, y: usize) -> Rgb {
        if p.is_finite() {
            return p;
        }
        self.nonfinite_pixels += 1;
        self.first_nonfinite.get_or_insert((x as u32, y as u32));
        Rgb::ZERO
    }
}

/// Per-pixel diagnostic counts of a diagnosed render, row-major like [`Image`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DiagnosticMap {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Self-hit rays per pixel.
    pub self_hits: Vec<u32>,
    /// Leaking rays per pixel.
    pub leaks: Vec<u32>,
    /// Camera samples per pixel (`spp`, or more where adaptive antialiasing refined).
    pub samples: Vec<u32>,
}
