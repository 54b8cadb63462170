//! The samples of one pixel as the inspector lists them: one row per sample sorted by its value,
//! with its path length and light path expressions ([`sample_rows`]), and a histogram of the
//! sample values on a log scale ([`histogram`]).
//!
//! A sample's *value* is the Rec. 709 luminance of its radiance (`bsdf::luminance`, the measure
//! of the LPE filter's share and of the diagram's shares), so a histogram bar, a row and a share
//! all speak of the same number.

use crate::bsdf::luminance;
use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayTree};

/// One light path of a sample: a node whose LPE is complete (ends at a light `L` or the
/// background `B`), and what it adds to the sample.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplePath {
    /// The node that ends the path (a shadow ray, or a ray that found an emitter or escaped).
    pub node: NodeId,
    /// Its light path expression.
    pub lpe: String,
    /// What it adds to the sample's radiance.
    pub contribution: Rgb,
    /// Light tracing and BDPT: the strategy `(s, t)` that made it.
    pub strategy: Option<[u32; 2]>,
}

impl SamplePath {
    /// Its LPE, and under light tracing and BDPT its strategy: `C<RD>L s=1 t=2`.
    #[must_use]
    pub fn label(&self) -> String {
        match self.strategy {
            Some([s, t]) => format!("{} s={s} t={t}", self.lpe),
            None => self.lpe.clone(),
        }
    }
}

/// One sample of the pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleRow {
    /// Index in `RayTree::samples`.
    pub index: usize,
    /// The sample's root (camera ray).
    pub root: NodeId,
    /// The sample's radiance.
    pub radiance: Rgb,
    /// Its luminance (the sort key; non-finite values sort first).
    pub value: f64,
    /// Rays along the path: the deepest non-shadow ray's depth + 1 (camera ray = 1).
    pub length: u32,
    /// Its complete paths, largest contribution (luminance) first; empty for a Whitted tree.
    pub paths: Vec<SamplePath>,
}

impl SampleRow {
    /// The path that carries most of the sample (`None` if it has no complete path, or if
    /// none carries light).
    #[must_use]
    pub fn dominant(&self) -> Option<&SamplePath> {
        self.paths
            .first()
            .filter(|p| luminance(p.contribution) > 0.0)
    }
}

/// Luminance of a sample's radiance, the value everything here sorts and bins by.
#[must_use]
pub fn sample_value(radiance: Rgb) -> f64 {
    luminance(radiance)
}

/// One row per sample of `tree`, sorted by value, largest first (ties by index); a non-finite
/// value (a NaN sample) comes first.
#[must_use]
pub fn sample_rows(tree: &RayTree) -> Vec<SampleRow> {
    let mut rows: Vec<SampleRow> = tree
        .samples
        .iter()
        .enumerate()
        .map(|(index, s)| {
            let mut length = 0;
            let mut paths = Vec::new();
            for id in tree.depth_first(s.root) {
                let n = tree.node(id);
                if n.kind != RayKind::Shadow {
                    length = length.max(n.depth + 1);
                }
                if let Some(p) = &n.path
                    && p.lpe.ends_with(['L', 'B'])
                {
                    paths.push(SamplePath {
                        node: id,
                        lpe: p.lpe.clone(),
                        contribution: p.contribution,
                        strategy: p.strategy,
                    });
                }
            }
            paths.sort_by(|a, b| luminance(b.contribution).total_cmp(&luminance(a.contribution)));
            SampleRow {
                index,
                root: s.root,
                radiance: s.radiance,
                value: sample_value(s.radiance),
                length,
                paths,
            }
        })
        .collect();
    rows.sort_by(|a, b| sort_key(b.value).total_cmp(&sort_key(a.value)));
    rows
}

/// Non-finite values sort above everything.
fn sort_key(v: f64) -> f64 {
    if v.is_finite() { v } else { f64::INFINITY }
}

/// Histogram bars per decade of the sample value.
pub const BINS_PER_DECADE: f64 = 2.0;

/// One bar: samples with `lo <= log10(value) < hi`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bin {
    /// Lower edge, log10 of the value.
    pub lo: f64,
    /// Upper edge.
    pub hi: f64,
    /// Sample indices in the bar.
    pub samples: Vec<usize>,
}

/// The pixel's sample values on a log scale.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Histogram {
    /// Bars of width `1 / BINS_PER_DECADE` decade from the smallest positive value's to the
    /// largest's (empty bars included, so the axis is even).
    pub bins: Vec<Bin>,
    /// Samples of value 0 (or below), which have no logarithm: counted apart.
    pub zero: Vec<usize>,
    /// Non-finite samples, counted apart.
    pub non_finite: Vec<usize>,
}

impl Histogram {
    /// Which bar holds sample `index` (`None` if it is zero or non-finite).
    #[must_use]
    pub fn bin_of(&self, index: usize) -> Option<usize> {
        self.bins.iter().position(|b| b.samples.contains(&index))
    }
}

/// Bin the sample values of `tree` (see [`Histogram`]).
#[must_use]
pub fn histogram(tree: &RayTree) -> Histogram {
    let mut h = Histogram::default();
    let mut positive: Vec<(usize, i64)> = Vec::new();
    for (i, s) in tree.samples.iter().enumerate() {
        let v = sample_value(s.radiance);
        if !v.is_finite() {
            h.non_finite.push(i);
        } else if v <= 0.0 {
            h.zero.push(i);
        } else {
            // Bin k holds [k, k + 1) / BINS_PER_DECADE in log10.
            positive.push((i, (v.log10() * BINS_PER_DECADE).floor() as i64));
        }
    }
    let (Some(lo), Some(hi)) = (
        positive.iter().map(|p| p.1).min(),
        positive.iter().map(|p| p.1).max(),
    ) else {
        return h;
    };
    h.bins = (lo..=hi)
        .map(|k| Bin {
            lo: k as f64 / BINS_PER_DECADE,
            hi: (k + 1) as f64 / BINS_PER_DECADE,
            samples: Vec::new(),
        })
        .collect();
    for (i, k) in positive {
        h.bins[(k - lo) as usize].samples.push(i);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::hand_tree::grey_samples;

    #[test]
    fn rows_are_sorted_by_value_with_their_paths() {
        let t = grey_samples(&[0.5, 8.0]);
        let rows = sample_rows(&t);
        assert_eq!(rows.iter().map(|r| r.index).collect::<Vec<_>>(), [1, 0]);
        assert_eq!(rows[0].length, 2);
        assert_eq!(rows[0].dominant().unwrap().lpe, "C<RD>L");
        assert!((rows[0].value - 8.0).abs() < 1e-12);
    }

    #[test]
    fn histogram_bins_by_half_decade_zero_apart() {
        let t = grey_samples(&[0.0, 8.0]);
        let h = histogram(&t);
        assert_eq!(h.zero, [0]);
        assert_eq!(h.bins.len(), 1);
        // log10(8) = 0.903: the bar [0.5, 1.0).
        assert_eq!((h.bins[0].lo, h.bins[0].hi), (0.5, 1.0));
        assert_eq!(h.bin_of(1), Some(0));
        let t = grey_samples(&[0.01, 8.0]);
        let h = histogram(&t);
        // log10(0.01) = -2 -> bar [-2, -1.5); 8 -> [0.5, 1): 6 bars.
        assert_eq!(h.bins.len(), 6);
        assert_eq!(h.bins[0].samples, [0]);
        assert_eq!(h.bins[5].samples, [1]);
        assert!(h.zero.is_empty());
    }
}
