//! The connection strategies (s, t) and their MIS weights (pbrt-v3 `ConnectBDPT`,
//! `MISWeight`; Veach 1997, section 10.3): `s` vertices from the light subpath, `t` from the
//! camera subpath. `s = 0`: the camera subpath found an emitter; `s = 1`: a light sampled from
//! the camera subpath's last vertex; `t = 1`: a light-subpath vertex connected to the lens
//! (splatted); otherwise the two end vertices joined by a visibility ray. The weight is the
//! balance heuristic over every strategy that could have made the same path, from the ratios
//! of forward and reverse area densities, delta vertices excluded.

use super::Bdpt;
use super::vertex::{Kind, Vertex};
use crate::integrator::light::connection_event;
use crate::integrator::offset::scaled_epsilon;
use crate::integrator::shading::shadow_end;
use crate::integrator::{RayCounts, Recorder};
use crate::lights::{AreaShape, Light};
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use crate::tree::{NodeId, PathInfo, RayKind, RayNode};
use glam::{DVec2, DVec3};

/// Shadow rays between two vertices stop this fraction short of the far one, so they do not
/// find its surface (as the path tracer's shadow rays to emitters).
const CONNECT_EPSILON: f64 = 1e-4;

/// One strategy's result: its unweighted contribution, MIS weight and, for `s = 1` and
/// `t = 1`, the vertex it sampled.
pub(super) struct Connection {
    pub unweighted: Rgb,
    pub weight: f64,
    pub sampled: Option<Vertex>,
}

/// `f` when it is not zero: densities of 0 stand for delta events (pbrt's `remap0`).
fn remap0(f: f64) -> f64 {
    if f == 0.0 { 1.0 } else { f }
}

