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
//! background. The recorder sees one node per ray with [`crate::tree::PathInfo`].

mod lights;
mod nee;

use lights::LightTable;

use nee::{event, transmits};

use super::{RayCounts, Recorder, Tracer};
use crate::bsdf::{Bsdf, LobeKind};
use crate::bvh::TraversalCost;
use crate::effects::EffectPlan;
use crate::math::{Ray, Rgb, beer};
use crate::media::MediaStack;
use crate::sampling::PixelSampler;
use crate::scene::{Film, Material, Scene};
use crate::tree::{
    Attenuation, DeltaTag, EndReason, HitInfo, NodeId, PathInfo, Pdf, RayKind, RayNode, Roulette,
};
use glam::{DVec2, DVec3};

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

/// The GGX roughness of `m`'s reflection and transmission lobes.
fn material_roughness(m: &Material) -> f64 {
    m.roughness
}

/// The path integrator (`settings.integrator: "path"`).
#[derive(Clone, Debug)]
pub struct PathTracer<'a> {
    /// The Whitted tracer's machinery: surface interactions, offsets, shadow rays, diagnostics.
    tracer: Tracer<'a>,
    strategy: PathStrategy,
    /// Lights that light sampling chooses among, in proportion to power: the scene's point and
    /// directional lights, then every emissive sphere, quad, triangle and mesh
    /// ([`Scene::area_light`]); built once here.
    lights: LightTable<'a>,
}

/// The scattering event that spawned the current ray, for the MIS weight of the emission it
/// finds.
#[derive(Clone, Copy, Debug)]
struct Prev {
    p: DVec3,
    object: usize,
    triangle: Option<u32>,
    pdf: f64,
    delta: bool,
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
            tracer: Tracer::with_plan(scene, plan),
            strategy,
            lights: LightTable::new(scene),
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
        self.tracer.scene()
    }

    /// The camera's image plane.
    #[must_use]
    pub fn film(&self) -> &Film<'a> {
        self.tracer.film()
    }

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
                let from = (p.object, p.triangle);
                self.tracer
                    .diagnose(&ray, spawn_point, from, hit, id, rec, counts);
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
            let si = self.tracer.surface(&ray, &hit, &media);
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
            ray = self
                .tracer
                .spawn_ray((hit.object, hit.triangle), p, side, bs.wi);
            spawn_point = p;
            prev = Some(Prev {
                p,
                object: hit.object,
                triangle: hit.triangle,
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
