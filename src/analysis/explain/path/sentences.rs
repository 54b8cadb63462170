//! The sentences of a path-traced pixel after its light path classes: which strategy found the
//! light (light or BSDF sampling, weighted by MIS), the sampled lobes and Russian roulette,
//! where energy went (max depth, blocked light samples, dropped samples) and how noisy the
//! estimate is.

use super::plural;
use crate::analysis::explain::{Sentence, SentenceKind, ids, luminance, num};
use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};

/// Which strategy found the light: next-event estimation or BSDF sampling (MIS-weighted).
pub(super) fn strategies(
    sentences: &mut Vec<Sentence>,
    (light, light_nodes): (Rgb, Vec<NodeId>),
    (bsdf, bsdf_nodes): (Rgb, Vec<NodeId>),
) {
    let total = luminance(light) + luminance(bsdf);
    if total <= 0.0 {
        return;
    }
    let mut nodes = light_nodes;
    nodes.extend(bsdf_nodes);
    sentences.push(Sentence {
        kind: SentenceKind::Event,
        text: format!(
            "light reached the path's surfaces {:.1}% by light sampling (shadow rays) and {:.1}% by BSDF sampling (a sampled ray hit an emitter), weighted by MIS (power heuristic)",
            100.0 * luminance(light) / total,
            100.0 * luminance(bsdf) / total
        ),
        nodes: ids(&nodes),
    });
}

/// Sampled lobes and Russian roulette.
pub(super) fn events_sentences(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let mut lobes: Vec<(&'static str, Vec<NodeId>)> = Vec::new();
    for n in tree.nodes.iter().filter(|n| n.kind != RayKind::Shadow) {
        let Some(lobe) = n.path.as_ref().and_then(|p| p.lobe) else {
            continue;
        };
        let name = lobe.name();
        match lobes.iter_mut().find(|l| l.0 == name) {
            Some(l) => l.1.push(n.id),
            None => lobes.push((name, vec![n.id])),
        }
    }
    if !lobes.is_empty() {
        lobes.sort_by_key(|l| std::cmp::Reverse(l.1.len()));
        let words: Vec<String> = lobes
            .iter()
            .map(|(k, v)| format!("{} {k}", v.len()))
            .collect();
        sentences.push(Sentence {
            kind: SentenceKind::Event,
            text: format!("bounces sampled from the BSDF: {}", words.join(", ")),
            nodes: lobes.into_iter().flat_map(|l| l.1).collect(),
        });
    }
    let decided: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.path.as_ref().is_some_and(|p| p.roulette.is_some()))
        .collect();
    if !decided.is_empty() {
        let q = |n: &RayNode| {
            n.path
                .as_ref()
                .and_then(|p| p.roulette)
                .map(|r| r.probability)
        };
        let lo = decided.iter().filter_map(|n| q(n)).fold(1.0, f64::min);
        let killed: Vec<NodeId> = decided
            .iter()
            .filter(|n| n.end == EndReason::RussianRoulette)
            .map(|n| n.id)
            .collect();
        sentences.push(Sentence {
            kind: SentenceKind::Event,
            text: format!(
                "Russian roulette from bounce {}: {} decision{}, {} path{} ended; survival probability down to {}, so a survivor's weight grew up to {:.2}x (unbiased: 1/q)",
                tree.settings.path.rr_depth,
                decided.len(),
                plural(decided.len()),
                killed.len(),
                plural(killed.len()),
                num(lo),
                1.0 / lo.max(f64::MIN_POSITIVE)
            ),
            nodes: if killed.is_empty() {
                decided.iter().map(|n| n.id).collect()
            } else {
                killed
            },
        });
    }
}

/// Max depth, blocked light samples and dropped samples.
pub(super) fn energy(tree: &RayTree, scene: &Scene, sentences: &mut Vec<Sentence>) {
    let cut: Vec<NodeId> = tree
        .nodes
        .iter()
        .filter(|n| n.end == EndReason::MaxDepth)
        .map(|n| n.id)
        .collect();
    if !cut.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text: format!(
                "{} path{} reached max depth {} and ended: light after more bounces is missing (a bias; raise max_depth and let Russian roulette end paths)",
                cut.len(),
                plural(cut.len()),
                tree.settings.max_depth
            ),
            nodes: cut,
        });
    }
    let blocked: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.kind == RayKind::Shadow && n.end == EndReason::Blocked)
        .collect();
    if !blocked.is_empty() {
        let mut by: Vec<&str> = Vec::new();
        let mut clear = false;
        for b in blocked.iter().filter_map(|n| n.shadow.as_ref()) {
            for o in &b.blockers {
                if !by.contains(&o.object_name.as_str()) {
                    by.push(&o.object_name);
                    let m = scene
                        .objects
                        .get(o.object)
                        .map(|o| &scene.materials[o.material]);
                    clear |= m.is_some_and(|m| m.transmissivity.max_element() > 0.0);
                }
            }
        }
        let shadow_rays = tree
            .nodes
            .iter()
            .filter(|n| n.kind == RayKind::Shadow)
            .count();
        let mut text = format!(
            "{} of {shadow_rays} light sample{} blocked by the {}",
            blocked.len(),
            plural(shadow_rays),
            by.join(", the ")
        );
        if clear {
            text.push_str(
                ": shadow rays stop at glass, so light through it can only be found by BSDF-sampled paths (caustics), which is noisy",
            );
        }
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text,
            nodes: blocked.iter().map(|n| n.id).collect(),
        });
    }
    let dropped: Vec<NodeId> = tree
        .samples
        .iter()
        .filter(|s| !s.radiance.is_finite())
        .map(|s| s.root)
        .collect();
    if !dropped.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "{} sample{} not a number or infinite and dropped (counted black), so no such value reaches the image",
                dropped.len(),
                if dropped.len() == 1 { " was" } else { "s were" }
            ),
            nodes: dropped,
        });
    }
}

/// The relative standard error of the pixel mean and the largest sample's share.
pub(super) fn noise(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let v: Vec<(f64, NodeId)> = tree
        .samples
        .iter()
        .filter(|s| s.radiance.is_finite())
        .map(|s| (luminance(s.radiance), s.root))
        .collect();
    let n = v.len() as f64;
    let sum: f64 = v.iter().map(|x| x.0).sum();
    if v.len() < 2 || sum <= 0.0 {
        return;
    }
    let mean = sum / n;
    let var = v.iter().map(|x| (x.0 - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let rel = var.sqrt() / n.sqrt() / mean;
    let (top, root) = v
        .iter()
        .copied()
        .fold((f64::MIN, v[0].1), |a, x| if x.0 > a.0 { x } else { a });
    let share = top / sum;
    sentences.push(Sentence {
        kind: SentenceKind::Energy,
        text: format!(
            "noise: relative standard error {:.1}% from {} samples (halves with 4x the samples); the brightest sample carries {:.1}% of the pixel",
            100.0 * rel,
            v.len(),
            100.0 * share
        ),
        nodes: vec![root],
    });
    if v.len() >= 8 && share > 0.5 {
        sentences.push(Sentence {
            kind: SentenceKind::Suspicious,
            text: format!(
                "a firefly: one sample of {} carries {:.0}% of the pixel (its path is rare and its weight large)",
                v.len(),
                100.0 * share
            ),
            nodes: vec![root],
        });
    }
}
