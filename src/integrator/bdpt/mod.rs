//! Bidirectional path tracing (issue 30): a camera subpath and a light subpath per pixel sample,
//! every strategy (s, t) that joins them, weighted by the balance heuristic over all the
//! strategies that could have made the same path (Veach 1997, chapter 10; pbrt-v3
//! `BDPTIntegrator`). See `docs/bidirectional.md`.
//!
//! - `walk.rs`: the subpaths, each vertex with its throughput and its forward and reverse
//!   densities per unit area (Russian roulette on both, as under `path`; Veach's adjoint
//!   shading-normal factor on the light subpath).
//! - `connect.rs`: the strategies and their MIS weights (`s = 0` the camera subpath found an
//!   emitter; `s = 1` a light sampled from its last vertex; `t = 1` a light-subpath vertex
//!   connected to the lens and splatted; otherwise a visibility ray joins the two ends).
//! - `vertex.rs`: the vertex and its densities.
//!
//! A camera sample's radiance is the sum of its strategies with `t >= 2` (recorded: each
//! strategy's connection node holds its `[s, t]`, unweighted value, MIS weight and weighted
//! contribution); the `t = 1` strategies are splatted by the render's light pass, from a second
//! light subpath per pixel sample seeded as under light tracing
//! ([`Bdpt::trace_splats`]), so a pixel is its samples' mean plus its splats over `spp`, bit for
//! bit in its recorded tree. `max_depth` bounds the scattering vertices at `max_depth + 1`, the
//! longest path `path` makes with the same setting.

mod connect;
mod vertex;
mod walk;

use super::{RayCounts, Recorder, Shading, Splat};
use crate::integrator::EffectPlan;
use crate::math::{Ray, Rgb};
use crate::sampling::PixelSampler;
use crate::scene::{Film, Scene};
use crate::tree::NodeId;
use vertex::{Kind, Vertex};

/// One strategy's part of a camera sample ([`Bdpt::trace_camera_observed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrategyPart {
    /// `[s, t]`, or `None` for the background the camera subpath escaped to.
    pub strategy: Option<[u32; 2]>,
    /// The contribution before its MIS weight.
    pub unweighted: Rgb,
    /// The MIS weight (1 for the background).
    pub weight: f64,
}

/// The bidirectional path tracer (`settings.integrator: "bdpt"`).
#[derive(Clone, Debug)]
pub struct Bdpt<'a> {
    core: Shading<'a>,
    /// The bounded objects' sphere radius (a directional light's disc).
    radius: f64,
}

impl<'a> Bdpt<'a> {
    /// The bidirectional path tracer of `scene`.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        let mut plan = EffectPlan::everything(scene);
        plan.translucent_shadows = false;
        plan.specular = false;
        Self {
            core: Shading::new(scene, plan),
            radius: scene.bounding_sphere().1,
        }
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene {
        self.core.scene
    }

