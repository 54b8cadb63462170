//! [`diff_text`]: a [`TreeDiff`] as text, one changed field a line.

use super::{FieldChange, TreeDiff};
use crate::math::Rgb;
use crate::tree::{NodeId, RayTree};
use serde_json::Value;

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
    format!("[{:.6}, {:.6}, {:.6}]", c.x, c.y, c.z)
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

/// The difference as text: settings, first divergence, every changed node (one field a line,
/// `old -> new`), the unmatched subtrees, then the pixel values.
#[must_use]
pub fn diff_text(d: &TreeDiff, a: &RayTree, b: &RayTree) -> String {
    use std::fmt::Write;
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
        if let Some(f) = &d.first_divergence {
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
        let _ = writeln!(
            s,
            "changed rays: {} of {} matched; only in a: {}, only in b: {}",
            d.changed.len(),
            d.matched,
            d.only_a.len(),
            d.only_b.len()
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
    let _ = writeln!(
        s,
        "pixel a {}  b {}  b - a {}",
        rgb(d.radiance_a),
        rgb(d.radiance_b),
        rgb(d.difference)
    );
    s
}
