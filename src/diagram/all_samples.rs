//! All samples of a pixel in one figure ([`super::DiagramOptions::all_samples`]): the rays of
//! every other sample drawn under the chosen one, each faded by its sample's share of the
//! largest sample value, so a firefly's path stands out and the dim samples stay a haze.
//!
//! The figure is framed, labelled and annotated on the chosen sample only; the other samples
//! keep the same contribution threshold ([`super::share::keep`]), ray kinds and draw depth.

use super::DiagramOptions;
use super::segments::{Seg3, seg3};
use super::share;
use crate::bsdf::luminance;
use crate::scene::Scene;
use crate::tree::RayTree;

/// The faintest opacity factor of a sample (a black one).
pub const MIN_FADE: f64 = 0.08;

/// The opacity factor of each sample: `MIN_FADE + (1 - MIN_FADE) * sqrt(v / v_max)`, with `v`
/// the luminance of the sample's radiance (the square root keeps a sample at 1 % of the largest
/// at 0.17 rather than invisible). A non-finite sample gets 1; where every sample is black,
/// every factor is `MIN_FADE`.
#[must_use]
pub fn sample_fades(tree: &RayTree) -> Vec<f64> {
    let values: Vec<f64> = tree.samples.iter().map(|s| luminance(s.radiance)).collect();
    let max = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    values
        .iter()
        .map(|v| {
            if !v.is_finite() {
                1.0
            } else if max > 0.0 {
                MIN_FADE + (1.0 - MIN_FADE) * (v.max(0.0) / max).sqrt()
            } else {
                MIN_FADE
            }
        })
        .collect()
}

/// The segments of every sample but `opts.sample`, with the sample index of each.
pub(super) fn other_segs<'a>(
    scene: &Scene,
    tree: &'a RayTree,
    opts: &DiagramOptions,
) -> Vec<(usize, Seg3<'a>)> {
    let mut out = Vec::new();
    if !opts.all_samples {
        return out;
    }
    for (k, s) in tree.samples.iter().enumerate() {
        if k == opts.sample {
            continue;
        }
        let kept = share::keep(tree, k, opts.min_share, &[]);
        out.extend(
            tree.depth_first(s.root)
                .into_iter()
                .filter(|id| kept.kept[id.index()])
                .map(|id| tree.node(id))
                .filter(|n| opts.kinds.contains(&n.kind))
                .filter(|n| opts.max_depth.is_none_or(|d| n.depth <= d))
                .map(|n| (k, seg3(scene, n))),
        );
    }
    out
}
