//! The binned SAH build (Wald 2007): [`Bvh::build`] and its recursive `Builder`, with the
//! binning and partition helpers.

use super::{Aabb, Bvh, Node, down, up};
use glam::DVec3;

/// Candidate split planes per axis.
const BINS: usize = 16;
/// Leaves never hold more primitives than this unless they all share one centroid.
const MAX_LEAF: usize = 8;
/// Cost of one node visit relative to one primitive test (SAH constant).
const TRAVERSAL_COST: f64 = 1.0;
/// Below this depth the SAH decides; deeper, splits fall back to the median (bounds the stack).
const SAH_DEPTH: u32 = 64;

/// Subtrees over at least this many primitives build their two halves in parallel (rayon);
/// smaller ones build sequentially into one vector.
const PARALLEL_MIN: usize = 4096;

impl Bvh {
    /// Build over `bounds` (one box per primitive; boxes are padded, see [`Aabb::padded`]).
    /// Large subtrees are built on rayon's pool; the tree does not depend on the threads (the
    /// same nodes in the same depth-first order).
    #[must_use]
    pub fn build(bounds: &[Aabb]) -> Self {
        assert!(
            u32::try_from(bounds.len()).is_ok(),
            "fewer than 2^32 primitives"
        );
        let b = Builder {
            boxes: bounds.iter().map(Aabb::padded).collect(),
            centers: bounds.iter().map(Aabb::center).collect(),
        };
        let mut order: Vec<u32> = (0..bounds.len() as u32).collect();
        let nodes = if bounds.is_empty() {
            Vec::new()
        } else {
            b.split_par(&mut order, 0, 0)
        };
        Bvh { nodes, order }
    }
}

/// The primitives' padded boxes and centroids, shared by every subtree's build.
struct Builder {
    boxes: Vec<Aabb>,
    centers: Vec<DVec3>,
}

impl Builder {
    fn range_bounds(&self, order: &[u32]) -> (Aabb, Aabb) {
        let mut b = Aabb::EMPTY;
        let mut c = Aabb::EMPTY;
        for &i in order {
            b = b.union(self.boxes[i as usize]);
            let p = self.centers[i as usize];
            c = c.union(Aabb { min: p, max: p });
        }
        (b, c)
    }

    /// The node over `order` (slots `lo..lo + order.len()`), as a leaf, and where to split it
    /// (partitioning `order`), or `None` for a leaf.
    fn decide(&self, order: &mut [u32], lo: usize, depth: u32) -> (Node, Option<usize>) {
        let (bounds, centers) = self.range_bounds(order);
        let node = Node {
            min: bounds.min.to_array().map(down),
            max: bounds.max.to_array().map(up),
            index: lo as u32,
            count: order.len() as u32,
        };
        let n = order.len();
        if n <= 1 {
            return (node, None);
        }
        let mid = if depth >= SAH_DEPTH {
            self.median_split(order, &centers)
        } else {
            match self.sah_split(order, &bounds, &centers) {
                Some(mid) => mid,
                None if n <= MAX_LEAF => None,
                None => self.median_split(order, &centers),
            }
        };
        // `None` from the median: all centroids coincide, an oversized leaf is the best there is.
        (node, mid)
    }

    /// Build the subtree over `order` (slots `lo..`) into `nodes`; returns its node index.
    fn split_into(&self, order: &mut [u32], lo: usize, depth: u32, nodes: &mut Vec<Node>) -> usize {
        let (node, mid) = self.decide(order, lo, depth);
        let at = nodes.len();
        nodes.push(node);
        let Some(mid) = mid else {
            return at;
        };
        let (left, right) = order.split_at_mut(mid);
        self.split_into(left, lo, depth + 1, nodes);
        let right = self.split_into(right, lo + mid, depth + 1, nodes);
        nodes[at].index = right as u32;
        nodes[at].count = 0;
        at
    }

    /// [`Builder::split_into`] of a fresh vector, the two halves of large subtrees in
    /// parallel; inner nodes' child indices are relative to the returned vector.
    fn split_par(&self, order: &mut [u32], lo: usize, depth: u32) -> Vec<Node> {
        if order.len() < PARALLEL_MIN {
            let mut nodes = Vec::with_capacity(order.len());
            self.split_into(order, lo, depth, &mut nodes);
            return nodes;
        }
        let (mut node, mid) = self.decide(order, lo, depth);
        let Some(mid) = mid else {
            return vec![node];
        };
        let (l, r) = order.split_at_mut(mid);
        let (left, right) = rayon::join(
            || self.split_par(l, lo, depth + 1),
            || self.split_par(r, lo + mid, depth + 1),
        );
        node.index = (1 + left.len()) as u32;
        node.count = 0;
        let left_len = left.len();
        let mut nodes = Vec::with_capacity(1 + left_len + right.len());
        nodes.push(node);
        // Placed behind this node (and the left subtree): inner nodes' child indices shift.
        nodes.extend(left.into_iter().map(|n| shifted(n, 1)));
        nodes.extend(right.into_iter().map(|n| shifted(n, 1 + left_len)));
        nodes
    }

