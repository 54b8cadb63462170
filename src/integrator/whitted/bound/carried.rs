//! A tighter bound on the radiance a ray carries, material by material, and the automatic
//! roulette weight it sets (`settings.roulette_below`).
//!
//! [`super::radiance_bound`] takes the largest local term and the largest split of any
//! material together, as if one material could emit like the brightest lamp and pass on all
//! light like clear glass; between glass objects its `1 + s + ... + s^k` then grows with the
//! depth. Each hit is on one material, so the recursion of the lecture's `trace` bounds, per
//! colour channel,
//!
//! - `L_0 = max(background, max_m B_m)`: a ray at the depth limit carries its hit's local term
//!   (its secondary rays are cut) or the background;
//! - `L_k = max(background, max_m (B_m + s_m L_(k-1)))`: a hit on material `m` adds its local
//!   term `B_m` and its secondary rays, whose weights sum to at most `s_m`, each carrying at most
//!   `L_(k-1)`,
//!
//! with `B_m` as in the module notes of [`super`] for material `m` alone, and `s_m =
//! max(reflectivity) + max(transmissivity)` (max channels), which also bounds the weight of the
//! one ray a Russian-roulette choice follows (its split weight over its probability). `L_k` grows
//! with `k` and stops growing as soon as no material both shines and passes light on: a scene
//! of lamps, mirrors and clear glass has `L_k = ` its brightest lamp (or background) at every
//! depth, where the shared bound is `k + 1` times that.

use super::{Terms, area_emission, light_irradiance};
use crate::math::Rgb;
use crate::scene::{IntegratorKind, Scene, Settings, ShadowMode};

/// The radiance (linear, display range 1) one roulette decision may move a sample by at most,
/// under the automatic `roulette_below`: a hit of throughput `tau` below the weight
/// `ROULETTE_RADIANCE / L` (`L` the [`carried_bound`]) carries at most `tau L <
/// ROULETTE_RADIANCE`, so following one of its two rays (weight divided by its probability)
/// instead of both changes the sample by less than that. Measured on
/// `benches/mitsuba-scenes/mirror-corridor.json`, `glass-emitters.json` and
/// `fixtures/nested.json` at 1 spp (docs/cost.md): RMSE against the split of at most 2.3e-4,
/// 0.17-0.49% of the pixels off by more than 1/255, where the split traced 1.1-2.3x the rays.
pub const ROULETTE_RADIANCE: f64 = 0.01;

/// The most linear radiance (any channel) a ray can carry with up to `max_depth` bounces left,
/// material by material (module notes); may be infinite. Far below [`super::radiance_bound`]
/// where it grows with depth (that one multiplies by `1 + s + ... + s^k`).
#[must_use]
pub fn carried_bound(scene: &Scene, max_depth: u32, shadows: ShadowMode) -> f64 {
    let Some(irradiance) = light_irradiance(scene, shadows) else {
        return f64::INFINITY;
    };
    let ambient = scene.ambient.max(Rgb::ZERO);
    let area = area_emission(scene);
    let terms: Vec<(Rgb, Rgb)> = scene
        .used_materials()
        .map(|m| {
            // The split's weights sum to at most `reflectivity + transmissivity` per channel;
            // where the roulette follows one ray instead, it divides that ray's weight by its
            // probability, `max(w_r) / (max(w_r) + max(w_t))` or the complement, so each
            // channel stays below `max(w_r) + max(w_t) <= max(reflectivity) +
            // max(transmissivity)`: the bound of both, since it is never below the first.
            let max = |c: Rgb| c.max_element().max(0.0);
            let split = Rgb::splat(max(m.reflectivity) + max(m.transmissivity));
            (Terms::of(m).local(ambient, irradiance, area), split)
        })
        .collect();
    let background = scene.background.max(Rgb::ZERO);
    let step = |carried: Rgb| {
        terms.iter().fold(background, |acc, &(local, split)| {
            acc.max(local + split * carried)
        })
    };
    // An infinite term (a point light on a lit surface) is infinite at once; checked before it
    // is carried on, where a material that passes nothing on (`0 x inf`, NaN) would drop it.
    let mut bound = step(Rgb::ZERO);
    for _ in 0..max_depth {
        if !bound.is_finite() {
            break;
        }
        let next = step(bound);
        if next == bound {
            break;
        }
        bound = next;
    }
    if bound.is_finite() {
        bound.max_element()
    } else {
        f64::INFINITY
    }
}

