//! The sentences of a Whitted pixel's explanation, in the order they are told: what the pixel
//! sees (its shares), the optical events (total internal reflection, Russian roulette) and
//! where energy went (cut, absorbed by Beer's law, blocked shadow rays).

use super::words::path_words;
use super::{
    SMALL_SHARE, Sentence, SentenceKind, Share, atten, deg, ids, luminance, node_term, num,
    outside_spots, rgb,
};
use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};

/// The samples a node's term is divided by.
fn spp(tree: &RayTree) -> f64 {
    tree.samples.len().max(1) as f64
}

/// Every non-shadow node's term grouped by its path in words, largest first, with its
/// fraction of the pixel's luminance.
pub(super) fn shares(tree: &RayTree) -> Vec<Share> {
    let pixel_lum = luminance(tree.radiance);
    let mut shares: Vec<Share> = Vec::new();
    for n in tree.nodes.iter().filter(|n| n.kind != RayKind::Shadow) {
        let value = node_term(tree, n);
        if value == Rgb::ZERO {
            continue;
        }
        let path = path_words(tree, n.id);
        match shares.iter_mut().find(|s| s.path == path) {
            Some(s) => {
                s.value += value;
                s.nodes.push(n.id);
            }
            None => shares.push(Share {
                path,
                value,
                fraction: 0.0,
                nodes: vec![n.id],
            }),
        }
    }
    for s in &mut shares {
        s.fraction = if pixel_lum > 0.0 {
            luminance(s.value) / pixel_lum
        } else {
            0.0
        };
    }
    shares.sort_by(|a, b| luminance(b.value).total_cmp(&luminance(a.value)));
    shares
}

/// What the pixel sees: one sentence per share of at least [`SMALL_SHARE`], one for the
/// smaller ones together, or that the pixel is black.
pub(super) fn sees(tree: &RayTree, scene: &Scene, shares: &[Share], sentences: &mut Vec<Sentence>) {
    let pixel_lum = luminance(tree.radiance);
    if shares.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "the pixel is black: no path brings light to the eye{}",
                outside_spots(tree, scene)
            ),
            nodes: tree.samples.iter().map(|s| s.root).collect(),
        });
    }
    let (big, small): (Vec<&Share>, Vec<&Share>) = shares
        .iter()
        .partition(|s| s.fraction >= SMALL_SHARE || pixel_lum <= 0.0);
    for s in &big {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!("{}: {:.1}% {}", s.path, 100.0 * s.fraction, rgb(s.value)),
            nodes: ids(&s.nodes),
        });
    }
    if !small.is_empty() {
        let value = small.iter().fold(Rgb::ZERO, |a, s| a + s.value);
        let nodes: Vec<NodeId> = small.iter().flat_map(|s| s.nodes.clone()).collect();
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "{} other paths, each under {:.1}%: {:.1}% {}",
                small.len(),
                100.0 * SMALL_SHARE,
                100.0 * luminance(value) / pixel_lum,
                rgb(value)
            ),
            nodes: ids(&nodes),
        });
    }
}

/// Total internal reflection: how many rays, inside what, and the first one's angles.
pub(super) fn total_internal_reflection(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let tir: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.interface.as_ref().is_some_and(|i| i.tir))
        .collect();
    let Some(first) = tir.first() else { return };
    let i = first.interface.as_ref().expect("filtered on interface");
    let crit = (i.n2 / i.n1).clamp(-1.0, 1.0).asin().to_degrees();
    let mut objects: Vec<&str> = tir
        .iter()
        .filter_map(|n| n.hit.as_ref().map(|h| h.object_name.as_str()))
        .collect();
    objects.dedup();
    sentences.push(Sentence {
        kind: SentenceKind::Event,
        text: format!(
            "total internal reflection at {} ray{} inside the {} (first at #{}: theta_i {:.1} deg > critical angle {:.1} deg, n {:.3} -> {:.3})",
            tir.len(),
            if tir.len() == 1 { "" } else { "s" },
            objects.join(", the "),
            first.id.0,
            deg(i.cos_i),
            crit,
            i.n1,
            i.n2
        ),
        nodes: tir.iter().map(|n| n.id).collect(),
    });
}

/// Russian roulette instead of the split at weak dielectric hits.
pub(super) fn roulette(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let rouletted: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.interface.as_ref().is_some_and(|i| i.roulette.is_some()))
        .collect();
    if rouletted.is_empty() {
        return;
    }
    let why = match (
        tree.settings.whitted.roulette_below,
        tree.settings.whitted.dielectric_roulette,
    ) {
        (_, Some(d)) => format!("from depth {d} (settings.dielectric_roulette)"),
        (Some(w), None) => format!("where the throughput was below {w:.2e}"),
        (None, None) => String::new(),
    };
    sentences.push(Sentence {
        kind: SentenceKind::Event,
        text: format!(
            "Russian roulette at {} glass hit{} {why}: one of the reflected and refracted rays followed, its weight divided by its probability (exact in expectation; the other ray is not traced)",
            rouletted.len(),
            if rouletted.len() == 1 { "" } else { "s" },
        ),
        nodes: rouletted.iter().map(|n| n.id).collect(),
    });
}

