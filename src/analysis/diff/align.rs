//! Two trees of one pixel side by side: one row per matched pair of nodes (or per node only one
//! tree has), depth-first, matched as [`super::diff`] matches them, so that the inspector's
//! "pin and compare" panel can draw the pinned and the current tree in two aligned columns.

use super::matched_children;
use crate::tree::{NodeId, RayTree};

/// One row of the side-by-side view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AlignedRow {
    /// The node of tree A (`None`: only B has this ray).
    pub a: Option<NodeId>,
    /// The node of tree B (`None`: only A has this ray).
    pub b: Option<NodeId>,
    /// Depth of the row (the ray's depth in its tree).
    pub depth: u32,
}

/// Every node of `a` and `b` exactly once, matched pairs on one row, depth-first: samples by
/// index, children by kind and order.
#[must_use]
pub fn align(a: &RayTree, b: &RayTree) -> Vec<AlignedRow> {
    let mut rows = Vec::new();
    let n = a.samples.len().max(b.samples.len());
    for i in 0..n {
        let ra = a.samples.get(i).map(|s| s.root);
        let rb = b.samples.get(i).map(|s| s.root);
        walk(a, b, ra, rb, &mut rows);
    }
    rows
}

fn walk(
    a: &RayTree,
    b: &RayTree,
    ia: Option<NodeId>,
    ib: Option<NodeId>,
    rows: &mut Vec<AlignedRow>,
) {
    let depth = match (ia, ib) {
        (Some(x), _) => a.node(x).depth,
        (None, Some(y)) => b.node(y).depth,
        (None, None) => return,
    };
    rows.push(AlignedRow {
        a: ia,
        b: ib,
        depth,
    });
    match (ia, ib) {
        (Some(x), Some(y)) => {
            for (ca, cb) in matched_children(a, a.node(x), b, b.node(y)) {
                walk(a, b, ca, cb, rows);
            }
        }
        (Some(x), None) => {
            for c in &a.node(x).children {
                walk(a, b, Some(*c), None, rows);
            }
        }
        (None, Some(y)) => {
            for c in &b.node(y).children {
                walk(a, b, None, Some(*c), rows);
            }
        }
        (None, None) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::super::diff;
    use super::*;
    use crate::{Scene, trace_pixel};

    #[test]
    fn every_node_once_and_pairs_as_the_diff_matches_them() {
        let mut scene = Scene::default_scene();
        let a = trace_pixel(&scene, 400, 200).unwrap();
        scene.settings.max_depth = 1;
        let b = trace_pixel(&scene, 400, 200).unwrap();
        let rows = align(&a, &b);
        let (mut seen_a, mut seen_b) = (vec![0; a.nodes.len()], vec![0; b.nodes.len()]);
        for r in &rows {
            if let Some(x) = r.a {
                seen_a[x.index()] += 1;
            }
            if let Some(y) = r.b {
                seen_b[y.index()] += 1;
            }
        }
        assert!(seen_a.iter().chain(&seen_b).all(|&n| n == 1));
        let d = diff(&a, &b);
        let pairs = rows.iter().filter(|r| r.a.is_some() && r.b.is_some());
        assert_eq!(pairs.clone().count(), d.matched);
        for c in &d.changed {
            assert!(pairs.clone().any(|r| r.a == Some(c.a) && r.b == Some(c.b)));
        }
        // Rows only A has are exactly the subtrees the diff lists.
        let only_a = rows.iter().filter(|r| r.b.is_none()).count();
        let want: usize = d.only_a.iter().map(|id| a.depth_first(*id).len()).sum();
        assert_eq!(only_a, want);
        assert!(only_a > 0);
    }
}
