//! Which rays a figure keeps: each ray's share of its sample's value, and the contribution
//! threshold ([`super::DiagramOptions::min_share`]) that leaves out the rays carrying less.
//!
//! A reflected, refracted or camera ray carries `throughput x radiance` (everything below it);
//! a shadow ray carries its part of its surface's local term, measured **unblocked**
//! (`surface throughput x Beer x BRDF cos x irradiance`), so a shadow ray that explains a dark
//! pixel (blocked, or dimmed by a translucent blocker) is kept when the light it stops would
//! have been visible. Shares are Rec. 709 luminance fractions of the sample's value, as in
//! `raytree explain`. In a black sample every share is 0/0, so shares fall back to the ray's
//! throughput (the part of the eye's view that follows the ray). A non-finite share counts as
//! 1: a NaN ray is always drawn.

use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};

/// Rec. 709 luminance (the measure of `raytree explain`'s shares).
fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

fn atten(n: &RayNode) -> Rgb {
    n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor)
}

/// What ray `n` adds to its sample's value (not divided by the sample count): for a shadow ray
/// its part of the surface's local term as cast (`unblocked = false`) or as if nothing were in
/// the way (`unblocked = true`).
#[must_use]
pub fn carried(tree: &RayTree, n: &RayNode, unblocked: bool) -> Rgb {
    match (n.kind, n.parent) {
        (RayKind::Shadow, Some(p)) => {
            let surface = tree.node(p);
            let arriving = match (&n.shadow, unblocked) {
                (Some(s), true) => s.irradiance,
                _ => n.radiance,
            };
            surface.throughput * atten(surface) * n.weight * arriving
        }
        _ => n.contribution(),
    }
}

/// Every node's share of the value of its sample, indexed by node id (see the module docs).
#[must_use]
pub fn shares(tree: &RayTree) -> Vec<f64> {
    let mut out = vec![0.0; tree.nodes.len()];
    for s in &tree.samples {
        let total = luminance(s.radiance);
        let by_throughput = !(total > 0.0 && total.is_finite());
        for id in tree.depth_first(s.root) {
            let n = tree.node(id);
            let share = if by_throughput {
                match (n.kind, n.parent) {
                    (RayKind::Shadow, Some(p)) => tree.node(p).throughput.max_element(),
                    _ => n.throughput.max_element(),
                }
            } else {
                luminance(carried(tree, n, true)) / total
            };
            out[id.index()] = if share.is_finite() { share } else { 1.0 };
        }
    }
    out
}

/// The rays of one sample a figure keeps, and what it leaves out.
#[derive(Clone, Debug, PartialEq)]
pub struct Kept {
    /// Per node id: drawn or not (nodes of other samples are `false`).
    pub kept: Vec<bool>,
    /// The threshold applied (a share of the sample's value, 0 = keep all).
    pub min_share: f64,
    /// Rays of the sample left out.
    pub dropped: usize,
    /// The part of the sample's value the left-out rays carry (their subtrees are disjoint:
    /// a left-out ray whose parent is kept, counted once with everything below it).
    pub dropped_share: f64,
}

/// Keep the rays of sample `sample` whose share is at least `min_share`, their ancestors
/// (so every kept ray hangs from a kept one), and the rays of `always` with their ancestors.
#[must_use]
pub fn keep(tree: &RayTree, sample: usize, min_share: f64, always: &[NodeId]) -> Kept {
    let mut kept = vec![false; tree.nodes.len()];
    let Some(s) = tree.samples.get(sample) else {
        return Kept {
            kept,
            min_share,
            dropped: 0,
            dropped_share: 0.0,
        };
    };
    let share = shares(tree);
    let order = tree.depth_first(s.root);
    let in_sample = {
        let mut v = vec![false; tree.nodes.len()];
        for id in &order {
            v[id.index()] = true;
        }
        v
    };
    mark_kept(tree, &order, &share, min_share, &mut kept);
    for id in always {
        if id.index() < kept.len() && in_sample[id.index()] {
            mark(tree, *id, &mut kept);
        }
    }
    let total = luminance(s.radiance);
    let mut dropped = 0;
    let mut lost = 0.0;
    for id in &order {
        let n = tree.node(*id);
        if kept[id.index()] {
            continue;
        }
        dropped += 1;
        if n.parent.is_some_and(|p| kept[p.index()]) {
            lost += luminance(carried(tree, n, false));
        }
    }
    let dropped_share = if total > 0.0 && total.is_finite() && lost.is_finite() {
        lost / total
    } else {
        0.0
    };
    Kept {
        kept,
        min_share,
        dropped,
        dropped_share,
    }
}

/// Mark `id` and its ancestors kept (stopping at the first one already kept).
fn mark(tree: &RayTree, id: NodeId, kept: &mut [bool]) {
    let mut cur = Some(id);
    while let Some(c) = cur {
        if kept[c.index()] {
            break;
        }
        kept[c.index()] = true;
        cur = tree.node(c).parent;
    }
}

/// Mark kept, in `kept` (indexed by node id), the rays of one sample (`order`: its nodes,
/// root first) whose share in `share` (from [`shares`]) is at least `min_share`, with their
/// ancestors, and the root. Work is linear in the sample's rays, so a caller that walks every
/// sample of a pixel with one `kept` and one `share` does work linear in the pixel's rays
/// (samples' subtrees are disjoint).
pub fn mark_kept(
    tree: &RayTree,
    order: &[NodeId],
    share: &[f64],
    min_share: f64,
    kept: &mut [bool],
) {
    let Some(root) = order.first() else {
        return;
    };
    mark(tree, *root, kept);
    for id in order {
        if share[id.index()] >= min_share || min_share <= 0.0 {
            mark(tree, *id, kept);
        }
    }
}