/// The roulette weight the Whitted tracer uses: `settings.roulette_below` when given, else 0:
/// every glass hit splits, so the default image is deterministic, the lecture's algorithm
/// (issue 32: the automatic roulette made 0.17% of `nested.json`'s pixels differ by more than
/// 1/255 from the exhaustive tree and every Whitted image with glass noisy at 1 spp). The cut
/// (`min_weight`) alone bounds the work; [`auto_roulette_below`] is the weight `raytree
/// effects` and `cost` suggest, opt-in.
#[must_use]
pub fn effective_roulette_below(scene: &Scene) -> f64 {
    scene.settings.whitted.roulette_below.unwrap_or(0.0)
}

/// The automatic roulette weight for `s` (max depth, shadows and what turns it off) on `scene`:
/// [`ROULETTE_RADIANCE`] over the [`carried_bound`], in
/// `[0, 1]`; 0 (always split) for the path integrator, an explicit `min_weight` (the
/// exhaustive tree of `min_weight 0` stays exhaustive), a tolerance of 0, the depth roulette
/// (`dielectric_roulette`) or an unbounded radiance.
#[must_use]
pub fn auto_roulette_below(scene: &Scene, s: &Settings) -> f64 {
    if s.integrator != IntegratorKind::Whitted
        || s.whitted.min_weight.is_some()
        || s.whitted.tolerance <= 0.0
        || s.whitted.dielectric_roulette.is_some()
    {
        return 0.0;
    }
    let bound = carried_bound(scene, s.max_depth, s.whitted.shadows);
    if !bound.is_finite() {
        return 0.0;
    }
    if bound <= 0.0 {
        return 1.0;
    }
    (ROULETTE_RADIANCE / bound).clamp(0.0, 1.0)
}

/// Whether some dielectric hits play Russian roulette instead of splitting, and why, in words
/// (`raytree effects`).
#[must_use]
pub fn roulette_note(scene: &Scene) -> (bool, String) {
    let s = &scene.settings;
    let glass = scene.used_materials().any(|m| m.is_transmissive());
    if !glass {
        return (false, "no transmissive material: nothing splits".into());
    }
    if s.integrator != IntegratorKind::Whitted {
        return (false, "the path integrator samples one ray per hit".into());
    }
    if let Some(d) = s.whitted.dielectric_roulette {
        return (
            true,
            format!(
                "settings.dielectric_roulette: from depth {d}, one of reflection and refraction"
            ),
        );
    }
    let w = effective_roulette_below(scene);
    let what = format!(
        "glass hits of throughput below {w:.2e} follow one of reflection and refraction, weight / \
         probability (exact in expectation)"
    );
    let suggested = auto_roulette_below(scene, s);
    match s.whitted.roulette_below {
        Some(0.0) => (
            false,
            "settings.roulette_below 0: every glass hit splits".into(),
        ),
        Some(_) => (true, format!("{what}; settings.roulette_below")),
        None if suggested > 0.0 => (
            false,
            format!(
                "off (the default: every glass hit splits, the image is deterministic and the cut \
                 bounds the work); opt in with --roulette-below {suggested:.2e} ({ROULETTE_RADIANCE} \
                 / the radiance a ray can carry, {:.3}) to follow one ray below that weight, exact \
                 in expectation but noisy (`raytree cost` measures what it saves)",
                carried_bound(scene, s.max_depth, s.whitted.shadows)
            ),
        ),
        None => (false, "off (the default): every glass hit splits".into()),
    }
}
