//! The integrators: what computes a camera ray's radiance, recording every ray into a
//! [`Recorder`] (a generic parameter: free when off).
//!
//! - [`Integrator`] and [`SceneIntegrator`] (`interface.rs`): the seam the render loop, the
//!   inspector and every command use; a new integrator is one more arm there and one folder.
//! - [`Shading`] (`shading.rs`): the core every integrator is built on — surface interaction,
//!   n1/n2 and Fresnel from the media stack, ray spawning with the offset strategy, shadow
//!   rays, diagnostics — and `direct.rs`, the one direct-light estimator with its recorded
//!   shadow event.
//! - [`Whitted`] (`whitted/`): the lecture's `trace(ray, objects, lights)` recursion.
//! - [`PathTracer`] (`path/`): unidirectional path tracing with NEE and MIS.
//! - [`LightTracer`] (`light/`): light tracing, paths from the lights splatted to the camera.
//! - [`Bdpt`] (`bdpt/`): bidirectional path tracing, every strategy (s, t) with MIS.
//!
//! See `docs/architecture.md`.

pub mod bdpt;
pub mod diagnose;
mod direct;
mod interface;
pub mod light;
pub mod offset;
mod path;
pub mod plan;
mod recorder;
mod shading;
mod shadow;
pub mod whitted;

pub use crate::interaction::SurfaceInteraction;
pub use crate::media::{MediaStack, Medium};
pub use bdpt::{Bdpt, StrategyPart};
pub use interface::{Integrator, SceneIntegrator};
pub use light::{LightTracer, Splat};
pub use path::{PathStrategy, PathTracer};
pub use plan::EffectPlan;
pub use recorder::{DiagnosticRecorder, NoopRecorder, Recorder, TreeRecorder};
pub use shading::Shading;
pub use whitted::{Whitted, bound, roulette};

use crate::math::Rgb;
use crate::tree::RayKind;

/// Stack for a thread that traces: the recursion goes `settings.max_depth` (up to 1024) levels
/// deep at about 2 KiB a level when rendering and 2.5 KiB when recording (measured from the
/// release build's frames), more than std's 2 MiB default for spawned threads (which
/// `max_depth` 1024 nearly filled before glossy lobes and overflowed after). The command line
/// gives rayon's render threads and the inspector's worker this much.
pub const THREAD_STACK_BYTES: usize = 16 << 20;

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays.
    pub camera: u64,
    /// Reflected rays.
    pub reflected: u64,
    /// Refracted rays.
    pub refracted: u64,
    /// Shadow rays actually cast.
    pub shadow: u64,
    /// Diffuse bounces sampled from the BSDF (path integrator).
    pub diffuse: u64,
    /// Rays of light subpaths (light tracing).
    pub light: u64,
    /// Connections of light-subpath vertices to the camera (light tracing).
    pub connection: u64,
    /// Spawned rays that re-hit the surface they left (counted only by diagnosing recorders).
    pub self_hits: u64,
    /// Spawned rays whose offset skipped a surface (counted only by diagnosing recorders).
    pub leaks: u64,
    /// Secondary rays not traced because their sample reached `settings.max_rays`.
    pub budget_cuts: u64,
    /// Dielectric hits that followed one of their reflected and refracted rays, chosen by
    /// Russian roulette (`settings.roulette_below`, `settings.dielectric_roulette`).
    pub roulette: u64,
    /// Samples that reached `settings.max_rays` (their trees were cut).
    pub budget_samples: u64,
    /// Samples whose radiance was not finite (NaN or infinite), dropped from their pixel's
    /// mean (counted as black) by the render loop.
    pub dropped_samples: u64,
    /// The first dropped sample `(x, y, sample index)` in scan order, to trace it.
    pub first_dropped: Option<(u32, u32, u32)>,
}

impl RayCounts {
    /// Whether camera sample `l` of pixel (x, y), index `s` (`at`), enters its pixel's sum:
    /// always under Whitted (a non-finite value makes the pixel non-finite, counted by the
    /// render); under the path integrator only when finite. A dropped sample (NaN or infinite)
    /// counts as black, is counted and the first one named, so no NaN reaches the image and
    /// the sample can be traced (`raytree trace`).
    #[inline]
    pub fn keep_sample(&mut self, l: Rgb, whitted: bool, at: (u32, u32, u32)) -> bool {
        if l.is_finite() || whitted {
            return true;
        }
        self.dropped_samples += 1;
        self.first_dropped.get_or_insert(at);
        false
    }

    /// All rays.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.camera
            + self.reflected
            + self.refracted
            + self.shadow
            + self.diffuse
            + self.light
            + self.connection
    }

    pub(crate) fn add_kind(&mut self, kind: RayKind) {
        match kind {
            RayKind::Camera => self.camera += 1,
            RayKind::Reflected => self.reflected += 1,
            RayKind::Refracted => self.refracted += 1,
            RayKind::Shadow => self.shadow += 1,
            RayKind::Diffuse => self.diffuse += 1,
            RayKind::Light => self.light += 1,
            RayKind::Connection => self.connection += 1,
        }
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
        self.diffuse += o.diffuse;
        self.light += o.light;
        self.connection += o.connection;
        self.self_hits += o.self_hits;
        self.leaks += o.leaks;
        self.budget_cuts += o.budget_cuts;
        self.roulette += o.roulette;
        self.budget_samples += o.budget_samples;
        self.dropped_samples += o.dropped_samples;
        self.first_dropped = match (self.first_dropped, o.first_dropped) {
            (Some(a), Some(b)) => Some(if (a.1, a.0, a.2) <= (b.1, b.0, b.2) {
                a
            } else {
                b
            }),
            (a, b) => a.or(b),
        };
    }
}
