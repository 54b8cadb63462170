//! The Whitted tracer, exactly as the lecture's `trace(ray, objects, lights)` recursion, with a
//! [`Recorder`] hook that sees every ray.

pub mod diagnose;
mod media;
pub mod offset;
mod recorder;
mod shadow;

pub use media::{MediaStack, Medium};
pub use recorder::{DiagnosticRecorder, NoopRecorder, Recorder, TreeRecorder};

use crate::bvh::TraversalCost;
use crate::effects::EffectPlan;
use crate::math::{self, Fresnel, Ray, Rgb, beer, reflect, refract};
use crate::mesh::shading;
use crate::scene::{Hit, Light, Material, OffsetStrategy, Scene};
use crate::tree::{
    Attenuation, EndReason, HitInfo, Interface, NodeId, RayKind, RayNode, ShadowInfo,
};
use glam::DVec3;

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays.
    pub camera: u64,
    /// Reflected rays.
    pub reflected: u64,
    /// Refracted rays.
    pub refracted: u64,
    /// Shadow rays actually cast.
    pub shadow: u64,
    /// Spawned rays that re-hit the surface they left (counted only by diagnosing recorders).
    pub self_hits: u64,
    /// Spawned rays whose offset skipped a surface (counted only by diagnosing recorders).
    pub leaks: u64,
}

impl RayCounts {
    /// All rays.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.camera + self.reflected + self.refracted + self.shadow
    }

    fn add_kind(&mut self, kind: RayKind) {
        match kind {
            RayKind::Camera => self.camera += 1,
            RayKind::Reflected => self.reflected += 1,
            RayKind::Refracted => self.refracted += 1,
            RayKind::Shadow => self.shadow += 1,
        }
    }
}

impl std::ops::AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
        self.self_hits += o.self_hits;
        self.leaks += o.leaks;
    }
}

/// Where a ray starts: the surface point and which side of it.
#[derive(Clone, Copy, Debug)]
struct Spawn {
    kind: RayKind,
    parent: Option<NodeId>,
    point: DVec3,
    /// The object the ray leaves (`None` for camera rays).
    object: Option<usize>,
    /// For meshes: the stored triangle the ray leaves.
    triangle: Option<u32>,
    weight: Rgb,
}

/// What the secondary rays of one hit add up to.
struct Secondary {
    total: Rgb,
    end: EndReason,
    truncated: Rgb,
}

/// State carried down one path of the tree.
#[derive(Clone, Copy, Debug)]
struct PathState<'m> {
    depth: u32,
    throughput: Rgb,
    /// By reference: most rays do not change media, so nothing is copied for them.
    media: &'m MediaStack,
}

/// Traces rays through one scene, running only the effects of its [`EffectPlan`].
#[derive(Clone, Copy, Debug)]
pub struct Tracer<'a> {
    scene: &'a Scene,
    plan: EffectPlan,
}

