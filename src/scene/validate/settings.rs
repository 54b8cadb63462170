//! Settings checks, shared by scene files and command-line overrides: `(json path, message)`
//! on error, the caller adds the file and position.

use crate::scene::desc::Settings;

/// Largest accepted `settings.spp` (and `adaptive.max_spp`).
pub const MAX_SPP: u32 = 65_536;

/// Largest accepted per-sample ray budget (2^32).
pub const MAX_RAYS_LIMIT: u64 = 1 << 32;

/// Validate settings (also used for command-line overrides): `(json path, message)` on error.
/// An integrator's own setting is named by its key in the flat record (`settings.rr_depth`,
/// [`crate::scene::desc::SettingsRecord`]): a scene file's check finds where the file writes it.
pub fn check_settings(s: &Settings) -> Result<Settings, (String, String)> {
    if s.spp == 0 || s.spp > 65_536 {
        return Err((
            "settings.spp".into(),
            format!("must be in 1..=65536, got {}", s.spp),
        ));
    }
    if s.max_depth > 1024 {
        return Err((
            "settings.max_depth".into(),
            format!("must be at most 1024, got {}", s.max_depth),
        ));
    }
    let eps = s.offset.epsilon;
    if !(eps.is_finite() && eps >= 0.0) {
        return Err((
            "settings.offset.epsilon".into(),
            format!("must be a finite number >= 0, got {eps}"),
        ));
    }
    if let Some(w) = s.whitted.min_weight
        && !(w.is_finite() && w >= 0.0)
    {
        return Err((
            "settings.min_weight".into(),
            format!("must be a finite number >= 0, got {w}"),
        ));
    }
    if let Some(w) = s.whitted.roulette_below
        && !(w.is_finite() && w >= 0.0)
    {
        return Err((
            "settings.roulette_below".into(),
            format!("must be a finite number >= 0, got {w}"),
        ));
    }
    if !(s.whitted.tolerance.is_finite() && s.whitted.tolerance >= 0.0) {
        return Err((
            "settings.tolerance".into(),
            format!("must be a finite number >= 0, got {}", s.whitted.tolerance),
        ));
    }
    if s.max_rays == 0 || s.max_rays > MAX_RAYS_LIMIT {
        return Err((
            "settings.max_rays".into(),
            format!("must be in 1..={MAX_RAYS_LIMIT}, got {}", s.max_rays),
        ));
    }
    if let Some(n) = s.whitted.light_samples
        && !(1..=MAX_LIGHT_SAMPLES).contains(&n)
    {
        return Err((
            "settings.light_samples".into(),
            format!("must be in 1..={MAX_LIGHT_SAMPLES}, got {n}"),
        ));
    }
    check_rr_depth(s.path.rr_depth).map_err(|m| ("settings.rr_depth".to_string(), m))?;
    if !(1..=MAX_GLOSSY_SAMPLES).contains(&s.whitted.glossy_samples) {
        return Err((
            "settings.glossy_samples".into(),
            format!(
                "must be in 1..={MAX_GLOSSY_SAMPLES}, got {}",
                s.whitted.glossy_samples
            ),
        ));
    }
    check_filter(&s.filter)?;
    if let Some(d) = s.whitted.dielectric_roulette
        && d > 1024
    {
        return Err((
            "settings.dielectric_roulette".into(),
            format!("must be at most 1024, got {d}"),
        ));
    }
    if let Some(a) = s.adaptive {
        check_adaptive(&a, s.spp)?;
    }
    Ok(*s)
}

/// Largest accepted `settings.rr_depth`.
pub const MAX_RR_DEPTH: u32 = 1024;

/// A Russian-roulette depth: the first bounce at which roulette may end a path, 1 to
/// [`MAX_RR_DEPTH`]. 0 is refused: bounce 1 is the first a path makes, so it would mean 1.
///
/// # Errors
/// The message for an out-of-range depth.
pub fn check_rr_depth(n: u32) -> Result<u32, String> {
    match n {
        0 => Err(
            "must be at least 1 (roulette from bounce N on; bounce 1 is the first, so 0 would mean the same as 1)"
                .into(),
        ),
        n if n > MAX_RR_DEPTH => Err(format!("must be at most {MAX_RR_DEPTH}, got {n}")),
        n => Ok(n),
    }
}

/// `settings.adaptive`: a finite threshold >= 0 and `max_spp` in `spp..=65536`. A first pass
/// of one sample is allowed: the neighbours' first passes give it a spread.
fn check_adaptive(a: &crate::scene::desc::AdaptiveDesc, spp: u32) -> Result<(), (String, String)> {
    if !(a.threshold.is_finite() && a.threshold >= 0.0) {
        return Err((
            "settings.adaptive.threshold".into(),
            format!("must be a finite number >= 0, got {}", a.threshold),
        ));
    }
    if let Some(m) = a.max_spp
        && !(spp..=65_536).contains(&m)
    {
        return Err((
            "settings.adaptive.max_spp".into(),
            format!("must be in spp..=65536 ({spp}..=65536), got {m}"),
        ));
    }
    Ok(())
}

/// Largest accepted `settings.glossy_samples`.
pub const MAX_GLOSSY_SAMPLES: u32 = 65_536;

/// Largest accepted `settings.light_samples`.
pub const MAX_LIGHT_SAMPLES: u32 = 65_536;

/// Largest pixel-filter radius (and Gaussian sigma), in pixels: a wider filter draws nearly
/// every camera ray far outside the image (`--filter gaussian:1e308` gave a background-only
/// image with no note).
pub const MAX_FILTER_RADIUS: f64 = 1024.0;

/// `settings.filter`: radius and sigma finite, > 0 and at most [`MAX_FILTER_RADIUS`] pixels.
fn check_filter(f: &crate::scene::desc::FilterDesc) -> Result<(), (String, String)> {
    use crate::scene::desc::FilterDesc;
    let positive = |name: &str, v: f64| {
        if !(v.is_finite() && v > 0.0) {
            Err((
                format!("settings.filter.{name}"),
                format!("must be a finite number > 0, got {v}"),
            ))
        } else if v > MAX_FILTER_RADIUS {
            Err((
                format!("settings.filter.{name}"),
                format!(
                    "must be at most {MAX_FILTER_RADIUS} pixels (wider, nearly every camera ray leaves the image), got {v:e}"
                ),
            ))
        } else {
            Ok(())
        }
    };
    match *f {
        FilterDesc::Box {} => Ok(()),
        FilterDesc::Tent { radius } => positive("radius", radius),
        FilterDesc::Gaussian { sigma, radius } => {
            positive("sigma", sigma)?;
            radius.map_or(Ok(()), |r| positive("radius", r))
        }
    }
}
