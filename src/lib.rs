//! raytree: a ray-path debugger — a Whitted ray tracer, a Monte Carlo path tracer, light
//! tracing and bidirectional path tracing that record and explain the paths of any pixel.
//!
//! Data flows one way: scene text (raytree JSON, or pbrt-v4 / Mitsuba 3 / glTF through
//! [`formats`]) -> [`Scene`] (validated) -> an [`Integrator`] ([`Whitted`], [`PathTracer`],
//! [`integrator::LightTracer`] or [`integrator::Bdpt`], chosen by [`SceneIntegrator`] from the
//! scene's tagged `settings.integrator`) with a [`Recorder`] -> radiance through the
//! [`mod@render`] loop, and optionally a [`RayTree`] whose contributions sum to the pixel bit for
//! bit, which every view (text, JSON, diagram, GUI, [`analysis`]) reads. The library does no
//! I/O. Where each concept lives: `docs/architecture.md`.
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
    DiagnosticRecorder, Integrator, NoopRecorder, PathTracer, RayCounts, Recorder, SceneIntegrator,
    TreeRecorder, Whitted,
};
pub use render::{
    DiagnosticMap, Image, RenderOptions, RenderStats, Rendered, render, render_pixel, trace_pixel,
};
pub use scene::{Scene, SceneError, Settings};
pub use tree::{NodeId, RayKind, RayNode, RayTree};
