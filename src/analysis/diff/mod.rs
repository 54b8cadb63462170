//! Compare two ray trees of one pixel (issue 17, "pin and compare"): walk both trees in
//! parallel, matching samples by index and children by kind and order (the i-th reflected child
//! of one with the i-th reflected child of the other), and report every changed field of the
//! matched nodes, the rays only one tree has, and the first divergent node: the shallowest
//! matched pair (breadth-first) whose hit object, set of child ray kinds or any number differs
//! beyond a relative [`REL_TOL`].
//!
//! Fields are compared through their serialized form (`raytree.tree/2`), so every field of
//! [`RayNode`] takes part except the structural `id`, `parent` and `children` (children are
//! compared by their kinds). A non-finite number serializes as `null` and so differs from any
//! finite one.

use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use serde::Serialize;
use serde_json::Value;
use std::collections::VecDeque;

/// Numbers closer than this, relative to the larger magnitude, are equal.
pub const REL_TOL: f64 = 1e-12;

/// One changed field: its path in the serialized node (`interface.fresnel.r`, `radiance[0]`)
/// and both values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FieldChange {
    /// Dotted path in the JSON form.
    pub field: String,
    /// Value in tree A.
    pub a: Value,
    /// Value in tree B.
    pub b: Value,
}

/// A matched pair of nodes and what changed between them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NodeChange {
    /// Node in tree A.
    pub a: NodeId,
    /// Node in tree B.
    pub b: NodeId,
    /// Their ray kind (matched nodes share it).
    pub kind: RayKind,
    /// Breadth-first level from the camera ray (0 = camera ray).
    pub level: u32,
    /// Changed fields (never empty).
    pub fields: Vec<FieldChange>,
}

/// The difference of two trees of one pixel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TreeDiff {
    /// Changed tree-level fields (`pixel`, `settings.*`).
    pub settings: Vec<FieldChange>,
    /// The shallowest matched pair that differs (breadth-first, then sample and child order).
    pub first_divergence: Option<NodeChange>,
    /// Every matched pair that differs, breadth-first (fields sorted by path).
    pub changed: Vec<NodeChange>,
    /// Number of matched pairs.
    pub matched: usize,
    /// Roots of subtrees only tree A has (no child of that kind and order in B).
    pub only_a: Vec<NodeId>,
    /// Roots of subtrees only tree B has.
    pub only_b: Vec<NodeId>,
    /// Pixel value of A.
    pub radiance_a: Rgb,
    /// Pixel value of B.
    pub radiance_b: Rgb,
    /// `radiance_b - radiance_a`.
    pub difference: Rgb,
    /// The first sampling decision that differs ([`decision_changes`]: the first sample with
    /// one, its shallowest), or `None`.
    pub first_decision: Option<DecisionChange>,
    /// Samples in which some decision differs.
    pub samples_with_decisions_changed: usize,
    /// Samples both trees have (matched by position).
    pub samples_matched: usize,
    /// `b - a` of the sample means with its standard error ([`pixel_difference`]).
    pub pixel: PixelDifference,
    /// Light tracing and BDPT: the pixel split by strategy in both trees ([`strategy_changes`];
    /// empty when neither tree has strategies).
    pub strategies: Vec<StrategyChange>,
}

/// One strategy's part of the pixel in both trees ([`crate::analysis::strategy_parts`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StrategyChange {
    /// `[s, t]`; `None` for what camera rays saw without a strategy.
    pub strategy: Option<[u32; 2]>,
    /// Its part of A's pixel value.
    pub a: Rgb,
    /// Its part of B's pixel value.
    pub b: Rgb,
    /// Its luminance-weighted mean MIS weight in A and B (`None` where it brought nothing).
    pub mis_weight: [Option<f64>; 2],
    /// Its recorded contributions in A and B.
    pub contributions: [usize; 2],
}

/// The strategies of `a` and `b` side by side, the largest part (of either tree) first.
#[must_use]
pub fn strategy_changes(a: &RayTree, b: &RayTree) -> Vec<StrategyChange> {
    use crate::analysis::strategy_parts::strategy_parts;
    let (pa, pb) = (strategy_parts(a), strategy_parts(b));
    let mut out: Vec<StrategyChange> = Vec::new();
    for (side, parts) in [(0, &pa), (1, &pb)] {
        for p in parts {
            let i = match out.iter().position(|c| c.strategy == p.strategy) {
                Some(i) => i,
                None => {
                    out.push(StrategyChange {
                        strategy: p.strategy,
                        a: Rgb::ZERO,
                        b: Rgb::ZERO,
                        mis_weight: [None; 2],
                        contributions: [0; 2],
                    });
                    out.len() - 1
                }
            };
            let c = &mut out[i];
            if side == 0 {
                c.a = p.value;
            } else {
                c.b = p.value;
            }
            c.mis_weight[side] = Some(p.mis_weight);
            c.contributions[side] = p.contributions;
        }
    }
    let size = |c: &StrategyChange| {
        crate::bsdf::luminance(c.a)
            .abs()
            .max(crate::bsdf::luminance(c.b).abs())
    };
    out.sort_by(|x, y| size(y).total_cmp(&size(x)));
    out
}

