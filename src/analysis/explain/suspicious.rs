//! What a renderer engineer should look at: self-hits, leaks, trapped TIR chains, clipped
//! and non-finite values.

use super::{Sentence, SentenceKind, atten, luminance, num, rgb};
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};

/// The suspicious sentences, in order: self-hits, leaks, trapped TIR chains, a clipped pixel
/// value, non-finite values.
pub(super) fn suspicious(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let offset = offset_text(tree);
    self_hits(tree, &offset, sentences);
    leaks(tree, &offset, sentences);
    trapped_tir(tree, sentences);
    let roots: Vec<NodeId> = tree.samples.iter().map(|s| s.root).collect();
    clipped(tree, &roots, sentences);
    non_finite(tree, roots, sentences);
}

/// The offset settings, as the self-hit and leak sentences name them ("offset normal 1e-4").
fn offset_text(tree: &RayTree) -> String {
    let st = &tree.settings;
    format!(
        "offset {} {:e}",
        serde_json::to_string(&st.offset.strategy)
            .unwrap_or_default()
            .trim_matches('"'),
        st.offset.epsilon
    )
}

/// Rays that re-hit the surface they left.
fn self_hits(tree: &RayTree, offset: &str, sentences: &mut Vec<Sentence>) {
    let self_hits: Vec<NodeId> = tree
        .nodes
        .iter()
        .filter(|n| n.self_hit)
        .map(|n| n.id)
        .collect();
    if !self_hits.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "{} ray{} re-hit the surface {} left (self-intersection: acne) with {offset}",
                self_hits.len(),
                if self_hits.len() == 1 { "" } else { "s" },
                if self_hits.len() == 1 { "it" } else { "they" }
            ),
            nodes: self_hits,
        });
    }
}

/// Rays whose spawn offset skipped a surface.
fn leaks(tree: &RayTree, offset: &str, sentences: &mut Vec<Sentence>) {
    let leaks: Vec<&RayNode> = tree.nodes.iter().filter(|n| n.leak.is_some()).collect();
    if let Some(l) = leaks.first().and_then(|n| n.leak.as_ref()) {
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "{} ray{} leaked: the spawn offset skipped a surface a zero offset would meet (first: the {} at {:.3e}) with {offset}",
                leaks.len(),
                if leaks.len() == 1 { "" } else { "s" },
                l.object_name,
                l.distance
            ),
            nodes: leaks.iter().map(|n| n.id).collect(),
        });
    }
}

/// TIR chains whose last total reflection was cut by max depth: trapped light lost.
fn trapped_tir(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let st = &tree.settings;
    for n in tree
        .nodes
        .iter()
        .filter(|n| n.end == EndReason::MaxDepth && n.interface.as_ref().is_some_and(|i| i.tir))
    {
        let mut chain = vec![n.id];
        let mut at = n;
        while let Some(p) = at.parent.map(|p| tree.node(p)) {
            if at.kind != RayKind::Reflected || !p.interface.as_ref().is_some_and(|i| i.tir) {
                break;
            }
            chain.push(p.id);
            at = p;
        }
        chain.reverse();
        let spp = tree.samples.len().max(1) as f64;
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "a chain of {} total internal reflection{} ends at max depth {} at #{}: path weight {} trapped and never traced",
                chain.len(),
                if chain.len() == 1 { "" } else { "s" },
                st.max_depth,
                n.id.0,
                num(luminance(n.throughput * atten(n) * n.truncated / spp))
            ),
            nodes: chain,
        });
    }
}

/// A finite pixel value above 1 in some channel, which the display clips (about the sample
/// roots `roots`).
fn clipped(tree: &RayTree, roots: &[NodeId], sentences: &mut Vec<Sentence>) {
    if tree.radiance.is_finite() && tree.radiance.max_element() > 1.0 {
        let ch: Vec<&str> = [
            ("R", tree.radiance.x),
            ("G", tree.radiance.y),
            ("B", tree.radiance.z),
        ]
        .iter()
        .filter(|(_, v)| *v > 1.0)
        .map(|(c, _)| *c)
        .collect();
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "the pixel value {} is above 1 in {}: the display clips it (8-bit 255), the EXR keeps it",
                rgb(tree.radiance),
                ch.join(", ")
            ),
            nodes: roots.to_vec(),
        });
    }
}

/// Rays carrying a value that is not finite, or a pixel that is not (then about the sample
/// roots `roots`).
fn non_finite(tree: &RayTree, roots: Vec<NodeId>, sentences: &mut Vec<Sentence>) {
    let bad: Vec<NodeId> = tree
        .nodes
        .iter()
        .filter(|n| {
            ![n.radiance, n.weight, n.throughput, n.local]
                .iter()
                .all(|c| c.is_finite())
        })
        .map(|n| n.id)
        .collect();
    if !bad.is_empty() || !tree.radiance.is_finite() {
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "non-finite value: the pixel is {} and {} ray{} carry values that are not a number or infinite",
                rgb(tree.radiance),
                bad.len(),
                if bad.len() == 1 { "" } else { "s" }
            ),
            nodes: if bad.is_empty() { roots } else { bad },
        });
    }
}
