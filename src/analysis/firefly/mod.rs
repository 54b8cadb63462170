//! Why one sample of a pixel is a firefly: which vertex of its dominant path made its weight
//! large. Pure, over a recorded path-integrator tree.
//!
//! A sample is a *firefly* when its value (luminance, [`super::samples::sample_value`]) is more
//! than [`FIREFLY_RATIO`] times the pixel's typical sample: the median of its samples' values, or
//! their mean where the median is 0 (a caustic pixel whose samples are mostly black). Its
//! *dominant path* is its complete path (LPE ending in `L` or `B`) of largest contribution; the
//! blamed vertex is found in this order:
//!
//! 1. **A caustic found by BSDF sampling**: the path's LPE matches `C.*[DG]S+L` and it ends with
//!    a ray that found the emitter (not a shadow ray). Next-event estimation cannot connect a
//!    diffuse or glossy point to a light through a specular chain (the shadow ray is blocked by
//!    the glass), so only the rare BSDF sample of the last diffuse/glossy bounce finds the light,
//!    with MIS weight 1 after the delta lobes (Veach 1997, section 9.2; pbrt-v4 section 13.4:
//!    emission after a specular bounce is counted in full). Blamed: that bounce.
//! 2. **Emission found by BSDF sampling with MIS weight near 1** (>= 0.9): the light strategy's
//!    pdf for that direction is far smaller than the BSDF's, or the emitter is not light-sampled
//!    (weight 1), so the whole emission rides on one BSDF sample. Blamed: the ray that found it.
//! 3. Otherwise the **largest factor** along the path: a continuation's `f |cos| / pdf` (large
//!    when the pdf is small where the BSDF is not), a Russian-roulette survival `1 / q` (pbrt-v4
//!    section 13.4.3: the throughput is divided by the survival probability), or the light
//!    sample's `f |cos| w_l / pdf_light` of the ending shadow ray (a small light pdf).

use super::samples::sample_value;
use crate::bsdf::{LobeKind, luminance};
use crate::lpe::Lpe;
use crate::tree::{NodeId, Pdf, RayKind, RayTree};

/// A sample is a firefly above this many times the pixel's typical sample value.
pub const FIREFLY_RATIO: f64 = 10.0;

/// The MIS weight from which emission found by BSDF sampling counts as "near 1".
pub const MIS_NEAR_ONE: f64 = 0.9;

/// What made the sample's weight large.
#[derive(Clone, Debug, PartialEq)]
pub enum Cause {
    /// A caustic path found by the BSDF sample of a diffuse/glossy bounce (the blamed node).
    Caustic {
        /// The bounce's BSDF pdf (solid angle).
        pdf: Option<f64>,
        /// The bounce's lobe (diffuse or glossy).
        lobe: LobeKind,
        /// The bounce's `f |cos| / pdf` (max channel): an ordinary weight. What is rare is the
        /// event, not the sample's pdf.
        weight: Option<f64>,
        /// How many of the pixel's samples found light this way (a caustic path ending at an
        /// emitter found by BSDF sampling, with a contribution): the event's estimated
        /// probability is this over the samples.
        events: usize,
    },
    /// Emission found by a BSDF-sampled ray with MIS weight `mis` near 1.
    BsdfEmission {
        /// The MIS weight.
        mis: f64,
        /// The ray's BSDF pdf.
        pdf: Option<f64>,
    },
    /// Russian roulette: the path survived with probability `q`, its throughput divided by it.
    Roulette {
        /// Survival probability.
        q: f64,
    },
    /// A BSDF sample with a large `f |cos| / pdf`.
    BsdfWeight {
        /// `f |cos| / pdf`, max channel.
        weight: f64,
        /// Its pdf (`None`: delta).
        pdf: Option<f64>,
    },
    /// A light sample with a large `f |cos| w / pdf`.
    LightSample {
        /// Light pdf (selection x solid angle).
        pdf: f64,
        /// Its MIS weight.
        mis: f64,
        /// `f |cos| w / pdf`, max channel.
        factor: f64,
    },
}

