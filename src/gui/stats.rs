//! Per-pixel debug statistics for the false-colour views, gathered by a cheap [`Recorder`] during
//! the same pass that renders the image (so the colour is bit-identical to `raytree render`).

use crate::math::Rgb;
use crate::trace::Recorder;
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
        if n.end == EndReason::MaxDepth {
            let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
            cut += (n.throughput * atten * n.truncated).max_element();
        }
    }
    s.cut = (cut / f64::from(spp.max(1))) as f32;
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
}

impl DebugView {
    /// All views in menu order.
    pub const ALL: [DebugView; 7] = [
        DebugView::Off,
        DebugView::Depth,
        DebugView::Rays,
        DebugView::Tir,
        DebugView::SelfHits,
        DebugView::Leaks,
        DebugView::Cut,
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
        }
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
        }
    }
}

/// The range of a view over the image: `(0, max)`, at least `(0, 1)`.
#[must_use]
pub fn range(view: DebugView, stats: &[PixelStats]) -> (f32, f32) {
    let max = stats.iter().map(|s| view.value(s)).fold(0.0f32, f32::max);
    (0.0, if max > 0.0 { max } else { 1.0 })
}

/// A perceptually ordered ramp (a compact "turbo"-like map): black for zero, then blue, cyan,
/// green, yellow, red as `t` goes from 0 to 1. Returns sRGB bytes.
#[must_use]
pub fn ramp(t: f32) -> [u8; 3] {
    if t <= 0.0 {
        return [0, 0, 0];
    }
    const STOPS: [[f32; 3]; 6] = [
        [0.05, 0.05, 0.35],
        [0.1, 0.35, 0.95],
        [0.1, 0.85, 0.85],
        [0.3, 0.9, 0.2],
        [0.98, 0.85, 0.1],
        [0.9, 0.1, 0.1],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let c = |k: usize| STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f;
    [0, 1, 2].map(|k| (c(k) * 255.0 + 0.5) as u8)
}

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
            let l = render_pixel(&scene, x, y, &mut rec, &mut counts, |_| {});
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
    fn ramp_is_black_at_zero_and_red_at_one() {
        assert_eq!(ramp(0.0), [0, 0, 0]);
        assert!(ramp(1.0)[0] > 200 && ramp(1.0)[2] < 50);
        assert_eq!(range(DebugView::Tir, &[PixelStats::default()]), (0.0, 1.0));
    }
}
