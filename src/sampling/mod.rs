//! Monte Carlo building blocks: a deterministic per-pixel sampler, warps from the unit square
//! with their pdfs, and importance-sampled pixel filters. See `docs/monte-carlo.md`.

#[cfg(test)]
pub(crate) mod chi2;
mod filter;
mod sobol;
#[cfg(test)]
mod tests;
pub mod warp;

pub use filter::PixelFilter;
pub use sobol::{PixelSampler, SplitMix64, mix64, nested_uniform_scramble, pixel_key, sample_2d};
