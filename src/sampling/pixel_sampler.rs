//! The per-pixel sampler seam: where every sample position (and, for stochastic integrators,
//! every random number of a camera sample) comes from.
//!
//! A sampler is deterministic in (seed, pixel, sample index, dimension): the render and the
//! re-trace of one pixel ask it the same questions in the same order and get the same bits, so
//! a recorded tree equals its rendered pixel. [`render_pixel`](crate::render::render_pixel) calls
//! [`PixelSampler::start_sample`] before each camera sample and takes the film offset inside
//! the pixel as the sample's first [`PixelSampler::next_2d`]; integrators draw further
//! dimensions from the same sampler. [`StratifiedJitter`] is the default, today's positions bit
//! for bit at seed 0.

/// A source of sample values in `[0, 1)`, restarted for each (pixel, sample index).
///
/// Implementations must be deterministic: after `start_sample(pixel, index)` the sequence of
/// `next_1d`/`next_2d` answers depends only on the sampler's configuration (seed, samples per
/// pixel), the pixel, the index and the position in the sequence (the dimension).
pub trait PixelSampler: Clone + Send + Sync {
    /// Start sample `index` of pixel `(x, y)`: the next value is dimension 0.
    fn start_sample(&mut self, pixel: (u32, u32), index: u32);
    /// The next dimension, in `[0, 1)`.
    fn next_1d(&mut self) -> f64;
    /// The next two dimensions, in `[0, 1)^2`.
    fn next_2d(&mut self) -> (f64, f64);
    /// Turn this (a copy of the pixel's sampler) into the sampler of adaptive antialiasing's
    /// second pass: samples `first..first + count` of the same pixels. The default continues
    /// the sequence (indices from `first` on); a stratified sampler puts the pass on its own
    /// complete grid of `count` strata, so that no stratum is left empty.
    fn refine(&mut self, first: u32, count: u32) {
        let _ = (first, count);
    }
}
