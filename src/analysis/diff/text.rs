//! [`diff_text`]: a [`TreeDiff`] as text, one changed field a line.

use super::{FieldChange, NodeChange, TreeDiff};
use crate::math::Rgb;
use crate::tree::{NodeId, RayTree};
use serde_json::Value;
use std::fmt::Write;

fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => "none".into(),
        v => v.to_string(),
    }
}

/// `field: a -> b`, as the settings and the changed rays list their fields.
fn change_text(f: &FieldChange) -> String {
    format!("{}: {} -> {}", f.field, value_text(&f.a), value_text(&f.b))
}

fn rgb(c: Rgb) -> String {
    let n = |v: f64| crate::text::num(v, 6);
    format!("[{}, {}, {}]", n(c.x), n(c.y), n(c.z))
}

fn ids(a: NodeId, b: NodeId) -> String {
    if a == b {
        format!("#{}", a.0)
    } else {
        format!("#{} / #{}", a.0, b.0)
    }
}

/// Rays in the subtree of `id`.
pub(super) fn subtree_len(t: &RayTree, id: NodeId) -> usize {
    t.depth_first(id).len()
}

/// The difference as text, short: the settings that differ, a summary count, the first
/// differing decision, the first divergence of values, and the pixel difference with its
/// standard error ([`diff_full_text`] adds every changed field).
#[must_use]
pub fn diff_text(d: &TreeDiff, a: &RayTree, b: &RayTree) -> String {
    let mut s = summary(d, a, b);
    if !d.trees_equal() {
        let fields: usize = d.changed.iter().map(|c| c.fields.len()).sum();
        let unmatched = d.only_a.len() + d.only_b.len();
        let _ = writeln!(
            s,
            "(--full lists every changed field: {fields} fields of {} rays, and {unmatched} unmatched subtrees)",
            d.changed.len()
        );
    }
    s
}

/// The difference as text, whole: [`diff_text`]'s summary, then every changed node (one field
/// a line, `old -> new`) and the unmatched subtrees.
#[must_use]
pub fn diff_full_text(d: &TreeDiff, a: &RayTree, b: &RayTree) -> String {
    let mut s = summary(d, a, b);
    if !d.trees_equal() {
        let _ = writeln!(
            s,
            "every changed field (one sample's recorded values, not estimates: no standard error):"
        );
        for c in &d.changed {
            let _ = writeln!(
                s,
                "{} {} (level {}):",
                c.kind.name(),
                ids(c.a, c.b),
                c.level
            );
            for f in &c.fields {
                let _ = writeln!(s, "    {}", change_text(f));
            }
        }
        for (side, t, list) in [("a", a, &d.only_a), ("b", b, &d.only_b)] {
            for id in list {
                let n = t.node(*id);
                let _ = writeln!(
                    s,
                    "only in {side}: {} #{} (subtree of {} rays)",
                    n.kind.name(),
                    id.0,
                    subtree_len(t, *id)
                );
            }
        }
    }
    s
}

/// The diff's summary: the settings changed, how the trees differ, the pixels and their
/// strategies.
fn summary(d: &TreeDiff, a: &RayTree, b: &RayTree) -> String {
    let mut s = String::new();
    for f in &d.settings {
        let _ = writeln!(s, "setting {}", change_text(f));
    }
    if d.trees_equal() {
        let _ = writeln!(
            s,
            "no difference: the trees are identical ({} rays matched)",
            d.matched
        );
    } else {
        differences_text(d, a, b, &mut s);
    }
    let _ = writeln!(
        s,
        "pixel a {}  b {}  b - a {}",
        rgb(d.radiance_a),
        rgb(d.radiance_b),
        rgb(d.difference)
    );
    s += &pixel_text(d);
    s += &strategy_text(d);
    s
}

/// How trees `a` and `b` differ: the rays changed and only in one, the first differing
/// decision and the first divergence.
fn differences_text(d: &TreeDiff, a: &RayTree, b: &RayTree, s: &mut String) {
    let rays = |t: &RayTree, l: &[NodeId]| l.iter().map(|id| subtree_len(t, *id)).sum::<usize>();
    let _ = writeln!(
        s,
        "changed rays: {} of {} matched; only in a: {} ({} rays), only in b: {} ({} rays)",
        d.changed.len(),
        d.matched,
        d.only_a.len(),
        rays(a, &d.only_a),
        d.only_b.len(),
        rays(b, &d.only_b)
    );
    match &d.first_decision {
        Some(c) => {
            let _ = writeln!(
                s,
                "first differing decision: sample {}, {} {} (depth {}), {}: a {}; b {}",
                c.sample,
                c.kind.name(),
                ids(c.a, c.b),
                c.depth,
                c.decision,
                c.in_a,
                c.in_b
            );
            let _ = writeln!(
                s,
                "    decisions differ in {} of {} samples; below a differing decision the paths differ, so their values differ too",
                d.samples_with_decisions_changed, d.samples_matched
            );
        }
        None => {
            let _ = writeln!(
                s,
                "no sampling decision differs (lobes, roulette outcomes and spawned rays agree): the values below differ by the settings alone"
            );
        }
    }
    if let Some(f) = &d.first_divergence {
        divergence_text(f, s);
    }
}

