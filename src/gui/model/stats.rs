//! Per-pixel debug statistics for the false-colour views, gathered by a cheap [`Recorder`] during
//! the same pass that renders the image (so the colour is bit-identical to `raytree render`).

use crate::aov::CLASSES;
use crate::integrator::Recorder;
use crate::math::Rgb;
use crate::tree::{EndReason, NodeId, RayNode};

/// What the debug views show for one pixel (summed over its samples).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelStats {
    /// Deepest recursion level reached by any ray.
    pub depth: u32,
    /// Rays of every kind.
    pub rays: u32,
    /// Total internal reflection events.
    pub tir: u32,
    /// Spawned rays whose first hit is the surface they left (`RayNode::self_hit`).
    pub self_hits: u32,
    /// Spawned rays whose offset skipped geometry (`RayNode::leak`).
    pub leaks: u32,
    /// Path weight cut off by `max_depth`, mean over samples (max channel of throughput x
    /// attenuation x truncated weight).
    pub cut: f32,
    /// Acceleration-structure work of every ray: boxes tested (BVH nodes, or in a small scene
    /// one per non-sphere object) plus primitive tests
    /// ([`crate::bvh::TraversalCost::total`]), the traversal heat map.
    pub traversal: u32,
    /// Monte Carlo statistics of the samples ([`crate::aov::pixel_from_nodes`]): relative
    /// standard error of the pixel mean.
    pub rel_err: f32,
    /// Samples taken.
    pub samples: u32,
    /// Mean path rays per sample (path integrator).
    pub path_length: f32,
    /// Russian-roulette terminations.
    pub roulette: u32,
    /// NaN/Inf samples dropped.
    pub dropped: u32,
    /// Share of each light transport class ([`crate::aov::CLASSES`]) in the pixel.
    pub shares: [f32; CLASSES.len()],
}

/// A [`Recorder`] that keeps a small scratch arena for one pixel and folds it into
/// [`PixelStats`]; reuse one per thread and call [`StatsRecorder::take`] after each pixel.
#[derive(Clone, Debug, Default)]
pub struct StatsRecorder {
    nodes: Vec<RayNode>,
}

impl Recorder for StatsRecorder {
    const RECORDS: bool = true;

    fn push(&mut self, _parent: Option<NodeId>, make: impl FnOnce() -> RayNode) -> Option<NodeId> {
        let id = NodeId(u32::try_from(self.nodes.len()).expect("fewer than 2^32 nodes"));
        self.nodes.push(make());
        Some(id)
    }

    fn update(&mut self, id: Option<NodeId>, edit: impl FnOnce(&mut RayNode)) {
        if let Some(id) = id {
            edit(&mut self.nodes[id.index()]);
        }
    }
}

impl StatsRecorder {
    /// Summarise the rays recorded since the last call and clear the arena.
    pub fn take(&mut self, spp: u32) -> PixelStats {
        let s = summarize(&self.nodes, spp);
        self.nodes.clear();
        s
    }
}

/// Fold recorded nodes (of one pixel, all samples) into [`PixelStats`].
#[must_use]
pub fn summarize(nodes: &[RayNode], spp: u32) -> PixelStats {
    let mut s = PixelStats::default();
    let mut cut = 0.0;
    for n in nodes {
        s.rays += 1;
        s.depth = s.depth.max(n.depth);
        if n.interface.as_ref().is_some_and(|i| i.tir) {
            s.tir += 1;
        }
        s.self_hits += u32::from(n.self_hit);
        s.leaks += u32::from(n.leak.is_some());
        s.traversal = s.traversal.saturating_add(n.traversal.total());
        if n.end == EndReason::MaxDepth {
            let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
            cut += (n.throughput * atten * n.truncated).max_element();
        }
    }
    s.cut = (cut / f64::from(spp.max(1))) as f32;
    let (mc, shares) = crate::aov::pixel_from_nodes(nodes);
    s.rel_err = mc.rel_err as f32;
    s.samples = mc.samples;
    s.path_length = mc.path_length as f32;
    s.roulette = mc.roulette;
    s.dropped = mc.dropped;
    s.shares = shares.map(|x| x as f32);
    s
}

