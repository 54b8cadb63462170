//! The Whitted integrator, exactly as the lecture's `trace(ray, objects, lights)` recursion:
//! closest hit, Beer's law on the segment, the local term (emitted + ambient + every light
//! through its shadow ray, `local.rs` over the shared estimator `crate::integrator::direct`),
//! and the reflected and refracted rays of each hit (`recursive.rs`), with glossy lobes
//! (`glossy.rs`), the cut and its automatic bound (`bound/`), the dielectric roulette
//! (`roulette.rs`) and the direct-only fast path over the same kernel (`direct_only.rs`).

pub mod bound;
mod direct_only;
mod glossy;
mod local;
mod recursive;
pub mod roulette;

use super::shading::{NoSamples, Shading};
use super::{MediaStack, RayCounts, Recorder};
use crate::bvh::TraversalCost;
use crate::integrator::EffectPlan;
use crate::interaction::SurfaceId;
use crate::math::{Ray, Rgb};
use crate::sampling::PixelSampler;
use crate::scene::{Film, Hit, Scene};
use crate::tree::{EndReason, NodeId, RayKind};
use glam::DVec3;

/// Where a ray starts: the surface point and which side of it.
#[derive(Clone, Copy, Debug)]
struct Spawn {
    kind: RayKind,
    parent: Option<NodeId>,
    point: DVec3,
    /// The surface the ray leaves (`None` for camera rays).
    from: Option<SurfaceId>,
    weight: Rgb,
}

/// What the secondary rays of one hit add up to.
struct Secondary {
    total: Rgb,
    end: EndReason,
    truncated: Rgb,
}

/// State carried down one path of the tree.
#[derive(Clone, Copy, Debug)]
struct PathState<'m> {
    depth: u32,
    throughput: Rgb,
    /// By reference: most rays do not change media, so nothing is copied for them.
    media: &'m MediaStack,
    /// No secondary ray is spawned once `RayCounts::total` reaches this (the sample's budget).
    ray_limit: u64,
    /// Below a ray sampled from a rough lobe: the number of samples `n` that lobe drew. Rough
    /// lobes below draw one ray each, and the min-weight cut compares `n x throughput` (the
    /// throughput of one sample's estimate, as with `spp`).
    glossy: Option<u32>,
}

/// The Whitted integrator over one scene, running only the effects of its [`EffectPlan`].
#[derive(Clone, Debug)]
pub struct Whitted<'a> {
    /// Surface interactions, offsets, shadow rays, lights: shared with every integrator.
    core: Shading<'a>,
    /// The plan spawns no secondary rays (nothing reflects or refracts): a camera ray's
    /// radiance is the local term at its hit, which [`Whitted::trace_direct_only`] computes
    /// without the recursion's bookkeeping when nothing is recorded.
    direct_only: bool,
    /// The cut in use: `settings.min_weight`, or the automatic one ([`bound`]).
    min_weight: f64,
    /// Dielectric hits of a throughput below this play Russian roulette between their two
    /// rays: `settings.roulette_below`, or the automatic weight ([`bound::carried`]).
    roulette_below: f64,
}