/// The first divergence: the ray and its first two changed fields.
fn divergence_text(f: &NodeChange, s: &mut String) {
    let head: Vec<String> = f
        .fields
        .iter()
        .take(2)
        .map(|c| format!("{} {} -> {}", c.field, value_text(&c.a), value_text(&c.b)))
        .collect();
    let more = f.fields.len().saturating_sub(2);
    let _ = writeln!(
        s,
        "first divergence: {} {} (level {}): {}{}",
        f.kind.name(),
        ids(f.a, f.b),
        f.level,
        head.join("; "),
        if more > 0 {
            format!(" (and {more} more fields)")
        } else {
            String::new()
        }
    );
}

/// Light tracing and BDPT: each strategy's part of the pixel in both trees (the parts of
/// either pixel under 0.1% of its luminance counted on one line).
fn strategy_text(d: &TreeDiff) -> String {
    use crate::bsdf::luminance;
    if d.strategies.is_empty() {
        return String::new();
    }
    let total = |f: fn(&super::StrategyChange) -> Rgb| {
        d.strategies.iter().map(|c| luminance(f(c))).sum::<f64>()
    };
    let (ta, tb) = (total(|c| c.a), total(|c| c.b));
    let share = |v: Rgb, t: f64| if t > 0.0 { luminance(v) / t } else { 0.0 };
    let mis = |m: Option<f64>| m.map_or("-".to_string(), |w| crate::text::num(w, 3));
    let mut s = String::from(
        "by strategy (its part of the pixel in a -> b, the share of each pixel's luminance, MIS weight a -> b):\n",
    );
    let mut small = 0;
    for c in &d.strategies {
        if share(c.a, ta).max(share(c.b, tb)) < 0.001 {
            small += 1;
            continue;
        }
        let name = c
            .strategy
            .map_or("no strategy".to_string(), |[s, t]| format!("s={s} t={t}"));
        let _ = writeln!(
            s,
            "    {name}: {} -> {} ({:.1}% -> {:.1}%), luminance b - a {}; MIS weight {} -> {}; {} -> {} contributions",
            rgb(c.a),
            rgb(c.b),
            100.0 * share(c.a, ta),
            100.0 * share(c.b, tb),
            crate::text::num(luminance(c.b) - luminance(c.a), 6),
            mis(c.mis_weight[0]),
            mis(c.mis_weight[1]),
            c.contributions[0],
            c.contributions[1]
        );
    }
    if small > 0 {
        let _ = writeln!(
            s,
            "    and {small} more strategies under 0.1% of both pixels"
        );
    }
    s
}

/// The sample means' difference with its standard error and what it says.
fn pixel_text(d: &TreeDiff) -> String {
    let p = &d.pixel;
    let [na, nb] = p.samples;
    let Some(se) = p.std_error else {
        return format!(
            "b - a from {na} and {nb} sample(s): no standard error from fewer than 2 samples a side (exact only if both settings are deterministic)\n"
        );
    };
    let mut how = if p.paired {
        format!("paired by sample, {na} samples")
    } else {
        format!("{na} and {nb} samples")
    };
    if p.splat_paths != [0, 0] {
        let [la, lb] = p.splat_paths;
        how += &format!(", and {la} and {lb} light paths that splatted here (not paired)");
    }
    let m = p.mean.to_array();
    let e = se.to_array();
    let beyond: Vec<&str> = ["R", "G", "B"]
        .into_iter()
        .enumerate()
        .filter(|(c, _)| m[*c].abs() > 2.0 * e[*c])
        .map(|(_, n)| n)
        .collect();
    let verdict = if !(p.mean.is_finite() && se.is_finite()) {
        "not finite: no verdict".to_string()
    } else if beyond.is_empty() {
        "within 2 standard errors in every channel: consistent with noise".to_string()
    } else {
        format!("beyond 2 standard errors in {}", beyond.join(", "))
    };
    format!(
        "b - a of the {} {} +/- {} (standard error, {how}): {verdict}\n",
        if p.splat_paths == [0, 0] {
            "sample means"
        } else {
            "pixels"
        },
        rgb(p.mean),
        rgb(se)
    )
}
