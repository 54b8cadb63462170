//! Which samples each pixel of a render takes: the [`AdaptivePlan`] of `settings.adaptive` or of
//! automatic antialiasing (`settings.antialiasing: "auto"`), and the words `raytree effects`
//! and the inspector use for it.

use crate::integrator::Integrator;
use crate::scene::{AUTO_THRESHOLD, Antialiasing};

/// Which samples the pixels of a render take when some take more than others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptivePlan {
    /// Samples of every pixel's first pass.
    pub first: u32,
    /// Samples of a refined pixel in all (first pass included).
    pub total: u32,
    /// Contrast above which a pixel is refined.
    pub threshold: f64,
    /// Automatic antialiasing: film positions of its own, the pixel's Owen-scrambled Sobol
    /// points (the scene's sampler is not used): the first pass is points `0..first`, a refined
    /// pixel continues the sequence to `total`.
    pub auto: bool,
}

/// Automatic antialiasing's first pass is `spp / AUTO_FIRST_DIVISOR` Sobol points, at least 2
/// (and at most `spp`). Two points of a (0, 2)-sequence are stratified in halves, so a pixel
/// alone has a spread; a first pass that grows with `spp` lets the image converge as `spp`
/// grows, where a fixed one misses, at any spp, features thinner than its sample spacing. On
/// `benches/mitsuba-scenes/glass-emitters.json` against a 1024-spp uniform reference, one probe
/// through each pixel centre as the first pass (tried first) gave 0.0065 at 64 spp and 0.0059
/// at 256 at 160x90, and 0.073 at 16 spp at 48x27, where this rule gives 0.0032, 0.0013 and
/// 0.0185 (docs/cost.md).
pub const AUTO_FIRST_DIVISOR: u32 = 16;

/// The plan of a render by `integrator`: `settings.adaptive` when set (first pass `spp`,
/// refined to its `max_spp`); otherwise, under `settings.antialiasing: "auto"`, automatic
/// antialiasing (a first pass of `spp / 16` Sobol points, at least 2, refined to `spp`
/// samples where the contrast exceeds [`AUTO_THRESHOLD`]) when
/// `spp >= 2`, no `settings.sampler` is chosen and the radiance of a camera sample is a
/// function of its film position alone ([`Integrator::film_only`]); `None`: every pixel takes
/// `spp` samples.
#[must_use]
pub fn adaptive_plan<I: Integrator>(integrator: &I) -> Option<AdaptivePlan> {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    // Light tracing divides every pixel's splats by the same `spp` (`super::splat`).
    if integrator.splats() {
        return None;
    }
    if let Some(a) = settings.adaptive {
        return Some(AdaptivePlan {
            first: spp,
            total: a.max_spp(spp).max(spp),
            threshold: a.threshold,
            auto: false,
        });
    }
    let auto = settings.antialiasing == Antialiasing::Auto
        && spp >= 2
        && settings.sampler.is_none()
        && integrator.film_only();
    auto.then_some(AdaptivePlan {
        first: (spp / AUTO_FIRST_DIVISOR).max(2).min(spp),
        total: spp,
        threshold: AUTO_THRESHOLD,
        auto: true,
    })
}

/// How the pixels of a render by `integrator` are sampled, in words (`raytree effects`): the
/// plan ([`adaptive_plan`]) and, for a uniform render of more than one sample, why automatic
/// antialiasing does not apply.
#[must_use]
pub fn antialiasing_note<I: Integrator>(integrator: &I) -> String {
    let settings = &integrator.scene().settings;
    let spp = settings.spp.max(1);
    match adaptive_plan(integrator) {
        Some(p) if p.auto => format!(
            "spp {spp}, automatic antialiasing: a first pass of {} Sobol points per pixel, {} \
             samples where a pixel's first pass and its 8 neighbours' differ (contrast > {}); \
             settings.antialiasing \"uniform\" for {spp} everywhere",
            p.first, p.total, p.threshold
        ),
        Some(p) => format!(
            "spp {spp}, adaptive: {} samples where a pixel's first {} and its neighbours' \
             differ (contrast > {})",
            p.total, p.first, p.threshold
        ),
        None if spp == 1 => "spp 1".to_string(),
        None => {
            let why = if settings.antialiasing == Antialiasing::Uniform {
                "settings.antialiasing uniform"
            } else if settings.sampler.is_some() {
                "settings.sampler chosen"
            } else if integrator.kind() != crate::scene::IntegratorKind::Whitted {
                "the path integrator's samples all differ"
            } else if !integrator.traces_packets() {
                "area lights or rough lobes make every sample differ"
            } else if integrator.film().has_lens() {
                "the lens makes every sample differ"
            } else {
                "the dielectric roulette makes every sample differ"
            };
            format!("spp {spp} in every pixel ({why})")
        }
    }
}
