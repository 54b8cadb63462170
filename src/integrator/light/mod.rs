//! Light tracing (particle tracing, issue 30): paths start on the lights and every vertex on a
//! non-specular surface connects to the camera, its contribution splatted to the pixel it
//! lands in (Veach 1997, section 10.2; pbrt-v4 `LightPathIntegrator`; Mitsuba 3 `ptracer`).
//! See `docs/bidirectional.md`.
//!
//! - The light: chosen in proportion to power ([`crate::lights::LightSampler`]), its emitted
//!   ray from [`crate::lights::Light::sample_le`]; the path's throughput starts at
//!   `Le |cos| / (p_light pdf_pos pdf_dir)` (flux).
//! - At each hit: if the BSDF has a non-delta lobe, one connection to the camera
//!   ([`crate::scene::Film::connect`], a lens point sampled for a thin lens): `beta f |cos|
//!   importance / d^2` if the segment is unblocked. Then Russian roulette (on the throughput
//!   relative to the emitted flux, from bounce `rr_depth` as under `path`) and a continuation
//!   sampled from the BSDF. Transmission carries flux (the BSDF's own convention, no `1/eta^2`),
//!   and shading normals get Veach's adjoint correction (`|wo.ns| |wi.ng| / |wo.ng|` in place
//!   of `|wi.ns|`, section 5.3).
//! - `max_depth` means what it means under `path`: a connection from the light path's vertex
//!   `d` (0 the first hit) makes a path of `d + 1` scattering vertices, allowed up to
//!   `max_depth + 1`.
//! - What the camera sees directly: one camera ray per pixel sample
//!   ([`LightTracer::trace_camera`]) adds the emission of its first hit's outer side, or the
//!   background. The light path never connects its emitter's own point to the camera, so
//!   nothing is counted twice. Paths whose camera-side vertex is specular (a lamp in a
//!   mirror, anything seen through glass) carry no light under light tracing: no connection
//!   can reach the pinhole through a delta lobe.
//!
//! The render (`crate::render`) runs one light path per pixel sample, seeded by that sample,
//! and adds the splats in path order, so an image does not depend on the thread count and a
//! pixel's recorded splats sum to it bit for bit.

mod walk;

use super::{RayCounts, Recorder, Shading};
use crate::integrator::EffectPlan;
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use crate::scene::{Film, Scene};
use crate::tree::{EndReason, NodeId, PathInfo, RayKind, RayNode};

pub use walk::Splat;
pub(crate) use walk::{adjoint_weight, connection_event, emitted_ray};

/// The light-tracing integrator (`settings.integrator: "light"`).
#[derive(Clone, Debug)]
pub struct LightTracer<'a> {
    /// Surface interactions, offsets, shadow rays and the light sampler.
    core: Shading<'a>,
}

/// The sampler seed of the light paths: the scene's seed mixed with this, so that light path
/// `s` of a pixel does not repeat the random numbers of its camera sample `s`.
pub const LIGHT_SEED: u64 = 0x5eed_11a7_9e37_79b9;

impl<'a> LightTracer<'a> {
    /// The light tracer of `scene`.
    #[must_use]
    pub fn new(scene: &'a Scene) -> Self {
        let mut plan = EffectPlan::everything(scene);
        // As under `path`: visibility tests, exact BSDF events.
        plan.translucent_shadows = false;
        plan.specular = false;
        Self {
            core: Shading::new(scene, plan),
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

    /// The camera sample's own part of the pixel: the emission of the first hit's outer side,
    /// or the background on a miss (the paths of no scattering vertex, which light paths do not
    /// make). One node, with its light path expression `CL` or `CB`.
    pub fn trace_camera<R: Recorder>(
        &self,
        camera: Ray,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        counts.add_kind(RayKind::Camera);
        let id = rec.push(None, || {
            let mut n = RayNode::new(
                RayKind::Camera,
                0,
                camera.origin,
                camera.origin,
                camera.direction,
            );
            n.path = Some(path_info());
            n
        });
        let seg = self.core.segment(
            (&camera, None),
            (camera.origin, None),
            &MediaStack::AIR,
            id,
            rec,
            counts,
        );
        let Some(hit) = seg.hit else {
            let c = self.scene().background;
            rec.update(id, |n| {
                n.end = EndReason::Miss;
                n.radiance = c;
                set_path(n, c, "CB");
            });
            return (c, id);
        };
        let media = MediaStack::AIR;
        let si = self.core.surface(&camera, &hit, &media);
        self.core.record_hit(&si, &hit, id, rec);
        let emitted = if si.entering {
            si.material.emission
        } else {
            Rgb::ZERO
        };
        let c = seg.atten * emitted;
        rec.update(id, |n| {
            n.end = EndReason::Surface;
            n.emitted = emitted;
            n.local = emitted;
            n.radiance = c;
            set_path(n, c, if emitted == Rgb::ZERO { "C" } else { "CL" });
        });
        (c, id)
    }
}

/// An empty estimator record (no lobe, nothing contributed yet).
pub(crate) fn path_info() -> PathInfo {
    PathInfo {
        lobe: None,
        pdf: None,
        bsdf_cos_pdf: None,
        mis_weight: None,
        roulette: None,
        strategy: None,
        unweighted: None,
        contribution: Rgb::ZERO,
        lpe: String::new(),
    }
}

/// A camera node's estimator record: its contribution and light path expression.
fn set_path(n: &mut RayNode, c: Rgb, lpe: &str) {
    if let Some(p) = n.path.as_mut() {
        p.contribution = c;
        p.mis_weight = Some(1.0);
        p.lpe = lpe.to_string();
    }
}
