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

impl Bvh {
    /// Build over `bounds` (one box per primitive; boxes are padded, see [`Aabb::padded`]).
    #[must_use]
    pub fn build(bounds: &[Aabb]) -> Self {
        assert!(
            u32::try_from(bounds.len()).is_ok(),
            "fewer than 2^32 primitives"
        );
        let mut b = Builder {
            boxes: bounds.iter().map(Aabb::padded).collect(),
            centers: bounds.iter().map(Aabb::center).collect(),
            order: (0..bounds.len() as u32).collect(),
            nodes: Vec::with_capacity(bounds.len()),
        };
        if !bounds.is_empty() {
            b.split(0, bounds.len(), 0);
        }
        Bvh {
            nodes: b.nodes,
            order: b.order,
        }
    }
}

struct Builder {
    boxes: Vec<Aabb>,
    centers: Vec<DVec3>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

impl Builder {
    fn range_bounds(&self, lo: usize, hi: usize) -> (Aabb, Aabb) {
        let mut b = Aabb::EMPTY;
        let mut c = Aabb::EMPTY;
        for &i in &self.order[lo..hi] {
            b = b.union(self.boxes[i as usize]);
            let p = self.centers[i as usize];
            c = c.union(Aabb { min: p, max: p });
        }
        (b, c)
    }

    /// Build the subtree over slots `lo..hi`; returns its node index.
    fn split(&mut self, lo: usize, hi: usize, depth: u32) -> usize {
        let (bounds, centers) = self.range_bounds(lo, hi);
        let at = self.nodes.len();
        self.nodes.push(Node {
            min: bounds.min.to_array().map(down),
            max: bounds.max.to_array().map(up),
            index: lo as u32,
            count: (hi - lo) as u32,
        });
        let n = hi - lo;
        if n <= 1 {
            return at;
        }
        let mid = if depth >= SAH_DEPTH {
            self.median_split(lo, hi, &centers)
        } else {
            match self.sah_split(lo, hi, &bounds, &centers) {
                Some(Some(mid)) => Some(mid),
                Some(None) => return at,
                None if n <= MAX_LEAF => return at,
                None => self.median_split(lo, hi, &centers),
            }
        };
        let Some(mid) = mid else {
            return at; // all centroids coincide: an oversized leaf is the best there is
        };
        self.split(lo, mid, depth + 1);
        let right = self.split(mid, hi, depth + 1);
        self.nodes[at].index = right as u32;
        self.nodes[at].count = 0;
        at
    }

    /// The best binned SAH split, partitioned; `None` when a leaf is cheaper (or no split
    /// exists). The outer `Option` says whether the SAH decided.
    fn sah_split(
        &mut self,
        lo: usize,
        hi: usize,
        bounds: &Aabb,
        centers: &Aabb,
    ) -> Option<Option<usize>> {
        let n = hi - lo;
        let extent = centers.max - centers.min;
        let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, bins left of the plane)
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let scale = BINS as f64 / extent[axis];
            let mut counts = [0usize; BINS];
            let mut boxes = [Aabb::EMPTY; BINS];
            for &i in &self.order[lo..hi] {
                let k = bin(self.centers[i as usize][axis], centers.min[axis], scale);
                counts[k] += 1;
                boxes[k] = boxes[k].union(self.boxes[i as usize]);
            }
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
        let scale = BINS as f64 / extent[axis];
        let (min, centers_of) = (centers.min[axis], &self.centers);
        let mid = partition(&mut self.order[lo..hi], |i| {
            bin(centers_of[i as usize][axis], min, scale) < left_bins
        });
        Some(Some(lo + mid))
    }

    /// Split at the median centroid along the widest axis; `None` if all centroids coincide.
    fn median_split(&mut self, lo: usize, hi: usize, centers: &Aabb) -> Option<usize> {
        let axis = (centers.max - centers.min).max_position();
        if centers.max[axis] <= centers.min[axis] {
            return None;
        }
        let mid = (hi - lo) / 2;
        let c = &self.centers;
        self.order[lo..hi].select_nth_unstable_by(mid, |&a, &b| {
            c[a as usize][axis].total_cmp(&c[b as usize][axis])
        });
        Some(lo + mid)
    }
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
