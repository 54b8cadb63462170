//! The render path of a plan without secondary rays (nothing reflects or refracts): a camera
//! ray's radiance is the local term at its closest hit. The recursive tracer computes the same
//! value bit for bit (`tests/scenes.rs` pins it on every pixel of a diffuse-only scene), but its
//! bookkeeping (tree hooks, traversal cost, media, recorded blockers, plan branches inside the
//! light loop) cost about 10-20% in time over a plain ray caster; here the light loop is
//! monomorphised on the plan's highlight flag and the offset strategy, so it holds no branch on
//! either and no call but the shadow query.

use super::Whitted;
use crate::bvh::TraversalCost;
use crate::bvh::wide::PACKET;
use crate::integrator::shading::{DELTA_U, cos_to_light};
use crate::integrator::{MediaStack, RayCounts};
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSample};
use crate::math::{Ray, Rgb};
use crate::scene::{Hit, OffsetStrategy};

/// [`OffsetStrategy`] as a const-generic parameter.
const NORMAL: u8 = 0;
const RAY: u8 = 1;
const SCALED: u8 = 2;
const ROBUST: u8 = 3;

const fn strategy(s: u8) -> OffsetStrategy {
    match s {
        NORMAL => OffsetStrategy::Normal,
        RAY => OffsetStrategy::Ray,
        SCALED => OffsetStrategy::Scaled,
        _ => OffsetStrategy::Robust,
    }
}

/// A light's shadow ray from a surface it faces, and the light's sample.
struct Unshadowed {
    /// The shadow ray (offset by the configured strategy).
    ray: Ray,
    /// How far it may go.
    seg: f64,
    /// The light's sample.
    ls: LightSample,
    /// The cosine at which the surface sees it (> 0).
    cos: f64,
}

/// The shading inputs of one hit: its interaction and diffuse albedo.
struct At<'h> {
    si: SurfaceInteraction<'h>,
    albedo: Rgb,
}

