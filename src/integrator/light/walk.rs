//! One light path ([`LightTracer::trace_light_path`]): from a light's emitted ray, at every
//! hit one connection to the camera (non-delta BSDFs only), then Russian roulette and one
//! continuation sampled from the BSDF, until the path misses, is absorbed, ends by roulette,
//! `max_depth` or the ray budget.

use super::{LightTracer, path_info};
use crate::bsdf::{Bsdf, BsdfSample, LobeKind};
use crate::integrator::offset::scaled_epsilon;
use crate::integrator::path::{event, russian_roulette, transmits};
use crate::integrator::shading::shadow_end;
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::{SurfaceId, SurfaceInteraction};
use crate::lights::EmittedRay;
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use crate::sampling::PixelSampler;
use crate::scene::Hit;
use crate::tree::{DeltaTag, EndReason, NodeId, PathInfo, Pdf, RayKind, RayNode};
use glam::{DVec2, DVec3};

/// A light-path vertex's contribution to a pixel: what the render adds to the pixel's splat
/// sum (before the division by `spp`).
#[derive(Clone, Debug, PartialEq)]
pub struct Splat {
    /// Film position in pixels.
    pub film: (f64, f64),
    /// The pixel it lands in.
    pub pixel: (u32, u32),
    /// `beta f |cos| importance / d^2`, unblocked (finite, not zero).
    pub contribution: Rgb,
    /// The connection's node, when recording.
    pub connection: Option<NodeId>,
    /// Vertices of the light subpath, the emitter's counted (`s` of the strategy (s, 1)).
    pub vertices: u32,
    /// The strategy's MIS weight (1 under light tracing; `contribution` is weighted).
    pub mis_weight: f64,
    /// The contribution before its MIS weight (`contribution` itself under light tracing).
    pub unweighted: Rgb,
    /// The light path expression read from the camera (recording only; empty otherwise).
    pub lpe: String,
}

/// How the ray just sampled was made: the lobe, its pdf and `f cos / pdf`.
type Sampled = (Option<LobeKind>, Option<Pdf>, Option<Rgb>);

/// Where the next ray leaves, copied out of the surface interaction (which borrows the media
/// stack the spawn changes).
struct Leaving {
    p: DVec3,
    /// Geometric normal on the incident side.
    n: DVec3,
    entering: bool,
    /// The material's index of refraction.
    ior: Option<f64>,
    from: SurfaceId,
}

/// One light path as it is walked.
struct LightWalk {
    /// Throughput: the flux the path carries.
    beta: Rgb,
    /// Throughput relative to the emitted flux (Russian roulette's measure, as under `path`).
    rel: Rgb,
    ray: Ray,
    spawn_point: DVec3,
    /// The surface the current ray left (`None` from a point or directional light).
    from: Option<SurfaceId>,
    parent: Option<NodeId>,
    /// The current ray's weight (its node's `weight`).
    weight: Rgb,
    sampled: Sampled,
    /// The events from the light so far (recording only).
    events: Vec<&'static str>,
    depth: u32,
    /// No ray is spawned once `RayCounts::total` reaches this.
    ray_limit: u64,
}