impl TreeDiff {
    /// The trees are the same: no changed node, no unmatched ray (settings may differ).
    #[must_use]
    pub fn trees_equal(&self) -> bool {
        self.changed.is_empty() && self.only_a.is_empty() && self.only_b.is_empty()
    }
}

fn numbers_differ(x: f64, y: f64) -> bool {
    // Bitwise-equal (including both infinite) is equal; otherwise relative.
    x != y && (x - y).abs() > REL_TOL * x.abs().max(y.abs())
}

/// Push every leaf of `a` and `b` that differs, under `path`.
fn compare(path: &str, a: &Value, b: &Value, out: &mut Vec<FieldChange>) {
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, va) in x {
                compare(&join(k), va, y.get(k).unwrap_or(&Value::Null), out);
            }
            for (k, vb) in y.iter().filter(|(k, _)| !x.contains_key(*k)) {
                compare(&join(k), &Value::Null, vb, out);
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                compare(&format!("{path}[{i}]"), va, vb, out);
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            if let (Some(x), Some(y)) = (x.as_f64(), y.as_f64())
                && numbers_differ(x, y)
            {
                out.push(FieldChange {
                    field: path.to_string(),
                    a: a.clone(),
                    b: b.clone(),
                });
            }
        }
        _ if a != b => out.push(FieldChange {
            field: path.to_string(),
            a: a.clone(),
            b: b.clone(),
        }),
        _ => {}
    }
}

fn node_value(n: &RayNode) -> Value {
    let mut v = serde_json::to_value(n).unwrap_or(Value::Null);
    if let Value::Object(m) = &mut v {
        for k in ["id", "parent", "children"] {
            m.remove(k);
        }
    }
    v
}

fn child_kinds(t: &RayTree, n: &RayNode) -> Value {
    Value::Array(
        n.children
            .iter()
            .map(|c| Value::String(t.node(*c).kind.name().into()))
            .collect(),
    )
}

/// The fields that differ between nodes `a` and `b`, the child kinds first.
fn node_changes(ta: &RayTree, a: &RayNode, tb: &RayTree, b: &RayNode) -> Vec<FieldChange> {
    let mut out = Vec::new();
    compare(
        "children (kinds)",
        &child_kinds(ta, a),
        &child_kinds(tb, b),
        &mut out,
    );
    compare("", &node_value(a), &node_value(b), &mut out);
    out
}

/// The children of `na` (in `a`) and `nb` (in `b`) paired by kind and order: the i-th
/// reflected child with the i-th reflected child, and so on for every kind in
/// [`RayKind::ALL`] order; a child without a partner is paired with `None`.
#[must_use]
pub fn matched_children(
    a: &RayTree,
    na: &RayNode,
    b: &RayTree,
    nb: &RayNode,
) -> Vec<(Option<NodeId>, Option<NodeId>)> {
    let mut out = Vec::new();
    for kind in RayKind::ALL {
        let of = |t: &RayTree, n: &RayNode| -> Vec<NodeId> {
            n.children
                .iter()
                .copied()
                .filter(|c| t.node(*c).kind == kind)
                .collect()
        };
        let (ca, cb) = (of(a, na), of(b, nb));
        for i in 0..ca.len().max(cb.len()) {
            out.push((ca.get(i).copied(), cb.get(i).copied()));
        }
    }
    out
}

/// A tree's settings as JSON (its flat record, `SettingsRecord`), with the defaults its serialization leaves out written in:
/// `antialiasing` "auto", `roulette_below` 0 (a tree records the weight whenever the
/// roulette was on), and the values in force of `rr_depth`, `glossy_samples` and `filter`
/// (issue 32: the default `rr_depth` 5 read as "none -> 2"), so that a diff does not read an
/// omitted default as "none".
fn settings_value(s: &crate::scene::Settings) -> Value {
    let record = crate::scene::desc::SettingsRecord::from(s);
    let mut v = serde_json::to_value(record).unwrap_or(Value::Null);
    if let Value::Object(m) = &mut v {
        m.entry("antialiasing").or_insert_with(|| "auto".into());
        m.entry("roulette_below").or_insert_with(|| 0.0.into());
        m.insert("rr_depth".into(), s.path.rr_depth.into());
        m.insert("glossy_samples".into(), s.whitted.glossy_samples.into());
        if let Ok(f) = serde_json::to_value(s.filter) {
            m.insert("filter".into(), f);
        }
    }
    v
}

