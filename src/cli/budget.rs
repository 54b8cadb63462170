//! Memory budgets checked before any work (issue 13): what a command may need is estimated from
//! the image size, the sample count and the per-sample ray budget, and what cannot fit in
//! `--max-memory` is refused (exit 2) or, for recorded trees, cut with a warning.

use anyhow::{Result, bail};
use raytree::{RayNode, RayTree, Scene};

/// Default `--max-memory` in MiB (4 GiB).
pub const DEFAULT_MIB: u64 = 4096;

/// Bytes a rendered pixel may need at once: the linear image (24), a row's copy while bands
/// are gathered (24), the encoder's input (`f32` RGB for EXR, 12) and its output (up to 12),
/// diagnostic counts (8).
pub const PIXEL_BYTES: u64 = 80;

/// Bytes one recorded ray may need while its tree is held and printed: the node itself, its
/// heap parts (names, the children list, under the path integrator the path record and its
/// light path string of up to one letter pair per bounce), the allocator's rounding, and the
/// analysis a command builds beside it (the explanation, the LPE filter's copy). JSON is
/// streamed (`say::json`), so the text never exists whole. Checked against the measured peak
/// by `tests/hostile/round3.rs`.
fn node_bytes(scene: &Scene) -> u64 {
    let node = std::mem::size_of::<RayNode>() as u64;
    // The text form: a line of about 300 bytes a ray.
    let heap = match scene.settings.integrator {
        raytree::scene::IntegratorKind::Whitted => 96 + 512,
        _ => 2 * u64::from(scene.settings.max_depth) + 96 + 512,
    };
    // Twice: the filtered or explained copy a command may hold beside the tree.
    2 * (node + heap)
}

/// The most samples one pixel can record: `spp`, or a refined pixel's total under adaptive or
/// automatic antialiasing (`--max-spp`).
fn max_samples(scene: &Scene) -> u64 {
    let integrator = raytree::SceneIntegrator::new(scene);
    let plan = raytree::render::adaptive_plan(&integrator).map_or(0, |p| p.total);
    u64::from(scene.settings.spp.max(plan).max(1))
}

/// The budget in MiB: `--max-memory`, else [`DEFAULT_MIB`] or half the process's
/// address-space limit when smaller (the rest for code, stacks and the allocator's arenas).
#[must_use]
pub fn mib(flag: Option<u64>) -> u64 {
    flag.unwrap_or_else(|| {
        let limit = std::fs::read_to_string("/proc/self/limits")
            .ok()
            .and_then(|s| address_space_limit(&s));
        limit.map_or(DEFAULT_MIB, |bytes| DEFAULT_MIB.min((bytes / 2) >> 20))
    })
}

/// The soft "Max address space" of a `/proc/self/limits` text, in bytes (`None`: unlimited).
fn address_space_limit(limits: &str) -> Option<u64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn budget_bytes(mib: u64) -> u64 {
    mib.saturating_mul(1 << 20)
}

fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / f64::from(1u32 << 30))
}

/// Refuse an image that cannot fit the budget.
pub fn check_image(scene: &Scene, mib: u64) -> Result<()> {
    check_image_with(scene, mib, PIXEL_BYTES)
}

/// Refuse an image that cannot fit the budget at `per_pixel` bytes a pixel.
pub fn check_image_with(scene: &Scene, mib: u64, per_pixel: u64) -> Result<()> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let need = u64::from(w) * u64::from(h) * per_pixel;
    if need > budget_bytes(mib) {
        bail!(
            "a {w}x{h} image needs about {} ({per_pixel} bytes per pixel), more than the memory budget of {mib} MiB; use a smaller --size or raise --max-memory",
            gib(need)
        );
    }
    Ok(())
}

/// Refuse an AOV render (`render --aov`) that cannot fit the budget: the beauty image, one
/// image per AOV and the per-pixel statistics ([`raytree::aov::McPixel`]).
pub fn check_aov_images(scene: &Scene, aovs: usize, mib: u64) -> Result<()> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let per_pixel =
        PIXEL_BYTES * (1 + aovs as u64) + std::mem::size_of::<raytree::aov::McPixel>() as u64;
    let need = u64::from(w) * u64::from(h) * per_pixel;
    if need > budget_bytes(mib) {
        bail!(
            "a {w}x{h} image with {aovs} AOVs needs about {} ({per_pixel} bytes per pixel), more than the memory budget of {mib} MiB; use a smaller --size, fewer --aov or raise --max-memory",
            gib(need)
        );
    }
    Ok(())
}

