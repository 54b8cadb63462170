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
use crate::tree::{NodeId, RayTree};

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

/// The most rays of the other samples one figure draws (the chosen sample is always drawn
/// whole). Past it, the dimmest samples are left out whole and the legend says how many: a
/// 16384-spp pixel stays a figure a viewer can open, not a 100 MB SVG.
pub const MAX_OTHER_RAYS: usize = 20_000;

/// The sample (its position in `tree.samples`) that carries the most light: the largest
/// finite luminance of its radiance, the first of equals; `None` for a tree without samples.
/// A non-finite sample is never chosen over a finite one (its figure would say nothing).
#[must_use]
pub fn brightest(tree: &RayTree) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (k, s) in tree.samples.iter().enumerate() {
        let v = luminance(s.radiance);
        let v = if v.is_finite() { v } else { f64::NEG_INFINITY };
        if best.is_none_or(|(_, b)| v > b) {
            best = Some((k, v));
        }
    }
    best.map(|(k, _)| k)
}

/// The other samples' segments a figure draws, and what the bound left out.
pub(super) struct Others<'a> {
    /// Each drawn segment with the position of its sample, in sample order.
    pub segs: Vec<(usize, Seg3<'a>)>,
    /// Samples left out whole by [`MAX_OTHER_RAYS`].
    pub left_out_samples: usize,
    /// The rays those samples would have drawn.
    pub left_out_rays: usize,
}

/// The segments of every sample but `opts.sample` (threshold, kinds and draw depth as for the
/// chosen one), brightest samples first up to [`MAX_OTHER_RAYS`] rays, drawn in sample order.
/// Linear in the pixel's rays: the shares are computed once and one `kept` array serves every
/// sample (their subtrees are disjoint).
pub(super) fn other_segs<'a>(
    scene: &Scene,
    tree: &'a RayTree,
    opts: &DiagramOptions,
) -> Others<'a> {
    let mut out = Others {
        segs: Vec::new(),
        left_out_samples: 0,
        left_out_rays: 0,
    };
    if !opts.all_samples {
        return out;
    }
    let share = share::shares(tree);
    let mut kept = vec![false; tree.nodes.len()];
    let mut per_sample: Vec<(usize, Vec<NodeId>)> = Vec::new();
    for (k, s) in tree.samples.iter().enumerate() {
        if k == opts.sample {
            continue;
        }
        let order = tree.depth_first(s.root);
        share::mark_kept(tree, &order, &share, opts.min_share, &mut kept);
        let ids: Vec<NodeId> = order
            .into_iter()
            .filter(|id| kept[id.index()])
            .filter(|id| {
                let n = tree.node(*id);
                opts.kinds.contains(&n.kind) && opts.max_depth.is_none_or(|d| n.depth <= d)
            })
            .collect();
        per_sample.push((k, ids));
    }
    // Brightest first (the order of `sample_fades`, the first of equals first).
    let fades = sample_fades(tree);
    let mut by_light: Vec<usize> = (0..per_sample.len()).collect();
    by_light.sort_by(|a, b| fades[per_sample[*b].0].total_cmp(&fades[per_sample[*a].0]));
    let mut chosen = vec![false; per_sample.len()];
    let mut total = 0;
    for i in by_light {
        let n = per_sample[i].1.len();
        if total + n <= MAX_OTHER_RAYS {
            total += n;
            chosen[i] = true;
        } else {
            out.left_out_samples += 1;
            out.left_out_rays += n;
        }
    }
    for ((k, ids), _) in per_sample.iter().zip(&chosen).filter(|(_, c)| **c) {
        out.segs
            .extend(ids.iter().map(|id| (*k, seg3(scene, tree.node(*id)))));
    }
    out
}
