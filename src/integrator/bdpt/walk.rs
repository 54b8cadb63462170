//! The two subpaths of a bidirectional sample (pbrt-v3 `GenerateCameraSubpath`,
//! `GenerateLightSubpath`, `RandomWalk`): each vertex with its throughput and its forward and
//! reverse area densities, recorded ray by ray.

use super::Bdpt;
use super::vertex::{Kind, Vertex};
use crate::bsdf::{Bsdf, BsdfSample, LobeKind};
use crate::integrator::light::{adjoint_weight, emitted_ray};
use crate::integrator::path::{event, russian_roulette, transmits};
use crate::integrator::{RayCounts, Recorder};
use crate::interaction::{SurfaceId, SurfaceInteraction};
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use crate::sampling::PixelSampler;
use crate::tree::{DeltaTag, EndReason, NodeId, PathInfo, Pdf, RayKind, RayNode};
use glam::{DVec2, DVec3};

/// Where a walk starts: its first ray, throughput and direction density, the node it hangs
/// under, and whether it carries importance (a light subpath).
pub(super) struct Start {
    pub ray: Ray,
    pub beta: Rgb,
    pub pdf_dir: f64,
    pub parent: Option<NodeId>,
    pub importance: bool,
    /// The surface the first ray leaves (an area light's object).
    pub from: Option<SurfaceId>,
}

/// The state of a walk between hits.
struct Step {
    ray: Ray,
    spawn_point: DVec3,
    from: Option<SurfaceId>,
    kind: RayKind,
    parent: Option<NodeId>,
    beta: Rgb,
    /// Throughput relative to the start (Russian roulette's measure).
    rel: Rgb,
    weight: Rgb,
    pdf_fwd: f64,
    sampled: (Option<LobeKind>, Option<Pdf>, Option<Rgb>),
    lpe: String,
    depth: u32,
    /// Whether the walk carries importance (a light subpath).
    importance: bool,
}

impl Step {
    /// The state before the first ray of a walk from `start`.
    fn first(start: &Start) -> Self {
        let importance = start.importance;
        Self {
            ray: start.ray,
            spawn_point: start.ray.origin,
            from: start.from,
            kind: if importance {
                RayKind::Light
            } else {
                RayKind::Camera
            },
            parent: start.parent,
            beta: start.beta,
            rel: Rgb::ONE,
            weight: start.beta,
            pdf_fwd: start.pdf_dir,
            sampled: (None, None, None),
            lpe: String::from(if importance { "L" } else { "C" }),
            depth: 0,
            importance,
        }
    }
}

