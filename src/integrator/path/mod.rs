//! The Monte Carlo path tracer (issue 15): unidirectional path tracing with next-event
//! estimation, multiple importance sampling (power heuristic) and Russian roulette, after the
//! path loop of pbrt-v4 (`PathIntegrator::Li`, section 13.4) and Veach 1997 (chapter 9 for MIS).
//! See `docs/path-tracing.md` for the estimator.
//!
//! At every hit: the emission of the outer side (MIS-weighted against the light sample that
//! could have found it), one light sample ([`nee`]), and one continuation direction sampled
//! from the material's BSDF ([`crate::bsdf::Bsdf`], the sum of its lobes). `max_depth` counts
//! bounces after the first hit as in Whitted (0 = direct light only: the continuation of the
//! first hit is still traced, for the emission MIS needs, but does nothing more). Beer's law
//! multiplies the throughput inside absorbing media (the media stack). Escaping rays see the
//! background. The recorder sees one node per ray with [`crate::tree::PathInfo`]. The loop
//! itself is in `walk` ([`PathTracer::trace_camera`]).

mod nee;
mod walk;

pub(crate) use nee::{event, transmits};

/// Russian roulette on a continuation of weight `weight` (`f |cos| / pdf`) for a path whose
/// throughput is `carried` (the path tracer's throughput, or a subpath's relative to its
/// start): survival probability `q = min(1, max(carried x weight))`, drawn from `sampler` and
/// recorded on node `id`; the weight divided by `q`, or `None` when the path ends. The one
/// roulette of the path tracer, light tracing and BDPT.
#[inline(always)]
pub(crate) fn russian_roulette<R: Recorder, S: PixelSampler>(
    carried: Rgb,
    weight: Rgb,
    id: Option<NodeId>,
    sampler: &mut S,
    rec: &mut R,
) -> Option<Rgb> {
    let q = (carried * weight).max_element().min(1.0);
    let survived = sampler.next_1d() < q;
    rec.update(id, |n| {
        if let Some(p) = n.path.as_mut() {
            p.roulette = Some(Roulette {
                probability: q,
                survived,
            });
        }
    });
    survived.then(|| weight / q)
}

use super::{Recorder, Shading};
use crate::integrator::EffectPlan;
use crate::interaction::SurfaceId;
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use crate::scene::{Film, Scene};
use crate::tree::{NodeId, Roulette};
use glam::DVec3;

/// Which estimator of direct light the path tracer uses (a switch for the tests that compare
/// them; scenes always use [`PathStrategy::Mis`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PathStrategy {
    /// Light sampling and BSDF sampling combined by the power heuristic (beta 2).
    #[default]
    Mis,
    /// Light sampling only: emission found by BSDF-sampled rays counts only where no light
    /// sample could have found it (camera rays, after delta lobes, emitters that are not
    /// sampled).
    LightOnly,
    /// BSDF sampling only: no light samples, so point and directional lights (which only light
    /// sampling can find) are not seen.
    BsdfOnly,
}

/// The path integrator (`settings.integrator: "path"`).
#[derive(Clone, Debug)]
pub struct PathTracer<'a> {
    /// Surface interactions, offsets, shadow rays, diagnostics and the light sampler (every
    /// point and directional light, then every emissive sphere, quad, triangle and mesh, chosen
    /// in proportion to power): shared with every integrator.
    core: Shading<'a>,
    strategy: PathStrategy,
}

/// The scattering event that spawned the current ray, for the MIS weight of the emission it
/// finds.
#[derive(Clone, Copy, Debug)]
struct Prev {
    p: DVec3,
    from: SurfaceId,
    pdf: f64,
    delta: bool,
}

impl<'a> PathTracer<'a> {
    /// The path tracer of `scene` with MIS.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        Self::with_strategy(scene, PathStrategy::Mis)
    }

    /// The path tracer with an explicit direct-light `strategy`.
    #[must_use]
    pub fn with_strategy(scene: &'a Scene, strategy: PathStrategy) -> Self {
        let mut plan = EffectPlan::everything(scene);
        // Shadow rays are visibility tests: the path tracer finds light through glass by
        // sampling the BSDF, not by Whitted's translucent-shadow approximation.
        plan.translucent_shadows = false;
        plan.specular = false;
        Self {
            core: Shading::new(scene, plan),
            strategy,
        }
    }

    /// The direct-light strategy.
    #[must_use]
    pub fn strategy(&self) -> PathStrategy {
        self.strategy
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene {
        self.core.scene
    }

    /// The camera's image plane.
    #[must_use]
    pub fn film(&self) -> &Film<'a> {
        &self.core.film
    }
}
