//! The recorder hook: a generic parameter of the tracer, so the no-op one compiles away.

use crate::math::Rgb;
use crate::tree::{EndReason, NodeId, RayNode};

/// Receives the rays of a trace. All methods take closures so that a recorder that ignores them
/// never builds the node data.
pub trait Recorder {
    /// Whether this recorder keeps anything. `false` lets the tracer skip optional bookkeeping
    /// and even the hooks themselves: on a plan without secondary rays the render path calls
    /// none (see `integrator::whitted::direct_only`), so a recorder that must see every ray says `true`.
    const RECORDS: bool;
    /// Whether the tracer runs the self-hit and leak diagnostics (extra intersections) and
    /// counts them in [`crate::RayCounts`]. Defaults to [`Recorder::RECORDS`], so the no-op
    /// recorder of the plain render pays nothing.
    const DIAGNOSE: bool = Self::RECORDS;
    /// A ray was spawned by `parent`; returns its id (or `None` when not recording).
    fn push(&mut self, parent: Option<NodeId>, make: impl FnOnce() -> RayNode) -> Option<NodeId>;
    /// Fill in node `id` once its results are known.
    fn update(&mut self, id: Option<NodeId>, edit: impl FnOnce(&mut RayNode));

    /// Whether the path integrator builds each path's light path expression and reports its
    /// contributions and ends through [`Recorder::contribution`] and [`Recorder::path_end`]
    /// (a recorder that keeps only those, `crate::aov::AovRecorder`, says `true` without
    /// recording nodes). Defaults to [`Recorder::RECORDS`].
    const PATHS: bool = Self::RECORDS;

    /// The path integrator added `c` to the sample's radiance, through the path whose light
    /// path expression is `lpe` followed by `event` and `end` (`L` or `B`), e.g. `C<RD>`,
    /// `<TS>`, `L`. Called where the sample's radiance grows, in that order, only when
    /// [`Recorder::PATHS`].
    #[inline(always)]
    fn contribution(&mut self, _lpe: &str, _event: &str, _end: char, _c: Rgb) {}

    /// The path integrator's sample ended after `segments` path rays (the camera ray and its
    /// continuations, shadow rays not counted) for `reason`. Only when [`Recorder::PATHS`].
    #[inline(always)]
    fn path_end(&mut self, _segments: u32, _reason: EndReason) {}
}

/// Records nothing; the render path uses it.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoopRecorder;

impl Recorder for NoopRecorder {
    const RECORDS: bool = false;

    #[inline(always)]
    fn push(&mut self, _: Option<NodeId>, _: impl FnOnce() -> RayNode) -> Option<NodeId> {
        None
    }

    #[inline(always)]
    fn update(&mut self, _: Option<NodeId>, _: impl FnOnce(&mut RayNode)) {}
}

/// Records nothing but runs the diagnostics, so a render can count self-hits and leaks.
#[derive(Clone, Copy, Debug, Default)]
pub struct DiagnosticRecorder;

impl Recorder for DiagnosticRecorder {
    const RECORDS: bool = false;
    const DIAGNOSE: bool = true;

    #[inline(always)]
    fn push(&mut self, _: Option<NodeId>, _: impl FnOnce() -> RayNode) -> Option<NodeId> {
        None
    }

    #[inline(always)]
    fn update(&mut self, _: Option<NodeId>, _: impl FnOnce(&mut RayNode)) {}
}

/// Records every node into an arena.
#[derive(Clone, Debug, Default)]
pub struct TreeRecorder {
    /// The nodes so far.
    pub nodes: Vec<RayNode>,
}

impl Recorder for TreeRecorder {
    const RECORDS: bool = true;

    fn push(&mut self, parent: Option<NodeId>, make: impl FnOnce() -> RayNode) -> Option<NodeId> {
        let id = NodeId(u32::try_from(self.nodes.len()).expect("fewer than 2^32 nodes"));
        let mut node = make();
        node.id = id;
        node.parent = parent;
        if let Some(p) = parent {
            self.nodes[p.index()].children.push(id);
        }
        self.nodes.push(node);
        Some(id)
    }

    fn update(&mut self, id: Option<NodeId>, edit: impl FnOnce(&mut RayNode)) {
        if let Some(id) = id {
            edit(&mut self.nodes[id.index()]);
        }
    }
}