    /// The camera's image plane.
    #[must_use]
    pub fn film(&self) -> &Film<'a> {
        &self.core.film
    }

    /// The longest path in scattering vertices: `max_depth + 1`, as under `path`.
    fn max_scattering(&self) -> usize {
        self.scene().settings.max_depth as usize + 1
    }

    /// One camera sample: its camera subpath from `ray`, a light subpath, and every strategy
    /// with `t >= 2`; the sum of their weighted contributions (and of the background the camera
    /// subpath escaped to), with the camera ray's node.
    #[inline]
    pub fn trace_camera<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        self.trace_camera_observed(ray, sampler, rec, counts, |_| {})
    }

    /// [`Bdpt::trace_camera`] that also hands every strategy's part to `observe`, in the order
    /// they are added (first the background the camera subpath escaped to, with
    /// [`StrategyPart::strategy`] `None`): the same random numbers and the same sum, so
    /// `raytree strategies` splits exactly the render's samples.
    pub fn trace_camera_observed<R: Recorder, S: PixelSampler, F: FnMut(StrategyPart)>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        mut observe: F,
    ) -> (Rgb, Option<NodeId>) {
        let mut cam: Vec<Vertex> = Vec::with_capacity(8);
        let mut light: Vec<Vertex> = Vec::with_capacity(8);
        let (mut l, root) = self.camera_subpath(ray, &mut cam, sampler, rec, counts);
        observe(StrategyPart {
            strategy: None,
            unweighted: l,
            weight: 1.0,
        });
        self.light_subpath(root, &mut light, sampler, rec, counts);
        for t in 2..=cam.len() {
            for s in 0..=light.len() {
                if s + t - 2 > self.max_scattering() {
                    continue;
                }
                let Some((c, node)) = self.connect((&light, &cam), (s, t), sampler, rec, counts)
                else {
                    continue;
                };
                let contribution = c.unweighted * c.weight;
                l += contribution;
                observe(StrategyPart {
                    strategy: Some([s as u32, t as u32]),
                    unweighted: c.unweighted,
                    weight: c.weight,
                });
                if R::RECORDS {
                    let lpe = Self::lpe(&light, &cam, c.sampled.as_ref(), (s, t));
                    let at = if s == 0 { cam[t - 1].id } else { node };
                    record(rec, at, (s, t), &c, lpe);
                }
            }
        }
        (l, root)
    }

    /// The `t = 1` strategies of light subpath `seed` (the pixel sample that seeds it; it
    /// starts on a light, anywhere): each light-subpath vertex on a non-specular surface
    /// connected to the lens, weighted, handed to `splat`. Returns the subpath's root node.
    pub fn trace_splats<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        seed: (u32, u32, u32),
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) -> Option<NodeId> {
        sampler.start_sample((seed.0, seed.1), seed.2);
        let mut light: Vec<Vertex> = Vec::with_capacity(8);
        let root = self.light_subpath(None, &mut light, sampler, rec, counts);
        for s in 2..=light.len() {
            if s - 1 > self.max_scattering() || !light[s - 1].connectible() {
                continue;
            }
            self.splat_one(&light, s, sampler, rec, counts, splat);
        }
        root
    }

    /// Strategy (s, 1): light-subpath vertex `s - 1` connected to the lens.
    fn splat_one<R: Recorder, S: PixelSampler, F: FnMut(Splat)>(
        &self,
        light: &[Vertex],
        s: usize,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
        splat: &mut F,
    ) {
        let film = &self.core.film;
        let u = if film.has_lens() {
            let (a, b) = sampler.next_2d();
            glam::DVec2::new(a, b)
        } else {
            glam::DVec2::ZERO
        };
        let qs = &light[s - 1];
        let Some(c) = film.connect(qs.p, u) else {
            return;
        };
        let camera = Vertex::at(Kind::Camera, c.lens);
        let wi = -c.direction;
        let l = qs.beta
            * qs.f(&camera, true)
            * (qs.ns.dot(wi).abs() * c.importance / (c.distance * c.distance));
        if l == Rgb::ZERO || !l.is_finite() {
            return;
        }
        let (vis, node) = self.visible(qs, &camera, (s, 1), rec, counts);
        if vis == 0.0 {
            return;
        }
        let weight = self.mis_weight(light, std::slice::from_ref(&camera), Some(&camera), (s, 1));
        let conn = connect::Connection {
            unweighted: l,
            weight,
            sampled: Some(camera),
        };
        let lpe = if R::RECORDS {
            Self::lpe(light, std::slice::from_ref(&camera), Some(&camera), (s, 1))
        } else {
            String::new()
        };
        record(rec, node, (s, 1), &conn, lpe.clone());
        splat(Splat {
            film: c.film,
            pixel: c.pixel(),
            contribution: l * weight,
            connection: node,
            vertices: s as u32,
            mis_weight: weight,
            unweighted: l,
            lpe,
        });
    }
}

/// Record strategy (s, t)'s result on node `at` (its connection, or for `s = 0` the ray that
/// found the emitter).
fn record<R: Recorder>(
    rec: &mut R,
    at: Option<NodeId>,
    (s, t): (usize, usize),
    c: &connect::Connection,
    lpe: String,
) {
    rec.update(at, |n| {
        if let Some(p) = n.path.as_mut() {
            p.strategy = Some([s as u32, t as u32]);
            p.mis_weight = Some(c.weight);
            p.unweighted = Some(c.unweighted);
            p.contribution += c.unweighted * c.weight;
            p.lpe = lpe;
        }
    });
}
