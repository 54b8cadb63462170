//! Monte Carlo building blocks: the per-pixel sampler seam ([`PixelSampler`]) with the default
//! [`StratifiedJitter`] and an Owen-scrambled Sobol sampler ([`SobolSampler`]), the scene's choice
//! between them ([`SceneSampler`]), warps from the unit square
//! with their pdfs, and importance-sampled pixel filters. See `docs/monte-carlo.md`.

mod adaptive;
#[cfg(test)]
pub(crate) mod chi2;
mod filter;
mod pixel_sampler;
mod scene_sampler;
mod sobol;
mod stratified;
#[cfg(test)]
mod tests;
pub mod warp;

pub use adaptive::{CONTRAST_FLOOR, Spread, contrast};
pub use filter::PixelFilter;
pub use pixel_sampler::PixelSampler;
pub use scene_sampler::{SamplerKind, SceneSampler};
pub use sobol::{SobolSampler, SplitMix64, mix64, nested_uniform_scramble, pixel_key, sample_2d};
pub use stratified::{StratifiedJitter, splitmix64, unit};