/// Compare trees `a` and `b` (normally of one pixel under two settings).
#[must_use]
pub fn diff(a: &RayTree, b: &RayTree) -> TreeDiff {
    let mut settings = Vec::new();
    compare(
        "pixel",
        &serde_json::to_value(a.pixel).unwrap_or(Value::Null),
        &serde_json::to_value(b.pixel).unwrap_or(Value::Null),
        &mut settings,
    );
    compare(
        "settings",
        &settings_value(&a.settings),
        &settings_value(&b.settings),
        &mut settings,
    );
    let mut changed = Vec::new();
    let (mut only_a, mut only_b) = (Vec::new(), Vec::new());
    let mut matched = 0;
    let mut queue: VecDeque<(NodeId, NodeId, u32)> = VecDeque::new();
    let n = a.samples.len().min(b.samples.len());
    for (sa, sb) in a.samples.iter().zip(&b.samples) {
        queue.push_back((sa.root, sb.root, 0));
    }
    only_a.extend(a.samples[n..].iter().map(|s| s.root));
    only_b.extend(b.samples[n..].iter().map(|s| s.root));
    while let Some((ia, ib, level)) = queue.pop_front() {
        let (na, nb) = (a.node(ia), b.node(ib));
        matched += 1;
        let fields = node_changes(a, na, b, nb);
        if !fields.is_empty() {
            changed.push(NodeChange {
                a: ia,
                b: ib,
                kind: na.kind,
                level,
                fields,
            });
        }
        for pair in matched_children(a, na, b, nb) {
            match pair {
                (Some(x), Some(y)) => queue.push_back((x, y, level + 1)),
                (Some(x), None) => only_a.push(x),
                (None, Some(y)) => only_b.push(y),
                (None, None) => {}
            }
        }
    }
    let decisions = decision_changes(a, b);
    TreeDiff {
        first_decision: decisions.first().cloned(),
        samples_with_decisions_changed: decisions.len(),
        samples_matched: n,
        pixel: pixel_difference(a, b),
        strategies: strategy_changes(a, b),
        settings,
        first_divergence: changed.first().cloned(),
        changed,
        matched,
        only_a,
        only_b,
        radiance_a: a.radiance,
        radiance_b: b.radiance,
        difference: b.radiance - a.radiance,
    }
}

mod decision;
mod text;
pub use decision::{DecisionChange, PixelDifference, decision_changes, pixel_difference};
#[cfg(test)]
use text::subtree_len;
pub use text::{diff_full_text, diff_text};

