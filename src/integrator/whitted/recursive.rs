//! The recursion of the lecture's `trace(ray, objects, lights)`: closest hit, Beer's law on the
//! segment, local shading, and the reflected and refracted rays of each hit.

use super::local::Local;
use super::{PathState, Secondary, Spawn, Whitted};
use crate::bvh::TraversalCost;
use crate::integrator::shading::Segment;
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::{SurfaceId, SurfaceInteraction};
use crate::math::{Ray, Rgb, reflect};
use crate::sampling::PixelSampler;
use crate::scene::Hit;
use crate::tree::{EndReason, Interface, NodeId, RayKind, RayNode};
use glam::DVec3;

impl Whitted<'_> {
    /// One ray of the tree; `found` is its closest hit and the traversal work when the caller
    /// already has them (camera rays traced by packet), otherwise they are computed here.
    // The ray, its known hit, where it starts and the path state, plus the sampler, recorder and counts every tracing function threads.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn trace_ray<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        found: Option<(Option<Hit>, TraversalCost)>,
        spawn: Spawn,
        state: PathState,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        counts.add_kind(spawn.kind);
        let id = rec.push(spawn.parent, || {
            let mut n = RayNode::new(
                spawn.kind,
                state.depth,
                spawn.point,
                ray.origin,
                ray.direction,
            );
            n.t_min = ray.t_min;
            n.weight = spawn.weight;
            n.throughput = state.throughput;
            n
        });
        let seg = (spawn.point, spawn.from);
        let Segment { hit, atten } =
            self.core
                .segment((&ray, found), seg, state.media, id, rec, counts);
        let Some(hit) = hit else {
            let radiance = atten * self.core.scene.background;
            rec.update(id, |n| {
                n.radiance = radiance;
                n.end = EndReason::Miss;
            });
            return (radiance, id);
        };
        let inner = self.shade(
            &ray,
            &hit,
            id,
            state.throughput * atten,
            state,
            sampler,
            rec,
            counts,
        );
        let radiance = atten * inner;
        rec.update(id, |n| n.radiance = radiance);
        (radiance, id)
    }

    /// Everything at a hit: local shading plus the weighted secondary rays (before the segment's
    /// attenuation).
    // The ray, its hit and node, the throughput and path state, plus the sampler, recorder and counts every tracing function threads.
    #[allow(clippy::too_many_arguments)]
    fn shade<R: Recorder, S: PixelSampler>(
        &self,
        ray: &Ray,
        hit: &Hit,
        id: Option<NodeId>,
        throughput: Rgb,
        state: PathState,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let si = self.core.surface(ray, hit, state.media);
        self.core.record_hit(&si, hit, id, rec);
        let Local {
            emitted,
            ambient,
            total: local,
        } = self.local(&si, (id, state.depth), sampler, rec, counts);
        rec.update(id, |node| {
            node.emitted = emitted;
            node.ambient = ambient;
            node.local = local;
        });

        if !(self.core.plan.reflection || self.core.plan.refraction) {
            // Nothing in the scene reflects or refracts: no secondary rays, no bookkeeping.
            rec.update(id, |node| {
                node.end = EndReason::Surface;
                node.truncated = Rgb::ZERO;
            });
            return local;
        }
        // Rough lobes are sampled (glossy.rs); the smooth ones split as the lecture's. An
        // index-matched rough interface stays a smooth pass-through (every microfacet sends
        // light straight on).
        let m = si.material;
        let rough = self.core.plan.glossy && m.is_rough();
        let split = self.split(&si, rough, throughput, state.depth, id, rec, counts);
        let at = Spawn {
            kind: RayKind::Reflected,
            parent: id,
            point: si.p,
            from: Some(SurfaceId {
                object: hit.object,
                triangle: hit.triangle,
            }),
            weight: Rgb::ZERO,
        };
        let mut acc = Secondary {
            total: local,
            end: EndReason::Surface,
            truncated: Rgb::ZERO,
        };
        let state = PathState {
            throughput,
            ..state
        };
        self.children(
            &mut acc,
            &si,
            ray.direction,
            split,
            at,
            state,
            sampler,
            rec,
            counts,
        );
        if rough {
            self.glossy_rays(&mut acc, &si, at, state, sampler, rec, counts);
        }
        rec.update(id, |node| {
            node.end = acc.end;
            node.truncated = acc.truncated;
        });
        acc.total
    }

    /// The smooth lobes' split at a hit: the mirror weight (the material's reflectivity, plus
    /// the Fresnel reflection of a transmissive one) and the refracted ray's direction and
    /// weight (none under total internal reflection, or where the dielectric is rough and
    /// sampled instead), each possibly chosen by Russian roulette; the interface's event is
    /// recorded on node `id`.
    // The hit, its roughness, the throughput and depth the roulettes read, plus the node, recorder and counts.
    #[allow(clippy::too_many_arguments)]
    // Always: it is called once per hit from the recursion, which LLVM does not inline into on
    // its own (measured: 0.8% more instructions on the classic scene with the hint alone).
    #[inline(always)]
    fn split<R: Recorder>(
        &self,
        si: &SurfaceInteraction,
        rough: bool,
        throughput: Rgb,
        depth: u32,
        id: Option<NodeId>,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Split {
        let m = si.material;
        let rough_dielectric = rough && m.is_transmissive() && super::glossy::refracts(si);
        let mut reflect_w = if rough {
            Rgb::ZERO
        } else {
            mirror_weight(m, si.cos_i)
        };
        let mut refraction = None;
        // Dielectric split (only where the material transmits).
        if self.core.plan.refraction && m.is_transmissive() && !rough_dielectric {
            let (mut event, dir) = self.core.interface(si, si.ns, si.cos_i);
            if let Some(eta) = m.thin {
                // A thin sheet: the index-matched interface passes the ray straight on, with
                // the sheet's total Fresnel instead (recorded as the event's fractions).
                event.fresnel = thin_fresnel(event.fresnel.model, si.cos_i, eta);
            }
            let f = event.fresnel;
            reflect_w += m.transmissivity * f.r;
            if let Some(dir) = dir {
                refraction = Some((dir, m.transmissivity * f.t));
            }
            let mut choice = None;
            // Russian roulette instead of the split: from a depth, or below a weight.
            let scene = self.core.scene;
            if let Some((dir, t)) = refraction
                && (scene
                    .settings
                    .whitted
                    .dielectric_roulette
                    .is_some_and(|from| depth >= from)
                    || throughput.max_element() < self.roulette_below)
            {
                let u = super::roulette::choice(scene.settings.seed, si.p, -si.wo);
                let (r, t, c) = super::roulette::decide(reflect_w, t, u);
                reflect_w = r;
                refraction = Some((dir, t));
                counts.roulette += u64::from(c.is_some());
                choice = c;
            }
            rec.update(id, |node| {
                node.interface = Some(Interface {
                    roulette: choice,
                    ..event
                });
            });
        }
        Split {
            reflect_w,
            refraction,
        }
    }

    /// The mirror and refracted rays of a smooth split (`d` the incoming direction), each
    /// traced into `acc` where its weight is above zero.
    // The accumulator, the hit, the incoming direction, the split and the spawn template and path state, plus the sampler, recorder and counts.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn children<R: Recorder, S: PixelSampler>(
        &self,
        acc: &mut Secondary,
        si: &SurfaceInteraction,
        d: DVec3,
        split: Split,
        at: Spawn,
        state: PathState,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        let (hit_object, m) = (si.from().object, si.material);
        if split.reflect_w.max_element() > 0.0 {
            let spawn = Spawn {
                weight: split.reflect_w,
                ..at
            };
            self.secondary(
                acc,
                spawn,
                reflect(d, si.ns),
                si.n,
                state,
                sampler,
                rec,
                counts,
            );
        }
        if let Some((dir, weight)) = split.refraction.filter(|r| r.1.max_element() > 0.0) {
            let media = if si.entering {
                state
                    .media
                    .entered(hit_object, m.ior.unwrap_or(state.media.ior()))
            } else {
                state.media.left(hit_object)
            };
            let spawn = Spawn {
                kind: RayKind::Refracted,
                weight,
                ..at
            };
            let state = PathState {
                media: &media,
                ..state
            };
            self.secondary(acc, spawn, dir, -si.n, state, sampler, rec, counts);
        }
    }

    /// Trace one secondary ray (or record why it was cut) and add its weighted radiance;
    /// `state` is the parent's, with the throughput at its hit and the child's media. The
    /// child's node, unless cut.
    // The accumulator, the ray to spawn (origin, direction, side) and the path state, plus the sampler, recorder and counts every tracing function threads.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn secondary<R: Recorder, S: PixelSampler>(
        &self,
        acc: &mut Secondary,
        spawn: Spawn,
        dir: DVec3,
        side: DVec3,
        state: PathState,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<NodeId> {
        let depth = state.depth;
        let child_throughput = state.throughput * spawn.weight;
        // Below a glossy split of n samples, one sample's estimate has n times the throughput.
        let estimate = match state.glossy {
            None => child_throughput,
            Some(n) => child_throughput * f64::from(n),
        };
        let cut = if depth >= self.core.scene.settings.max_depth {
            Some(EndReason::MaxDepth)
        } else if estimate.max_element() < self.min_weight {
            Some(EndReason::MinWeight)
        } else if counts.total() >= state.ray_limit {
            counts.budget_cuts += 1;
            Some(EndReason::RayBudget)
        } else {
            None
        };
        if let Some(reason) = cut {
            acc.truncated += spawn.weight;
            if acc.end != EndReason::MaxDepth {
                acc.end = reason;
            }
            return None;
        }
        if acc.end == EndReason::Surface {
            acc.end = EndReason::Continued;
        }
        let from = spawn.from.expect("secondary rays leave a surface");
        let ray = self.core.spawn_ray(from, spawn.point, side, dir);
        let state = PathState {
            depth: depth + 1,
            throughput: child_throughput,
            ..state
        };
        let (l, id) = self.trace_ray(ray, None, spawn, state, sampler, rec, counts);
        acc.total += spawn.weight * l;
        id
    }
}

