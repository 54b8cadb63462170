//! The guide features of one camera sample: the albedo and the shading normal at the first
//! non-delta hit, followed through mirrors and smooth glass (and through surfaces whose delta
//! lobes carry more than the rest) along the branch that carries the most (the albedo tinted by the mirror and Fresnel weights on the way), as Intel OIDN asks of
//! its albedo and normal buffers. A feature ray draws no random number, so gathering features
//! leaves the beauty samples untouched.

use crate::bsdf::{Bsdf, BsdfSample, Lobe, LobeKind, MAX_LOBES, luminance};
use crate::integrator::Whitted;
use crate::math::{Ray, Rgb};
use crate::media::MediaStack;
use glam::{DVec2, DVec3};

/// Delta bounces followed before giving up (a ray trapped between mirrors).
pub const MAX_DELTA_BOUNCES: u32 = 8;

/// The features of one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FeatureSample {
    /// Reflectance of the first non-delta surface (the sum of its non-delta lobes' weights),
    /// times the weights of the delta events before it; 1 for a ray that escapes (the
    /// background passes through the demodulation unchanged), 0 for a surface with no lobe (a
    /// pure emitter).
    pub albedo: Rgb,
    /// Shading normal there, on the side the ray arrived from; zero for an escaping ray.
    pub normal: DVec3,
    /// The emission the camera ray sees directly: its first hit's outer-side emission (zero
    /// otherwise). Exactly the first-hit emission term both integrators add to the sample
    /// (weight 1 for a camera ray), so the denoiser can keep it out of the filter.
    pub emitted: Rgb,
}

/// The features along camera `ray` (the tracer's scene, offsets and surface interactions).
#[must_use]
pub fn first_non_delta(tracer: &Whitted<'_>, camera: Ray) -> FeatureSample {
    let scene = tracer.scene();
    let mut media = MediaStack::AIR;
    let mut tint = Rgb::ONE;
    let mut ray = camera;
    let mut normal = DVec3::ZERO;
    let mut emitted = None;
    for _ in 0..=MAX_DELTA_BOUNCES {
        let Some(hit) = scene.intersect(&ray, f64::INFINITY) else {
            return FeatureSample {
                albedo: tint,
                normal: DVec3::ZERO,
                emitted: emitted.unwrap_or(Rgb::ZERO),
            };
        };
        let si = tracer.core().surface(&ray, &hit, &media);
        normal = si.ns;
        // Only the first hit's: what the camera sees directly.
        let seen = *emitted.get_or_insert(if si.entering {
            si.material.emission
        } else {
            Rgb::ZERO
        });
        let bsdf = Bsdf::at(&si, si.material.roughness);
        if bsdf.lobes().next().is_none() {
            return FeatureSample {
                albedo: Rgb::ZERO,
                normal,
                emitted: seen,
            };
        }
        let albedo: Rgb = bsdf
            .lobes()
            .filter(|(l, _)| !l.is_delta())
            .map(|(l, _)| l.weight())
            .sum();
        let branch = strongest_delta_branch(&bsdf, &si);
        // A surface stops the feature ray unless a delta branch carries more than its
        // non-delta lobes (a mirror ball with a trace of diffuse is followed).
        if branch.is_none_or(|(_, w)| luminance(w) <= luminance(albedo)) {
            return FeatureSample {
                albedo: tint * albedo,
                normal,
                emitted: seen,
            };
        }
        let Some((s, w)) = branch else {
            break;
        };
        tint *= w;
        let transmits = matches!(
            s.kind,
            LobeKind::SpecularTransmission | LobeKind::GlossyTransmission
        );
        let (p, n, entering, ior) = (si.p, si.n, si.entering, si.material.ior);
        let side = if s.wi.dot(n) < 0.0 { -n } else { n };
        let from = crate::interaction::SurfaceId {
            object: hit.object,
            triangle: hit.triangle,
        };
        ray = tracer.core().spawn_ray(from, p, side, s.wi);
        if transmits {
            media = if entering {
                media.entered(hit.object, ior.unwrap_or(media.ior()))
            } else {
                media.left(hit.object)
            };
        }
    }
    FeatureSample {
        albedo: Rgb::ZERO,
        normal,
        emitted: emitted.unwrap_or(Rgb::ZERO),
    }
}

/// The delta branch carrying the most at `si`, with its weight: the first and the last delta
/// lobe's events (mirror, Fresnel reflection, refraction), compared by their weight f |cos| (a
/// delta sample's value is its coefficient over |cos|).
fn strongest_delta_branch(
    bsdf: &Bsdf,
    si: &crate::interaction::SurfaceInteraction<'_>,
) -> Option<(BsdfSample, Rgb)> {
    let mut delta = [Lobe::Lambert { albedo: Rgb::ZERO }; MAX_LOBES];
    let mut k = 0;
    for (l, _) in bsdf.lobes().filter(|(l, _)| l.is_delta()) {
        delta[k] = *l;
        k += 1;
    }
    let specular = Bsdf::new(*bsdf.frame(), &delta[..k]);
    let u = DVec2::splat(0.5);
    [1e-9, 1.0 - 1e-9]
        .into_iter()
        .filter_map(|uc| specular.sample(si.wo, uc, u))
        .filter(|s| s.value.is_finite())
        .map(|s| (s, s.value * s.wi.dot(si.ns).abs()))
        .max_by(|a, b| luminance(a.1).total_cmp(&luminance(b.1)))
}
