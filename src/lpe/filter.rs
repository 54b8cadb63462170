//! Keep only the paths of a ray tree whose light path expression matches.

use super::Lpe;
use crate::math::Rgb;
use crate::tree::{NodeId, RayTree, SampleRecord};

/// A tree filtered by light path expressions ([`filter_tree`]).
#[derive(Clone, Debug)]
pub struct LpeFilter {
    /// The kept nodes (renumbered `0..`, parents before children) and the samples that keep one.
    pub tree: RayTree,
    /// Complete paths (a node whose `lpe` ends in `L` or `B`) that match.
    pub matched: usize,
    /// Complete paths in the tree.
    pub paths: usize,
    /// What the matching paths add to the pixel (the mean over samples of their contributions).
    pub radiance: Rgb,
    /// `radiance` over the pixel's radiance, by luminance (`None` for a black pixel).
    pub share: Option<f64>,
    /// For each node of `tree`, its id in the unfiltered tree (the filter renumbers).
    pub original: Vec<NodeId>,
}

impl LpeFilter {
    /// What matched, in words: `3 of 130 paths match, 99.5% of the pixel (radiance [..])`
    /// (the header of `raytree trace --lpe`, and the inspector's filter line).
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "{} of {} paths match, {} of the pixel (radiance {})",
            self.matched,
            self.paths,
            self.share
                .map_or_else(|| "none".to_owned(), |s| format!("{:.1}%", 100.0 * s)),
            crate::text::rgb(self.radiance)
        )
    }
}

/// Whether a recorded string is a complete path (it ends at a light or the background).
fn complete(lpe: &str) -> bool {
    lpe.ends_with(['L', 'B'])
}

/// Keep the nodes of `tree` that lie on a complete path matching any of `lpes`: a node is kept
/// when its own recorded string or one of its descendants' is complete and matches. `None` when
/// the tree holds no path-integrator records (a Whitted tree).
#[must_use]
pub fn filter_tree(tree: &RayTree, lpes: &[Lpe]) -> Option<LpeFilter> {
    filter(tree, lpes, false)
}

/// As [`filter_tree`], but a sample without a matching path keeps its camera ray (alone), so
/// the filtered tree still has the pixel's `spp` samples and every per-sample mean and share
/// computed from it (the inspector's Explain and breakdown) stays one of the whole pixel.
#[must_use]
pub fn filter_tree_all_samples(tree: &RayTree, lpes: &[Lpe]) -> Option<LpeFilter> {
    filter(tree, lpes, true)
}

fn filter(tree: &RayTree, lpes: &[Lpe], all_samples: bool) -> Option<LpeFilter> {
    if !tree.nodes.iter().any(|n| n.path.is_some()) {
        return None;
    }
    let n = tree.nodes.len();
    let mut hit = vec![false; n];
    let (mut matched, mut paths) = (0, 0);
    let (mut sum, mut total) = (Rgb::ZERO, Rgb::ZERO);
    for (i, node) in tree.nodes.iter().enumerate() {
        let Some(p) = &node.path else { continue };
        total += p.contribution;
        if complete(&p.lpe) {
            paths += 1;
            if lpes.iter().any(|l| l.matches(&p.lpe)) {
                matched += 1;
                hit[i] = true;
                sum += p.contribution;
            }
        }
    }
    // A node is kept if it or a descendant matches: mark every ancestor of a match.
    let mut keep = vec![false; n];
    for i in (0..n).filter(|i| hit[*i]) {
        let mut at = Some(tree.nodes[i].id);
        while let Some(id) = at {
            if keep[id.index()] {
                break;
            }
            keep[id.index()] = true;
            at = tree.node(id).parent;
        }
    }
    if all_samples {
        for s in &tree.samples {
            keep[s.root.index()] = true;
        }
    }
    let mut out = tree.clone();
    out.nodes.clear();
    out.samples.clear();
    let mut new_id = vec![None; n];
    let mut original = Vec::new();
    for s in &tree.samples {
        if !keep[s.root.index()] {
            continue;
        }
        let root = NodeId(u32::try_from(out.nodes.len()).ok()?);
        for id in tree.depth_first(s.root) {
            if !keep[id.index()] {
                continue;
            }
            let mut node = tree.node(id).clone();
            let new = NodeId(u32::try_from(out.nodes.len()).ok()?);
            new_id[id.index()] = Some(new);
            node.id = new;
            original.push(id);
            node.parent = node.parent.and_then(|p| new_id[p.index()]);
            node.children.retain(|c| keep[c.index()]);
            out.nodes.push(node);
        }
        for node in &mut out.nodes[root.index()..] {
            for c in &mut node.children {
                *c = new_id[c.index()]?;
            }
        }
        out.samples.push(SampleRecord { root, ..s.clone() });
    }
    let spp = tree.samples.len().max(1) as f64;
    let lum = |c: Rgb| crate::bsdf::luminance(c);
    let share = (lum(total) > 0.0).then(|| lum(sum) / lum(total));
    Some(LpeFilter {
        tree: out,
        matched,
        paths,
        radiance: sum / spp,
        share,
        original,
    })
}