impl Bdpt<'_> {
    /// The camera subpath of camera ray `ray`: the lens vertex, then at most `max_depth + 2`
    /// surface vertices (`s = 0` strategies reach `max_depth + 1` scattering vertices). Returns
    /// the background the path escaped to (its throughput times the background; weight 1: no
    /// light subpath starts on the background) and the camera ray's node.
    pub(super) fn camera_subpath<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        path: &mut Vec<Vertex>,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let mut camera = Vertex::at(Kind::Camera, ray.origin);
        camera.beta = Rgb::ONE;
        path.push(camera);
        let start = Start {
            ray,
            beta: Rgb::ONE,
            pdf_dir: self.core.film.pdf_dir(ray.origin, ray.direction),
            parent: None,
            importance: false,
            from: None,
        };
        let max = self.scene().settings.max_depth as usize + 3;
        self.random_walk(start, max, path, sampler, rec, counts)
    }

    /// The light subpath of one sample: a light chosen by power, its emitted ray, then at most
    /// `max_depth + 1` surface vertices (`t = 1` strategies reach `max_depth + 1` scattering
    /// vertices), its first ray recorded under `parent`.
    pub(super) fn light_subpath<R: Recorder, S: PixelSampler>(
        &self,
        parent: Option<NodeId>,
        path: &mut Vec<Vertex>,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<NodeId> {
        let lights = &self.core.lights;
        if lights.is_empty() {
            return None;
        }
        let (index, light, p_choose) = lights.choose(sampler.next_1d());
        let (a, b) = sampler.next_2d();
        let (c, d) = sampler.next_2d();
        let er = light.sample_le(DVec2::new(a, b), DVec2::new(c, d))?;
        let pdf0 = er.pdf_pos * p_choose;
        let beta = er.weight() / p_choose;
        if !(pdf0 > 0.0 && beta.is_finite() && beta.max_element() > 0.0) {
            return None;
        }
        let mut v = Vertex::at(Kind::Light { index }, er.origin);
        v.ng = er.normal.unwrap_or(DVec3::ZERO);
        v.ns = v.ng;
        v.le = er.le;
        v.beta = er.le / pdf0;
        v.pdf_fwd = pdf0;
        v.delta_light = er.delta_pos || er.delta_dir;
        v.infinite = er.delta_dir;
        path.push(v);
        let ray = emitted_ray(self.scene(), &er);
        let start = Start {
            ray,
            beta,
            pdf_dir: er.pdf_dir,
            parent,
            importance: true,
            from: light.object().map(|object| SurfaceId {
                object,
                triangle: None,
            }),
        };
        let max = self.scene().settings.max_depth as usize + 2;
        let (_, root) = self.random_walk(start, max, path, sampler, rec, counts);
        // A directional light's first hit is placed by its disc (per unit area there, times the
        // cosine); the light's own direction is a delta.
        if path[0].infinite {
            if let Some(v1) = path.get_mut(1) {
                let cos = if v1.on_surface() {
                    v1.ng.dot(er.direction).abs()
                } else {
                    1.0
                };
                v1.pdf_fwd = er.pdf_pos * cos;
            }
            path[0].pdf_fwd = 0.0;
        }
        root
    }

    /// Extend `path` (its endpoint vertex already in it) from `start` until it has `max`
    /// vertices, misses, is absorbed, ends by roulette or the ray budget. Returns the
    /// background seen by an escaping camera subpath, and the first ray's node.
    fn random_walk<R: Recorder, S: PixelSampler>(
        &self,
        start: Start,
        max: usize,
        path: &mut Vec<Vertex>,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let ray_limit = counts
            .total()
            .saturating_add(self.scene().settings.max_rays);
        let mut w = Step::first(&start);
        let mut media = MediaStack::AIR;
        let mut bsdf = Bsdf::EMPTY;
        let mut root = None;
        loop {
            let id = self.push_ray(&w, rec, counts);
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
                return (self.escape(&w, path.len(), id, rec), root);
            };
            let si = self.core.surface(&w.ray, &hit, &media);
            self.core.record_hit(&si, &hit, id, rec);
            bsdf.reset_at(&si, si.material.roughness);
            let Some(prev) = path.last() else {
                return (Rgb::ZERO, root);
            };
            let v = surface_vertex(&si, &w, bsdf, id);
            let v = Vertex {
                pdf_fwd: prev.convert_density(w.pdf_fwd, &v),
                ..v
            };
            path.push(v);
            let ended = if path.len() >= max {
                Some(EndReason::MaxDepth)
            } else if bsdf.lobes().next().is_none() {
                Some(EndReason::Surface)
            } else if counts.total() >= ray_limit {
                counts.budget_cuts += 1;
                Some(EndReason::RayBudget)
            } else {
                None
            };
            if let Some(reason) = ended {
                end(rec, id, reason);
                return (Rgb::ZERO, root);
            }
            let Some(next) = self.scatter(&si, &bsdf, &w, path.len(), sampler, id, rec) else {
                return (Rgb::ZERO, root);
            };
            end(rec, id, EndReason::Continued);
            let crossing = transmits(next.bs.kind).then_some((si.entering, si.material.ior));
            self.advance::<R>(&mut w, path, &si, &bsdf, next, id);
            if let Some((entering, ior)) = crossing {
                media = media.crossed(hit.object, entering, ior);
            }
        }
    }

    /// What an escaping ray sees: nothing for a light subpath; for a camera subpath the
    /// background through its throughput, recorded as the `s = 0` strategy's contribution
    /// (weight 1: no light subpath starts on the background).
    fn escape<R: Recorder>(
        &self,
        w: &Step,
        vertices: usize,
        id: Option<NodeId>,
        rec: &mut R,
    ) -> Rgb {
        rec.update(id, |n| n.end = EndReason::Miss);
        if w.importance {
            return Rgb::ZERO;
        }
        let c = w.beta * self.scene().background;
        rec.update(id, |n| {
            if let Some(p) = n.path.as_mut() {
                p.contribution = c;
                p.mis_weight = Some(1.0);
                p.strategy = Some([0, vertices as u32 + 1]);
                p.lpe.push('B');
            }
        });
        c
    }

    /// The BSDF sample that continues the walk from the vertex at `si` (the `vertices`-th),
    /// after Russian roulette from `rr_depth` on; `None` (its end recorded on node `id`) when
    /// the sample fails, lands on the wrong side, or roulette or a zero weight ends the walk.
    // The hit, its BSDF and the walk's state and length, plus the sampler, node and recorder.
    #[allow(clippy::too_many_arguments)]
    fn scatter<R: Recorder, S: PixelSampler>(
        &self,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        w: &Step,
        vertices: usize,
        sampler: &mut S,
        id: Option<NodeId>,
        rec: &mut R,
    ) -> Option<Scatter> {
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let sample = bsdf.sample(si.wo, uc, DVec2::new(u.0, u.1)).filter(|s| {
            let below = s.wi.dot(si.n) < 0.0;
            below == transmits(s.kind) && s.value.is_finite()
        });
        let Some(bs) = sample else {
            end(rec, id, EndReason::Absorbed);
            return None;
        };
        let f_cos_pdf = if w.importance {
            adjoint_weight(si, &bs)
        } else {
            bs.weight(bs.wi.dot(si.ns))
        };
        let mut weight = f_cos_pdf;
        let bounce = vertices as u32 - 1;
        if bounce >= self.scene().settings.path.rr_depth {
            let Some(survived) = russian_roulette(w.rel, weight, id, sampler, rec) else {
                end(rec, id, EndReason::RussianRoulette);
                return None;
            };
            weight = survived;
        }
        if weight == Rgb::ZERO || !weight.is_finite() {
            end(rec, id, EndReason::Absorbed);
            return None;
        }
        Some(Scatter {
            bs,
            weight,
            f_cos_pdf,
        })
    }

    /// The walk's next ray from the last vertex of `path` (at `si`, node `id`) along the
    /// sampled direction: the step's densities in both directions (the forward one for the
    /// next vertex, the reverse one onto the vertex before), the throughput, the ray and
    /// what its node records.
    fn advance<R: Recorder>(
        &self,
        w: &mut Step,
        path: &mut [Vertex],
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        next: Scatter,
        id: Option<NodeId>,
    ) {
        let Scatter {
            bs,
            weight,
            f_cos_pdf,
        } = next;
        // The densities of this step in both directions. Through a delta lobe the densities
        // are deltas in projected solid angle, which cancel between strategies, times the
        // cosines that turn them into area densities: `|cos|` here, the far end's cosine
        // and distance by `convert_density`. Leaving the cosines out (pbrt-v3's 0, read as
        // 1) left the geometry factors of the specular chain in the MIS ratios: a caustic
        // seen on a floor near its glass ball gave the light strategy 2-8% of the weight.
        let n = path.len();
        let (fwd, rev) = if bs.delta {
            path[n - 1].delta = true;
            (bs.wi.dot(si.n).abs(), si.wo.dot(si.n).abs())
        } else {
            (bs.pdf, bsdf.pdf_rev(si.wo, bs.wi))
        };
        path[n - 1].event = event(bs.kind);
        let (last, before) = (path[n - 1], &mut path[n - 2]);
        before.pdf_rev = last.convert_density(rev, before);
        w.pdf_fwd = fwd;
        w.beta *= weight;
        w.rel *= weight;
        let side = if bs.wi.dot(si.n) < 0.0 { -si.n } else { si.n };
        w.ray = self.core.spawn_ray(si.from(), si.p, side, bs.wi);
        w.spawn_point = si.p;
        w.from = Some(si.from());
        w.parent = id;
        w.weight = weight;
        w.depth += 1;
        if !w.importance {
            w.kind = match bs.kind {
                LobeKind::Diffuse => RayKind::Diffuse,
                LobeKind::SpecularReflection | LobeKind::GlossyReflection => RayKind::Reflected,
                _ => RayKind::Refracted,
            };
        }
        let pdf = if bs.delta {
            Pdf::Delta(DeltaTag::Delta)
        } else {
            Pdf::Density(bs.pdf)
        };
        w.sampled = (Some(bs.kind), Some(pdf), Some(f_cos_pdf));
        if R::RECORDS {
            w.lpe.push_str(event(bs.kind));
        }
    }
}