impl Whitted<'_> {
    /// Radiance along an unrecorded camera ray (closest hit `found`, or found here) when the
    /// plan spawns no secondary rays: the sum of emitted, ambient and every light through an
    /// opaque shadow ray (any-hit), as [`Whitted::local`] computes it.
    pub(super) fn trace_direct_only(
        &self,
        ray: &Ray,
        found: Option<Option<Hit>>,
        counts: &mut RayCounts,
    ) -> Rgb {
        counts.camera += 1;
        let scene = self.scene();
        let hit = match found {
            Some(hit) => hit,
            None => scene.intersect(ray, f64::INFINITY),
        };
        let Some(hit) = hit else {
            return scene.background;
        };
        let (total, at) = self.shading_at(ray, &hit);
        let Some(at) = at else {
            return total;
        };
        use OffsetStrategy as O;
        match (self.plan().specular, scene.settings.offset.strategy) {
            (false, O::Normal) => self.lights::<false, NORMAL>(&at, total, counts),
            (false, O::Ray) => self.lights::<false, RAY>(&at, total, counts),
            (false, O::Scaled) => self.lights::<false, SCALED>(&at, total, counts),
            (false, O::Robust) => self.lights::<false, ROBUST>(&at, total, counts),
            (true, O::Normal) => self.lights::<true, NORMAL>(&at, total, counts),
            (true, O::Ray) => self.lights::<true, RAY>(&at, total, counts),
            (true, O::Scaled) => self.lights::<true, SCALED>(&at, total, counts),
            (true, O::Robust) => self.lights::<true, ROBUST>(&at, total, counts),
        }
    }

    /// [`Whitted::trace_direct_only`] of a packet of camera rays with their closest hits
    /// (`hits[i]` for `rays[i]`, from [`crate::Scene::intersect_packet`]), into `out`: the same
    /// radiance bit for bit, but each light's shadow rays from the packet's hits are tested
    /// together ([`crate::Scene::occluded_packet`]). Every ray adds its lights in light order,
    /// as the single path does.
    ///
    /// # Panics
    /// If `hits` or `out` is shorter than `rays`, or there are more than
    /// [`crate::bvh::wide::PACKET`] rays.
    pub(crate) fn trace_direct_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        out: &mut [Rgb],
        counts: &mut RayCounts,
    ) {
        use OffsetStrategy as O;
        let args = (rays, hits, out, counts);
        match (self.plan().specular, self.scene().settings.offset.strategy) {
            (false, O::Normal) => self.packet_lights::<false, NORMAL>(args),
            (false, O::Ray) => self.packet_lights::<false, RAY>(args),
            (false, O::Scaled) => self.packet_lights::<false, SCALED>(args),
            (false, O::Robust) => self.packet_lights::<false, ROBUST>(args),
            (true, O::Normal) => self.packet_lights::<true, NORMAL>(args),
            (true, O::Ray) => self.packet_lights::<true, RAY>(args),
            (true, O::Scaled) => self.packet_lights::<true, SCALED>(args),
            (true, O::Robust) => self.packet_lights::<true, ROBUST>(args),
        }
    }

    /// The shading inputs of `hit` on `ray` and its radiance without lights, or only the
    /// radiance when no light can add to it ([`Whitted::trace_direct_only`]'s first half).
    #[inline(always)]
    fn shading_at(&self, ray: &Ray, hit: &Hit) -> (Rgb, Option<At<'_>>) {
        let si = self.core.surface(ray, hit, &MediaStack::AIR);
        let m = si.material;
        let albedo = m.diffuse.at(si.p);
        let emitted = if si.entering { m.emission } else { Rgb::ZERO };
        let total = emitted + self.scene().ambient * albedo;
        if m.diffuse.is_black() && m.specular == Rgb::ZERO {
            return (total, None);
        }
        (total, Some(At { si, albedo }))
    }

    /// [`Whitted::trace_direct_packet`] for one plan and offset strategy.
    fn packet_lights<const SPECULAR: bool, const STRATEGY: u8>(
        &self,
        (rays, hits, out, counts): (&[Ray], &[Option<Hit>], &mut [Rgb], &mut RayCounts),
    ) {
        let scene = self.scene();
        let n = rays.len();
        assert!(n <= PACKET && hits.len() >= n && out.len() >= n);
        let mut ats: Vec<Option<At>> = Vec::with_capacity(n);
        for (i, ray) in rays.iter().enumerate() {
            counts.camera += 1;
            let (total, at) = match &hits[i] {
                Some(hit) => self.shading_at(ray, hit),
                None => (scene.background, None),
            };
            out[i] = total;
            ats.push(at);
        }
        // Per light: the shadow rays of the hits it faces, tested together.
        let mut shadows = Vec::with_capacity(n);
        let (mut of, mut seg, mut add) = ([0usize; PACKET], [0.0; PACKET], [Rgb::ZERO; PACKET]);
        let mut blocked = [false; PACKET];
        for light in self.lights_on() {
            shadows.clear();
            for (i, at) in ats.iter().enumerate() {
                let Some(at) = at else { continue };
                let Some(u) = self.unshadowed(strategy(STRATEGY), &at.si, light, counts) else {
                    continue;
                };
                let k = shadows.len();
                let add_k = Self::unshadowed_add::<SPECULAR>(&at.si, at.albedo, &u);
                (of[k], seg[k], add[k]) = (i, u.seg, add_k);
                shadows.push(u.ray);
            }
            let k = shadows.len();
            scene.occluded_packet(&shadows, &seg[..k], &mut blocked[..k]);
            for k in 0..k {
                if !blocked[k] {
                    out[of[k]] += add[k];
                }
            }
        }
    }

    /// Adds every light's contribution at `at` to `total`: [`Whitted::direct`] without the
    /// recording, for opaque shadows. A light behind the surface or blocked adds nothing (there,
    /// exactly zero), so neither is evaluated further.
    #[inline(always)]
    fn lights<const SPECULAR: bool, const STRATEGY: u8>(
        &self,
        at: &At,
        mut total: Rgb,
        counts: &mut RayCounts,
    ) -> Rgb {
        for light in self.lights_on() {
            let Some(u) = self.unshadowed(strategy(STRATEGY), &at.si, light, counts) else {
                continue;
            };
            if self
                .scene()
                .occluded(&u.ray, u.seg, &mut TraversalCost::default())
            {
                continue;
            }
            total += Self::unshadowed_add::<SPECULAR>(&at.si, at.albedo, &u);
        }
        total
    }

    /// The point and directional lights the plan keeps: the loop of both light loops here.
    #[inline(always)]
    fn lights_on(&self) -> impl Iterator<Item = &Light<'_>> + '_ {
        let plan = self.plan();
        self.core
            .lights
            .delta_lights()
            .iter()
            .enumerate()
            .filter(move |(i, _)| plan.light_on(*i))
            .map(|(_, l)| l)
    }

    /// The unrecorded light-loop body shared by the single rays and packets: the light sampled
    /// from `si`, and unless it is behind the surface its shadow ray (counted). `strategy` is a
    /// constant in the callers' loops.
    #[inline(always)]
    fn unshadowed(
        &self,
        strategy: OffsetStrategy,
        si: &SurfaceInteraction,
        light: &Light,
        counts: &mut RayCounts,
    ) -> Option<Unshadowed> {
        let ls = light.sample_li(si.p, DELTA_U)?;
        let cos = cos_to_light(si.n, si.ns, ls.direction);
        if cos <= 0.0 {
            return None;
        }
        counts.shadow += 1;
        let at = (si.from(), si.p, si.n);
        let (ray, seg) = self
            .core
            .shadow_ray(strategy, at, ls.direction, ls.distance);
        Some(Unshadowed { ray, seg, ls, cos })
    }

    /// What an unblocked [`Unshadowed`] adds at `si` (diffuse albedo `albedo`):
    /// `brdf * cos * value`, the recorded path's `weight * (value * Rgb::ONE)` bit for bit.
    #[inline(always)]
    fn unshadowed_add<const SPECULAR: bool>(
        si: &SurfaceInteraction,
        albedo: Rgb,
        u: &Unshadowed,
    ) -> Rgb {
        let wi = u.ls.direction;
        let (_, weight) =
            Self::light_weight(SPECULAR, si.material, albedo, si.ns, (wi, si.wo), u.cos);
        weight * u.ls.value()
    }
}
