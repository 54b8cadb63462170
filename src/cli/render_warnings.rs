//! The warnings every render prints about its image (`raytree render`, with or without AOVs).

use super::args::RenderArgs;
use super::output::ImageFormat;
use super::say::warnln;

/// The warnings every render prints about its image, with or without AOVs: EXR channels
/// clamped, samples cut by the ray budget, pixels not finite (written black, with the first
/// one's tree).
pub fn warn_image(
    a: &RenderArgs,
    scene: &raytree::Scene,
    stats: &raytree::RenderStats,
    clamped: usize,
    format: ImageFormat,
) {
    if clamped > 0 && format == ImageFormat::Exr {
        warnln!(
            "warning: {clamped} pixels had a channel beyond the 32-bit float range (3.4e38) and were clamped to it in {}",
            a.output.display()
        );
    }
    let r = &stats.rays;
    if r.budget_samples > 0 {
        warnln!(
            "warning: {} samples reached the ray budget of {} rays per sample (--max-rays); {} secondary rays were cut there (`raytree trace` records the weight cut)",
            r.budget_samples,
            scene.settings.max_rays,
            r.budget_cuts
        );
    }
    if let Some((x, y)) = stats.first_nonfinite {
        warnln!(
            "warning: {} pixels were not finite and were written black; first at {x},{y} (`raytree trace --pixel {x},{y}`); its tree:",
            stats.nonfinite_pixels
        );
        if let Some(tree) = raytree::trace_pixel(scene, x, y) {
            super::say::err(&raytree::text::tree_text(&tree));
        }
    }
}