/// Where energy went: the weight cut by max depth, by the min weight and by the ray budget.
pub(super) fn cuts(tree: &RayTree, scene: &Scene, sentences: &mut Vec<Sentence>) {
    let spp = spp(tree);
    let st = &tree.settings;
    for (reason, what) in [
        (EndReason::MaxDepth, format!("max depth {}", st.max_depth)),
        (
            EndReason::MinWeight,
            match scene.settings.whitted.min_weight {
                None => format!(
                    "the automatic min weight {:.2e}",
                    st.whitted.min_weight.unwrap_or(0.0)
                ),
                Some(w) => format!("min weight {w:.2e}"),
            },
        ),
        (
            EndReason::RayBudget,
            format!("the ray budget of {} rays per sample", st.max_rays),
        ),
    ] {
        let cut: Vec<&RayNode> = tree.nodes.iter().filter(|n| n.end == reason).collect();
        if cut.is_empty() {
            continue;
        }
        let weight = cut.iter().fold(Rgb::ZERO, |a, n| {
            a + n.throughput * atten(n) * n.truncated / spp
        });
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text: format!(
                "cut by {what}: {} ray{} spawned no secondary rays, leaving path weight {} untraced (the share of the pixel's paths that was not followed)",
                cut.len(),
                if cut.len() == 1 { "" } else { "s" },
                num(luminance(weight))
            ),
            nodes: cut.iter().map(|n| n.id).collect(),
        });
    }
}

/// What Beer's law absorbed in one medium, and on which ray segments.
struct Absorbed {
    medium: usize,
    lost: Rgb,
    nodes: Vec<NodeId>,
}

/// Absorbed by Beer's law, per medium (in the order the media are first met).
pub(super) fn absorbed(tree: &RayTree, scene: &Scene, sentences: &mut Vec<Sentence>) {
    let spp = spp(tree);
    let mut absorbed: Vec<Absorbed> = Vec::new();
    for n in &tree.nodes {
        let Some(a) = &n.attenuation else { continue };
        if a.factor == Rgb::ONE || n.kind == RayKind::Shadow {
            continue;
        }
        let carried = match n.hit {
            Some(_) => {
                n.local
                    + n.children
                        .iter()
                        .map(|c| tree.node(*c))
                        .filter(|c| c.kind != RayKind::Shadow)
                        .fold(Rgb::ZERO, |s, c| s + c.weight * c.radiance)
            }
            None => scene.background,
        };
        let lost = n.throughput * (Rgb::ONE - a.factor) * carried / spp;
        match absorbed.iter_mut().find(|x| x.medium == a.medium) {
            Some(x) => {
                x.lost += lost;
                x.nodes.push(n.id);
            }
            None => absorbed.push(Absorbed {
                medium: a.medium,
                lost,
                nodes: vec![n.id],
            }),
        }
    }
    for Absorbed {
        medium,
        lost,
        nodes,
    } in absorbed
    {
        let name = scene
            .objects
            .get(medium)
            .map_or("an absorbing object", |o| o.name.as_str());
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text: format!(
                "absorbed by Beer's law in the {name}: {} of pixel value on {} ray segment{}",
                rgb(lost),
                nodes.len(),
                if nodes.len() == 1 { "" } else { "s" }
            ),
            nodes,
        });
    }
}

/// Shadow rays blocked or dimmed: by what, and what they would have added unblocked.
pub(super) fn blocked(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let spp = spp(tree);
    let blocked: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| matches!(n.end, EndReason::Blocked | EndReason::Attenuated))
        .collect();
    if blocked.is_empty() {
        return;
    }
    let mut lost = Rgb::ZERO;
    let mut by: Vec<&str> = Vec::new();
    for n in &blocked {
        let Some(sh) = &n.shadow else { continue };
        let surface = n.parent.map(|p| tree.node(p));
        let carry = surface.map_or(Rgb::ONE, |s| s.throughput * atten(s));
        lost += carry * n.weight * sh.irradiance * (Rgb::ONE - sh.transmittance) / spp;
        for b in &sh.blockers {
            if !by.contains(&b.object_name.as_str()) {
                by.push(&b.object_name);
            }
        }
    }
    let text = if lost == Rgb::ZERO {
        format!(
            "{} shadow ray{} blocked or dimmed (by the {}), none of which would have lit its surface (BRDF x cos is 0 there)",
            blocked.len(),
            if blocked.len() == 1 { "" } else { "s" },
            by.join(", the ")
        )
    } else {
        format!(
            "{} shadow ray{} blocked or dimmed by the {}: unblocked they would add {} to the pixel",
            blocked.len(),
            if blocked.len() == 1 { "" } else { "s" },
            by.join(", the "),
            rgb(lost)
        )
    };
    sentences.push(Sentence {
        kind: SentenceKind::Energy,
        text,
        nodes: blocked.iter().map(|n| n.id).collect(),
    });
}