/// A thin sheet's reflected and transmitted fractions at cosine `cos_i`: `R' = 2R / (1 + R)`
/// of the exact `R` whatever `settings.fresnel` (as Mitsuba's `thindielectric`), recorded with
/// `rs = rp = R'` (the sheet's unpolarised total).
fn thin_fresnel(model: crate::math::FresnelModel, cos_i: f64, eta: f64) -> crate::math::Fresnel {
    let r = crate::bsdf::thin_reflectance(cos_i.abs(), eta);
    crate::math::Fresnel {
        model,
        rs: r,
        rp: r,
        r,
        t: 1.0 - r,
    }
}

/// A smooth split: the mirror ray's weight and the refracted ray's direction and weight.
#[derive(Clone, Copy)]
struct Split {
    reflect_w: Rgb,
    refraction: Option<(DVec3, Rgb)>,
}

/// The smooth mirror ray's weight: `reflectivity`, times the conductor Fresnel per channel for
/// a conductor or the coating's dielectric Fresnel for a coated material (so the reflected node's recorded `weight` is `scale * F(cos_i)`; no node field
/// is added, which would grow every recorded node and the memory-derived ray budgets).
fn mirror_weight(m: &crate::scene::Material, cos_i: f64) -> Rgb {
    match (m.conductor, m.coating) {
        (Some(ior), _) => m.reflectivity * ior.fresnel(cos_i),
        (None, Some(c)) => m.reflectivity * crate::bsdf::fr_dielectric(cos_i.abs(), c.eta),
        (None, None) => m.reflectivity,
    }
}