impl<'a> Tracer<'a> {
    /// A tracer over `scene` with its settings and the effects the scene calls for.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        Self::with_plan(scene, EffectPlan::for_scene(scene))
    }

    /// A tracer with an explicit plan (e.g. [`EffectPlan::everything`] for comparisons).
    #[must_use]
    pub fn with_plan(scene: &'a Scene, plan: EffectPlan) -> Self {
        Self { scene, plan }
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// The effects this tracer runs.
    #[must_use]
    pub fn plan(&self) -> &EffectPlan {
        &self.plan
    }

    /// Radiance along a camera ray, recording into `rec` and counting into `counts`.
    pub fn trace_camera<R: Recorder>(
        &self,
        ray: Ray,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let spawn = Spawn {
            kind: RayKind::Camera,
            parent: None,
            point: ray.origin,
            object: None,
            triangle: None,
            weight: Rgb::ONE,
        };
        let state = PathState {
            depth: 0,
            throughput: Rgb::ONE,
            media: &MediaStack::AIR,
        };
        self.trace_ray(ray, spawn, state, rec, counts)
    }

    /// Offset a spawn point on `object` (for meshes: on stored `triangle`) by the configured
    /// strategy ([`offset::spawn`]).
    #[inline]
    fn spawn_ray(
        &self,
        (object, triangle): (usize, Option<u32>),
        point: DVec3,
        side: DVec3,
        direction: DVec3,
    ) -> Ray {
        let shape = || self.scene.surface_shape(object, triangle);
        offset::spawn(self.scene.settings.offset, shape, point, side, direction)
    }

    /// Run the diagnostics for a spawned ray, count and record them.
    #[allow(clippy::too_many_arguments)]
    fn diagnose<R: Recorder>(
        &self,
        ray: &Ray,
        point: DVec3,
        from: (usize, Option<u32>),
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

    fn trace_ray<R: Recorder>(
        &self,
        ray: Ray,
        spawn: Spawn,
        state: PathState,
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
        let mut cost = TraversalCost::default();
        let hit = self.scene.intersect_counted(&ray, f64::INFINITY, &mut cost);
        rec.update(id, |n| n.traversal = cost);
        if R::DIAGNOSE
            && let Some(object) = spawn.object
        {
            let from = (object, spawn.triangle);
            self.diagnose(&ray, spawn.point, from, hit, id, rec, counts);
        }
        // Beer's law on this segment, inside the innermost absorbing medium.
        // (Checked only when the plan has absorption: no per-ray cost otherwise.)
        let medium = if self.plan.absorption {
            state.media.top().map(|m| m.object as usize)
        } else {
            None
        };
        let absorption = medium.map_or(Rgb::ZERO, |o| self.scene.material_of(o).absorption);
        let mut atten = Rgb::ONE;
        if medium.is_some() && absorption != Rgb::ZERO {
            // Path length from the true spawn point, so the offset does not bias Beer's law.
            let distance = hit.map_or(f64::INFINITY, |h| (ray.at(h.t) - spawn.point).length());
            atten = beer(absorption, distance);
            rec.update(id, |n| {
                n.attenuation = Some(Attenuation {
                    medium: medium.unwrap_or(0),
                    distance,
                    absorption,
                    factor: atten,
                });
            });
        }
        let Some(hit) = hit else {
            let radiance = atten * self.scene.background;
            rec.update(id, |n| {
                n.radiance = radiance;
                n.end = EndReason::Miss;
            });
            return (radiance, id);
        };
        let inner = self.shade(&ray, &hit, id, state.throughput * atten, state, rec, counts);
        let radiance = atten * inner;
        rec.update(id, |n| n.radiance = radiance);
        (radiance, id)
    }

    /// Everything at a hit: local shading plus the weighted secondary rays (before the segment's
    /// attenuation).
    #[allow(clippy::too_many_arguments)]
    fn shade<R: Recorder>(
        &self,
        ray: &Ray,
        hit: &Hit,
        id: Option<NodeId>,
        throughput: Rgb,
        state: PathState,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let scene = self.scene;
        let m = scene.material_of(hit.object);
        let d = ray.direction;
        let p = ray.at(hit.t);
        let entering = d.dot(hit.normal) < 0.0;
        // Geometric normal on the incident side: decides sides and offsets.
        let n = if entering { hit.normal } else { -hit.normal };
        // Shading normal on the incident side: lighting, mirror and Snell (mesh::shading rule).
        let smooth = hit.triangle.and_then(|_| scene.shading_normal(hit, p));
        let ns = match smooth {
            None => n,
            Some(s) => {
                let ns = shading::shading_normal(d, n, s, entering);
                self.consistent_shading_normal(d, n, ns, hit.object, m, entering, state.media)
            }
        };
        let cos_i = (-d.dot(ns)).clamp(0.0, 1.0);
        rec.update(id, |node| {
            node.hit = Some(HitInfo {
                t: hit.t,
                point: p,
                normal: hit.normal,
                object: hit.object,
                object_name: scene.objects[hit.object].name.clone(),
                material: m.name.clone(),
                entering,
                cos_i,
                triangle: scene.source_triangle(hit),
                shading_normal: smooth.map(|_| if entering { ns } else { -ns }),
            });
        });
        let albedo = m.diffuse.at(p);
        let emitted = if entering { m.emission } else { Rgb::ZERO };
        let ambient = scene.ambient * albedo;
        let mut local = emitted + ambient;
        if !m.diffuse.is_black() || m.specular != Rgb::ZERO {
            for (i, light) in scene.lights.iter().enumerate() {
                if !self.plan.light_on(i) {
                    continue;
                }
                let at = ((hit.object, hit.triangle), p);
                let normals = (n, ns);
                local += self.direct(
                    (i, light),
                    at,
                    normals,
                    -d,
                    albedo,
                    m,
                    id,
                    state.depth,
                    rec,
                    counts,
                );
            }
        }
        rec.update(id, |node| {
            node.emitted = emitted;
            node.ambient = ambient;
            node.local = local;
        });

        if !(self.plan.reflection || self.plan.refraction) {
            // Nothing in the scene reflects or refracts: no secondary rays, no bookkeeping.
            rec.update(id, |node| {
                node.end = EndReason::Surface;
                node.truncated = Rgb::ZERO;
            });
            return local;
        }
        // Dielectric split (only where the material transmits).
        let mut reflect_w = m.reflectivity;
        let mut refraction = None;
        if self.plan.refraction && m.is_transmissive() {
            let (event, dir) = self.interface(d, ns, cos_i, hit.object, m, entering, *state.media);
            let f = event.fresnel;
            reflect_w += m.transmissivity * f.r;
            if let Some(dir) = dir {
                refraction = Some((dir, m.transmissivity * f.t));
            }
            rec.update(id, |node| node.interface = Some(event));
        }
        let at = Spawn {
            kind: RayKind::Reflected,
            parent: id,
            point: p,
            object: Some(hit.object),
            triangle: hit.triangle,
            weight: Rgb::ZERO,
        };
        let mut acc = Secondary {
            total: local,
            end: EndReason::Surface,
            truncated: Rgb::ZERO,
        };
        if reflect_w.max_element() > 0.0 {
            let spawn = Spawn {
                weight: reflect_w,
                ..at
            };
            self.secondary(
                &mut acc,
                spawn,
                reflect(d, ns),
                n,
                throughput,
                state.depth,
                state.media,
                rec,
                counts,
            );
        }
        if let Some((dir, weight)) = refraction.filter(|r| r.1.max_element() > 0.0) {
            let media = if entering {
                state
                    .media
                    .entered(hit.object, m.ior.unwrap_or(state.media.ior()))
            } else {
                state.media.left(hit.object)
            };
            let spawn = Spawn {
                kind: RayKind::Refracted,
                weight,
                ..at
            };
            self.secondary(
                &mut acc,
                spawn,
                dir,
                -n,
                throughput,
                state.depth,
                &media,
                rec,
                counts,
            );
        }
        let Secondary {
            total,
            end,
            truncated,
        } = acc;
        rec.update(id, |node| {
            node.end = end;
            node.truncated = truncated;
        });
        total
    }

    /// `ns`, or the geometric `n` where refracting with `ns` would cross to the wrong side of
    /// the surface (mesh::shading rule).
    #[allow(clippy::too_many_arguments)]
    fn consistent_shading_normal(
        &self,
        d: DVec3,
        n: DVec3,
        ns: DVec3,
        object: usize,
        m: &Material,
        entering: bool,
        media: &MediaStack,
    ) -> DVec3 {
        if ns != n && self.plan.refraction && m.is_transmissive() {
            let cos = (-d.dot(ns)).clamp(0.0, 1.0);
            let (_, t) = self.interface(d, ns, cos, object, m, entering, *media);
            if t.is_some_and(|t| !shading::refraction_consistent(n, t)) {
                return n;
            }
        }
        ns
    }

    /// Trace one secondary ray (or record why it was cut) and add its weighted radiance.
    #[allow(clippy::too_many_arguments)]
    fn secondary<R: Recorder>(
        &self,
        acc: &mut Secondary,
        spawn: Spawn,
        dir: DVec3,
        side: DVec3,
        throughput: Rgb,
        depth: u32,
        media: &MediaStack,
        rec: &mut R,
        counts: &mut RayCounts,
    ) {
        let settings = &self.scene.settings;
        let child_throughput = throughput * spawn.weight;
        let cut = if depth >= settings.max_depth {
            Some(EndReason::MaxDepth)
        } else if child_throughput.max_element() < settings.min_weight {
            Some(EndReason::MinWeight)
        } else {
            None
        };
        if let Some(reason) = cut {
            acc.truncated += spawn.weight;
            if acc.end != EndReason::MaxDepth {
                acc.end = reason;
            }
            return;
        }
        if acc.end == EndReason::Surface {
            acc.end = EndReason::Continued;
        }
        let object = spawn.object.expect("secondary rays leave a surface");
        let ray = self.spawn_ray((object, spawn.triangle), spawn.point, side, dir);
        let state = PathState {
            depth: depth + 1,
            throughput: child_throughput,
            media,
        };
        let (l, _) = self.trace_ray(ray, spawn, state, rec, counts);
        acc.total += spawn.weight * l;
    }

    /// n1, n2, Snell and Fresnel at a transmissive hit; the refracted direction unless TIR.
    #[allow(clippy::too_many_arguments)]
    fn interface(
        &self,
        d: DVec3,
        n: DVec3,
        cos_i: f64,
        object: usize,
        m: &Material,
        entering: bool,
        media: MediaStack,
    ) -> (Interface, Option<DVec3>) {
        let (n1, n2) = if entering {
            let n1 = media.ior();
            (n1, m.ior.unwrap_or(n1))
        } else {
            let n2 = media.left(object).ior();
            (m.ior.unwrap_or(n2), n2)
        };
        let model = self.scene.settings.fresnel;
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
                };
                (event, None)
            }
        }
    }

    /// One light's contribution at `p`: (diffuse/pi + Blinn-Phong) x irradiance x cos x shadow.
    #[allow(clippy::too_many_arguments)]
    fn direct<R: Recorder>(
        &self,
        (light, l): (usize, &Light),
        (from, p): ((usize, Option<u32>), DVec3),
        (n, ns): (DVec3, DVec3),
        wo: DVec3,
        albedo: Rgb,
        m: &Material,
        parent: Option<NodeId>,
        depth: u32,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Rgb {
        let (wi, dist, irradiance) = l.sample(p);
        // Shade with ns; the light is behind if either normal says so (the shadow ray leaves
        // on the geometric side, so a light below the geometric surface cannot be reached).
        let cos = if n.dot(wi) > 0.0 {
            ns.dot(wi)
        } else {
            n.dot(wi)
        };
        let ray = self.spawn_ray(from, p, n, wi);
        let id = rec.push(parent, || {
            let mut node = RayNode::new(RayKind::Shadow, depth, p, ray.origin, ray.direction);
            node.t_min = ray.t_min;
            node
        });
        let brdf = if cos > 0.0 {
            let highlight = if self.plan.specular {
                blinn_phong(m, ns, wi, wo)
            } else {
                Rgb::ZERO
            };
            albedo * std::f64::consts::FRAC_1_PI + highlight
        } else {
            Rgb::ZERO
        };
        let weight = brdf * cos.max(0.0);
        if cos <= 0.0 {
            rec.update(id, |node| {
                node.weight = weight;
                node.end = EndReason::LightBehind;
                node.shadow = Some(self.shadow_info(
                    light,
                    dist,
                    cos,
                    brdf,
                    irradiance,
                    Vec::new(),
                    Rgb::ZERO,
                ));
            });
            return Rgb::ZERO;
        }
        counts.add_kind(RayKind::Shadow);
        // The light is at `dist` from `p`; a normal offset moves the origin by its epsilon, so
        // stop that much short of the light (no square root on this hot path).
        let eps = self.scene.settings.offset.epsilon;
        let seg = match self.scene.settings.offset.strategy {
            OffsetStrategy::Normal => (dist - eps).max(0.0),
            OffsetStrategy::Ray => dist,
            OffsetStrategy::Scaled => (dist - offset::scaled_epsilon(eps, p)).max(0.0),
            OffsetStrategy::Robust => (dist - (ray.origin - p).length()).max(0.0),
        };
        if R::DIAGNOSE {
            let first = self.scene.intersect(&ray, seg);
            self.diagnose(&ray, p, from, first, id, rec, counts);
        }
        // Blockers are collected only when recording (no `Vec` on the render path).
        let mut blockers = R::RECORDS.then(Vec::new);
        let mut cost = TraversalCost::default();
        let transmittance = shadow::transmission(
            self.scene,
            &ray,
            seg,
            self.plan.translucent_shadows,
            blockers.as_mut(),
            &mut cost,
        );
        let arriving = irradiance * transmittance;
        rec.update(id, |node| {
            node.traversal = cost;
            node.weight = weight;
            node.radiance = arriving;
            node.end = if transmittance == Rgb::ONE {
                EndReason::Unblocked
            } else if transmittance == Rgb::ZERO {
                EndReason::Blocked
            } else {
                EndReason::Attenuated
            };
            node.shadow = Some(self.shadow_info(
                light,
                dist,
                cos,
                brdf,
                irradiance,
                blockers.unwrap_or_default(),
                transmittance,
            ));
        });
        weight * arriving
    }

    #[allow(clippy::too_many_arguments)]
    fn shadow_info(
        &self,
        light: usize,
        distance: f64,
        cos_theta: f64,
        brdf: Rgb,
        irradiance: Rgb,
        blockers: Vec<crate::tree::Blocker>,
        transmittance: Rgb,
    ) -> ShadowInfo {
        ShadowInfo {
            light,
            light_name: self.scene.lights[light].name.clone(),
            distance,
            cos_theta,
            brdf,
            irradiance,
            blockers,
            transmittance,
        }
    }
}

/// Blinn-Phong highlight `specular * (N.H)^shininess` (zero without a specular colour).
fn blinn_phong(m: &Material, n: DVec3, wi: DVec3, wo: DVec3) -> Rgb {
    if m.specular == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let Some(h) = (wi + wo).try_normalize() else {
        return Rgb::ZERO;
    };
    m.specular * n.dot(h).max(0.0).powf(m.shininess)
}
