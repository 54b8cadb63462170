//! The integrator seam: what the render loop, the inspector's worker and every command ask of
//! "the thing that computes a camera ray's radiance", so that an integrator added later (the
//! path tracer) appears in all of them.
//!
//! [`Integrator`] is the interface (generic methods, so it is used through generics, never as a
//! trait object: the recorder stays a generic parameter and costs nothing when off).
//! [`SceneIntegrator`] is the one a scene's `settings.integrator` chooses: [`Whitted`], the
//! lecture's recursion, or [`PathTracer`], the Monte Carlo path tracer.

use super::shading::NoSamples;
use super::{Bdpt, LightTracer, PathTracer, RayCounts, Recorder, Splat, Whitted};
use crate::bvh::TraversalCost;
use crate::integrator::EffectPlan;
use crate::math::{Ray, Rgb};
use crate::sampling::PixelSampler;
use crate::scene::{Film, Hit, IntegratorKind, Scene};
use crate::tree::NodeId;

/// Computes the radiance along camera rays of one scene.
pub trait Integrator: Sync {
    /// Which integrator this is (the `settings.integrator` name).
    fn kind(&self) -> IntegratorKind;

    /// The scene traced.
    fn scene(&self) -> &Scene;

    /// The scene camera's image plane (camera rays).
    fn film(&self) -> &Film<'_>;

    /// Radiance along camera `ray`, recording into `rec` and counting into `counts`; random
    /// numbers come from `sampler`, already started at this camera sample with its film offset
    /// drawn. Returns the root node when `rec` records.
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>);

    /// Whether the render may trace camera rays as packets through
    /// [`Integrator::camera_packet_radiance`]: true only for integrators that draw nothing from
    /// the sampler past the film offset (a packet holds rays of 64 different pixels).
    fn traces_packets(&self) -> bool;

    /// Whether a camera sample's radiance is a function of its film position alone: the
    /// Whitted integrator drawing nothing from the sampler past the film offset (no area
    /// light, no rough lobe: [`Integrator::traces_packets`]), without a lens and without the
    /// dielectric roulette (its hashed choices make neighbouring samples differ where the
    /// image has no edge). Automatic antialiasing needs it (`crate::render::adaptive_plan`).
    fn film_only(&self) -> bool {
        let settings = &self.scene().settings;
        self.kind() == IntegratorKind::Whitted
            && self.traces_packets()
            && !self.film().has_lens()
            && settings.whitted.dielectric_roulette.is_none()
    }

    /// The radiance of a packet of camera rays (at most [`crate::bvh::wide::PACKET`]) whose
    /// closest hits and traversal costs are known (from [`Scene::intersect_packet`]), into
    /// `out`: bit for bit what [`Integrator::camera_radiance`] gives each ray. Called only when
    /// [`Integrator::traces_packets`].
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        found: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    );

    /// Whether the integrator also traces paths from the lights whose connections land in
    /// other pixels (light tracing): the render then runs one light path per pixel sample
    /// ([`Integrator::trace_light_path`]) and adds the splats to the camera samples' mean
    /// (`crate::render`).
    fn splats(&self) -> bool {
        false
    }

    /// Light path `seed` (the pixel sample that seeds it), each contribution handed to
    /// `splat`; recorded into `rec`, returning its root node. Called only when
    /// [`Integrator::splats`]; the default traces nothing.
    fn trace_light_path<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        let _ = (seed, sampler, rec, counts, splat);
        None
    }
}

impl Integrator for Whitted<'_> {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Whitted
    }

    #[inline]
    fn scene(&self) -> &Scene {
        Whitted::scene(self)
    }

    #[inline]
    fn film(&self) -> &Film<'_> {
        Whitted::film(self)
    }

    /// Whitted ray tracing draws from `sampler` only for area lights' shadow rays.
    #[inline]
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        self.trace_camera(ray, sampler, rec, counts)
    }

    /// Packets only without area lights (their shadow rays draw from the pixel's sampler).
    #[inline]
    fn traces_packets(&self) -> bool {
        !(self.plan().area_lights || self.plan().glossy)
    }

    #[inline]
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        found: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        self.trace_camera_packet(rays, found, out, rec, counts);
    }
}

impl Integrator for PathTracer<'_> {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Path
    }

    #[inline]
    fn scene(&self) -> &Scene {
        PathTracer::scene(self)
    }

    #[inline]
    fn film(&self) -> &Film<'_> {
        PathTracer::film(self)
    }

    #[inline]
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        self.trace_camera(ray, sampler, rec, counts)
    }

    /// Never: every path draws from its pixel's sampler.
    #[inline]
    fn traces_packets(&self) -> bool {
        false
    }

    /// Not called ([`Integrator::traces_packets`] is false); traces each ray alone, its
    /// random numbers all 0.5.
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        _: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        for (ray, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.trace_camera(*ray, &mut NoSamples, rec, counts).0;
        }
    }
}

impl Integrator for LightTracer<'_> {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Light
    }

    #[inline]
    fn scene(&self) -> &Scene {
        LightTracer::scene(self)
    }

    #[inline]
    fn film(&self) -> &Film<'_> {
        LightTracer::film(self)
    }

    /// The camera ray's own part (what it sees directly); draws nothing from `sampler`.
    #[inline]
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        _: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        self.trace_camera(ray, rec, counts)
    }

    /// Never: the light paths are the render's main work, and they are traced one by one.
    #[inline]
    fn traces_packets(&self) -> bool {
        false
    }

    /// Not called ([`Integrator::traces_packets`] is false); traces each ray alone.
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        _: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        for (ray, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.trace_camera(*ray, rec, counts).0;
        }
    }

    fn splats(&self) -> bool {
        true
    }

    #[inline]
    fn trace_light_path<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        LightTracer::trace_light_path(self, seed, sampler, rec, counts, splat)
    }
}