impl Bdpt<'_> {
    /// The light of a light vertex (`Kind::Light`) or of the emitter a surface vertex lies on,
    /// with its selection probability.
    fn light_of(&self, v: &Vertex) -> Option<(&Light<'_>, f64)> {
        match v.kind {
            Kind::Light { index } => {
                let lights = &self.core.lights;
                Some((lights.lights().get(index)?, lights.probability(index)))
            }
            _ => self.core.lights.area(v.emitter?),
        }
    }

    /// The density per unit area at `next` with which vertex `v` (its predecessor `prev`)
    /// samples `next` (pbrt-v3 `Vertex::Pdf`).
    fn pdf(&self, v: &Vertex, prev: Option<&Vertex>, next: &Vertex) -> f64 {
        let wn = (next.p - v.p).normalize_or_zero();
        let pdf = match v.kind {
            Kind::Light { .. } => {
                return match self.light_of(v) {
                    Some((light, _)) => v.pdf_light(light, next, self.radius),
                    None => 0.0,
                };
            }
            Kind::Camera => self.core.film.pdf_dir(v.p, wn),
            Kind::Surface => match prev {
                Some(prev) => v.bsdf.pdf((prev.p - v.p).normalize_or_zero(), wn),
                None => 0.0,
            },
        };
        v.convert_density(pdf, next)
    }

    /// The MIS weight of strategy (s, t) for the path of `light[..s]` and `cam[..t]` (`sampled`
    /// replacing the light end for `s = 1` or the camera end for `t = 1`).
    pub(super) fn mis_weight(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        sampled: Option<&Vertex>,
        (s, t): (usize, usize),
    ) -> f64 {
        if s + t == 2 {
            return 1.0;
        }
        let end = |path: &[Vertex], n: usize, replaced: bool| -> Option<Vertex> {
            (n > 0).then(|| match (replaced, sampled) {
                (true, Some(v)) => *v,
                _ => path[n - 1],
            })
        };
        let qs = end(light, s, s == 1);
        let pt = end(cam, t, t == 1);
        let qs_minus = (s > 1).then(|| &light[s - 2]);
        let pt_minus = (t > 1).then(|| &cam[t - 2]);
        // (forward, reverse, delta) of every vertex, with this strategy's connection applied.
        let mut lp: Vec<(f64, f64, bool)> = light[..s]
            .iter()
            .map(|v| (v.pdf_fwd, v.pdf_rev, v.delta))
            .collect();
        let mut cp: Vec<(f64, f64, bool)> = cam[..t]
            .iter()
            .map(|v| (v.pdf_fwd, v.pdf_rev, v.delta))
            .collect();
        if let Some(q) = &qs {
            lp[s - 1] = (q.pdf_fwd, q.pdf_rev, false);
        }
        if let Some(p) = &pt {
            cp[t - 1] = (p.pdf_fwd, p.pdf_rev, false);
            cp[t - 1].1 = match &qs {
                Some(q) => self.pdf(q, qs_minus, p),
                None => self
                    .light_of(p)
                    .zip(pt_minus)
                    .map_or(0.0, |((l, pc), m)| p.pdf_light_origin(l, pc, m)),
            };
            if let Some(m) = pt_minus {
                cp[t - 2].1 = match &qs {
                    Some(q) => self.pdf(p, Some(q), m),
                    None => self
                        .light_of(p)
                        .map_or(0.0, |(l, _)| p.pdf_light(l, m, self.radius)),
                };
            }
        }
        if let (Some(q), Some(p)) = (&qs, &pt) {
            lp[s - 1].1 = self.pdf(p, pt_minus, q);
            if let Some(m) = qs_minus {
                lp[s - 2].1 = self.pdf(q, Some(p), m);
            }
        }
        let delta_light = qs.is_some_and(|q| {
            if s == 1 {
                q.delta_light
            } else {
                light[0].delta_light
            }
        });
        let sum = other_strategies(&cp, &lp, delta_light, self.scene().settings.path.mis);
        1.0 / (1.0 + sum)
    }

    /// Strategy (s, t) with `t >= 2` (a camera sample's own), unweighted, with its weight;
    /// `None` where it carries nothing. `s = 1` draws its light from `sampler`.
    pub(super) fn connect<R: Recorder, S: PixelSampler>(
        &self,
        (light, cam): (&[Vertex], &[Vertex]),
        (s, t): (usize, usize),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<(Connection, Option<NodeId>)> {
        let pt = &cam[t - 1];
        let (l, sampled, node) = match s {
            0 => {
                if pt.le == Rgb::ZERO {
                    return None;
                }
                (pt.le * pt.beta, None, None)
            }
            1 => {
                if !pt.connectible() {
                    return None;
                }
                let q = self.sample_light(pt, sampler)?;
                let l = pt.beta * pt.f(&q, false) * q.beta * geometry(pt, &q);
                if l == Rgb::ZERO {
                    return None;
                }
                let (vis, id) = self.visible(pt, &q, (s, t), rec, counts);
                (l * vis, Some(q), id)
            }
            _ => {
                let qs = &light[s - 1];
                if !(qs.connectible() && pt.connectible()) {
                    return None;
                }
                let l = qs.beta * qs.f(pt, true) * pt.f(qs, false) * pt.beta * geometry(qs, pt);
                if l == Rgb::ZERO {
                    return None;
                }
                let (vis, id) = self.visible(pt, qs, (s, t), rec, counts);
                (l * vis, None, id)
            }
        };
        if l == Rgb::ZERO || !l.is_finite() {
            return None;
        }
        let weight = self.mis_weight(light, cam, sampled.as_ref(), (s, t));
        let c = Connection {
            unweighted: l,
            weight,
            sampled,
        };
        Some((c, node))
    }

    /// A light vertex sampled for strategy s = 1 from camera vertex `pt`: a light chosen by
    /// power; on an area light a point uniform by area (the density `pdf_light_origin` gives),
    /// a point light's position, or a directional light's direction (at infinity).
    fn sample_light<S: PixelSampler>(&self, pt: &Vertex, sampler: &mut S) -> Option<Vertex> {
        let lights = &self.core.lights;
        if lights.is_empty() {
            return None;
        }
        let (index, light, p_choose) = lights.choose(sampler.next_1d());
        let (a, b) = sampler.next_2d();
        let mut q = Vertex::at(Kind::Light { index }, pt.p);
        match *light {
            Light::Area {
                shape: AreaShape::Sphere { center, .. },
                ..
            } => {
                // The path tracer's cone sampling (pbrt-v3 samples s = 1 by `Sample_Li` too);
                // the MIS weights keep the light's area density, as pbrt's do.
                let ls = light.sample_li(pt.p, (a, b))?;
                let y = pt.p + ls.direction * ls.distance;
                let n = (y - center).normalize_or_zero();
                let pdf_area = ls.pdf * n.dot(ls.direction).abs() / (ls.distance * ls.distance);
                let area = light_area(light);
                q.p = y;
                q.ng = n;
                q.ns = n;
                q.pdf_fwd = p_choose / area;
                q.beta = ls.radiance / (p_choose * pdf_area);
            }
            Light::Area { .. } => {
                let er = light.sample_le(DVec2::new(a, b), DVec2::new(0.5, 0.5))?;
                let n = er.normal?;
                if n.dot(pt.p - er.origin) <= 0.0 {
                    return None;
                }
                q.p = er.origin;
                q.ng = n;
                q.ns = n;
                q.pdf_fwd = er.pdf_pos * p_choose;
                q.beta = er.le / q.pdf_fwd;
            }
            Light::Point {
                position,
                intensity,
                spot,
            } => {
                // A spot light's intensity towards `pt` (nothing outside its cone).
                let falloff =
                    spot.map_or(1.0, |c| c.falloff((pt.p - position).normalize_or_zero()));
                if falloff <= 0.0 {
                    return None;
                }
                q.p = position;
                q.pdf_fwd = p_choose;
                q.beta = if spot.is_some() {
                    intensity * falloff / p_choose
                } else {
                    intensity / p_choose
                };
                q.delta_light = true;
            }
            Light::Directional {
                direction,
                irradiance,
                radius,
                ..
            } => {
                q.p = pt.p - direction * (2.0 * radius);
                q.infinite = true;
                q.delta_light = true;
                q.beta = irradiance / p_choose;
            }
        }
        (q.pdf_fwd.is_finite() && q.beta.is_finite()).then_some(q)
    }

    /// The visibility of `far` from camera-side vertex `near` (a recorded `connection` node
    /// under `near`'s ray when recording): 1 or 0.
    pub(super) fn visible<R: Recorder>(
        &self,
        near: &Vertex,
        far: &Vertex,
        (s, t): (usize, usize),
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (f64, Option<NodeId>) {
        let d = far.p - near.p;
        let dist = if far.infinite {
            f64::INFINITY
        } else {
            d.length()
        };
        let wi = d.normalize_or_zero();
        let Some(from) = near.from else {
            return (0.0, None);
        };
        let side = if wi.dot(near.ng) < 0.0 {
            -near.ng
        } else {
            near.ng
        };
        let strategy = self.scene().settings.offset.strategy;
        let (ray, seg) = self
            .core
            .shadow_ray(strategy, (from, near.p, side), wi, dist);
        // A far end on a surface is offset towards the near one as well (pbrt-v3
        // `SpawnRayTo`): aimed at the surface point itself, a ray whose origin is offset along
        // the near normal crosses the far surface before its end when the two face each other
        // at a slant (a wall and a box side 0.4 apart lost 0.3% of their light).
        let (ray, seg) = if far.infinite || !far.on_surface() {
            (ray, seg * (1.0 - CONNECT_EPSILON))
        } else {
            let out = if (ray.origin - far.p).dot(far.ng) < 0.0 {
                -far.ng
            } else {
                far.ng
            };
            let eps = scaled_epsilon(self.scene().settings.offset.epsilon, far.p);
            let to = far.p + eps * out - ray.origin;
            let len = to.length();
            let ray = crate::math::Ray::new(ray.origin, to / len, ray.t_min);
            (ray, len * (1.0 - CONNECT_EPSILON))
        };
        counts.add_kind(RayKind::Connection);
        let id = rec.push(near.id, || {
            let mut n = RayNode::new(RayKind::Connection, 0, near.p, ray.origin, wi);
            n.t_min = ray.t_min;
            n.throughput = near.beta;
            n.path = Some(PathInfo {
                strategy: Some([s as u32, t as u32]),
                ..crate::integrator::light::path_info()
            });
            n
        });
        let cast = self.core.cast((&ray, seg), (near.p, from), id, rec, counts);
        let vis = if cast.transmittance == Rgb::ZERO {
            0.0
        } else {
            1.0
        };
        rec.update(id, |n| {
            n.traversal = cast.cost;
            n.radiance = cast.transmittance;
            n.end = shadow_end(cast.transmittance);
        });
        (vis, id)
    }

    /// The light path expression of strategy (s, t), read from the camera.
    pub(super) fn lpe(
        light: &[Vertex],
        cam: &[Vertex],
        sampled: Option<&Vertex>,
        (s, t): (usize, usize),
    ) -> String {
        let mut out = String::from("C");
        let inner = if s == 0 { t - 1 } else { t.saturating_sub(1) };
        for v in cam.iter().take(inner).skip(1) {
            out.push_str(v.event);
        }
        let side = |v: &Vertex, other: &Vertex| {
            let d = other.p - v.p;
            d.dot(v.ng) * v.wo.dot(v.ng) > 0.0
        };
        if s >= 1 && t >= 2 {
            let pt = &cam[t - 1];
            let other = if s == 1 {
                sampled.copied().unwrap_or(light[0])
            } else {
                light[s - 1]
            };
            out.push_str(connection_event(&pt.bsdf, side(pt, &other)));
        }
        if s >= 2 {
            let qs = &light[s - 1];
            let other = if t == 1 {
                sampled.copied().unwrap_or(cam[0])
            } else {
                cam[t - 1]
            };
            out.push_str(connection_event(&qs.bsdf, side(qs, &other)));
            for v in light[1..s - 1].iter().rev() {
                out.push_str(v.event);
            }
        }
        out.push('L');
        out
    }
}

/// The geometry term between two vertices without visibility: `|cos| |cos| / d^2` with the
/// shading normals of the vertices on surfaces; towards a light at infinity the cosine at the
/// near end only.
fn geometry(a: &Vertex, b: &Vertex) -> f64 {
    let d = b.p - a.p;
    let d2 = d.length_squared();
    if d2 == 0.0 {
        return 0.0;
    }
    let w: DVec3 = d / d2.sqrt();
    let mut g = if a.infinite || b.infinite {
        1.0
    } else {
        1.0 / d2
    };
    if a.on_surface() {
        g *= a.ns.dot(w).abs();
    }
    if b.on_surface() {
        g *= b.ns.dot(w).abs();
    }
    g
}

/// The surface area of an area light (1 for the others).
fn light_area(light: &Light<'_>) -> f64 {
    match light {
        Light::Area { shape, .. } => shape.area(),
        _ => 1.0,
    }
}

/// The sum in a strategy's MIS weight `1 / (1 + sum)` over the strategies that could have made
/// the same path (Veach 1997, section 10.2; pbrt-v3's `MISWeight`): walking from the
/// connection towards the camera (`cam`) and towards the light (`light`), each vertex's
/// (forward, reverse, delta) densities, the running ratio of reverse to forward densities,
/// counted where neither end of the moved connection is a delta vertex (`delta_light`: the
/// path's light is a point, spot or directional light).
fn other_strategies(
    cam: &[(f64, f64, bool)],
    light: &[(f64, f64, bool)],
    delta_light: bool,
    heuristic: crate::scene::MisHeuristic,
) -> f64 {
    let mut sum = 0.0;
    let mut ri = 1.0;
    for i in (1..cam.len()).rev() {
        ri *= remap0(cam[i].1) / remap0(cam[i].0);
        if !cam[i].2 && !cam[i - 1].2 {
            sum += heuristic.term(ri);
        }
    }
    ri = 1.0;
    for i in (0..light.len()).rev() {
        ri *= remap0(light[i].1) / remap0(light[i].0);
        let before_delta = if i > 0 { light[i - 1].2 } else { delta_light };
        if !light[i].2 && !before_delta {
            sum += heuristic.term(ri);
        }
    }
    sum
}
