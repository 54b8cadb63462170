//! The Whitted tracer, exactly as the lecture's `trace(ray, objects, lights)` recursion, with a
//! [`Recorder`] hook that sees every ray.

mod area;
pub mod bound;
pub mod diagnose;
mod direct_only;
mod glossy;
mod integrator;
mod lights;
mod local;
pub mod offset;
mod path;
mod recorder;
mod recursive;
pub mod roulette;
mod shadow;

pub use crate::interaction::SurfaceInteraction;
pub use crate::media::{MediaStack, Medium};
pub use integrator::{Integrator, SceneIntegrator, Whitted};
pub use lights::LightSample;
pub use path::{PathStrategy, PathTracer, overflowing_lights};
pub use recorder::{DiagnosticRecorder, NoopRecorder, Recorder, TreeRecorder};

use crate::bvh::TraversalCost;
use crate::effects::EffectPlan;
use crate::math::{Ray, Rgb};
use crate::sampling::PixelSampler;
use crate::scene::{Film, Hit, Scene};
use crate::tree::{EndReason, NodeId, RayKind};
use glam::DVec3;

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
        self.camera + self.reflected + self.refracted + self.shadow + self.diffuse
    }

    fn add_kind(&mut self, kind: RayKind) {
        match kind {
            RayKind::Camera => self.camera += 1,
            RayKind::Reflected => self.reflected += 1,
            RayKind::Refracted => self.refracted += 1,
            RayKind::Shadow => self.shadow += 1,
            RayKind::Diffuse => self.diffuse += 1,
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

/// Where a ray starts: the surface point and which side of it.
#[derive(Clone, Copy, Debug)]
struct Spawn {
    kind: RayKind,
    parent: Option<NodeId>,
    point: DVec3,
    /// The object the ray leaves (`None` for camera rays).
    object: Option<usize>,
    /// For meshes: the stored triangle the ray leaves.
    triangle: Option<u32>,
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

/// Traces rays through one scene, running only the effects of its [`EffectPlan`].
#[derive(Clone, Copy, Debug)]
pub struct Tracer<'a> {
    scene: &'a Scene,
    plan: EffectPlan,
    /// The plan spawns no secondary rays (nothing reflects or refracts): a camera ray's
    /// radiance is the local term at its hit, which [`Tracer::trace_direct_only`] computes
    /// without the recursion's bookkeeping when nothing is recorded.
    direct_only: bool,
    /// The camera's image plane, its field of view evaluated once.
    film: Film<'a>,
    /// The cut in use: `settings.min_weight`, or the automatic one ([`bound`]).
    min_weight: f64,
    /// Dielectric hits of a throughput below this play Russian roulette between their two
    /// rays: `settings.roulette_below`, or the automatic weight ([`bound::carried`]).
    roulette_below: f64,
}

impl<'a> Tracer<'a> {
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
            scene,
            plan,
            direct_only,
            film: scene.camera.film(),
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
        &self.film
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// The effects this tracer runs.
    #[must_use]
    pub fn plan(&self) -> &EffectPlan {
        &self.plan
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

    /// [`Tracer::trace_camera`] for a camera ray whose closest hit is already known: `found` is
    /// what [`Scene::intersect_counted`] returns for it over `(ray.t_min, infinity)` and the work
    /// that took, e.g. from [`Scene::intersect_packet`] over a tile of camera rays. The result
    /// is the same as tracing the ray from scratch (the hit is the same bit for bit). Packets
    /// are traced only when the plan has no area lights ([`Tracer::traces_packets`]), so no
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
        self.trace_camera_general(ray, Some(found), &mut lights::NoSamples, rec, counts)
    }

    /// [`Tracer::trace_camera_found`] of a packet of camera rays (at most
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
            object: None,
            triangle: None,
            weight: Rgb::ONE,
        };
        let cuts = counts.budget_cuts;
        let state = PathState {
            depth: 0,
            throughput: Rgb::ONE,
            media: &MediaStack::AIR,
            ray_limit: counts.total().saturating_add(self.scene.settings.max_rays),
            glossy: None,
        };
        let out = self.trace_ray(ray, found, spawn, state, sampler, rec, counts);
        counts.budget_samples += u64::from(counts.budget_cuts > cuts);
        out
    }

    /// Offset a spawn point on `object` (for meshes: on stored `triangle`) by the configured
    /// strategy ([`offset::spawn`]).
    #[inline]
    pub(crate) fn spawn_ray(
        &self,
        (object, triangle): (usize, Option<u32>),
        point: DVec3,
        side: DVec3,
        direction: DVec3,
    ) -> Ray {
        let shape = || self.scene.surface_shape(object, triangle);
        offset::spawn(self.scene.settings.offset, shape, point, side, direction)
    }

    /// Run the diagnostics for a spawned ray, count and record them.
    #[allow(clippy::too_many_arguments)]
    fn diagnose<R: Recorder>(
        &self,
        ray: &Ray,
        point: DVec3,
        from: (usize, Option<u32>),
        hit: Option<Hit>,
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        let d = diagnose::diagnose(self.scene, ray, point, from, hit);
        counts.self_hits += u64::from(d.self_hit);
        counts.leaks += u64::from(d.leak.is_some());
        rec.update(id, |n| {
            n.self_hit = d.self_hit;
            n.leak = d.leak;
        });
    }
}