impl<'a> Whitted<'a> {
    /// A tracer over `scene` with its settings and the effects the scene calls for.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        Self::with_plan(scene, EffectPlan::for_scene(scene))
    }

    /// A tracer with an explicit plan (e.g. [`EffectPlan::everything`] for comparisons).
    #[must_use]
    pub fn with_plan(scene: &'a Scene, plan: EffectPlan) -> Self {
        // Area lights draw from the pixel's sampler: not on the direct-only path.
        let direct_only = plan.direct_only() && !plan.area_lights;
        Self {
            core: Shading::new(scene, plan),
            direct_only,
            min_weight: bound::effective_min_weight(scene),
            roulette_below: bound::carried::effective_roulette_below(scene),
        }
    }

    /// The throughput below which secondary rays are cut: the scene's `min_weight`, or when
    /// absent the automatic cut for its tolerance ([`bound::auto_min_weight`]).
    #[must_use]
    pub fn min_weight(&self) -> f64 {
        self.min_weight
    }

    /// The throughput below which a dielectric hit follows one of its rays, chosen by Russian
    /// roulette, instead of both: `settings.roulette_below`, or when absent the automatic
    /// weight ([`bound::carried::auto_roulette_below`]); 0 under the path integrator.
    #[must_use]
    pub fn roulette_below(&self) -> f64 {
        self.roulette_below
    }

    /// The scene camera's image plane ([`crate::scene::Camera::film`]): its camera rays, the
    /// same as [`crate::scene::Camera::ray`]'s, without evaluating the field of view per ray.
    #[must_use]
    pub fn film(&self) -> &Film<'a> {
        &self.core.film
    }

    /// The shading core (surface interactions, offsets, shadow rays, lights).
    #[must_use]
    pub fn core(&self) -> &Shading<'a> {
        &self.core
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene {
        self.core.scene
    }

    /// The effects this tracer runs.
    #[must_use]
    pub fn plan(&self) -> &EffectPlan {
        &self.core.plan
    }

    /// Radiance along a camera ray, recording into `rec` and counting into `counts`; the
    /// random numbers of the area lights' shadow rays come from `sampler` (already started at
    /// this camera sample), so a re-traced pixel reproduces its value bit for bit.
    pub fn trace_camera<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        if self.direct_only && !R::RECORDS && !R::DIAGNOSE {
            return (self.trace_direct_only(&ray, None, counts), None);
        }
        self.trace_camera_general(ray, None, sampler, rec, counts)
    }

    /// [`Whitted::trace_camera`] for a camera ray whose closest hit is already known: `found` is
    /// what [`Scene::intersect_counted`] returns for it over `(ray.t_min, infinity)` and the work
    /// that took, e.g. from [`Scene::intersect_packet`] over a tile of camera rays. The result
    /// is the same as tracing the ray from scratch (the hit is the same bit for bit). Packets
    /// are traced only when the plan has no area lights (`Integrator::traces_packets`), so no
    /// random number is drawn here.
    pub fn trace_camera_found<R: Recorder>(
        &self,
        ray: Ray,
        found: (Option<Hit>, TraversalCost),
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        if self.direct_only && !R::RECORDS && !R::DIAGNOSE {
            return (self.trace_direct_only(&ray, Some(found.0), counts), None);
        }
        self.trace_camera_general(ray, Some(found), &mut NoSamples, rec, counts)
    }

    /// [`Whitted::trace_camera_found`] of a packet of camera rays (at most
    /// [`crate::bvh::wide::PACKET`]) with their hits and costs from
    /// [`Scene::intersect_packet`], the radiance of `rays[i]` into `out[i]`, the same bits. On
    /// the direct-only path (nothing recorded or diagnosed) the shadow rays of the packet's hits
    /// are traced as packets too; otherwise ray by ray.
    ///
    /// # Panics
    /// If `found`, `cost` or `out` is shorter than `rays`.
    pub fn trace_camera_packet<R: Recorder>(
        &self,
        rays: &[Ray],
        (found, cost): (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        if self.direct_only && !R::RECORDS && !R::DIAGNOSE {
            self.trace_direct_packet(rays, found, out, counts);
            return;
        }
        for (i, ray) in rays.iter().enumerate() {
            out[i] = self
                .trace_camera_found(*ray, (found[i], cost[i]), rec, counts)
                .0;
        }
    }

    fn trace_camera_general<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        found: Option<(Option<Hit>, TraversalCost)>,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let spawn = Spawn {
            kind: RayKind::Camera,
            parent: None,
            point: ray.origin,
            from: None,
            weight: Rgb::ONE,
        };
        let cuts = counts.budget_cuts;
        let state = PathState {
            depth: 0,
            throughput: Rgb::ONE,
            media: &MediaStack::AIR,
            ray_limit: counts
                .total()
                .saturating_add(self.core.scene.settings.max_rays),
            glossy: None,
        };
        let out = self.trace_ray(ray, found, spawn, state, sampler, rec, counts);
        counts.budget_samples += u64::from(counts.budget_cuts > cuts);
        out
    }
}
