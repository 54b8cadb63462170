//! raytree: a recursive (Whitted) ray tracer that records and explains the ray tree of any pixel.
//!
//! Data flows one way: scene JSON -> [`Scene`] (validated) -> [`Whitted`] with a [`Recorder`]
//! -> radiance, and optionally a [`RayTree`] that every view (text, JSON, diagram, GUI) reads.
//! The library does no I/O.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod analysis;
pub mod aov;
pub mod bsdf;
pub mod bvh;
pub mod codec;
pub mod denoise;
pub mod diagram;
pub mod effects;
pub mod finite;
pub mod formats;
pub mod geometry;
#[cfg(feature = "gui")]
pub mod gui;
pub mod input;
pub mod integrator;
pub mod interaction;
pub mod lights;
pub mod lpe;
pub mod math;
pub mod media;
pub mod mesh;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod text;
pub mod tree;

pub use integrator::{
    DiagnosticRecorder, Integrator, NoopRecorder, RayCounts, Recorder, SceneIntegrator,
    TreeRecorder, Whitted,
};
pub use render::{
    DiagnosticMap, Image, RenderStats, render, render_diagnosed, render_pixel, render_pixel_with,
    render_sample_map, render_with, trace_pixel,
};
pub use scene::{Scene, SceneError, Settings};
pub use tree::{NodeId, RayKind, RayNode, RayTree};
