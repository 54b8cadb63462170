//! The collapse of the binary BVH into the wide one: [`WideBvh::from_binary`], which opens the
//! largest binary children until a node has [`WIDTH`] of them and cuts small subtrees into
//! leaves of [`GROUP`]-slot groups.

use super::{EMPTY, GROUP, Group, LEAF, Node, U32, WIDTH, WideBvh};
use crate::bvh::{Bvh, down, up};

/// Binary subtrees with at most this many primitives become one leaf.
pub(super) const LEAF_MAX: u32 = 8;
/// Most slots one leaf reference holds: its group count has 4 bits (at most 15 groups).
pub(super) const LEAF_SLOTS: u32 = 15 * GROUP as u32;

impl WideBvh {
    /// Collapse `bvh` (whose slots number `bvh.order.len()`).
    #[must_use]
    pub fn from_binary(bvh: &Bvh) -> Self {
        let mut w = WideBvh::default();
        let Some(root) = bvh.bounds() else {
            return w;
        };
        w.center = root.center();
        w.magnitude = (root.max - root.min).max_element() * 0.5;
        w.exact_only = !(w.magnitude < 1e18 && w.magnitude > 1e-18)
            || 4.0 * f64::EPSILON * w.center.abs().max_element() > U32 * w.magnitude;
        w.root = Some((bvh.nodes[0].min, bvh.nodes[0].max));
        let sizes = subtree_sizes(bvh);
        let pad = 32.0 * U32 * w.magnitude;
        w.stack = w.build(bvh, &sizes, 0, pad).1 + 1;
        w
    }

    /// Build the wide node for binary node `at` (inner, or the root); returns its index and
    /// the most stack entries a traversal below it pushes.
    fn build(&mut self, bvh: &Bvh, sizes: &[(u32, u32)], at: usize, pad: f64) -> (u32, usize) {
        let mut kids = vec![at];
        loop {
            // Open the largest expandable child until there are WIDTH of them.
            let open = kids
                .iter()
                .enumerate()
                .filter(|&(_, &k)| bvh.nodes[k].count == 0 && sizes[k].1 > LEAF_MAX)
                .max_by(|a, b| area(&bvh.nodes[*a.1]).total_cmp(&area(&bvh.nodes[*b.1])));
            match open {
                Some((i, &k)) if kids.len() < WIDTH => {
                    kids.swap_remove(i);
                    kids.push(k + 1);
                    kids.push(bvh.nodes[k].index as usize);
                }
                _ => break,
            }
        }
        let me = self.nodes.len();
        self.nodes.push(Node {
            // Empty slots: min above max, so no ray enters them.
            bounds: [
                [f32::INFINITY; WIDTH],
                [f32::INFINITY; WIDTH],
                [f32::INFINITY; WIDTH],
                [f32::NEG_INFINITY; WIDTH],
                [f32::NEG_INFINITY; WIDTH],
                [f32::NEG_INFINITY; WIDTH],
            ],
            child: [EMPTY; WIDTH],
        });
        let mut deepest = 0;
        for (lane, &k) in kids.iter().enumerate() {
            let n = &bvh.nodes[k];
            for a in 0..3 {
                let c = self.center[a];
                self.nodes[me].bounds[a][lane] = down(f64::from(n.min[a]) - c - pad);
                self.nodes[me].bounds[a + 3][lane] = up(f64::from(n.max[a]) - c + pad);
            }
            let (first, count) = sizes[k];
            let child = if n.count > 0 || count <= LEAF_MAX {
                // A binary leaf can be oversized (primitives sharing one centroid, e.g.
                // duplicated triangles): more slots than one leaf reference holds.
                let (child, need) = self.leaves(me, lane, first, count);
                deepest = deepest.max(need);
                child
            } else {
                let (child, need) = self.build(bvh, sizes, k, pad);
                deepest = deepest.max(need);
                child
            };
            self.nodes[me].child[lane] = child;
        }
        (me as u32, kids.len() - 1 + deepest)
    }

    /// A reference to slots `first..first + count` in lane `lane` of node `parent`: one leaf
    /// when they fit ([`LEAF_SLOTS`]), else a node whose lanes all repeat the parent lane's
    /// box and split the slots evenly (recursively). Returns the reference and the most stack
    /// entries a traversal below it pushes.
    fn leaves(&mut self, parent: usize, lane: usize, first: u32, count: u32) -> (u32, usize) {
        if count <= LEAF_SLOTS {
            return (self.leaf(first, count), 0);
        }
        let me = self.nodes.len();
        let mut node = self.nodes[parent];
        for row in &mut node.bounds {
            *row = [row[lane]; WIDTH];
        }
        node.child = [EMPTY; WIDTH];
        self.nodes.push(node);
        let part = count.div_ceil(WIDTH as u32);
        let mut deepest = 0;
        let mut lanes = 0;
        let mut slot = first;
        while slot < first + count {
            let n = part.min(first + count - slot);
            let (child, need) = self.leaves(me, lanes, slot, n);
            self.nodes[me].child[lanes] = child;
            deepest = deepest.max(need);
            lanes += 1;
            slot += n;
        }
        for row in 0..6 {
            // Unused lanes (never for more than LEAF_SLOTS slots, kept for safety): empty.
            let empty = if row < 3 {
                f32::INFINITY
            } else {
                f32::NEG_INFINITY
            };
            self.nodes[me].bounds[row][lanes..].fill(empty);
        }
        (me as u32, lanes - 1 + deepest)
    }

    /// Groups for slots `first..first + count` (at most [`LEAF_SLOTS`]); returns the leaf
    /// reference.
    fn leaf(&mut self, first: u32, count: u32) -> u32 {
        let start = self.groups.len() as u32;
        let mut slot = first;
        while slot < first + count {
            let n = (first + count - slot).min(GROUP as u32);
            self.groups.push(Group {
                first: slot,
                count: n,
            });
            slot += n;
        }
        let groups = self.groups.len() as u32 - start;
        assert!(start < 1 << 27 && groups < 16, "leaf of at most 15 groups");
        LEAF | start << 4 | groups
    }
}

fn area(n: &crate::bvh::Node) -> f32 {
    let e = [0, 1, 2].map(|a| n.max[a] - n.min[a]);
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
}

/// `(first slot, primitive count)` of every binary node's subtree.
fn subtree_sizes(bvh: &Bvh) -> Vec<(u32, u32)> {
    let mut sizes = vec![(0, 0); bvh.nodes.len()];
    // Depth-first layout: children follow their parent, so a reverse sweep sees them first.
    for i in (0..bvh.nodes.len()).rev() {
        let n = &bvh.nodes[i];
        sizes[i] = if n.count > 0 {
            (n.index, n.count)
        } else {
            let (l, r) = (sizes[i + 1], sizes[n.index as usize]);
            (l.0.min(r.0), l.1 + r.1)
        };
    }
    sizes
}