impl LightTracer<'_> {
    /// Light path `seed` (pixel x, y and sample s: it seeds the random numbers; the path starts
    /// on a light, anywhere), each camera connection handed to `splat` in the order made;
    /// recorded into `rec`. Returns the root node when recording.
    pub fn trace_light_path<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        let lights = &self.core.lights;
        if lights.is_empty() {
            return None;
        }
        sampler.start_sample((seed.0, seed.1), seed.2);
        let (_, light, p_light) = lights.choose(sampler.next_1d());
        let (a, b) = sampler.next_2d();
        let (c, d) = sampler.next_2d();
        let er = light.sample_le(DVec2::new(a, b), DVec2::new(c, d))?;
        let beta = er.weight() / p_light;
        if !(beta.is_finite() && beta.max_element() > 0.0) {
            return None;
        }
        let mut w = LightWalk {
            beta,
            rel: Rgb::ONE,
            ray: emitted_ray(self.scene(), &er),
            spawn_point: er.origin,
            from: light.object().map(|object| SurfaceId {
                object,
                triangle: None,
            }),
            parent: None,
            weight: beta,
            sampled: (None, None, None),
            events: Vec::new(),
            depth: 0,
            ray_limit: counts
                .total()
                .saturating_add(self.scene().settings.max_rays),
        };
        let mut root = None;
        let mut media = MediaStack::AIR;
        let mut bsdf = Bsdf::EMPTY;
        loop {
            let id = self.push_light_ray(&w, rec, counts);
            root = root.or(id);
            let seg = self.core.segment(
                (&w.ray, None),
                (w.spawn_point, w.from),
                &media,
                id,
                rec,
                counts,
            );
            if seg.atten != Rgb::ONE {
                w.beta *= seg.atten;
            }
            let Some(hit) = seg.hit else {
                end(id, EndReason::Miss, rec);
                break;
            };
            let at = (id, &hit);
            if !self.scatter(
                (&mut w, &mut media),
                at,
                &mut bsdf,
                sampler,
                rec,
                counts,
                splat,
            ) {
                break;
            }
        }
        root
    }

    /// Count and record the current ray of the light path.
    fn push_light_ray<R: Recorder>(
        &self,
        w: &LightWalk,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<NodeId> {
        counts.add_kind(RayKind::Light);
        rec.push(w.parent, || {
            let mut n = RayNode::new(
                RayKind::Light,
                w.depth,
                w.spawn_point,
                w.ray.origin,
                w.ray.direction,
            );
            n.t_min = w.ray.t_min;
            n.weight = w.weight;
            n.throughput = w.beta;
            n.path = Some(PathInfo {
                lobe: w.sampled.0,
                pdf: w.sampled.1,
                bsdf_cos_pdf: w.sampled.2,
                lpe: format!("L{}", w.events.concat()),
                ..path_info()
            });
            n
        })
    }

    /// Everything at a hit of the light path: its record, the connection to the camera, and
    /// the continuation (roulette, a direction sampled from the BSDF). False when the path
    /// ends here.
    // The walk and its media, the hit, the BSDF scratch, the sampler, recorder, counts and sink.
    #[allow(clippy::too_many_arguments)]
    fn scatter<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        (w, media): (&mut LightWalk, &mut MediaStack),
        (id, hit): (Option<NodeId>, &Hit),
        bsdf: &mut Bsdf,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> bool {
        let settings = &self.scene().settings;
        let si = self.core.surface(&w.ray, hit, media);
        self.core.record_hit(&si, hit, id, rec);
        bsdf.reset_at(&si, si.material.roughness);
        if bsdf.lobes().next().is_none() {
            return end(id, EndReason::Surface, rec);
        }
        if !bsdf.is_delta() {
            self.connect(w, (&si, bsdf), id, sampler, rec, counts, splat);
        }
        if w.depth >= settings.max_depth {
            return end(id, EndReason::MaxDepth, rec);
        }
        if counts.total() >= w.ray_limit {
            counts.budget_cuts += 1;
            return end(id, EndReason::RayBudget, rec);
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let sample = bsdf.sample(si.wo, uc, DVec2::new(u.0, u.1)).filter(|s| {
            let below = s.wi.dot(si.n) < 0.0;
            below == transmits(s.kind) && s.value.is_finite()
        });
        let Some(bs) = sample else {
            return end(id, EndReason::Absorbed, rec);
        };
        let f_cos_pdf = adjoint_weight(&si, &bs);
        let mut weight = f_cos_pdf;
        if w.depth + 1 >= settings.path.rr_depth {
            let Some(survived) = russian_roulette(w.rel, weight, id, sampler, rec) else {
                return end(id, EndReason::RussianRoulette, rec);
            };
            weight = survived;
        }
        if weight == Rgb::ZERO || !weight.is_finite() {
            return end(id, EndReason::Absorbed, rec);
        }
        end(id, EndReason::Continued, rec);
        w.beta *= weight;
        w.rel *= weight;
        let at = Leaving {
            p: si.p,
            n: si.n,
            entering: si.entering,
            ior: si.material.ior,
            from: si.from(),
        };
        self.spawn_next((w, media), &at, &bs, (f_cos_pdf, weight));
        w.parent = id;
        w.depth += 1;
        true
    }

    /// The next ray of the light path along the sampled `bs`, through the media it enters or
    /// leaves, offset by the scene's strategy.
    fn spawn_next(
        &self,
        (w, media): (&mut LightWalk, &mut MediaStack),
        at: &Leaving,
        bs: &BsdfSample,
        (f_cos_pdf, weight): (Rgb, Rgb),
    ) {
        if transmits(bs.kind) {
            *media = media.crossed(at.from.object, at.entering, at.ior);
        }
        let side = if bs.wi.dot(at.n) < 0.0 { -at.n } else { at.n };
        w.ray = self.core.spawn_ray(at.from, at.p, side, bs.wi);
        w.spawn_point = at.p;
        w.from = Some(at.from);
        let pdf = if bs.delta {
            Pdf::Delta(DeltaTag::Delta)
        } else {
            Pdf::Density(bs.pdf)
        };
        w.sampled = (Some(bs.kind), Some(pdf), Some(f_cos_pdf));
        w.weight = weight;
        w.events.push(event(bs.kind));
    }

    /// The connection of the light path's vertex `si` (BSDF `bsdf`, ray node `id`) to the
    /// camera: `beta f |cos| importance / d^2` through the lens point, splatted when the
    /// segment is unblocked. A thin lens draws its lens point from `sampler`.
    // The walk, the vertex, its node, the sampler, recorder, counts and sink.
    #[allow(clippy::too_many_arguments)]
    fn connect<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        w: &LightWalk,
        (si, bsdf): (&SurfaceInteraction, &Bsdf),
        id: Option<NodeId>,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) {
        let film = &self.core.film;
        let u = if film.has_lens() {
            let (a, b) = sampler.next_2d();
            DVec2::new(a, b)
        } else {
            DVec2::ZERO
        };
        let Some(c) = film.connect(si.p, u) else {
            return;
        };
        let wi = -c.direction;
        let f = bsdf.eval(si.wo, wi);
        let factor = f * (adjoint_cos(si, wi) * c.importance / (c.distance * c.distance));
        if factor == Rgb::ZERO || !factor.is_finite() {
            return;
        }
        let side = if wi.dot(si.n) < 0.0 { -si.n } else { si.n };
        let from = si.from();
        let strategy = self.scene().settings.offset.strategy;
        let (ray, seg) = self
            .core
            .shadow_ray(strategy, (from, si.p, side), wi, c.distance);
        counts.add_kind(RayKind::Connection);
        let cid = rec.push(id, || {
            let mut n = RayNode::new(RayKind::Connection, w.depth, si.p, ray.origin, wi);
            n.t_min = ray.t_min;
            n.weight = factor;
            n.throughput = w.beta;
            n
        });
        let cast = self.core.cast((&ray, seg), (si.p, from), cid, rec, counts);
        let contribution = w.beta * factor * cast.transmittance;
        let reflects = wi.dot(si.n) > 0.0;
        let lpe = if R::RECORDS {
            camera_lpe(connection_event(bsdf, reflects), &w.events)
        } else {
            String::new()
        };
        rec.update(cid, |n| {
            n.traversal = cast.cost;
            n.radiance = cast.transmittance;
            n.end = shadow_end(cast.transmittance);
            n.path = Some(PathInfo {
                bsdf_cos_pdf: Some(f * adjoint_cos(si, wi)),
                mis_weight: Some(1.0),
                contribution,
                lpe: lpe.clone(),
                ..path_info()
            });
        });
        if contribution == Rgb::ZERO {
            return;
        }
        if !contribution.is_finite() {
            counts.dropped_samples += 1;
            return;
        }
        splat(Splat {
            film: c.film,
            pixel: c.pixel(),
            contribution,
            connection: cid,
            vertices: w.depth + 2,
            mis_weight: 1.0,
            unweighted: contribution,
            lpe,
        });
    }
}

