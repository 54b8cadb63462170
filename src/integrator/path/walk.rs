//! The path loop ([`PathTracer::trace_camera`]): from a camera ray, at every hit the emission
//! of the outer side (MIS-weighted), one light sample (`super::nee`), Russian roulette and one
//! continuation sampled from the BSDF, until the path misses, is absorbed, ends by roulette,
//! max depth or the ray budget; then, when recording, each node's radiance filled back from
//! the end of the path.

use super::nee::{event, transmits};
use super::{PathStrategy, PathTracer, Prev};
use crate::bsdf::{Bsdf, BsdfSample, LobeKind};
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::{SurfaceId, SurfaceInteraction};
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use crate::sampling::PixelSampler;
use crate::scene::Hit;
use crate::scene::Material;
use crate::tree::{DeltaTag, EndReason, NodeId, PathInfo, Pdf, RayKind, RayNode};
use glam::DVec2;

/// The GGX roughness of `m`'s reflection and transmission lobes.
fn material_roughness(m: &Material) -> f64 {
    m.roughness
}

/// Per vertex, when recording: to fill each node's `radiance` back from the end of the path.
struct Link {
    id: Option<NodeId>,
    atten: Rgb,
    /// Local term (weighted emission plus the light sample), or the background of a miss.
    local: Rgb,
    /// The continuation's weight (zero when the path ended here).
    next: Rgb,
}

/// How the ray just sampled was made, recorded on its node: the lobe, its pdf and `f cos / pdf`.
type Sampled = (Option<LobeKind>, Option<Pdf>, Option<Rgb>);

/// One path as it is walked: what it carries, the ray being traced and how it was made.
struct Walk {
    /// The radiance gathered so far (the sum of the contributions, in the recorder's order).
    l: Rgb,
    /// Throughput.
    beta: Rgb,
    ray: Ray,
    spawn_point: glam::DVec3,
    kind: RayKind,
    parent: Option<NodeId>,
    /// The current ray's weight (its node's `weight`).
    weight: Rgb,
    /// The scattering event that spawned the current ray (`None` for the camera ray).
    prev: Option<Prev>,
    sampled: Sampled,
    /// The light path expression so far (recording only).
    lpe: String,
    /// One link per vertex (recording only).
    chain: Vec<Link>,
    depth: u32,
    /// No ray is spawned once `RayCounts::total` reaches this (the sample's budget).
    ray_limit: u64,
}

/// Where the next ray leaves: what [`PathTracer::spawn_next`] needs of the hit, copied out of
/// its surface interaction (which borrows the media stack the spawn changes).
struct Leaving<'h> {
    hit: &'h Hit,
    /// The hit point.
    p: glam::DVec3,
    /// Geometric normal on the incident side.
    n: glam::DVec3,
    entering: bool,
    /// The material's index of refraction.
    ior: Option<f64>,
}

/// A hit's vertex as the walk sees it: the ray's node, its link, and the hit.
struct Vertex<'h> {
    id: Option<NodeId>,
    link: Link,
    hit: &'h Hit,
}