/// The false-colour views.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DebugView {
    /// The rendered image.
    #[default]
    Off,
    /// Deepest bounce.
    Depth,
    /// Rays per pixel.
    Rays,
    /// Total internal reflection events.
    Tir,
    /// Self-intersections (acne).
    SelfHits,
    /// Offsets that skipped geometry.
    Leaks,
    /// Path weight cut off by max depth.
    Cut,
    /// BVH nodes and primitive tests of all the pixel's rays.
    Traversal,
    /// Relative standard error of the pixel mean (Monte Carlo noise).
    Noise,
    /// Samples per pixel.
    Samples,
    /// Mean path rays per sample.
    PathLength,
    /// Russian-roulette terminations.
    Roulette,
    /// NaN/Inf samples dropped.
    Dropped,
    /// Share of light transport class `k` ([`crate::aov::CLASSES`]) in the pixel.
    Share(u8),
}

/// Menu labels of the class shares, in [`CLASSES`] order.
const SHARE_LABELS: [&str; CLASSES.len()] = [
    "share: emission (CS*L)",
    "share: background (CS*B)",
    "share: direct (CS*[DG]L)",
    "share: environment (CS*[DG]B)",
    "share: caustics (CS*[DG]S+[LB])",
    "share: indirect (CS*[DG]S*[DG].*[LB])",
];

impl DebugView {
    /// All views in menu order.
    pub const ALL: [DebugView; 19] = [
        DebugView::Off,
        DebugView::Depth,
        DebugView::Rays,
        DebugView::Tir,
        DebugView::SelfHits,
        DebugView::Leaks,
        DebugView::Cut,
        DebugView::Traversal,
        DebugView::Noise,
        DebugView::Samples,
        DebugView::PathLength,
        DebugView::Roulette,
        DebugView::Dropped,
        DebugView::Share(0),
        DebugView::Share(1),
        DebugView::Share(2),
        DebugView::Share(3),
        DebugView::Share(4),
        DebugView::Share(5),
    ];

    /// Menu label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            DebugView::Off => "image",
            DebugView::Depth => "bounce depth",
            DebugView::Rays => "rays per pixel",
            DebugView::Tir => "TIR events",
            DebugView::SelfHits => "self-intersections",
            DebugView::Leaks => "offset leaks",
            DebugView::Cut => "weight cut by max depth",
            DebugView::Traversal => "BVH traversal cost",
            DebugView::Noise => "noise (relative standard error)",
            DebugView::Samples => "samples per pixel",
            DebugView::PathLength => "mean path length (rays per sample)",
            DebugView::Roulette => "Russian-roulette terminations",
            DebugView::Dropped => "NaN/Inf samples dropped",
            DebugView::Share(k) => SHARE_LABELS.get(usize::from(k)).copied().unwrap_or("share"),
        }
    }

    /// Whether the colour range ends at the 99th percentile rather than the maximum.
    #[must_use]
    pub fn clips(self) -> bool {
        matches!(self, DebugView::Traversal | DebugView::Noise)
    }

    /// The scalar this view maps to colour.
    #[must_use]
    pub fn value(self, s: &PixelStats) -> f32 {
        match self {
            DebugView::Off => 0.0,
            DebugView::Depth => s.depth as f32,
            DebugView::Rays => s.rays as f32,
            DebugView::Tir => s.tir as f32,
            DebugView::SelfHits => s.self_hits as f32,
            DebugView::Leaks => s.leaks as f32,
            DebugView::Cut => s.cut,
            DebugView::Traversal => s.traversal as f32,
            DebugView::Noise => s.rel_err,
            DebugView::Samples => s.samples as f32,
            DebugView::PathLength => s.path_length,
            DebugView::Roulette => s.roulette as f32,
            DebugView::Dropped => s.dropped as f32,
            DebugView::Share(k) => s.shares.get(usize::from(k)).copied().unwrap_or(0.0),
        }
    }
}

/// The range of a view over the image: `(0, max)`, at least `(0, 1)`. For the traversal cost,
/// whose tail is long (a few pixels behind many glass bounces cost 10x the median), `max` is
/// the 99th percentile and the pixels above it show as the top of the ramp
/// ([`DebugView::clips`]).
#[must_use]
pub fn range(view: DebugView, stats: &[PixelStats]) -> (f32, f32) {
    if matches!(view, DebugView::Share(_)) {
        return (0.0, 1.0);
    }
    let max = if view.clips() && !stats.is_empty() {
        let mut v: Vec<f32> = stats.iter().map(|s| view.value(s)).collect();
        let k = (v.len() - 1) * 99 / 100;
        *v.select_nth_unstable_by(k, f32::total_cmp).1
    } else {
        stats.iter().map(|s| view.value(s)).fold(0.0f32, f32::max)
    };
    (0.0, if max > 0.0 { max } else { 1.0 })
}

