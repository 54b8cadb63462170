//! Explaining a path-traced pixel (issue 15): the Whitted words ("floor seen through the glass
//! ball") describe one deterministic tree; a path tree is many sampled paths, so its pixel is
//! explained by light path classes (read from each contributing node's light path expression),
//! by the strategy that found the light (light sampling or BSDF sampling, combined by MIS), by
//! what Russian roulette and max depth ended, and by how noisy the estimate is.
//!
//! The shares are exact: a node's `path.contribution` is what it adds to its sample's radiance
//! (a sample's radiance is their sum), so `contribution / spp` summed over the tree is the pixel
//! value of the finite samples.

use super::words::chain;
use super::{Explanation, Sentence, SentenceKind, Share, ids, luminance, num, rgb};
use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};

/// One event of a light path expression: `C`, `L`, `B` or `<RD>`-style (type, scatter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Event {
    Camera,
    Light,
    Background,
    Scatter { transmit: bool, scatter: u8 },
}

impl Event {
    fn specular(self) -> bool {
        matches!(self, Event::Scatter { scatter: b'S', .. })
    }
}

/// The events of `lpe` (the alphabet the path integrator records; anything else is skipped).
pub(super) fn events(lpe: &str) -> Vec<Event> {
    let b = lpe.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'C' => out.push(Event::Camera),
            b'L' => out.push(Event::Light),
            b'B' => out.push(Event::Background),
            b'<' if i + 2 < b.len() => {
                out.push(Event::Scatter {
                    transmit: b[i + 1] == b'T',
                    scatter: b[i + 2],
                });
                while i < b.len() && b[i] != b'>' {
                    i += 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// The class of a light-carrying path in words, from its events, and the index of the vertex
/// (into the scatter events) that names its surface.
pub(super) fn class(ev: &[Event]) -> (&'static str, Option<usize>) {
    let scatters: Vec<Event> = ev
        .iter()
        .copied()
        .filter(|e| matches!(e, Event::Scatter { .. }))
        .collect();
    let background = ev.last() == Some(&Event::Background);
    let rough: Vec<usize> = (0..scatters.len())
        .filter(|&i| !scatters[i].specular())
        .collect();
    match (rough.as_slice(), background) {
        ([], true) if scatters.is_empty() => ("background seen directly", None),
        ([], true) => ("background seen in mirrors and glass", None),
        ([], false) if scatters.is_empty() => ("an emitter seen directly", None),
        ([], false) => ("an emitter seen in mirrors and glass", None),
        (r, true) => ("light from the background", r.first().copied()),
        ([i], false) if *i + 1 == scatters.len() => ("direct light", Some(*i)),
        ([i], false) => ("caustic: light through or off specular surfaces", Some(*i)),
        (r, false) if scatters[r[r.len() - 1] + 1..].iter().any(|e| e.specular()) => {
            ("indirect light with a caustic", r.first().copied())
        }
        (r, false) => ("indirect light", r.first().copied()),
    }
}

/// Where scatter event `k` happened: the hit of the `k`-th ray of the chain.
fn surface(chain: &[&RayNode], k: usize) -> Option<String> {
    chain
        .get(k)
        .and_then(|n| n.hit.as_ref())
        .map(|h| h.object_name.clone())
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Explain a path-traced pixel.
pub(super) fn explain_path(tree: &RayTree, scene: &Scene) -> Explanation {
    let spp = tree.samples.len().max(1) as f64;
    let pixel_lum = luminance(tree.radiance);
    let mut sentences = Vec::new();
    let mut shares: Vec<Share> = Vec::new();
    let mut example: Vec<String> = Vec::new();
    let (mut by_light, mut by_bsdf) = (Rgb::ZERO, Rgb::ZERO);
    let (mut light_nodes, mut bsdf_nodes) = (Vec::new(), Vec::new());
    for n in &tree.nodes {
        let Some(p) = &n.path else { continue };
        if p.contribution == Rgb::ZERO || !p.contribution.is_finite() {
            continue;
        }
        let value = p.contribution / spp;
        let ev = events(&p.lpe);
        let (words, at) = class(&ev);
        let chain = chain(tree, n.id);
        let path = match at.and_then(|k| surface(&chain, k)) {
            Some(object) => format!("{words} on the {object}"),
            None => words.to_string(),
        };
        // Emission found by a sampled ray (not the camera's) competes with light sampling.
        if n.kind == RayKind::Shadow {
            by_light += value;
            light_nodes.push(n.id);
        } else if n.kind != RayKind::Camera && ev.last() == Some(&Event::Light) {
            by_bsdf += value;
            bsdf_nodes.push(n.id);
        }
        match shares.iter().position(|s| s.path == path) {
            Some(i) => {
                shares[i].value += value;
                shares[i].nodes.push(n.id);
            }
            None => {
                shares.push(Share {
                    path,
                    value,
                    fraction: 0.0,
                    nodes: vec![n.id],
                });
                example.push(p.lpe.clone());
            }
        }
    }
    for s in &mut shares {
        s.fraction = if pixel_lum > 0.0 {
            luminance(s.value) / pixel_lum
        } else {
            0.0
        };
    }
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&a, &b| luminance(shares[b].value).total_cmp(&luminance(shares[a].value)));
    let shares: Vec<(Share, String)> = order
        .into_iter()
        .map(|i| (shares[i].clone(), example[i].clone()))
        .collect();
    if shares.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "the pixel is black: none of its {} sampled path{} reached light",
                tree.samples.len(),
                plural(tree.samples.len())
            ),
            nodes: tree.samples.iter().map(|s| s.root).collect(),
        });
    }
    for (s, lpe) in &shares {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "{} (e.g. {lpe}): {:.1}% {}",
                s.path,
                100.0 * s.fraction,
                rgb(s.value)
            ),
            nodes: ids(&s.nodes),
        });
    }
    strategies(
        &mut sentences,
        (by_light, light_nodes),
        (by_bsdf, bsdf_nodes),
    );
    events_sentences(tree, &mut sentences);
    energy(tree, scene, &mut sentences);
    noise(tree, &mut sentences);
    super::suspicious(tree, &mut sentences);
    Explanation {
        pixel: tree.pixel,
        radiance: tree.radiance,
        shares: shares.into_iter().map(|(s, _)| s).collect(),
        sentences,
    }
}

/// Which strategy found the light: next-event estimation or BSDF sampling (MIS-weighted).
fn strategies(
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
fn events_sentences(tree: &RayTree, sentences: &mut Vec<Sentence>) {
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
                tree.settings.rr_depth,
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
fn energy(tree: &RayTree, scene: &Scene, sentences: &mut Vec<Sentence>) {
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
                "{} sample{} NaN or infinite and dropped (counted black) so no NaN reaches the image",
                dropped.len(),
                if dropped.len() == 1 { " was" } else { "s were" }
            ),
            nodes: dropped,
        });
    }
}

/// The relative standard error of the pixel mean and the largest sample's share.
fn noise(tree: &RayTree, sentences: &mut Vec<Sentence>) {
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