impl PathTracer<'_> {
    /// The radiance of one path sample along camera `ray`; random numbers from `sampler`
    /// (already started at this camera sample). The sum of the contributions, in the order the
    /// recorder sees them.
    pub fn trace_camera<R: Recorder, S: PixelSampler>(
        &self,
        camera: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let cuts = counts.budget_cuts;
        let mut w = Walk {
            l: Rgb::ZERO,
            beta: Rgb::ONE,
            ray: camera,
            spawn_point: camera.origin,
            kind: RayKind::Camera,
            parent: None,
            weight: Rgb::ONE,
            prev: None,
            sampled: (None, None, None),
            lpe: String::new(),
            chain: Vec::new(),
            depth: 0,
            ray_limit: counts
                .total()
                .saturating_add(self.scene().settings.max_rays),
        };
        let mut root = None;
        let mut media = MediaStack::AIR;
        // One BSDF for the whole path, reset in place at each hit (no 300-byte copy per hit).
        let mut bsdf = Bsdf::EMPTY;
        loop {
            let id = self.push_ray(&mut w, rec, counts);
            root = root.or(id);
            let from = w.prev.map(|p| p.from);
            let seg = self.core.segment(
                (&w.ray, None),
                (w.spawn_point, from),
                &media,
                id,
                rec,
                counts,
            );
            // Only inside an absorbing medium (the same bits as multiplying by 1 elsewhere).
            if seg.atten != Rgb::ONE {
                w.beta *= seg.atten;
            }
            let link = Link {
                id,
                atten: seg.atten,
                local: Rgb::ZERO,
                next: Rgb::ZERO,
            };
            let Some(hit) = seg.hit else {
                self.miss(&mut w, link, rec);
                break;
            };
            let v = Vertex {
                id,
                link,
                hit: &hit,
            };
            if !self.scatter((&mut w, &mut media), v, &mut bsdf, sampler, rec, counts) {
                break;
            }
        }
        counts.budget_samples += u64::from(counts.budget_cuts > cuts);
        if R::RECORDS {
            // Each ray's radiance: attenuation x (local + next weight x the next ray's), so the
            // tree reads as Whitted's (analysis::invariants).
            let mut after = Rgb::ZERO;
            for link in w.chain.iter().rev() {
                after = link.atten * (link.local + link.next * after);
                rec.update(link.id, |n| n.radiance = after);
            }
        }
        (w.l, root)
    }

    /// Count and record the current ray (its node, with how it was sampled).
    #[inline(always)]
    fn push_ray<R: Recorder>(
        &self,
        w: &mut Walk,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<NodeId> {
        counts.add_kind(w.kind);
        if R::PATHS {
            w.lpe.push_str(match w.sampled.0 {
                None => "C",
                Some(k) => event(k),
            });
        }
        let w = &*w;
        rec.push(w.parent, || {
            let mut n = RayNode::new(
                w.kind,
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
                mis_weight: None,
                roulette: None,
                strategy: None,
                unweighted: None,
                contribution: Rgb::ZERO,
                lpe: w.lpe.clone(),
            });
            n
        })
    }

    /// An escaping ray sees the background (not sampled by light sampling: weight 1).
    #[inline(always)]
    fn miss<R: Recorder>(&self, w: &mut Walk, mut link: Link, rec: &mut R) {
        let background = self.scene().background;
        let c = w.beta * background;
        w.l += c;
        if R::PATHS {
            rec.contribution(&w.lpe, "", 'B', c);
            rec.path_end(w.depth + 1, EndReason::Miss);
        }
        link.local = background;
        rec.update(link.id, |n| {
            n.end = EndReason::Miss;
            if let Some(p) = n.path.as_mut() {
                p.contribution = c;
                p.mis_weight = Some(1.0);
                p.lpe.push('B');
            }
        });
        if R::RECORDS {
            w.chain.push(link);
        }
    }

    /// Everything at a hit: its record, the MIS-weighted emission, the light sample and the
    /// continuation (roulette, then a direction sampled from the BSDF, spawned as the next
    /// ray). False when the path ends here.
    #[inline(always)]
    fn scatter<R: Recorder, S: PixelSampler>(
        &self,
        (w, media): (&mut Walk, &mut MediaStack),
        v: Vertex,
        bsdf: &mut Bsdf,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> bool {
        let Vertex { id, mut link, hit } = v;
        let si = self.core.surface(&w.ray, hit, media);
        self.core.record_hit(&si, hit, id, rec);
        self.emission(w, &si, (hit.object, &mut link), rec);
        if w.depth > self.scene().settings.max_depth {
            return self.stop(w, link, EndReason::MaxDepth, rec);
        }
        bsdf.reset_at(&si, material_roughness(si.material));
        if bsdf.lobes().next().is_none() {
            return self.stop(w, link, EndReason::Surface, rec);
        }
        if self.strategy != PathStrategy::BsdfOnly && !bsdf.is_delta() {
            let at = (id, w.depth);
            let (c, local) = self.nee(&si, bsdf, w.beta, at, &w.lpe, sampler, rec, counts);
            w.l += c;
            link.local += local;
        }
        if counts.total() >= w.ray_limit {
            counts.budget_cuts += 1;
            return self.stop(w, link, EndReason::RayBudget, rec);
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let sample = bsdf.sample(si.wo, uc, DVec2::new(u.0, u.1));
        // A sampled direction must leave on the side its event says (a shading normal can
        // point a reflection under the geometric surface): otherwise the path ends.
        let sample = sample.filter(|s| {
            let below = s.wi.dot(si.n) < 0.0;
            below == transmits(s.kind) && s.value.is_finite()
        });
        let Some(bs) = sample else {
            return self.stop(w, link, EndReason::Absorbed, rec);
        };
        let f_cos_pdf = bs.weight(bs.wi.dot(si.ns));
        let Some(weight) = self.roulette(w, f_cos_pdf, id, sampler, rec) else {
            return self.stop(w, link, EndReason::RussianRoulette, rec);
        };
        if weight == Rgb::ZERO {
            return self.stop(w, link, EndReason::Absorbed, rec);
        }
        self.mark_end(w.depth, &link, EndReason::Continued, rec);
        w.beta *= weight;
        link.next = weight;
        let at = Leaving {
            hit,
            p: si.p,
            n: si.n,
            entering: si.entering,
            ior: si.material.ior,
        };
        self.spawn_next((w, media), &at, (&bs, f_cos_pdf, weight));
        w.parent = id;
        if R::RECORDS {
            w.chain.push(link);
        }
        w.depth += 1;
        true
    }

    /// Emission of the outer side of `object`, weighted against the light sample that could
    /// have found it: added to the path and to the vertex's local term.
    #[inline(always)]
    fn emission<R: Recorder>(
        &self,
        w: &mut Walk,
        si: &SurfaceInteraction,
        (object, link): (usize, &mut Link),
        rec: &mut R,
    ) {
        let m = si.material;
        if !(si.entering && m.emission != Rgb::ZERO) {
            return;
        }
        let mis = self.emission_weight(w.prev, object, w.ray.direction);
        let emitted = m.emission * mis;
        let c = w.beta * emitted;
        w.l += c;
        if R::PATHS {
            rec.contribution(&w.lpe, "", 'L', c);
        }
        link.local = emitted;
        rec.update(link.id, |n| {
            n.emitted = emitted;
            if let Some(p) = n.path.as_mut() {
                p.contribution = c;
                p.mis_weight = Some(mis);
                p.lpe.push('L');
            }
        });
    }

    /// Russian roulette from bounce `rr_depth` on (this is bounce `depth + 1`): the
    /// continuation's weight `f cos / pdf`, divided by the survival probability
    /// `min(1, max(beta x weight))` when it plays; `None` when the path does not survive.
    #[inline(always)]
    fn roulette<R: Recorder, S: PixelSampler>(
        &self,
        w: &Walk,
        f_cos_pdf: Rgb,
        id: Option<NodeId>,
        sampler: &mut S,
        rec: &mut R,
    ) -> Option<Rgb> {
        if w.depth + 1 >= self.scene().settings.path.rr_depth {
            super::russian_roulette(w.beta, f_cos_pdf, id, sampler, rec)
        } else {
            Some(f_cos_pdf)
        }
    }

    /// The next ray from the sampled direction `bs` where the path leaves `at` (`f_cos_pdf` and
    /// the weight after roulette recorded on it): through the media it enters or leaves,
    /// offset by the scene's strategy.
    #[inline(always)]
    fn spawn_next(
        &self,
        (w, media): (&mut Walk, &mut MediaStack),
        at: &Leaving,
        (bs, f_cos_pdf, weight): (&BsdfSample, Rgb, Rgb),
    ) {
        let Leaving {
            hit,
            p,
            n,
            entering,
            ior,
        } = *at;
        if transmits(bs.kind) {
            *media = media.crossed(hit.object, entering, ior);
        }
        let side = if bs.wi.dot(n) < 0.0 { -n } else { n };
        let from = SurfaceId {
            object: hit.object,
            triangle: hit.triangle,
        };
        w.ray = self.core.spawn_ray(from, p, side, bs.wi);
        w.spawn_point = p;
        w.prev = Some(Prev {
            p,
            from,
            pdf: bs.pdf,
            delta: bs.delta,
        });
        w.kind = match bs.kind {
            LobeKind::Diffuse => RayKind::Diffuse,
            LobeKind::SpecularReflection | LobeKind::GlossyReflection => RayKind::Reflected,
            LobeKind::SpecularTransmission | LobeKind::GlossyTransmission => RayKind::Refracted,
        };
        let pdf = if bs.delta {
            Pdf::Delta(DeltaTag::Delta)
        } else {
            Pdf::Density(bs.pdf)
        };
        w.sampled = (Some(bs.kind), Some(pdf), Some(f_cos_pdf));
        w.weight = weight;
    }

    /// Record why the path ends (or `Continued`) at the vertex of `link` and its local term.
    #[inline(always)]
    fn mark_end<R: Recorder>(&self, depth: u32, link: &Link, reason: EndReason, rec: &mut R) {
        if R::PATHS && reason != EndReason::Continued {
            rec.path_end(depth + 1, reason);
        }
        rec.update(link.id, |n| {
            n.end = reason;
            n.local = link.local;
        });
    }

    /// End the path at the vertex of `link` for `reason`: false, for the walk's loop.
    #[inline(always)]
    fn stop<R: Recorder>(&self, w: &mut Walk, link: Link, reason: EndReason, rec: &mut R) -> bool {
        self.mark_end(w.depth, &link, reason, rec);
        if R::RECORDS {
            w.chain.push(link);
        }
        false
    }
}
