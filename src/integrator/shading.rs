//! The shading core every integrator is built on ([`Shading`]): the scene, the effect plan, the
//! camera's film and the light sampler, and what each integrator does at a surface the same
//! way — the surface interaction of a hit (geometric and shading normal), n1/n2, Snell and
//! Fresnel at an interface from the media stack, spawning a ray with the offset strategy, the
//! shadow ray towards a light and its cast (visibility or the translucent approximation), and
//! the diagnostics of a spawned ray. The direct-light estimator built on it is `direct.rs`.

use super::{RayCounts, Recorder, diagnose, offset, shadow};
use crate::bvh::TraversalCost;
use crate::geometry::Shape;
use crate::integrator::EffectPlan;
use crate::interaction::{SurfaceId, SurfaceInteraction};
use crate::lights::LightSampler;
use crate::math::{self, Fresnel, Ray, Rgb, beer, refract};
use crate::media::MediaStack;
use crate::mesh::shading;
use crate::sampling::PixelSampler;
use crate::scene::{Film, Hit, OffsetStrategy, Scene};
use crate::tree::{Attenuation, Blocker, EndReason, HitInfo, Interface, NodeId, RayKind};
use glam::DVec3;

/// The shadow ray to a sampled point on an emitter (or to where it meets the emitter first)
/// stops this fraction short of it, so it does not find the emitter itself (pbrt-v4's
/// `ShadowEpsilon` in `SpawnRayTo`).
const SHADOW_EPSILON: f64 = 1e-4;

/// A mesh emitter's own hit more than this fraction of the distance (plus twice the shadow
/// ray's origin offset, which shortens the ray to the sampled point's plane) short of its
/// sampled point hides the point. An occluding part of the mesh closer than that to the point
/// is not seen as one (a small error on nearly touching surfaces).
const HIDDEN_BY_ITSELF: f64 = 1e-3;

/// What every integrator shades with: one per integrator, built once.
#[derive(Clone, Debug)]
pub struct Shading<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The effects the integrator runs.
    pub plan: EffectPlan,
    /// The camera's image plane, its field of view evaluated once.
    pub film: Film<'a>,
    /// Every light (point, directional, area), chosen in proportion to power.
    pub lights: LightSampler<'a>,
}

/// What a ray's segment found ([`Shading::segment`]): its closest hit and the attenuation of
/// the medium it crossed (Beer's law; 1 outside absorbing media).
pub(crate) struct Segment {
    /// The closest hit, if any.
    pub hit: Option<Hit>,
    /// Beer's law along the segment (from the true spawn point to the hit; 0 or 1 for a miss).
    pub atten: Rgb,
}

/// What a cast shadow ray found ([`Shading::cast_shadow`]).
pub(crate) struct Cast {
    /// The fraction of the light that arrives (1 unblocked, 0 blocked).
    pub transmittance: Rgb,
    /// The blockers passed or stopped at (empty unless recording).
    pub blockers: Vec<Blocker>,
    /// The traversal work.
    pub cost: TraversalCost,
}

impl<'a> Shading<'a> {
    /// The core of an integrator over `scene` running `plan`.
    #[must_use]
    pub fn new(scene: &'a Scene, plan: EffectPlan) -> Self {
        Self {
            scene,
            plan,
            film: scene.camera.film(),
            lights: scene.light_sampler(),
        }
    }

