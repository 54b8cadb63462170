//! Settings checks, shared by scene files and command-line overrides: `(json path, message)`
//! on error, the caller adds the file and position.

use crate::scene::desc::Settings;

/// Largest accepted per-sample ray budget (2^32).
pub const MAX_RAYS_LIMIT: u64 = 1 << 32;

/// Validate settings (also used for command-line overrides): `(json path, message)` on error.
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
    if let Some(w) = s.min_weight
        && !(w.is_finite() && w >= 0.0)
    {
        return Err((
            "settings.min_weight".into(),
            format!("must be a finite number >= 0, got {w}"),
        ));
    }
    if let Some(w) = s.roulette_below
        && !(w.is_finite() && w >= 0.0)
    {
        return Err((
            "settings.roulette_below".into(),
            format!("must be a finite number >= 0, got {w}"),
        ));
    }
    if !(s.tolerance.is_finite() && s.tolerance >= 0.0) {
        return Err((
            "settings.tolerance".into(),
            format!("must be a finite number >= 0, got {}", s.tolerance),
        ));
    }
    if s.max_rays == 0 || s.max_rays > MAX_RAYS_LIMIT {
        return Err((
            "settings.max_rays".into(),
            format!("must be in 1..={MAX_RAYS_LIMIT}, got {}", s.max_rays),
        ));
    }
    if let Some(n) = s.light_samples
        && !(1..=MAX_LIGHT_SAMPLES).contains(&n)
    {
        return Err((
            "settings.light_samples".into(),
            format!("must be in 1..={MAX_LIGHT_SAMPLES}, got {n}"),
        ));
    }
    if s.rr_depth > 1024 {
        return Err((
            "settings.rr_depth".into(),
            format!("must be at most 1024, got {}", s.rr_depth),
        ));
    }
    if !(1..=MAX_GLOSSY_SAMPLES).contains(&s.glossy_samples) {
        return Err((
            "settings.glossy_samples".into(),
            format!(
                "must be in 1..={MAX_GLOSSY_SAMPLES}, got {}",
                s.glossy_samples
            ),
        ));
    }
    check_filter(&s.filter)?;
    if let Some(d) = s.dielectric_roulette
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

/// `settings.filter`: radius and sigma finite and > 0.
fn check_filter(f: &crate::scene::desc::FilterDesc) -> Result<(), (String, String)> {
    use crate::scene::desc::FilterDesc;
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err((
                format!("settings.filter.{name}"),
                format!("must be a finite number > 0, got {v}"),
            ))
        }
    };
    match *f {
        FilterDesc::Box => Ok(()),
        FilterDesc::Tent { radius } => positive("radius", radius),
        FilterDesc::Gaussian { sigma, radius } => {
            positive("sigma", sigma)?;
            radius.map_or(Ok(()), |r| positive("radius", r))
        }
    }
}