pub use crate::aov::ramp;

/// sRGB bytes of one pixel in `view` given its `(0, max)` range.
#[must_use]
pub fn false_colour(view: DebugView, s: &PixelStats, max: f32) -> [u8; 3] {
    ramp(view.value(s) / max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{render_pixel, trace_pixel};
    use crate::{RayCounts, Scene};

    #[test]
    fn stats_match_the_recorded_tree_and_the_colour_is_unchanged() {
        let scene = Scene::default_scene();
        for (x, y) in [(300, 200), (420, 170), (10, 10), (330, 150)] {
            let tree = trace_pixel(&scene, x, y).unwrap();
            let mut rec = StatsRecorder::default();
            let mut counts = RayCounts::default();
            let l = render_pixel(
                &crate::integrator::SceneIntegrator::new(&scene),
                &mut crate::sampling::SceneSampler::for_settings(&scene.settings),
                (x, y),
                &mut rec,
                &mut counts,
                |_| {},
            )
            .0;
            assert_eq!(l, tree.radiance);
            let s = rec.take(1);
            assert_eq!(s, summarize(&tree.nodes, 1));
            assert_eq!(s.rays as usize, tree.nodes.len());
            assert_eq!(s.depth, tree.nodes.iter().map(|n| n.depth).max().unwrap());
        }
    }

    #[test]
    fn a_shallow_limit_cuts_weight_and_a_deep_one_reaches_depth() {
        let mut scene = Scene::default_scene();
        scene.settings.max_depth = 1;
        // The glass ball: a camera ray through it needs more than one bounce.
        let (mut cut_any, mut deep) = (false, 0);
        for x in (0..640).step_by(16) {
            let t = trace_pixel(&scene, x, 180).unwrap();
            let s = summarize(&t.nodes, 1);
            cut_any |= s.cut > 0.0;
            deep = deep.max(s.depth);
        }
        assert!(cut_any);
        assert_eq!(deep, 1);
    }

    #[test]
    fn traversal_view_sums_every_rays_bvh_work_and_finds_the_mesh() {
        let json = r#"{"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40,
            "width": 40, "height": 40},
            "materials": {"m": {"diffuse": [0.8, 0.8, 0.8]}},
            "objects": [{"type": "mesh", "file": "ico", "material": "m"}],
            "lights": [{"type": "point", "position": [2, 2, 4], "intensity": [20, 20, 20]}]}"#;
        let data = crate::mesh::generate::icosphere(4);
        let scene = Scene::from_json_with(json, &mut |_| {
            Ok::<crate::mesh::MeshData, String>(data.clone())
        })
        .unwrap();
        let at = |x, y| {
            let tree = trace_pixel(&scene, x, y).unwrap();
            let s = summarize(&tree.nodes, 1);
            let sum: u32 = tree.nodes.iter().map(|n| n.traversal.total()).sum();
            assert_eq!(s.traversal, sum);
            s
        };
        // The centre hits the sphere (camera and shadow ray walk its BVH); a corner misses it.
        let (centre, corner) = (at(20, 20), at(0, 0));
        assert!(
            centre.traversal > 3 * corner.traversal.max(1),
            "{centre:?} {corner:?}"
        );
        assert_eq!(DebugView::Traversal.value(&centre), centre.traversal as f32);
        assert!(DebugView::ALL.contains(&DebugView::Traversal));
    }

    #[test]
    fn ramp_is_black_at_zero_and_red_at_one() {
        assert_eq!(ramp(0.0), [0, 0, 0]);
        assert!(ramp(1.0)[0] > 200 && ramp(1.0)[2] < 50);
        assert_eq!(range(DebugView::Tir, &[PixelStats::default()]), (0.0, 1.0));
        // The traversal view ends at the 99th percentile: one outlier does not wash it out.
        let costs: Vec<PixelStats> = (1..=200)
            .map(|i| PixelStats {
                traversal: if i == 200 { 100_000 } else { i },
                ..PixelStats::default()
            })
            .collect();
        assert_eq!(range(DebugView::Traversal, &costs), (0.0, 198.0));
        assert_eq!(range(DebugView::Rays, &costs), (0.0, 1.0));
    }
}