/// The explanation of one firefly sample.
#[derive(Clone, Debug, PartialEq)]
pub struct Firefly {
    /// The sample's index.
    pub sample: usize,
    /// Its value (luminance).
    pub value: f64,
    /// The pixel's typical sample value (median, or mean where the median is 0).
    pub typical: f64,
    /// Whether `typical` is the median (else the mean).
    pub by_median: bool,
    /// The dominant path's end node and LPE.
    pub path: NodeId,
    /// Its LPE.
    pub lpe: String,
    /// The blamed vertex (a ray whose factor made the weight large).
    pub node: NodeId,
    /// Why.
    pub cause: Cause,
    /// The product of `1 / q` of the Russian-roulette survivals along the path (1 without
    /// any): the gain roulette gave the sample's weight.
    pub roulette_gain: f64,
    /// The pixel's samples.
    pub samples: usize,
    /// Light tracing and BDPT: the strategy `(s, t)` of the dominant path and its MIS weight.
    pub strategy: Option<([u32; 2], f64)>,
}

impl Firefly {
    /// `value / typical`.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.value / self.typical
    }

    /// One sentence for the inspector (ends with the blamed node's id).
    #[must_use]
    pub fn sentence(&self) -> String {
        let what = if self.by_median { "median" } else { "mean" };
        let head = format!(
            "Sample {} is {:.0}x the pixel's {what} ({} vs {}), through {} (#{}): ",
            self.sample,
            self.ratio(),
            g(self.value),
            g(self.typical),
            self.lpe,
            self.path.0
        );
        let why = match &self.cause {
            Cause::Caustic {
                pdf,
                lobe,
                weight,
                events,
            } => format!(
                "a caustic found by BSDF sampling. {}; the sample itself is ordinary{}, what is rare is the event: {} of the pixel's {} samples found the light this way",
                self.caustic_reach(if *lobe == LobeKind::Diffuse {
                    "diffuse"
                } else {
                    "glossy"
                }),
                match weight {
                    Some(w) => format!(" (f cos/pdf = {}{})", g(*w), pdf_inner(*pdf)),
                    None => pdf_text(*pdf),
                },
                events,
                self.samples
            ),
            Cause::BsdfEmission { mis, pdf } => format!(
                "emission found by BSDF sampling{} with MIS weight {mis:.3}, near 1: the light strategy could hardly have sampled this direction",
                pdf_text(*pdf)
            ),
            Cause::Roulette { q } => format!(
                "Russian roulette kept the path with probability q = {} and divided its throughput by q (x{})",
                g(*q),
                g(1.0 / q)
            ),
            Cause::BsdfWeight { weight, pdf } => format!(
                "a BSDF sample with f cos/pdf = {}{}",
                g(*weight),
                pdf_text(*pdf)
            ),
            Cause::LightSample { pdf, mis, factor } => format!(
                "a light sample with a small pdf {}: f cos w/pdf = {} (MIS weight {mis:.3})",
                g(*pdf),
                g(*factor)
            ),
        };
        let gain = if self.roulette_gain > 1.0 && !matches!(self.cause, Cause::Roulette { .. }) {
            format!(
                "; Russian roulette multiplied the path's weight by {}",
                g(self.roulette_gain)
            )
        } else {
            String::new()
        };
        let strategy = match self.strategy {
            Some(([s, t], w)) if !matches!(self.cause, Cause::Caustic { .. }) => format!(
                "; its light came by strategy s={s} t={t} ({}) at MIS weight {w:.3}",
                crate::analysis::strategy_parts::strategy_words(Some([s, t]))
            ),
            _ => String::new(),
        };
        format!("{head}{why}{gain}{strategy} (#{}).", self.node.0)
    }

    /// Why a caustic's camera path carries it: under the path tracer the light sample cannot
    /// reach the light through the specular chain, so the `lobe` bounce's BSDF sample carries
    /// it at full weight; under BDPT the strategies from the light's side find such paths too,
    /// and MIS weighs this one by its recorded weight.
    fn caustic_reach(&self, lobe: &str) -> String {
        match self.strategy {
            Some(([s, t], w)) => format!(
                "The camera path hit the lamp after the {lobe} bounce (strategy s={s} t={t}); the strategies from the light's side find such paths too, so MIS weighs this one {w:.3}"
            ),
            None => format!(
                "Light sampling cannot reach the light through the specular chain, so only the {lobe} bounce's BSDF sample finds it, at full MIS weight"
            ),
        }
    }
}