/// The ray `er` leaves its light along, off an area light's surface by the scene's epsilon
/// scaled to the point (the emitter's own triangle is not known for a mesh, so no other offset
/// applies); shared by light tracing and BDPT's light subpaths.
pub(crate) fn emitted_ray(scene: &crate::scene::Scene, er: &EmittedRay) -> Ray {
    match er.normal {
        Some(n) => {
            let eps = scaled_epsilon(scene.settings.offset.epsilon, er.origin);
            Ray::new(er.origin + eps * n, er.direction, 0.0)
        }
        None => Ray::new(er.origin, er.direction, 0.0),
    }
}

/// Record why the light path ends (or `Continued`) at the vertex of node `id`: false, for the
/// walk's loop.
fn end<R: Recorder>(id: Option<NodeId>, reason: EndReason, rec: &mut R) -> bool {
    rec.update(id, |n| n.end = reason);
    false
}

/// The cosine importance transport weighs direction `wi` with at `si`: `|wi.ns|`, or with a
/// shading normal Veach's adjoint form `|wo.ns| |wi.ng| / |wo.ng|` (1997, section 5.3, eq.
/// 5.17; pbrt-v3 `CorrectShadingNormal`), `wo` the direction back along the light path.
fn adjoint_cos(si: &SurfaceInteraction, wi: DVec3) -> f64 {
    if si.smooth.is_none() {
        return wi.dot(si.ns).abs();
    }
    let d = si.wo.dot(si.n).abs();
    if d == 0.0 {
        0.0
    } else {
        si.wo.dot(si.ns).abs() * wi.dot(si.n).abs() / d
    }
}

