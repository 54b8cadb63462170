//! `raytree render --denoise / --features`: the render with its guide buffers, the denoised
//! image, and the albedo and normal images beside the output (`raytree::denoise`).

use super::args::RenderArgs;
use super::output::{ImageFormat, Origin, OutputSet, encode_counting};
use super::say::sayln;
use anyhow::Result;
use raytree::denoise::{DenoiseParams, Features, denoise, gather_counted};
use raytree::sampling::SceneSampler;
use raytree::{DiagnosticMap, Image, RenderStats, Scene, SceneIntegrator};
use std::cell::RefCell;
use std::path::Path;
use std::time::Instant;

/// Bytes a pixel may need at once with the features and the filter: the rows' per-pixel
/// results (88), the features (64), the image (24), the demodulated albedo and illumination and
/// their next pass (96), the variance and its blur (32), a pass's output (56), the encoders (24).
pub const PIXEL_BYTES: u64 = 384;

/// The reserved guide outputs (when `--features`) and what the render leaves for them.
pub struct Guides {
    denoise: bool,
    files: Option<(usize, usize)>,
    features: RefCell<Option<Features>>,
}

/// `out.png` -> `out.NAME.png`.
fn beside(output: &Path, name: &str) -> std::path::PathBuf {
    let ext = output.extension().and_then(|e| e.to_str()).unwrap_or("png");
    output.with_extension(format!("{name}.{ext}"))
}

impl Guides {
    /// `None` unless `--denoise` or `--features`; reserves the feature files.
    pub fn create(a: &RenderArgs, set: &mut OutputSet) -> Result<Option<Self>> {
        if !a.denoise && !a.features {
            return Ok(None);
        }
        let files = if a.features {
            Some((
                set.reserve(&beside(&a.output, "albedo"), Origin::Derived("--features"))?,
                set.reserve(&beside(&a.output, "normal"), Origin::Derived("--features"))?,
            ))
        } else {
            None
        };
        Ok(Some(Self {
            denoise: a.denoise,
            files,
            features: RefCell::new(None),
        }))
    }

    /// Render with the features (the same image as the plain render) and, with `--denoise`,
    /// return the denoised image; prints the filter's time.
    /// Also returns the samples each pixel took (for `--spp-map`).
    pub fn render(
        &self,
        scene: &Scene,
        progress: &(dyn Fn(u32) + Sync),
    ) -> (Image, RenderStats, DiagnosticMap) {
        let sampler = SceneSampler::for_settings(&scene.settings);
        let (image, stats, features, map) =
            gather_counted(&SceneIntegrator::new(scene), &sampler, progress);
        let image = if self.denoise {
            let t = Instant::now();
            let out = denoise(&image, &features, &DenoiseParams::default());
            let _ = sayln!(
                "denoised in {:.3} s (a-trous, {} passes; the traced trees are of the raw samples)",
                t.elapsed().as_secs_f64(),
                DenoiseParams::default().iterations
            );
            out
        } else {
            image
        };
        *self.features.borrow_mut() = Some(features);
        (image, stats, map)
    }

    /// Stage the albedo and normal images (with `--features`) in `set`.
    pub fn stage(self, set: &mut OutputSet, format: ImageFormat) -> Result<()> {
        if let (Some((albedo, normal)), Some(f)) = (self.files, self.features.into_inner()) {
            set.stage(albedo, &encode_counting(&f.albedo_image(), format)?.0)?;
            set.stage(normal, &encode_counting(&f.normal_image(), format)?.0)?;
        }
        Ok(())
    }
}
