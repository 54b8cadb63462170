//! The strategy sentence of a bidirectional or light-traced pixel (issue 30): which strategies
//! `(s, t)` brought its light, with their share, how often each contributed, the MIS weight its
//! light carried and an example light path; in place of the path tracer's light-or-BSDF
//! sentence, which these trees do not fit (they have connections, not shadow rays).

use crate::analysis::explain::{Sentence, SentenceKind, ids, luminance, num};
use crate::analysis::strategy_parts::{StrategyPart, strategy_parts, strategy_words};
use crate::tree::RayTree;

pub(super) use crate::analysis::strategy_parts::has_strategies;

/// The strategies that brought the pixel's light, largest first; nothing for a black pixel.
pub(super) fn bidirectional(tree: &RayTree, sentences: &mut Vec<Sentence>) {
    let groups = strategy_parts(tree);
    let total: f64 = groups.iter().map(|g| luminance(g.value)).sum();
    if !(total > 0.0 && total.is_finite()) {
        return;
    }
    let samples = tree.samples.len();
    let parts: Vec<String> = groups
        .iter()
        .filter(|g| luminance(g.value) / total >= 0.001)
        .map(|g| part_text(g, total, samples))
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

/// `97.0% from s=2 t=1 (light tracing: ..., e.g. C<RD>SSL; 3 contributions over 64 samples,
/// MIS weight 0.98)`.
fn part_text(g: &StrategyPart, total: f64, samples: usize) -> String {
    let example = if g.example.is_empty() {
        String::new()
    } else {
        format!(", e.g. {}", g.example)
    };
    format!(
        "{:.1}% from {} ({}{example}; {} contribution{} over {samples} sample{}, MIS weight {})",
        100.0 * luminance(g.value) / total,
        g.name(),
        strategy_words(g.strategy),
        g.contributions,
        super::plural(g.contributions),
        super::plural(samples),
        num(g.mis_weight)
    )
}
