//! Monte Carlo statistics of a pixel and the debug views that map them to colour.

use super::AovRender;

/// What one pixel's samples did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct McPixel {
    /// Samples taken (`settings.spp`, or `max_spp` where adaptive antialiasing refined the
    /// pixel; a dropped sample counts, as black).
    pub samples: u32,
    /// Samples whose radiance was NaN or infinite, dropped (counted black).
    pub dropped: u32,
    /// Samples whose path Russian roulette ended.
    pub roulette: u32,
    /// Mean path rays per sample (the camera ray and its continuations; shadow rays not
    /// counted). 0 under Whitted (it reports no paths).
    pub path_length: f64,
    /// Mean sample luminance (Rec. 709 weights).
    pub mean: f64,
    /// Relative standard error of the pixel mean: `sqrt(s^2 / n) / mean` with `s^2` the
    /// samples' unbiased luminance variance; 0 for a black pixel or a single sample (not
    /// estimable).
    pub rel_err: f64,
}

impl McPixel {
    /// Set [`McPixel::mean`] and [`McPixel::rel_err`] from the samples' luminances.
    pub fn set_spread(&mut self, lums: &[f64]) {
        let (mean, rel) = spread(lums);
        self.mean = mean;
        self.rel_err = rel;
    }
}

/// Mean and relative standard error of the mean of `x` (two passes: the mean, then the squared
/// deviations from it, so a constant sample set gives exactly 0).
#[must_use]
pub fn spread(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    if x.is_empty() {
        return (0.0, 0.0);
    }
    let mean = x.iter().sum::<f64>() / n;
    if x.len() < 2 || mean <= 0.0 {
        return (mean, 0.0);
    }
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt() / mean)
}

/// A debug view of an [`AovRender`]: one scalar per pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum McView {
    /// Relative standard error of the pixel mean ([`McPixel::rel_err`]).
    Noise,
    /// Samples per pixel.
    Spp,
    /// Mean path rays per sample.
    PathLength,
    /// Russian-roulette terminations per pixel.
    Roulette,
    /// NaN/Inf samples dropped per pixel.
    Dropped,
    /// The share of AOV `k` in the pixel (luminance of the AOV over the beauty's).
    Share(usize),
}

impl McView {
    /// The names [`McView::parse`] takes (`share:NAME` for an AOV's share).
    pub const NAMES: [&'static str; 6] = [
        "noise",
        "spp",
        "path-length",
        "roulette",
        "dropped",
        "share:AOV",
    ];

    /// The view called `name`; `share:NAME` names one of `aovs`.
    ///
    /// # Errors
    /// A message listing the views, or the AOVs for an unknown `share:` name.
    pub fn parse(name: &str, aovs: &[&str]) -> Result<Self, String> {
        Ok(match name {
            "noise" => Self::Noise,
            "spp" => Self::Spp,
            "path-length" => Self::PathLength,
            "roulette" => Self::Roulette,
            "dropped" => Self::Dropped,
            _ => {
                let Some(aov) = name.strip_prefix("share:") else {
                    return Err(format!(
                        "unknown debug view {}; the views are {}",
                        crate::input::quote(name),
                        Self::NAMES.join(", ")
                    ));
                };
                if aov.is_empty() {
                    return Err(
                        "debug view \"share:\" needs the name of an AOV: share:NAME, with --aov NAME=LPE"
                            .into(),
                    );
                }
                let Some(k) = aovs.iter().position(|a| *a == aov) else {
                    return Err(format!(
                        "debug view {}: no AOV named {} (give it with --aov NAME=LPE)",
                        crate::input::quote(name),
                        crate::input::quote(aov)
                    ));
                };
                Self::Share(k)
            }
        })
    }

    /// A file-name friendly name (`noise`, `share-caustics`), given the AOV names.
    #[must_use]
    pub fn file_name(&self, aovs: &[&str]) -> String {
        match self {
            Self::Share(k) => format!("share-{}", aovs.get(*k).copied().unwrap_or("?")),
            Self::Noise => "noise".into(),
            Self::Spp => "spp".into(),
            Self::PathLength => "path-length".into(),
            Self::Roulette => "roulette".into(),
            Self::Dropped => "dropped".into(),
        }
    }

    /// What the colour scale measures, for the legend.
    #[must_use]
    pub fn label(&self, aovs: &[&str]) -> String {
        match self {
            Self::Noise => "relative standard error of the pixel mean".into(),
            Self::Spp => "samples per pixel".into(),
            Self::PathLength => "mean path rays per sample".into(),
            Self::Roulette => "Russian-roulette terminations per pixel".into(),
            Self::Dropped => "non-finite samples dropped per pixel".into(),
            Self::Share(k) => format!(
                "share of AOV {} in the pixel (luminance)",
                aovs.get(*k).copied().unwrap_or("?")
            ),
        }
    }

    /// Whether the view needs the path integrator (Whitted reports no paths).
    #[must_use]
    pub fn needs_paths(&self) -> bool {
        matches!(self, Self::PathLength | Self::Roulette | Self::Share(_))
    }

    /// The value of pixel `i` of `r`.
    #[must_use]
    pub fn value(&self, r: &AovRender, i: usize) -> f64 {
        let p = &r.mc[i];
        match self {
            Self::Noise => p.rel_err,
            Self::Spp => f64::from(p.samples),
            Self::PathLength => p.path_length,
            Self::Roulette => f64::from(p.roulette),
            Self::Dropped => f64::from(p.dropped),
            Self::Share(k) => {
                let lum = crate::bsdf::luminance;
                let total = lum(r.beauty.pixels[i]);
                if total > 0.0 {
                    lum(r.aovs[*k].pixels[i]) / total
                } else {
                    0.0
                }
            }
        }
    }

    /// Every pixel's value, row-major.
    #[must_use]
    pub fn values(&self, r: &AovRender) -> Vec<f64> {
        (0..r.mc.len()).map(|i| self.value(r, i)).collect()
    }

    /// The colour scale's range `(0, max)`: shares on `[0, 1]`; the noise up to its 99th
    /// percentile (a few fireflies would wash the rest out); the rest up to the maximum (at
    /// least 1).
    #[must_use]
    pub fn range(&self, values: &[f64]) -> (f64, f64) {
        let max = match self {
            Self::Share(_) => 1.0,
            Self::Noise if !values.is_empty() => {
                let mut v = values.to_vec();
                let k = (v.len() - 1) * 99 / 100;
                *v.select_nth_unstable_by(k, f64::total_cmp).1
            }
            _ => values.iter().copied().fold(0.0, f64::max),
        };
        (0.0, if max > 0.0 { max } else { 1.0 })
    }
}

/// A perceptually ordered ramp (a compact "turbo"-like map): black for zero, then blue, cyan,
/// green, yellow, red as `t` goes from 0 to 1. Returns sRGB bytes.
#[must_use]
pub fn ramp(t: f32) -> [u8; 3] {
    if t <= 0.0 {
        return [0, 0, 0];
    }
    const STOPS: [[f32; 3]; 6] = [
        [0.05, 0.05, 0.35],
        [0.1, 0.35, 0.95],
        [0.1, 0.85, 0.85],
        [0.3, 0.9, 0.2],
        [0.98, 0.85, 0.1],
        [0.9, 0.1, 0.1],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let c = |k: usize| STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f;
    [0, 1, 2].map(|k| (c(k) * 255.0 + 0.5) as u8)
}