/// Lower the scene's per-sample ray budget so that the recorded tree of one pixel fits the
/// memory budget; refuse when not even each sample's camera and shadow rays fit. Returns the
/// ray budget when the memory lowered it.
pub fn fit_tree(scene: &mut Scene, mib: u64) -> Result<Option<u64>> {
    let spp = max_samples(scene);
    let per_node = node_bytes(scene);
    // A sample's rays: at most `max_rays`, plus the last secondary ray's shadow rays.
    let extra = scene.lights.len() as u64 + 1;
    let fit = camera_bytes(scene, mib) / per_node / spp;
    if fit <= extra {
        bail!(
            "the tree of {spp} samples needs at least {} ({} rays per sample at {per_node} bytes), more than the memory budget of {mib} MiB; lower --spp or raise --max-memory",
            gib(spp * (extra + 1) * per_node),
            extra + 1
        );
    }
    let cap = fit - extra;
    if scene.settings.max_rays > cap {
        scene.settings.max_rays = cap;
        return Ok(Some(cap));
    }
    Ok(None)
}

/// Whether the scene's integrator splats light paths into pixels (light tracing, BDPT).
fn splats(scene: &Scene) -> bool {
    matches!(
        scene.settings.integrator,
        raytree::scene::IntegratorKind::Light | raytree::scene::IntegratorKind::Bdpt
    )
}

/// The part of the budget a traced pixel's camera samples may use: all of it, or half under
/// splatting integrators (the other half is for the light paths that land in the pixel,
/// [`splat_paths`]).
fn camera_bytes(scene: &Scene, mib: u64) -> u64 {
    let all = budget_bytes(mib);
    if splats(scene) { all / 2 } else { all }
}

/// Rays one recorded light path may hold: a light ray per vertex (at most `max_depth + 2`) and
/// a connection to the camera from each.
fn nodes_per_light_path(scene: &Scene) -> u64 {
    2 * (u64::from(scene.settings.max_depth) + 3)
}

/// The most light paths a traced pixel may record within the budget's other half.
#[must_use]
pub fn splat_paths(scene: &Scene, mib: u64) -> u64 {
    let all = budget_bytes(mib);
    (all - camera_bytes(scene, mib)) / node_bytes(scene) / nodes_per_light_path(scene)
}

/// Trace pixel (x, y) within the memory budget (after [`fit_tree`]): under light tracing and
/// BDPT, refuse a pixel that more light paths land in than the budget can record. `None` when
/// the pixel is outside the image.
pub fn trace(scene: &Scene, (x, y): (u32, u32), mib: u64) -> Result<Option<RayTree>> {
    let limit = splat_paths(scene, mib);
    raytree::render::trace_pixel_within(scene, x, y, limit).map_err(|e| {
        let need = e.paths * nodes_per_light_path(scene) * node_bytes(scene);
        anyhow::anyhow!(
            "{} light paths land in pixel {x},{y}; recording them may need about {:.1} MiB ({} rays a path at {} bytes), more than the half of the memory budget of {mib} MiB kept for them (room for {} path{}); lower --spp or --size, or raise --max-memory",
            e.paths,
            need as f64 / f64::from(1u32 << 20),
            nodes_per_light_path(scene),
            node_bytes(scene),
            e.limit,
            if e.limit == 1 { "" } else { "s" }
        )
    })
}

/// Samples of `tree` cut by their ray budget.
#[must_use]
pub fn cut_samples(tree: &RayTree) -> usize {
    tree.samples
        .iter()
        .filter(|s| {
            tree.depth_first(s.root)
                .iter()
                .any(|&id| tree.node(id).end == raytree::tree::EndReason::RayBudget)
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_address_space_limit_is_read_from_proc_limits() {
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(address_space_limit(unlimited), None);
        let capped = "Max stack size            8388608              unlimited            bytes\n\
                      Max address space         2147483648           2147483648           bytes\n";
        assert_eq!(address_space_limit(capped), Some(2_147_483_648));
        assert_eq!(mib(Some(7)), 7);
    }
}
