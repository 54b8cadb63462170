//! The path loop ([`PathTracer::trace_camera`]): from a camera ray, at every hit the emission
//! of the outer side (MIS-weighted), one light sample (`super::nee`), Russian roulette and one
//! continuation sampled from the BSDF, until the path misses, is absorbed, ends by roulette,
//! max depth or the ray budget; then, when recording, each node's radiance filled back from
//! the end of the path.

use super::nee::{event, transmits};
use super::{PathStrategy, PathTracer, Prev};
use crate::bsdf::{Bsdf, LobeKind};
use crate::bvh::TraversalCost;
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::SurfaceId;
use crate::math::{Ray, Rgb, beer};
use crate::media::MediaStack;
use crate::sampling::PixelSampler;
use crate::scene::Material;
use crate::tree::{
    Attenuation, DeltaTag, EndReason, HitInfo, NodeId, PathInfo, Pdf, RayKind, RayNode, Roulette,
};
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

impl PathTracer<'_> {
    /// The radiance of one path sample along camera `ray`; random numbers from `sampler`
    /// (already started at this camera sample). The sum of the contributions, in the order the
    /// recorder sees them.
    #[allow(clippy::too_many_lines)]
    pub fn trace_camera<R: Recorder, S: PixelSampler>(
        &self,
        camera: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let scene = self.scene();
        let settings = &scene.settings;
        let ray_limit = counts.total().saturating_add(settings.max_rays);
        let cuts = counts.budget_cuts;
        let mut l = Rgb::ZERO;
        let mut beta = Rgb::ONE;
        let mut media = MediaStack::AIR;
        let mut ray = camera;
        let mut spawn_point = camera.origin;
        let mut kind = RayKind::Camera;
        let mut parent: Option<NodeId> = None;
        let mut root = None;
        let mut weight = Rgb::ONE;
        let mut prev: Option<Prev> = None;
        let mut sampled: (Option<LobeKind>, Option<Pdf>, Option<Rgb>) = (None, None, None);
        let mut lpe = String::new();
        let mut chain: Vec<Link> = Vec::new();
        let mut depth = 0u32;
        // One BSDF for the whole path, reset in place at each hit (no 300-byte copy per hit).
        let mut bsdf = Bsdf::EMPTY;
        loop {
            counts.add_kind(kind);
            if R::PATHS {
                lpe.push_str(match sampled.0 {
                    None => "C",
                    Some(k) => event(k),
                });
            }
            let id = rec.push(parent, || {
                let mut n = RayNode::new(kind, depth, spawn_point, ray.origin, ray.direction);
                n.t_min = ray.t_min;
                n.weight = weight;
                n.throughput = beta;
                n.path = Some(PathInfo {
                    lobe: sampled.0,
                    pdf: sampled.1,
                    bsdf_cos_pdf: sampled.2,
                    mis_weight: None,
                    roulette: None,
                    contribution: Rgb::ZERO,
                    lpe: lpe.clone(),
                });
                n
            });
            root = root.or(id);
            let mut cost = TraversalCost::default();
            let hit = scene.intersect_counted(&ray, f64::INFINITY, &mut cost);
            rec.update(id, |n| n.traversal = cost);
            if R::DIAGNOSE
                && let Some(p) = prev
            {
                self.core
                    .diagnose((&ray, spawn_point, p.from), hit, id, rec, counts);
            }
            // Beer's law on this segment (from the true spawn point, as Whitted).
            let mut atten = Rgb::ONE;
            if let Some(medium) = media.top() {
                let object = medium.object as usize;
                let absorption = scene.material_of(object).absorption;
                if absorption != Rgb::ZERO {
                    let distance =
                        hit.map_or(f64::INFINITY, |h| (ray.at(h.t) - spawn_point).length());
                    atten = beer(absorption, distance);
                    beta *= atten;
                    rec.update(id, |n| {
                        n.attenuation = Some(Attenuation {
                            medium: object,
                            distance,
                            absorption,
                            factor: atten,
                        });
                    });
                }
            }
            let mut link = Link {
                id,
                atten,
                local: Rgb::ZERO,
                next: Rgb::ZERO,
            };
            let Some(hit) = hit else {
                // An escaping ray sees the background (not sampled by light sampling: weight 1).
                let c = beta * scene.background;
                l += c;
                if R::PATHS {
                    rec.contribution(&lpe, "", 'B', c);
                    rec.path_end(depth + 1, EndReason::Miss);
                }
                link.local = scene.background;
                rec.update(id, |n| {
                    n.end = EndReason::Miss;
                    if let Some(p) = n.path.as_mut() {
                        p.contribution = c;
                        p.mis_weight = Some(1.0);
                        p.lpe.push('B');
                    }
                });
                if R::RECORDS {
                    chain.push(link);
                }
                break;
            };
            let si = self.core.surface(&ray, &hit, &media);
            let m = si.material;
            rec.update(id, |n| {
                n.hit = Some(HitInfo {
                    t: hit.t,
                    point: si.p,
                    normal: hit.normal,
                    object: hit.object,
                    object_name: scene.objects[hit.object].name.clone(),
                    material: m.name.clone(),
                    entering: si.entering,
                    cos_i: si.cos_i,
                    triangle: scene.source_triangle(&hit),
                    shading_normal: si.smooth.map(|_| si.outward_shading_normal()),
                });
            });
            // Emission of the outer side, weighted against the light sample that could have
            // found it.
            if si.entering && m.emission != Rgb::ZERO {
                let w = self.emission_weight(prev, hit.object, ray.direction);
                let emitted = m.emission * w;
                let c = beta * emitted;
                l += c;
                if R::PATHS {
                    rec.contribution(&lpe, "", 'L', c);
                }
                link.local = emitted;
                rec.update(id, |n| {
                    n.emitted = emitted;
                    if let Some(p) = n.path.as_mut() {
                        p.contribution = c;
                        p.mis_weight = Some(w);
                        p.lpe.push('L');
                    }
                });
            }
            let end = |reason: EndReason, rec: &mut R, link: &Link| {
                if R::PATHS && reason != EndReason::Continued {
                    rec.path_end(depth + 1, reason);
                }
                rec.update(id, |n| {
                    n.end = reason;
                    n.local = link.local;
                });
            };
            if depth > settings.max_depth {
                end(EndReason::MaxDepth, rec, &link);
                if R::RECORDS {
                    chain.push(link);
                }
                break;
            }
            bsdf.reset_at(&si, material_roughness(m));
            if bsdf.lobes().next().is_none() {
                end(EndReason::Surface, rec, &link);
                if R::RECORDS {
                    chain.push(link);
                }
                break;
            }
            if self.strategy != PathStrategy::BsdfOnly && !bsdf.is_delta() {
                let (c, local) =
                    self.nee(&si, &bsdf, beta, (id, depth), &lpe, sampler, rec, counts);
                l += c;
                link.local += local;
            }
            if counts.total() >= ray_limit {
                counts.budget_cuts += 1;
                end(EndReason::RayBudget, rec, &link);
                if R::RECORDS {
                    chain.push(link);
                }
                break;
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
                end(EndReason::Absorbed, rec, &link);
                if R::RECORDS {
                    chain.push(link);
                }
                break;
            };
            let f_cos_pdf = bs.weight(bs.wi.dot(si.ns));
            let mut w = f_cos_pdf;
            // Russian roulette from bounce rr_depth on (this is bounce depth + 1).
            if depth + 1 >= settings.rr_depth {
                let q = (beta * w).max_element().min(1.0);
                let survived = sampler.next_1d() < q;
                rec.update(id, |n| {
                    if let Some(p) = n.path.as_mut() {
                        p.roulette = Some(Roulette {
                            probability: q,
                            survived,
                        });
                    }
                });
                if !survived {
                    end(EndReason::RussianRoulette, rec, &link);
                    if R::RECORDS {
                        chain.push(link);
                    }
                    break;
                }
                w /= q;
            }
            if w == Rgb::ZERO {
                end(EndReason::Absorbed, rec, &link);
                if R::RECORDS {
                    chain.push(link);
                }
                break;
            }
            end(EndReason::Continued, rec, &link);
            beta *= w;
            link.next = w;
            let (p, n, entering) = (si.p, si.n, si.entering);
            if transmits(bs.kind) {
                media = if entering {
                    media.entered(hit.object, m.ior.unwrap_or(media.ior()))
                } else {
                    media.left(hit.object)
                };
            }
            let side = if bs.wi.dot(n) < 0.0 { -n } else { n };
            let from = SurfaceId {
                object: hit.object,
                triangle: hit.triangle,
            };
            ray = self.core.spawn_ray(from, p, side, bs.wi);
            spawn_point = p;
            prev = Some(Prev {
                p,
                from,
                pdf: bs.pdf,
                delta: bs.delta,
            });
            kind = match bs.kind {
                LobeKind::Diffuse => RayKind::Diffuse,
                LobeKind::SpecularReflection | LobeKind::GlossyReflection => RayKind::Reflected,
                LobeKind::SpecularTransmission | LobeKind::GlossyTransmission => RayKind::Refracted,
            };
            let pdf = if bs.delta {
                Pdf::Delta(DeltaTag::Delta)
            } else {
                Pdf::Density(bs.pdf)
            };
            sampled = (Some(bs.kind), Some(pdf), Some(f_cos_pdf));
            weight = w;
            parent = id;
            if R::RECORDS {
                chain.push(link);
            }
            depth += 1;
        }
        counts.budget_samples += u64::from(counts.budget_cuts > cuts);
        if R::RECORDS {
            // Each ray's radiance: attenuation x (local + next weight x the next ray's), so the
            // tree reads as Whitted's (analysis::invariants).
            let mut after = Rgb::ZERO;
            for link in chain.iter().rev() {
                after = link.atten * (link.local + link.next * after);
                rec.update(link.id, |n| n.radiance = after);
            }
        }
        (l, root)
    }
}