fn g(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e4) {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

fn pdf_text(pdf: Option<f64>) -> String {
    pdf.map_or_else(|| " (delta pdf)".into(), |p| format!(" (pdf {})", g(p)))
}

fn pdf_inner(pdf: Option<f64>) -> String {
    pdf.map_or_else(|| ", delta pdf".into(), |p| format!(", pdf {}", g(p)))
}

/// The pixel's typical sample value and whether it is the median (else the mean): `None` when
/// every sample is 0 or there are none.
#[must_use]
pub fn typical(tree: &RayTree) -> Option<(f64, bool)> {
    let mut v: Vec<f64> = tree
        .samples
        .iter()
        .map(|s| sample_value(s.radiance))
        .filter(|v| v.is_finite())
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    let mean = v.iter().sum::<f64>() / n as f64;
    if median > 0.0 {
        Some((median, true))
    } else if mean > 0.0 {
        Some((mean, false))
    } else {
        None
    }
}

/// Whether sample `sample` is a firefly (see the module docs); a non-finite one is not (it is
/// counted apart, as the render drops it).
#[must_use]
pub fn is_firefly(tree: &RayTree, sample: usize) -> bool {
    let Some(s) = tree.samples.get(sample) else {
        return false;
    };
    let v = sample_value(s.radiance);
    v.is_finite() && typical(tree).is_some_and(|(t, _)| v > FIREFLY_RATIO * t)
}

/// Explain sample `sample` if it is a firefly with a dominant path; `None` otherwise (not a
/// firefly, a Whitted tree, no complete path).
#[must_use]
pub fn explain(tree: &RayTree, sample: usize) -> Option<Firefly> {
    let s = tree.samples.get(sample)?;
    let (typical, by_median) = typical(tree)?;
    let value = sample_value(s.radiance);
    // A non-finite value (a NaN sample, which the render drops) is no firefly.
    if !value.is_finite() || value <= FIREFLY_RATIO * typical {
        return None;
    }
    let end = tree
        .depth_first(s.root)
        .into_iter()
        .filter(|id| {
            tree.node(*id)
                .path
                .as_ref()
                .is_some_and(|p| p.lpe.ends_with(['L', 'B']))
        })
        .max_by(|a, b| contribution(tree, *a).total_cmp(&contribution(tree, *b)))?;
    let e = tree.node(end);
    let info = e.path.as_ref()?;
    // The chain from the camera to the end.
    let mut chain = vec![end];
    let mut at = e.parent;
    while let Some(p) = at {
        chain.push(p);
        at = tree.node(p).parent;
    }
    chain.reverse();
    let (node, mut cause) = blame(tree, &chain, end)?;
    if let Cause::Caustic { events, .. } = &mut cause {
        *events = caustic_samples(tree);
    }
    Some(Firefly {
        sample,
        value,
        typical,
        by_median,
        path: end,
        lpe: info.lpe.clone(),
        node,
        cause,
        roulette_gain: roulette_gain(tree, &chain),
        samples: tree.samples.len(),
        strategy: info.strategy.map(|st| (st, info.mis_weight.unwrap_or(1.0))),
    })
}

/// The product of `1 / q` over the Russian-roulette survivals along `chain`.
fn roulette_gain(tree: &RayTree, chain: &[NodeId]) -> f64 {
    chain
        .iter()
        .filter_map(|&id| tree.node(id).path.as_ref()?.roulette)
        .filter(|r| r.survived && r.probability > 0.0)
        .map(|r| 1.0 / r.probability)
        .product()
}

/// A caustic: a diffuse or glossy bounce, then a specular chain, then the light.
const CAUSTIC_LPE: &str = "C.*[DG]S+L";

/// Whether node `n` (its path record `p`) is a ray that found an emitter by BSDF sampling: not
/// a shadow ray, not the camera ray, its LPE ending at the light.
fn found_emission(n: &crate::tree::RayNode, p: &crate::tree::PathInfo) -> bool {
    n.kind != RayKind::Shadow && n.depth > 0 && p.lpe.ends_with('L')
}

/// Whether `id` ends a caustic found by BSDF sampling ([`CAUSTIC_LPE`], [`found_emission`])
/// with a positive contribution.
fn is_caustic_end(tree: &RayTree, id: NodeId, caustic: &Lpe) -> bool {
    let n = tree.node(id);
    n.path.as_ref().is_some_and(|p| {
        found_emission(n, p) && luminance(p.contribution) > 0.0 && caustic.matches(&p.lpe)
    })
}

/// How many of the tree's samples have a caustic path found by BSDF sampling.
fn caustic_samples(tree: &RayTree) -> usize {
    let Ok(caustic) = Lpe::parse(CAUSTIC_LPE) else {
        return 0;
    };
    tree.samples
        .iter()
        .filter(|s| {
            tree.depth_first(s.root)
                .into_iter()
                .any(|id| is_caustic_end(tree, id, &caustic))
        })
        .count()
}

fn contribution(tree: &RayTree, id: NodeId) -> f64 {
    tree.node(id)
        .path
        .as_ref()
        .map_or(0.0, |p| luminance(p.contribution))
}

fn density(p: Option<Pdf>) -> Option<f64> {
    match p {
        Some(Pdf::Density(d)) => Some(d),
        _ => None,
    }
}

/// The blamed vertex of the path `chain` (camera first) ending at `end`.
fn blame(tree: &RayTree, chain: &[NodeId], end: NodeId) -> Option<(NodeId, Cause)> {
    let e = tree.node(end);
    let info = e.path.as_ref()?;
    if found_emission(e, info) {
        let caustic = Lpe::parse(CAUSTIC_LPE).ok()?;
        if caustic.matches(&info.lpe) {
            let bounce = chain.iter().rev().copied().find(|id| {
                tree.node(*id).path.as_ref().is_some_and(|p| {
                    matches!(
                        p.lobe,
                        Some(
                            LobeKind::Diffuse
                                | LobeKind::GlossyReflection
                                | LobeKind::GlossyTransmission
                        )
                    )
                })
            })?;
            let info = tree.node(bounce).path.as_ref()?;
            let (pdf, lobe) = (density(info.pdf), info.lobe?);
            let weight = info.bsdf_cos_pdf.map(|w| w.max_element());
            let events = 0; // counted over the pixel's samples by `explain`
            return Some((
                bounce,
                Cause::Caustic {
                    pdf,
                    lobe,
                    weight,
                    events,
                },
            ));
        }
        let mis = info.mis_weight.unwrap_or(1.0);
        if mis >= MIS_NEAR_ONE && density(info.pdf).is_some() {
            let pdf = density(info.pdf);
            return Some((end, Cause::BsdfEmission { mis, pdf }));
        }
    }
    // The largest factor along the path.
    let mut best: Option<(f64, NodeId, Cause)> = None;
    let mut consider = |f: f64, id: NodeId, c: Cause| {
        if f.is_finite() && best.as_ref().is_none_or(|b| f > b.0) {
            best = Some((f, id, c));
        }
    };
    for &id in &chain[1..] {
        let n = tree.node(id);
        let Some(p) = &n.path else { continue };
        if n.kind == RayKind::Shadow {
            if let (Some(pdf), Some(fc)) = (density(p.pdf), p.bsdf_cos_pdf) {
                let mis = p.mis_weight.unwrap_or(1.0);
                let factor = fc.max_element() * mis / pdf;
                consider(factor, id, Cause::LightSample { pdf, mis, factor });
            }
            continue;
        }
        if let Some(w) = p.bsdf_cos_pdf {
            let weight = w.max_element();
            let pdf = density(p.pdf);
            consider(weight, id, Cause::BsdfWeight { weight, pdf });
        }
        let roulette = n
            .parent
            .and_then(|q| tree.node(q).path.as_ref()?.roulette)
            .filter(|r| r.survived && r.probability < 1.0 && r.probability > 0.0);
        if let Some(r) = roulette {
            consider(
                1.0 / r.probability,
                id,
                Cause::Roulette { q: r.probability },
            );
        }
    }
    best.map(|(_, id, c)| (id, c))
}

#[cfg(test)]
mod tests;