    /// The best binned SAH split, partitioned (`Some(None)`: a leaf is cheaper); `None` when
    /// the SAH cannot decide (no split plane separates the centroids). The three axes are
    /// binned in one pass over the primitives.
    fn sah_split(&self, order: &mut [u32], bounds: &Aabb, centers: &Aabb) -> Option<Option<usize>> {
        let n = order.len();
        let extent = centers.max - centers.min;
        let scale = [0, 1, 2].map(|a| BINS as f64 / extent[a]);
        // A NaN extent is binned too (all in bin 0: no split), as it always was.
        let active = [0, 1, 2].map(|a| extent[a] > 0.0 || extent[a].is_nan());
        let mut counts = [[0usize; BINS]; 3];
        let mut boxes = [[Aabb::EMPTY; BINS]; 3];
        for &i in order.iter() {
            let (b, c) = (self.boxes[i as usize], self.centers[i as usize]);
            for axis in 0..3 {
                if active[axis] {
                    let k = bin(c[axis], centers.min[axis], scale[axis]);
                    counts[axis][k] += 1;
                    boxes[axis][k] = boxes[axis][k].union(b);
                }
            }
        }
        let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, bins left of the plane)
        for axis in (0..3).filter(|&a| active[a]) {
            let (counts, boxes) = (&counts[axis], &boxes[axis]);
            let mut right_area = [0.0; BINS];
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
            for k in (1..BINS).rev() {
                acc = acc.union(boxes[k]);
                cnt += counts[k];
                right_area[k] = acc.half_area() * cnt as f64;
            }
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
            for k in 0..BINS - 1 {
                acc = acc.union(boxes[k]);
                cnt += counts[k];
                if cnt == 0 || cnt == n {
                    continue;
                }
                let cost = acc.half_area() * cnt as f64 + right_area[k + 1];
                if best.is_none_or(|b| cost < b.0) {
                    best = Some((cost, axis, k + 1));
                }
            }
        }
        let (cost, axis, left_bins) = best?;
        let area = bounds.half_area();
        let split_cost = TRAVERSAL_COST + if area > 0.0 { cost / area } else { 0.0 };
        if n <= MAX_LEAF && split_cost >= n as f64 {
            return Some(None);
        }
        let (min, centers_of) = (centers.min[axis], &self.centers);
        let mid = partition(order, |i| {
            bin(centers_of[i as usize][axis], min, scale[axis]) < left_bins
        });
        Some(Some(mid))
    }

    /// Split at the median centroid along the widest axis; `None` if all centroids coincide.
    fn median_split(&self, order: &mut [u32], centers: &Aabb) -> Option<usize> {
        let axis = (centers.max - centers.min).max_position();
        if centers.max[axis] <= centers.min[axis] {
            return None;
        }
        let mid = order.len() / 2;
        let c = &self.centers;
        order.select_nth_unstable_by(mid, |&a, &b| {
            c[a as usize][axis].total_cmp(&c[b as usize][axis])
        });
        Some(mid)
    }
}

/// `n` moved `by` places down the node vector: an inner node's right-child index moves with it
/// (a leaf's index is a primitive slot and stays).
fn shifted(mut n: Node, by: usize) -> Node {
    if n.count == 0 {
        n.index += by as u32;
    }
    n
}

fn bin(x: f64, min: f64, scale: f64) -> usize {
    (((x - min) * scale) as usize).min(BINS - 1)
}

/// In-place partition: elements satisfying `left` first; returns how many.
fn partition(v: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for j in 0..v.len() {
        if left(v[j]) {
            v.swap(k, j);
            k += 1;
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boxes of scattered sizes with clusters and exact duplicates (median splits and
    /// oversized leaves too).
    fn boxes(n: usize) -> Vec<Aabb> {
        let mut s = 0x9e37_79b9_u64;
        let mut next = || {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|i| {
                let p = if i % 10 == 0 {
                    DVec3::splat(0.25) // a cluster of identical centroids
                } else {
                    DVec3::new(next(), next() * next(), next()) * 100.0
                };
                Aabb {
                    min: p,
                    max: p + DVec3::new(next(), next(), 0.0),
                }
            })
            .collect()
    }

    #[test]
    fn parallel_build_is_the_sequential_build() {
        for n in [
            PARALLEL_MIN - 1,
            PARALLEL_MIN,
            3 * PARALLEL_MIN + 17,
            40_000,
        ] {
            let b = boxes(n);
            let builder = Builder {
                boxes: b.iter().map(Aabb::padded).collect(),
                centers: b.iter().map(Aabb::center).collect(),
            };
            let mut order: Vec<u32> = (0..n as u32).collect();
            let mut nodes = Vec::new();
            builder.split_into(&mut order, 0, 0, &mut nodes);
            let bvh = Bvh::build(&b);
            assert_eq!(bvh.nodes, nodes, "{n} boxes");
            assert_eq!(bvh.order, order, "{n} boxes");
            // And on one thread.
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| Bvh::build(&b)), bvh);
        }
    }
}