/// The light path's continuation weight `f |cos| / pdf` with [`adjoint_cos`].
pub(crate) fn adjoint_weight(si: &SurfaceInteraction, bs: &BsdfSample) -> Rgb {
    if bs.pdf > 0.0 {
        bs.value * (adjoint_cos(si, bs.wi) / bs.pdf)
    } else {
        Rgb::ZERO
    }
}

/// The event of a connection through `bsdf`'s non-delta lobes: diffuse reflection when it has
/// a diffuse lobe (Lambert or a plastic's base) and the camera is on the light's side, otherwise glossy reflection or
/// transmission.
pub(crate) fn connection_event(bsdf: &Bsdf, reflects: bool) -> &'static str {
    let lambert = bsdf.lobes().any(|(l, _)| l.is_diffuse());
    match (reflects, lambert) {
        (true, true) => "<RD>",
        (true, false) => "<RG>",
        (false, _) => "<TG>",
    }
}

/// The light path expression read from the camera: `C`, the connection's event, the light
/// path's events from the last to the first, `L`.
fn camera_lpe(last: &str, events: &[&str]) -> String {
    let mut s = String::from("C");
    s.push_str(last);
    for e in events.iter().rev() {
        s.push_str(e);
    }
    s.push('L');
    s
}

#[cfg(test)]
mod tests {
    use super::camera_lpe;

    #[test]
    fn the_light_path_expression_reads_from_the_camera() {
        assert_eq!(camera_lpe("<RD>", &["<TS>", "<TS>"]), "C<RD><TS><TS>L");
        assert_eq!(camera_lpe("<RD>", &[]), "C<RD>L");
    }
}