impl Integrator for Bdpt<'_> {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Bdpt
    }

    #[inline]
    fn scene(&self) -> &Scene {
        Bdpt::scene(self)
    }

    #[inline]
    fn film(&self) -> &Film<'_> {
        Bdpt::film(self)
    }

    #[inline]
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        self.trace_camera(ray, sampler, rec, counts)
    }

    /// Never: every sample draws from its pixel's sampler.
    #[inline]
    fn traces_packets(&self) -> bool {
        false
    }

    /// Not called ([`Integrator::traces_packets`] is false).
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        _: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        for (ray, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.trace_camera(*ray, &mut NoSamples, rec, counts).0;
        }
    }

    fn splats(&self) -> bool {
        true
    }

    #[inline]
    fn trace_light_path<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        self.trace_splats(seed, sampler, rec, counts, splat)
    }
}

/// The integrator a scene's `settings.integrator` names, ready to trace. Every command builds
/// this one, so a new [`IntegratorKind`] is one more arm here and nothing else in the commands.
#[derive(Clone, Debug)]
pub enum SceneIntegrator<'a> {
    /// `"whitted"`.
    Whitted(Whitted<'a>),
    /// `"path"`.
    Path(PathTracer<'a>),
    /// `"light"`.
    Light(LightTracer<'a>),
    /// `"bdpt"`.
    Bdpt(Bdpt<'a>),
}

impl<'a> SceneIntegrator<'a> {
    /// The integrator of `scene.settings.integrator` with the effects the scene calls for.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        Self::with_plan(scene, EffectPlan::for_scene(scene))
    }

    /// The integrator of `scene.settings.integrator` with an explicit effect plan.
    #[must_use]
    pub fn with_plan(scene: &'a Scene, plan: EffectPlan) -> Self {
        match scene.settings.integrator {
            IntegratorKind::Whitted => Self::Whitted(Whitted::with_plan(scene, plan)),
            // The path tracer runs every effect (its own plan): `plan` is Whitted's.
            IntegratorKind::Path => Self::Path(PathTracer::new(scene)),
            IntegratorKind::Light => Self::Light(LightTracer::new(scene)),
            IntegratorKind::Bdpt => Self::Bdpt(Bdpt::new(scene)),
        }
    }

    /// The Whitted tracer, when that is the integrator.
    #[must_use]
    pub fn whitted(&self) -> Option<&Whitted<'a>> {
        match self {
            Self::Whitted(t) => Some(t),
            Self::Path(_) | Self::Light(_) | Self::Bdpt(_) => None,
        }
    }
}

impl Integrator for SceneIntegrator<'_> {
    fn kind(&self) -> IntegratorKind {
        match self {
            Self::Whitted(t) => t.kind(),
            Self::Path(t) => t.kind(),
            Self::Light(t) => t.kind(),
            Self::Bdpt(t) => t.kind(),
        }
    }

    #[inline]
    fn scene(&self) -> &Scene {
        match self {
            Self::Whitted(t) => Integrator::scene(t),
            Self::Path(t) => Integrator::scene(t),
            Self::Light(t) => Integrator::scene(t),
            Self::Bdpt(t) => Integrator::scene(t),
        }
    }

    #[inline]
    fn film(&self) -> &Film<'_> {
        match self {
            Self::Whitted(t) => Integrator::film(t),
            Self::Path(t) => Integrator::film(t),
            Self::Light(t) => Integrator::film(t),
            Self::Bdpt(t) => Integrator::film(t),
        }
    }

    #[inline]
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        match self {
            Self::Whitted(t) => t.camera_radiance(ray, sampler, rec, counts),
            Self::Path(t) => t.camera_radiance(ray, sampler, rec, counts),
            Self::Light(t) => t.camera_radiance(ray, sampler, rec, counts),
            Self::Bdpt(t) => t.camera_radiance(ray, sampler, rec, counts),
        }
    }

    #[inline]
    fn traces_packets(&self) -> bool {
        match self {
            Self::Whitted(t) => t.traces_packets(),
            Self::Path(t) => t.traces_packets(),
            Self::Light(t) => t.traces_packets(),
            Self::Bdpt(t) => t.traces_packets(),
        }
    }

    #[inline]
    fn camera_packet_radiance<R: Recorder>(
        &self,
        rays: &[Ray],
        found: (&[Option<Hit>], &[TraversalCost]),
        out: &mut [Rgb],
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        match self {
            Self::Whitted(t) => t.camera_packet_radiance(rays, found, out, rec, counts),
            Self::Path(t) => t.camera_packet_radiance(rays, found, out, rec, counts),
            Self::Light(t) => t.camera_packet_radiance(rays, found, out, rec, counts),
            Self::Bdpt(t) => t.camera_packet_radiance(rays, found, out, rec, counts),
        }
    }

    #[inline]
    fn splats(&self) -> bool {
        matches!(self, Self::Light(_) | Self::Bdpt(_))
    }

    #[inline]
    fn trace_light_path<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        match self {
            Self::Light(t) => t.trace_light_path(seed, sampler, rec, counts, splat),
            Self::Bdpt(t) => t.trace_splats(seed, sampler, rec, counts, splat),
            Self::Whitted(_) | Self::Path(_) => None,
        }
    }
}
