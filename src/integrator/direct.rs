//! The one direct-light estimator ([`Shading::direct`]): one light sample at a surface, its
//! shadow ray and the recorded shadow event, for every light (point, directional, area) and
//! every integrator. What differs between integrators is only how a sample is weighed — the
//! Whitted local term's `(albedo/pi + Blinn-Phong) cos` for delta lights and the distribution
//! ray tracer's `/ N` for area lights (`whitted/local.rs`), the path tracer's `f |cos| mis / pdf`
//! (`path/nee.rs`) — given by a [`DirectKernel`]. The estimator of one light sample is
//!
//! `L_direct = weight(wi) x arriving(wi)`, `arriving = L_e(wi) V(wi)` (times Beer's law or the
//! `1 / pdf` where the kernel puts it),
//!
//! (pbrt-v4 section 13.4, Veach 1997 eq. 8.10; for delta lights the lecture's local term, where
//! `L_e / pdf` is the irradiance `E` of a surface facing the light). A shadow node is recorded
//! here, in one place: its ray, weight, the light's [`ShadowInfo`] (with the area sample), the
//! light-behind case (no ray cast) and the end reason from the transmittance.

use super::shading::{Shading, shadow_end};
use super::{RayCounts, Recorder};
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSample};
use crate::math::Rgb;
use crate::tree::{AreaSample, EndReason, NodeId, RayKind, RayNode, ShadowInfo};
use glam::DVec3;

/// How an integrator weighs one light sample at a surface.
pub(crate) struct LightEval {
    /// The cosine recorded for the light (`ShadowInfo::cos_theta`).
    pub cos: f64,
    /// The BSDF value recorded for the light (`ShadowInfo::brdf`).
    pub brdf: Rgb,
    /// What multiplies the arriving light: the shadow node's weight.
    pub weight: Rgb,
    /// What the light delivers before visibility (the kernel's own, computed once: for
    /// Whitted the sample's value `radiance / pdf`, for the path tracer its radiance).
    pub value: Rgb,
    /// The MIS weight of the light sample (1 without MIS).
    pub mis: f64,
    /// The geometric normal on the side the shadow ray leaves from.
    pub side: DVec3,
    /// Nothing can arrive (the light is behind the surface, or the weight is zero): the
    /// shadow ray is recorded but not cast.
    pub behind: bool,
}

/// An integrator's part of the direct-light estimator.
pub(crate) trait DirectKernel {
    /// The weight of light sample `ls` of `light` at `si`.
    fn eval(&self, si: &SurfaceInteraction, light: &Light, ls: &LightSample) -> LightEval;

    /// What arrives at `si` along the sample (weighed as `eval`) through a shadow ray of
    /// transmittance `t`.
    fn arriving(&self, si: &SurfaceInteraction, sample: (&LightSample, &LightEval), t: Rgb) -> Rgb;

    /// Fill in the integrator's own record of a shadow node when it is pushed (recording only).
    fn annotate(
        &self,
        node: &mut RayNode,
        si: &SurfaceInteraction,
        (ls, eval): (&LightSample, &LightEval),
    ) {
        let _ = (node, si, ls, eval);
    }
}

/// One light sample's outcome ([`Shading::direct`]).
pub(crate) struct Direct {
    /// `weight x arriving`: what the sample adds at the surface (exactly zero when blocked or
    /// behind).
    pub local: Rgb,
    /// The recorded shadow node.
    pub id: Option<NodeId>,
    /// The shadow ray was cast (not behind).
    pub cast: bool,
    /// The geometric normal on the side the shadow ray left from.
    pub side: DVec3,
}

/// Which light a sample is of, and which of its samples at this hit.
#[derive(Clone, Copy)]
pub(crate) struct LightPick<'l, 'a> {
    /// Index in [`crate::lights::LightSampler::lights`] (delta light `k` is index `k`).
    pub index: usize,
    /// The light.
    pub light: &'l Light<'a>,
    /// The sample's number among the light's samples at this hit (recorded for area lights).
    pub k: u32,
}

impl Shading<'_> {
    /// One sample `u` of `pick.light` at `si`, weighed by `kernel`, its shadow ray recorded as
    /// a child of `parent` at `depth`: `None` when the light cannot be sampled from `si` (an
    /// area light whose outer side `si` cannot see; nothing is recorded).
    #[inline(always)]
    pub(crate) fn direct<K: DirectKernel, R: Recorder>(
        &self,
        si: &SurfaceInteraction,
        pick: LightPick,
        (u, kernel): ((f64, f64), &K),
        (parent, depth): (Option<NodeId>, u32),
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> Option<Direct> {
        let light = pick.light;
        let ls = light.sample_li(si.p, u)?;
        let eval = kernel.eval(si, light, &ls);
        let strategy = self.scene.settings.offset.strategy;
        let from = si.from();
        let (ray, seg) =
            self.shadow_ray(strategy, (from, si.p, eval.side), ls.direction, ls.distance);
        let seg = match light.object() {
            Some(object) => self.emitter_shadow_length(object, &ray, seg, si.p),
            None => seg,
        };
        let id = rec.push(parent, || {
            let mut node = RayNode::new(RayKind::Shadow, depth, si.p, ray.origin, ray.direction);
            node.t_min = ray.t_min;
            node.weight = eval.weight;
            kernel.annotate(&mut node, si, (&ls, &eval));
            node
        });
        let info = |blockers, transmittance| {
            self.shadow_info(si, pick, (&ls, &eval), blockers, transmittance)
        };
        if eval.behind {
            rec.update(id, |node| {
                node.end = EndReason::LightBehind;
                node.shadow = Some(info(Vec::new(), Rgb::ZERO));
            });
            return Some(Direct {
                local: Rgb::ZERO,
                id,
                cast: false,
                side: eval.side,
            });
        }
        let cast = self.cast_shadow((&ray, seg), (si.p, from), id, rec, counts);
        let t = cast.transmittance;
        let arriving = kernel.arriving(si, (&ls, &eval), t);
        rec.update(id, |node| {
            node.traversal = cast.cost;
            node.radiance = arriving;
            node.end = shadow_end(t);
            node.shadow = Some(info(cast.blockers, t));
        });
        // A blocked light adds exactly nothing (not `0 * inf` for a light on the surface), as in
        // the direct-only path, which does not evaluate blocked lights at all.
        let local = if t == Rgb::ZERO {
            Rgb::ZERO
        } else {
            eval.weight * arriving
        };
        Some(Direct {
            local,
            id,
            cast: true,
            side: eval.side,
        })
    }

    /// The recorded light of a shadow ray: which light, its name, the sample's geometry and
    /// weights, the blockers and what passed them.
    fn shadow_info(
        &self,
        si: &SurfaceInteraction,
        pick: LightPick,
        (ls, eval): (&LightSample, &LightEval),
        blockers: Vec<crate::tree::Blocker>,
        transmittance: Rgb,
    ) -> ShadowInfo {
        let scene = self.scene;
        let object = pick.light.object();
        ShadowInfo {
            light: object.map_or(pick.index, |o| scene.lights.len() + o),
            light_name: scene.light_name(pick.index, pick.light).to_string(),
            distance: ls.distance,
            cos_theta: eval.cos,
            brdf: eval.brdf,
            irradiance: ls.value(),
            blockers,
            transmittance,
            area: object.map(|object| AreaSample {
                object,
                point: si.p + ls.distance * ls.direction,
                direction: ls.direction,
                pdf: ls.pdf,
                radiance: ls.radiance,
                sample: pick.k,
            }),
        }
    }
}