/// A BSDF sample that continues a walk: the sample, its weight after roulette, and
/// `f |cos| / pdf` before it (what the ray's node records).
struct Scatter {
    bs: BsdfSample,
    weight: Rgb,
    f_cos_pdf: Rgb,
}

/// The vertex a walk finds at `si` (node `id`): where, its normals and BSDF, the walk's
/// throughput, and for a camera subpath the emission it sees (`le`, the `s = 0` strategy).
fn surface_vertex(si: &SurfaceInteraction, w: &Step, bsdf: Bsdf, id: Option<NodeId>) -> Vertex {
    let mut v = Vertex::at(Kind::Surface, si.p);
    v.ng = si.n;
    v.ns = si.ns;
    v.wo = si.wo;
    v.beta = w.beta;
    v.smooth = si.smooth.is_some();
    v.bsdf = bsdf;
    v.from = Some(si.from());
    v.id = id;
    if !w.importance && si.entering && si.material.emission != Rgb::ZERO {
        v.le = si.material.emission;
        v.emitter = Some(si.from().object);
    }
    v
}

/// Record why the walk ends (or `Continued`) at the hit of node `id`.
fn end<R: Recorder>(rec: &mut R, id: Option<NodeId>, reason: EndReason) {
    rec.update(id, |n| n.end = reason);
}

impl Bdpt<'_> {
    /// Count and record the current ray of a walk.
    fn push_ray<R: Recorder>(
        &self,
        w: &Step,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<NodeId> {
        counts.add_kind(w.kind);
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
                lpe: w.lpe.clone(),
                ..crate::integrator::light::path_info()
            });
            n
        })
    }
}
