//! A light-traced or bidirectional pixel split by the strategy `(s, t)` that brought each part
//! of its light (issue 30): what `explain`'s strategy sentence and `diff`'s per-strategy table
//! both read. Each part is in pixel units: a camera sample's contributions over the samples
//! taken, a splat's over the tree's `splat_divisor`, so the parts add up to the pixel (what
//! camera rays saw without a strategy, under light tracing the emitters and the background,
//! is its own part).

use crate::bsdf::luminance;
use crate::math::Rgb;
use crate::tree::{NodeId, RayTree};

/// One strategy's part of a pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct StrategyPart {
    /// `[s, t]`; `None` for what camera rays saw directly without a strategy.
    pub strategy: Option<[u32; 2]>,
    /// Its part of the pixel value.
    pub value: Rgb,
    /// The recorded contributions it sums.
    pub contributions: usize,
    /// Its MIS weights' mean, weighted by the luminance of the contributions.
    pub mis_weight: f64,
    /// The nodes that carry it.
    pub nodes: Vec<NodeId>,
    /// The light path expression of its largest contribution.
    pub example: String,
}

impl StrategyPart {
    /// `s=2 t=1`, or `no strategy`.
    #[must_use]
    pub fn name(&self) -> String {
        self.strategy
            .map_or("no strategy".to_string(), |[s, t]| format!("s={s} t={t}"))
    }
}

/// What strategy `(s, t)` is, in words (`None`: what camera rays saw without a strategy).
#[must_use]
pub fn strategy_words(strategy: Option<[u32; 2]>) -> &'static str {
    match strategy {
        None => "seen directly by camera rays",
        Some([0, _]) => "the camera path hit an emitter",
        Some([1, _]) => "light sampling from the camera path",
        Some([_, 1]) => "light tracing: a light path splatted to the camera",
        Some(_) => "a connection between a light and a camera path",
    }
}

/// Whether `tree` holds bidirectional strategies (a `light` or `bdpt` tree).
#[must_use]
pub fn has_strategies(tree: &RayTree) -> bool {
    !tree.splats.is_empty()
        || tree
            .nodes
            .iter()
            .any(|n| n.path.as_ref().is_some_and(|p| p.strategy.is_some()))
}

/// Per node, the factor that turns its recorded contribution into pixel units: 1 / samples
/// under the camera samples, 1 / `splat_divisor` on a splat's connection, 0 elsewhere (the
/// connections a recorded light path made to other pixels).
fn pixel_scale(tree: &RayTree) -> Vec<f64> {
    let mut scale = vec![0.0; tree.nodes.len()];
    let per_sample = 1.0 / tree.samples.len().max(1) as f64;
    for s in &tree.samples {
        for id in tree.depth_first(s.root) {
            scale[id.index()] = per_sample;
        }
    }
    let per_splat = 1.0 / f64::from(tree.splat_divisor.max(1));
    for s in &tree.splats {
        if let Some(f) = scale.get_mut(s.connection.index()) {
            *f = per_splat;
        }
    }
    scale
}

/// The parts of the pixel by strategy, largest luminance first; empty for a tree without
/// strategies ([`has_strategies`]) or a black pixel.
#[must_use]
pub fn strategy_parts(tree: &RayTree) -> Vec<StrategyPart> {
    if !has_strategies(tree) {
        return Vec::new();
    }
    let scale = pixel_scale(tree);
    let mut parts: Vec<(StrategyPart, f64, f64)> = Vec::new();
    for n in &tree.nodes {
        let Some(p) = &n.path else { continue };
        let k = scale[n.id.index()];
        if k == 0.0 || p.contribution == Rgb::ZERO || !p.contribution.is_finite() {
            continue;
        }
        let lum = luminance(p.contribution);
        let i = match parts.iter().position(|g| g.0.strategy == p.strategy) {
            Some(i) => i,
            None => {
                let part = StrategyPart {
                    strategy: p.strategy,
                    value: Rgb::ZERO,
                    contributions: 0,
                    mis_weight: 0.0,
                    nodes: Vec::new(),
                    example: String::new(),
                };
                parts.push((part, 0.0, f64::NEG_INFINITY));
                parts.len() - 1
            }
        };
        let (g, lum_sum, best) = &mut parts[i];
        g.value += p.contribution * k;
        g.mis_weight += lum * p.mis_weight.unwrap_or(1.0);
        *lum_sum += lum;
        g.contributions += 1;
        g.nodes.push(n.id);
        if lum > *best {
            *best = lum;
            g.example.clone_from(&p.lpe);
        }
    }
    let mut out: Vec<StrategyPart> = parts
        .into_iter()
        .map(|(mut g, lum_sum, _)| {
            g.mis_weight = if lum_sum > 0.0 {
                g.mis_weight / lum_sum
            } else {
                0.0
            };
            g
        })
        .collect();
    out.sort_by(|a, b| luminance(b.value).total_cmp(&luminance(a.value)));
    out
}
