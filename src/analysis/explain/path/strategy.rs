//! The strategy sentence of a bidirectional or light-traced pixel (issue 30): which strategies
//! `(s, t)` brought its light, with their share, how often each contributed, the MIS weight its
//! light carried and an example light path; in place of the path tracer's light-or-BSDF
//! sentence, which these trees do not fit (they have connections, not shadow rays).

use crate::analysis::explain::{Sentence, SentenceKind, ids, luminance, num};
use crate::math::Rgb;
use crate::tree::{NodeId, RayTree};

/// One strategy's part of the pixel.
struct Group {
    /// `[s, t]`; `None` for what camera rays saw directly without a strategy (under light
    /// tracing: emitters and the background).
    strategy: Option<[u32; 2]>,
    value: Rgb,
    /// Luminance-weighted sum of the MIS weights.
    weighted_mis: f64,
    /// Luminance of `value` at full weight (for the mean MIS weight).
    lum: f64,
    contributions: usize,
    nodes: Vec<NodeId>,
    /// The light path expression of its largest contribution.
    example: (f64, String),
}

/// What strategy `(s, t)` is, in words.
fn strategy_words(strategy: Option<[u32; 2]>) -> &'static str {
    match strategy {
        None => "seen directly by camera rays",
        Some([0, _]) => "the camera path hit an emitter",
        Some([1, _]) => "light sampling from the camera path",
        Some([_, 1]) => "light tracing: a light path splatted to the camera",
        Some(_) => "a connection between a light and a camera path",
    }
}

/// Whether `tree` holds bidirectional strategies (a `light` or `bdpt` tree).
pub(super) fn has_strategies(tree: &RayTree) -> bool {
    !tree.splats.is_empty()
        || tree
            .nodes
            .iter()
            .any(|n| n.path.as_ref().is_some_and(|p| p.strategy.is_some()))
}

/// The strategies that brought the pixel's light, largest first; nothing for a black pixel.
pub(super) fn bidirectional(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let mut groups: Vec<Group> = Vec::new();
    let counted = tree.pixel_nodes();
    for n in &tree.nodes {
        let Some(p) = &n.path else { continue };
        if p.contribution == Rgb::ZERO || !p.contribution.is_finite() || !counted[n.id.index()] {
            continue;
        }
        let lum = luminance(p.contribution);
        let g = match groups.iter().position(|g| g.strategy == p.strategy) {
            Some(i) => &mut groups[i],
            None => {
                groups.push(Group {
                    strategy: p.strategy,
                    value: Rgb::ZERO,
                    weighted_mis: 0.0,
                    lum: 0.0,
                    contributions: 0,
                    nodes: Vec::new(),
                    example: (f64::NEG_INFINITY, String::new()),
                });
                groups.last_mut().expect("just pushed")
            }
        };
        g.value += p.contribution;
        g.weighted_mis += lum * p.mis_weight.unwrap_or(1.0);
        g.lum += lum;
        g.contributions += 1;
        g.nodes.push(n.id);
        if lum > g.example.0 {
            g.example = (lum, p.lpe.clone());
        }
    }
    let total: f64 = groups.iter().map(|g| luminance(g.value)).sum();
    if !(total > 0.0 && total.is_finite()) {
        return;
    }
    groups.sort_by(|a, b| luminance(b.value).total_cmp(&luminance(a.value)));
    let samples = tree.samples.len();
    let parts: Vec<String> = groups
        .iter()
        .filter(|g| luminance(g.value) / total >= 0.001)
        .map(|g| {
            let name = g
                .strategy
                .map_or("no strategy".to_string(), |[s, t]| format!("s={s} t={t}"));
            let mis = if g.lum > 0.0 { g.weighted_mis / g.lum } else { 0.0 };
            let example = if g.example.1.is_empty() {
                String::new()
            } else {
                format!(", e.g. {}", g.example.1)
            };
            format!(
                "{:.1}% from {name} ({}{example}; {} contribution{} over {samples} sample{}, MIS weight {})",
                100.0 * luminance(g.value) / total,
                strategy_words(g.strategy),
                g.contributions,
                super::plural(g.contributions),
                super::plural(samples),
                num(mis)
            )
        })
        .collect();
    let small = groups.len() - parts.len();
    let rest = if small > 0 {
        format!("; {small} more under 0.1%")
    } else {
        String::new()
    };
    sentences.push(Sentence {
        kind: SentenceKind::Event,
        text: format!("the light came {}{rest}", parts.join(", ")),
        nodes: ids(&groups
            .iter()
            .flat_map(|g| g.nodes.clone())
            .collect::<Vec<_>>()),
    });
}