    /// The surface interaction of `hit` for `ray` arriving through `media`.
    #[inline(always)]
    pub(crate) fn surface<'s>(
        &'s self,
        ray: &Ray,
        hit: &Hit,
        media: &'s MediaStack,
    ) -> SurfaceInteraction<'s> {
        let d = ray.direction;
        let p = ray.at(hit.t);
        let entering = d.dot(hit.normal) < 0.0;
        let n = if entering { hit.normal } else { -hit.normal };
        // Built by value where it is returned: an interaction assembled and then moved is a
        // 176-byte `memcpy` per hit (measured: 3% of the classic scene's render time). `smooth`
        // is an argument so that the common case writes a constant `None` (a spilled `None`
        // re-read as 16 bytes stalled store forwarding: 2% of a glass-emitters render, perf).
        let with = |smooth: Option<DVec3>, ns: DVec3, cos_i: f64| SurfaceInteraction {
            p,
            wo: -d,
            entering,
            n,
            ns,
            smooth,
            cos_i,
            object: hit.object,
            triangle: hit.triangle,
            material: self.scene.material_of(hit.object),
            media,
        };
        let cos = |ns: DVec3| (-d.dot(ns)).clamp(0.0, 1.0);
        match hit.triangle.and_then(|_| self.scene.shading_normal(hit, p)) {
            None => with(None, n, cos(n)),
            Some(s) => {
                let ns = shading::shading_normal(d, n, s, entering);
                let ns = self.consistent_shading_normal(&with(Some(s), n, 0.0), ns);
                with(Some(s), ns, cos(ns))
            }
        }
    }

    /// `ns`, or the geometric normal `si.n` where refracting with `ns` would cross to the wrong
    /// side of the surface (mesh::shading rule).
    fn consistent_shading_normal(&self, si: &SurfaceInteraction, ns: DVec3) -> DVec3 {
        let n = si.n;
        if ns != n && self.plan.refraction && si.material.is_transmissive() {
            let d = -si.wo;
            let cos = (-d.dot(ns)).clamp(0.0, 1.0);
            let (_, t) = self.interface(si, ns, cos);
            if t.is_some_and(|t| !shading::refraction_consistent(n, t)) {
                return n;
            }
        }
        ns
    }

    /// n1, n2 (from the media stack), Snell and Fresnel at transmissive `si` with shading
    /// normal `n` (incident side) and incidence cosine `cos_i`; the refracted direction unless
    /// TIR. Inlined: returned through memory, its 100-byte record was stored and reloaded at
    /// every dielectric hit.
    #[inline(always)]
    pub(crate) fn interface(
        &self,
        si: &SurfaceInteraction,
        n: DVec3,
        cos_i: f64,
    ) -> (Interface, Option<DVec3>) {
        let (d, object, m, media) = (-si.wo, si.object, si.material, si.media);
        let (n1, n2) = if si.entering {
            let n1 = media.ior();
            (n1, m.ior.unwrap_or(n1))
        } else {
            let n2 = media.ior_outside(object);
            (m.ior.unwrap_or(n2), n2)
        };
        let model = self.scene.settings.whitted.fresnel;
        match refract(d, n, n1 / n2) {
            Some(t) => {
                let fresnel: Fresnel = math::fresnel(model, n1, n2, cos_i, t.cos_t);
                let event = Interface {
                    n1,
                    n2,
                    cos_i,
                    cos_t: Some(t.cos_t),
                    fresnel,
                    tir: false,
                    roulette: None,
                };
                (event, Some(t.direction))
            }
            None => {
                let event = Interface {
                    n1,
                    n2,
                    cos_i,
                    cos_t: None,
                    fresnel: math::fresnel_tir(model),
                    tir: true,
                    roulette: None,
                };
                (event, None)
            }
        }
    }

    /// Offset a spawn point on surface `from` by the configured strategy ([`offset::spawn`]).
    #[inline]
    pub(crate) fn spawn_ray(
        &self,
        from: SurfaceId,
        point: DVec3,
        side: DVec3,
        direction: DVec3,
    ) -> Ray {
        let shape = || self.scene.surface_shape(from.object, from.triangle);
        offset::spawn(self.scene.settings.offset, shape, point, side, direction)
    }

    /// The segment of a recorded ray (node `id`) spawned at `point` on `from` (`None`: a camera
    /// ray) through `media`: its closest hit (`found` when the caller already has it and the
    /// work it took, e.g. from a packet), the traversal work recorded, the diagnostics when the
    /// recorder runs them, and Beer's law inside the innermost absorbing medium, recorded as
    /// the node's attenuation. Absorption is looked up only when the plan has it (no per-ray
    /// cost otherwise). The distance runs from the true spawn point, so the offset does not bias
    /// Beer's law.
    #[inline(always)]
    pub(crate) fn segment<R: Recorder>(
        &self,
        (ray, found): (&Ray, Option<(Option<Hit>, TraversalCost)>),
        (point, from): (DVec3, Option<SurfaceId>),
        media: &MediaStack,
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Segment {
        let (hit, cost) = found.unwrap_or_else(|| {
            let mut cost = TraversalCost::default();
            let hit = self.scene.intersect_counted(ray, f64::INFINITY, &mut cost);
            (hit, cost)
        });
        rec.update(id, |n| n.traversal = cost);
        if R::DIAGNOSE
            && let Some(from) = from
        {
            self.diagnose((ray, point, from), hit, id, rec, counts);
        }
        let medium = if self.plan.absorption {
            media.top().map(|m| m.object as usize)
        } else {
            None
        };
        let mut atten = Rgb::ONE;
        if let Some(medium) = medium {
            let absorption = self.scene.material_of(medium).absorption;
            if absorption != Rgb::ZERO {
                let distance = hit.map_or(f64::INFINITY, |h| (ray.at(h.t) - point).length());
                atten = beer(absorption, distance);
                rec.update(id, |n| {
                    n.attenuation = Some(Attenuation {
                        medium,
                        distance,
                        absorption,
                        factor: atten,
                    });
                });
            }
        }
        Segment { hit, atten }
    }

    /// Run the diagnostics for a ray spawned at `point` on `from` whose closest hit is `hit`,
    /// count and record them on node `id`.
    pub(crate) fn diagnose<R: Recorder>(
        &self,
        (ray, point, from): (&Ray, DVec3, SurfaceId),
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

    /// The shadow ray from `p` (on `from`, geometric normal `n` on the side of the light) to a
    /// light at `dist` along `wi`, offset by `strategy`, and how far it may go: the light's
    /// distance less the offset, so the offset origin does not reach past the light (no square
    /// root except for `robust`). The direct-only path passes a constant `strategy`, so each of
    /// its loops holds one arm.
    #[inline(always)]
    pub(crate) fn shadow_ray(
        &self,
        strategy: OffsetStrategy,
        (from, p, n): (SurfaceId, DVec3, DVec3),
        wi: DVec3,
        dist: f64,
    ) -> (Ray, f64) {
        let eps = self.scene.settings.offset.epsilon;
        match strategy {
            OffsetStrategy::Normal => (Ray::new(p + eps * n, wi, 0.0), (dist - eps).max(0.0)),
            OffsetStrategy::Ray => (Ray::new(p, wi, eps), dist),
            OffsetStrategy::Scaled => {
                let e = offset::scaled_epsilon(eps, p);
                (Ray::new(p + e * n, wi, 0.0), (dist - e).max(0.0))
            }
            OffsetStrategy::Robust => {
                let shape = || self.scene.surface_shape(from.object, from.triangle);
                let origin = offset::robust_origin(&shape(), p, n);
                let ray = Ray::new(origin, wi, 0.0);
                (ray, (dist - (origin - p).length()).max(0.0))
            }
        }
    }

    /// Cast a recorded shadow ray (from `p` on surface `from`): count it, diagnose it when the
    /// recorder does, and find its transmittance; the blockers are collected only when
    /// recording (no `Vec` on the render path).
    #[inline(always)]
    pub(crate) fn cast_shadow<R: Recorder>(
        &self,
        (ray, seg): (&Ray, f64),
        (p, from): (DVec3, SurfaceId),
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Cast {
        counts.add_kind(RayKind::Shadow);
        self.cast((ray, seg), (p, from), id, rec, counts)
    }

    /// [`Shading::cast_shadow`] without counting the ray (the caller counts it as its own
    /// kind: a light tracer's connection to the camera).
    #[inline(always)]
    pub(crate) fn cast<R: Recorder>(
        &self,
        (ray, seg): (&Ray, f64),
        (p, from): (DVec3, SurfaceId),
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Cast {
        if R::DIAGNOSE {
            let first = self.scene.intersect(ray, seg);
            self.diagnose((ray, p, from), first, id, rec, counts);
        }
        let mut blockers = R::RECORDS.then(Vec::new);
        let mut cost = TraversalCost::default();
        let transmittance = shadow::transmission(
            self.scene,
            ray,
            seg,
            self.plan.translucent_shadows,
            blockers.as_mut(),
            &mut cost,
        );
        Cast {
            transmittance,
            blockers: blockers.unwrap_or_default(),
            cost,
        }
    }

    /// The hit as recorded on the ray's node.
    #[inline(always)]
    pub(crate) fn record_hit<R: Recorder>(
        &self,
        si: &SurfaceInteraction,
        hit: &Hit,
        id: Option<NodeId>,
        rec: &mut R,
    ) {
        let scene = self.scene;
        rec.update(id, |n| {
            n.hit = Some(HitInfo {
                t: hit.t,
                point: si.p,
                normal: hit.normal,
                object: hit.object,
                object_name: scene.objects[hit.object].name.clone(),
                material: si.material.name.clone(),
                entering: si.entering,
                cos_i: si.cos_i,
                triangle: scene.source_triangle(hit),
                shading_normal: si.smooth.map(|_| si.outward_shading_normal()),
            });
        });
    }

    /// The length of the shadow ray `ray` (nominal length `seg`, from the offset origin of
    /// shading point `p`) to a point sampled on area light `object`. The offset origin sees the
    /// emitter along a slightly different line: near a sphere's silhouette that line enters it
    /// earlier than the sampled point (1.7% of the samples of a 14-degree cone were found
    /// blocked by the light itself), so the ray stops [`SHADOW_EPSILON`] short of where it
    /// first meets the emitter. A non-convex emissive mesh can hide the sampled point behind
    /// another of its own triangles: then the ray keeps its full length, and casting it finds
    /// the mesh in the way (visibility 0).
    pub(crate) fn emitter_shadow_length(
        &self,
        object: usize,
        ray: &Ray,
        seg: f64,
        p: DVec3,
    ) -> f64 {
        let scene = self.scene;
        // The distance alone (the prepared object's test, without the normal `Shape::intersect`
        // would compute): the same bits.
        let own = scene.object_t(object, ray, seg);
        let hidden = matches!(scene.objects[object].shape, Shape::Mesh(_))
            && own
                .is_some_and(|t| t < seg * (1.0 - HIDDEN_BY_ITSELF) - 2.0 * ray.origin.distance(p));
        if hidden {
            return seg;
        }
        own.unwrap_or(seg) * (1.0 - SHADOW_EPSILON)
    }
}

/// A recorded shadow ray's end reason from its transmittance.
pub(crate) fn shadow_end(transmittance: Rgb) -> EndReason {
    if transmittance == Rgb::ONE {
        EndReason::Unblocked
    } else if transmittance == Rgb::ZERO {
        EndReason::Blocked
    } else {
        EndReason::Attenuated
    }
}

/// The cosine at which a light in direction `wi` is seen: against the shading normal `ns`,
/// unless the light is behind the geometric normal `n` (the shadow ray leaves on the geometric
/// side, so a light below the geometric surface cannot be reached).
#[inline(always)]
pub(crate) fn cos_to_light(n: DVec3, ns: DVec3, wi: DVec3) -> f64 {
    if n.dot(wi) > 0.0 {
        ns.dot(wi)
    } else {
        n.dot(wi)
    }
}

/// The 2D sample passed to a delta light's [`crate::lights::Light::sample_li`], which ignores
/// it.
pub(crate) const DELTA_U: (f64, f64) = (0.5, 0.5);

/// The sampler of camera rays traced without one (packets, which run only when the plan has
/// no area lights): it is never drawn from, and would give the square's centre if it were.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NoSamples;

impl PixelSampler for NoSamples {
    fn start_sample(&mut self, _: (u32, u32), _: u32) {}
    fn next_1d(&mut self) -> f64 {
        0.5
    }
    fn next_2d(&mut self) -> (f64, f64) {
        DELTA_U
    }
}
