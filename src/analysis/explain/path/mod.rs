//! Explaining a path-traced pixel (issue 15): the Whitted words ("floor seen through the glass
//! ball") describe one deterministic tree; a path tree is many sampled paths, so its pixel is
//! explained by light path classes (read from each contributing node's light path expression),
//! by the strategy that found the light (light sampling or BSDF sampling, combined by MIS), by
//! what Russian roulette and max depth ended, and by how noisy the estimate is.
//!
//! The shares are exact: a node's `path.contribution` is what it adds to its sample's radiance
//! (a sample's radiance is their sum), so `contribution / spp` summed over the tree is the pixel
//! value of the finite samples. This file reads the classes and their shares; the sentences
//! after them (strategies, lobes and roulette, energy, noise) are in `sentences`.

mod sentences;
mod strategy;

use super::words::chain;
use super::{Explanation, Sentence, SentenceKind, Share, ids, luminance, rgb};
use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use sentences::{energy, events_sentences, noise, strategies};

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
    let mut sentences = Vec::new();
    let c = contributions(tree);
    sees(tree, scene, &c.classes, &mut sentences);
    if strategy::has_strategies(tree) {
        strategy::bidirectional(tree, &mut sentences);
    } else {
        strategies(
            &mut sentences,
            (c.by_light.value, c.by_light.nodes),
            (c.by_bsdf.value, c.by_bsdf.nodes),
        );
    }
    events_sentences(tree, &mut sentences);
    energy(tree, scene, &mut sentences);
    noise(tree, &mut sentences);
    super::suspicious(tree, &mut sentences);
    Explanation {
        pixel: tree.pixel,
        radiance: tree.radiance,
        shares: c.classes.into_iter().map(|c| c.share).collect(),
        sentences,
    }
}

/// One light path class's share of the pixel, with the expression of its first path.
struct ClassShare {
    share: Share,
    example: String,
}

/// Light found by one strategy, and the nodes that found it.
#[derive(Default)]
struct Found {
    value: Rgb,
    nodes: Vec<NodeId>,
}

/// What the pixel's counted, finite contributions add up to: per light path class (largest
/// first), and per strategy that found the light.
struct Contributions {
    classes: Vec<ClassShare>,
    /// By light sampling (shadow rays).
    by_light: Found,
    /// By BSDF sampling: emission found by a sampled ray (not the camera's), which competes
    /// with light sampling.
    by_bsdf: Found,
}

/// The contributions of `tree`'s nodes, grouped by class and by strategy.
fn contributions(tree: &RayTree) -> Contributions {
    let spp = tree.samples.len().max(1) as f64;
    let pixel_lum = luminance(tree.radiance);
    let mut shares: Vec<Share> = Vec::new();
    let mut example: Vec<String> = Vec::new();
    let (mut by_light, mut by_bsdf) = (Found::default(), Found::default());
    let counted = tree.pixel_nodes();
    for n in &tree.nodes {
        let Some(p) = &n.path else { continue };
        if p.contribution == Rgb::ZERO || !p.contribution.is_finite() || !counted[n.id.index()] {
            continue;
        }
        let value = p.contribution / spp;
        let ev = events(&p.lpe);
        let path = class_words(tree, n, &ev);
        // Emission found by a sampled ray (not the camera's) competes with light sampling.
        if n.kind == RayKind::Shadow {
            by_light.value += value;
            by_light.nodes.push(n.id);
        } else if n.kind != RayKind::Camera && ev.last() == Some(&Event::Light) {
            by_bsdf.value += value;
            by_bsdf.nodes.push(n.id);
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
    let classes = order
        .into_iter()
        .map(|i| ClassShare {
            share: shares[i].clone(),
            example: example[i].clone(),
        })
        .collect();
    Contributions {
        classes,
        by_light,
        by_bsdf,
    }
}

/// The class of node `n`'s path (with events `ev`) in words, on the surface that names it.
fn class_words(tree: &RayTree, n: &RayNode, ev: &[Event]) -> String {
    let (words, at) = class(ev);
    let chain = chain(tree, n.id);
    match at.and_then(|k| surface(&chain, k)) {
        Some(object) => format!("{words} on the {object}"),
        None => words.to_string(),
    }
}

/// What the pixel sees: one sentence per class with an example path, or that it is black.
fn sees(tree: &RayTree, scene: &Scene, classes: &[ClassShare], sentences: &mut Vec<Sentence>) {
    if classes.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "the pixel is black: none of its {} sampled path{} reached light{}",
                tree.samples.len(),
                plural(tree.samples.len()),
                super::outside_spots(tree, scene)
            ),
            nodes: tree.samples.iter().map(|s| s.root).collect(),
        });
    }
    for ClassShare { share: s, example } in classes {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "{} (e.g. {example}): {:.1}% {}",
                s.path,
                100.0 * s.fraction,
                rgb(s.value)
            ),
            nodes: ids(&s.nodes),
        });
    }
}