pub mod align;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::FresnelModel;
    use crate::{Scene, trace_pixel};

    #[test]
    fn identical_settings_give_no_difference() {
        let scene = Scene::default_scene();
        let t = trace_pixel(&scene, 400, 200).unwrap();
        let d = diff(&t, &t.clone());
        assert!(d.trees_equal() && d.settings.is_empty(), "{d:#?}");
        assert_eq!(d.first_divergence, None);
        assert_eq!(d.matched, t.nodes.len());
        assert_eq!(d.difference, Rgb::ZERO);
        assert!(diff_text(&d, &t, &t).starts_with("no difference"));
    }

    /// Defaults a tree leaves out read as their values: auto antialiasing is "auto", not
    /// "none"; the default roulette (off since issue 32) is 0.
    #[test]
    fn omitted_defaults_read_as_their_values() {
        let mut scene = Scene::default_scene();
        let a = trace_pixel(&scene, 400, 200).unwrap();
        scene.settings.antialiasing = crate::scene::Antialiasing::Uniform;
        scene.settings.whitted.roulette_below = Some(0.25);
        let b = trace_pixel(&scene, 400, 200).unwrap();
        let d = diff(&a, &b);
        let text = |f: &str| {
            let c = d.settings.iter().find(|c| c.field == f).expect(f);
            (c.a.to_string(), c.b.to_string())
        };
        assert_eq!(
            text("settings.antialiasing"),
            ("\"auto\"".into(), "\"uniform\"".into())
        );
        let (was, now) = text("settings.roulette_below");
        assert!(was == "0.0" && now == "0.25", "{was} -> {now}");
    }

    /// Issue 32: the default roulette depth (5, left out of a tree's JSON) reads as 5, not
    /// "none", and an unchanged default is no change.
    #[test]
    fn the_default_rr_depth_reads_as_its_value() {
        let mut scene = Scene::default_scene();
        scene.settings.integrator = crate::scene::IntegratorKind::Path;
        let a = trace_pixel(&scene, 400, 200).unwrap();
        assert!(diff(&a, &a.clone()).settings.is_empty());
        scene.settings.path.rr_depth = 2;
        let b = trace_pixel(&scene, 400, 200).unwrap();
        let d = diff(&a, &b);
        let c = d
            .settings
            .iter()
            .find(|c| c.field == "settings.rr_depth")
            .expect("rr_depth changed");
        assert_eq!(
            (c.a.to_string(), c.b.to_string()),
            (crate::scene::desc::DEFAULT_RR_DEPTH.to_string(), "2".into())
        );
    }

    #[test]
    fn schlick_first_diverges_at_the_camera_rays_fresnel_r() {
        let mut scene = Scene::default_scene();
        let a = trace_pixel(&scene, 400, 200).unwrap();
        scene.settings.whitted.fresnel = FresnelModel::Schlick;
        let b = trace_pixel(&scene, 400, 200).unwrap();
        let d = diff(&a, &b);
        assert_eq!(d.settings.len(), 1, "{:?}", d.settings);
        assert_eq!(d.settings[0].field, "settings.fresnel");
        let f = d.first_divergence.as_ref().expect("they differ");
        assert_eq!(
            (f.a, f.b, f.kind, f.level),
            (NodeId(0), NodeId(0), RayKind::Camera, 0)
        );
        // Fields come in the order of their paths: the interface's model, then R, the first
        // number to change.
        let fields: Vec<&str> = f.fields.iter().map(|c| c.field.as_str()).collect();
        assert_eq!(
            fields[..2],
            ["interface.fresnel.model", "interface.fresnel.r"],
            "{fields:?}"
        );
        assert!(fields.contains(&"interface.fresnel.t") && fields.contains(&"radiance[0]"));
        let (ra, rb) = (
            a.nodes[0].interface.as_ref().unwrap().fresnel.r,
            b.nodes[0].interface.as_ref().unwrap().fresnel.r,
        );
        assert!(ra != rb);
        assert_eq!(f.fields[1].a.as_f64(), Some(ra));
        assert_eq!(f.fields[1].b.as_f64(), Some(rb));
        assert_eq!(d.difference, b.radiance - a.radiance);
        // The structure is the same: every ray matched.
        assert!(d.only_a.is_empty() && d.only_b.is_empty());
        let text = diff_text(&d, &a, &b);
        assert!(
            text.contains(
                "first divergence: camera #0 (level 0): interface.fresnel.model exact -> schlick; interface.fresnel.r 0.04"
            ),
            "{text}"
        );
    }

    #[test]
    fn a_lower_max_depth_leaves_subtrees_only_in_a() {
        let mut scene = Scene::default_scene();
        let a = trace_pixel(&scene, 400, 200).unwrap();
        scene.settings.max_depth = 1;
        let b = trace_pixel(&scene, 400, 200).unwrap();
        let d = diff(&a, &b);
        assert!(d.only_b.is_empty());
        let lost: usize = d.only_a.iter().map(|id| subtree_len(&a, *id)).sum();
        assert_eq!(lost, a.nodes.len() - b.nodes.len());
        assert_eq!(d.matched, b.nodes.len());
        // The shallowest change is where the cut happened (level 1, the refracted ray) or
        // above it; the camera ray's radiance changes with it.
        let f = d.first_divergence.unwrap();
        assert_eq!(f.level, 0, "the camera ray's radiance changes");
        assert!(f.fields.iter().any(|c| c.field == "radiance[0]"));
    }

    #[test]
    fn numbers_differ_relatively() {
        assert!(!numbers_differ(1.0, 1.0 + 1e-15));
        assert!(numbers_differ(1.0, 1.0 + 1e-11));
        assert!(numbers_differ(0.0, 1e-300));
        assert!(!numbers_differ(f64::INFINITY, f64::INFINITY));
        let mut out = Vec::new();
        compare(
            "x",
            &serde_json::json!({"p": [1.0, 2.0], "s": "a"}),
            &serde_json::json!({"p": [1.0, 2.5], "s": "b", "n": 1}),
            &mut out,
        );
        let fields: Vec<&str> = out.iter().map(|f| f.field.as_str()).collect();
        assert_eq!(fields, ["x.p[1]", "x.s", "x.n"]);
    }
}
