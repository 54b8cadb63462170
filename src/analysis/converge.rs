//! Convergence of stochastic renders (issue 16): relative RMSE against a reference versus
//! samples per pixel and versus seconds, per series (an estimator, sampler or setting), with the
//! least-squares slope of each curve on log-log axes (a plain Monte Carlo estimator has slope
//! -1/2 against samples). Pure apart from reading the clock.

use crate::denoise::{DenoiseParams, denoise, gather_sampled};
use crate::integrator::{Integrator, PathStrategy, PathTracer, SceneIntegrator};
use crate::math::Rgb;
use crate::render::{Image, render};
use crate::sampling::{PixelSampler, SceneSampler};
use crate::scene::{IntegratorKind, SamplerKind, Scene};
use serde::Serialize;
use web_time::Instant;

/// The relative error's offset: `(img - ref) / (ref + REL_OFFSET)`, as `benches/vs_mitsuba.py`.
pub const REL_OFFSET: f64 = 0.01;

/// Relative RMSE of `img` against `reference`: the root mean square over pixels and channels of
/// `(img - ref) / (ref + 0.01)`; `None` if the sizes differ or the image is empty.
#[must_use]
pub fn rel_rmse(img: &Image, reference: &Image) -> Option<f64> {
    if (img.width, img.height) != (reference.width, reference.height) || img.pixels.is_empty() {
        return None;
    }
    let rel = || {
        img.pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, r)| (*a - *r) / (*r + Rgb::splat(REL_OFFSET)))
    };
    let n = 3.0 * img.pixels.len() as f64;
    let sq: f64 = rel().map(Rgb::length_squared).sum();
    let plain = (sq / n).sqrt();
    if plain.is_finite() {
        return Some(plain);
    }
    // Relative errors whose squares overflow (a background of 1e200 against a reference near
    // 0): the same root from errors scaled by the largest (issue 27), when that is finite.
    let top = rel().map(|e| e.abs().max_element()).fold(0.0, f64::max);
    if !(top.is_finite() && top > 0.0) {
        return Some(plain);
    }
    let scaled: f64 = rel().map(|e| (e / top).length_squared()).sum();
    Some(top * (scaled / n).sqrt())
}

/// The least-squares slope of `ln y` against `ln x` over the points with both positive and
/// finite; `None` with fewer than two distinct `x`.
#[must_use]
pub fn loglog_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (pts.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

/// What one curve renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Series {
    /// The scene's integrator and sampler as set (path: MIS, Sobol unless the scene says).
    Default,
    /// Path tracing with light sampling only.
    LightOnly,
    /// Path tracing with BSDF sampling only.
    BsdfOnly,
    /// The scene's integrator with the Owen-scrambled Sobol sampler.
    Sobol,
    /// The scene's integrator with stratified jitter (the film offset stratified, the other
    /// dimensions independent).
    Stratified,
    /// The scene's integrator with Russian roulette from this bounce on.
    RrDepth(u32),
    /// [`Series::Default`] denoised ([`crate::denoise`]); its time includes the feature rays
    /// and the filter.
    Denoised,
}

impl Series {
    /// Parse a `--series` name: `default`, `light-only`, `bsdf-only`, `sobol`, `stratified`,
    /// `rr:N`, `denoise`.
    ///
    /// # Errors
    /// An unknown name, with the accepted ones.
    pub fn parse(s: &str) -> Result<Self, String> {
        Ok(match s {
            "default" => Self::Default,
            "light-only" => Self::LightOnly,
            "bsdf-only" => Self::BsdfOnly,
            "sobol" => Self::Sobol,
            "stratified" => Self::Stratified,
            "denoise" => Self::Denoised,
            _ => match s.strip_prefix("rr:").map(str::parse::<u32>) {
                Some(Ok(n)) => Self::RrDepth(
                    crate::scene::check_rr_depth(n).map_err(|e| format!("{s}: the depth {e}"))?,
                ),
                _ => {
                    return Err(format!(
                        "unknown series {s:?}: expected default, light-only, bsdf-only, sobol, stratified, rr:N or denoise"
                    ));
                }
            },
        })
    }

    /// The name in reports.
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Default => "default".into(),
            Self::LightOnly => "light-only".into(),
            Self::BsdfOnly => "bsdf-only".into(),
            Self::Sobol => "sobol".into(),
            Self::Stratified => "stratified".into(),
            Self::RrDepth(n) => format!("rr:{n}"),
            Self::Denoised => "denoise".into(),
        }
    }

    /// Whether the series needs the path integrator.
    #[must_use]
    pub fn needs_path(&self) -> bool {
        matches!(self, Self::LightOnly | Self::BsdfOnly | Self::RrDepth(_))
    }

    /// The default series for `scene`: for the path integrator the MIS estimator (with the
    /// scene's sampler) against light and BSDF sampling alone, the other sampler and the
    /// denoised default; otherwise the default, the other sampler and denoised.
    #[must_use]
    pub fn defaults(scene: &Scene) -> Vec<Self> {
        let other = match scene.settings.sampler_kind() {
            SamplerKind::Sobol => Self::Stratified,
            SamplerKind::Stratified => Self::Sobol,
        };
        if scene.settings.integrator == IntegratorKind::Path {
            vec![
                Self::Default,
                Self::LightOnly,
                Self::BsdfOnly,
                other,
                Self::Denoised,
            ]
        } else {
            vec![Self::Default, other, Self::Denoised]
        }
    }
}

/// One point of a curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Point {
    /// Samples per pixel.
    pub spp: u32,
    /// Wall-clock seconds of the render (and filter).
    pub seconds: f64,
    /// Relative RMSE against the reference ([`rel_rmse`]).
    pub rel_rmse: f64,
}

/// One curve and its fitted slopes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Curve {
    /// The series.
    pub series: Series,
    /// Its name.
    pub name: String,
    /// One point per spp.
    pub points: Vec<Point>,
    /// Slope of log rel-RMSE against log spp.
    pub slope_spp: Option<f64>,
    /// Slope of log rel-RMSE against log seconds.
    pub slope_seconds: Option<f64>,
}

/// Render `scene` at its settings' spp as `series` draws it; the image and the seconds taken.
#[must_use]
pub fn render_series(scene: &Scene, series: Series) -> (Image, f64) {
    let mut s = scene.clone();
    if let Series::RrDepth(n) = series {
        s.settings.path.rr_depth = n;
    }
    // A sampler series names its sampler in the settings too, so automatic antialiasing (its
    // own film positions, for the default series) stands aside and the series is that sampler.
    match series {
        Series::Sobol => s.settings.sampler = Some(SamplerKind::Sobol),
        Series::Stratified => s.settings.sampler = Some(SamplerKind::Stratified),
        _ => {}
    }
    let strat = SceneSampler::for_settings(&s.settings);
    let start = Instant::now();
    let image = match series {
        Series::LightOnly => run(
            &PathTracer::with_strategy(&s, PathStrategy::LightOnly),
            &strat,
        ),
        Series::BsdfOnly => run(
            &PathTracer::with_strategy(&s, PathStrategy::BsdfOnly),
            &strat,
        ),
        Series::Sobol | Series::Stratified => {
            let kind = match series {
                Series::Sobol => SamplerKind::Sobol,
                _ => SamplerKind::Stratified,
            };
            let sampler = SceneSampler::new(kind, s.settings.spp, s.settings.seed);
            run(&SceneIntegrator::new(&s), &sampler)
        }
        Series::Denoised => {
            let (image, _, features) = gather_sampled(&SceneIntegrator::new(&s), &strat, &|_| {});
            denoise(&image, &features, &DenoiseParams::default())
        }
        Series::Default | Series::RrDepth(_) => run(&SceneIntegrator::new(&s), &strat),
    };
    (image, start.elapsed().as_secs_f64())
}

fn run<I: Integrator, S: PixelSampler>(integrator: &I, sampler: &S) -> Image {
    render(
        integrator,
        &crate::render::RenderOptions::new().with_sampler(sampler.clone()),
        &|_| {},
    )
    .image
}

/// The reference: the scene's integrator at `spp` samples in every pixel (uniform
/// antialiasing: automatic antialiasing's unrefined pixels stop at their first pass, which
/// is not the best estimate of the pixel's integral).
#[must_use]
pub fn reference(scene: &Scene, spp: u32) -> Image {
    let mut s = scene.clone();
    s.settings.spp = spp.max(1);
    s.settings.antialiasing = crate::scene::Antialiasing::Uniform;
    render_series(&s, Series::Default).0
}

/// Every series at every spp of `spps` against `reference` (of the scene's size); `progress`
/// is called with (renders done, renders in all).
#[must_use]
pub fn converge(
    scene: &Scene,
    reference: &Image,
    series: &[Series],
    spps: &[u32],
    progress: &dyn Fn(usize, usize),
) -> Vec<Curve> {
    let total = series.len() * spps.len();
    let mut done = 0;
    let mut s = scene.clone();
    series
        .iter()
        .map(|&se| {
            let points: Vec<Point> = spps
                .iter()
                .map(|&spp| {
                    s.settings.spp = spp.max(1);
                    let (img, seconds) = render_series(&s, se);
                    done += 1;
                    progress(done, total);
                    Point {
                        spp: s.settings.spp,
                        seconds,
                        rel_rmse: rel_rmse(&img, reference).unwrap_or(f64::NAN),
                    }
                })
                .collect();
            let xy = |f: fn(&Point) -> f64| -> Vec<(f64, f64)> {
                points.iter().map(|p| (f(p), p.rel_rmse)).collect()
            };
            Curve {
                series: se,
                name: se.name(),
                slope_spp: loglog_slope(&xy(|p| f64::from(p.spp))),
                slope_seconds: loglog_slope(&xy(|p| p.seconds)),
                points,
            }
        })
        .collect()
}

/// Pairs `(i, j)`, `i < j`, of curves whose rel-RMSE is the same at every point: the same spp
/// list and every value equal (bitwise, or within 1e-12 relative). On the plot one hides the
/// other, so the report says so (issue 32, item 17).
#[must_use]
pub fn identical(curves: &[Curve]) -> Vec<(usize, usize)> {
    let same = |a: &Curve, b: &Curve| {
        a.points.len() == b.points.len()
            && !a.points.is_empty()
            && a.points.iter().zip(&b.points).all(|(p, q)| {
                p.spp == q.spp
                    && (p.rel_rmse == q.rel_rmse
                        || (p.rel_rmse - q.rel_rmse).abs()
                            <= 1e-12 * p.rel_rmse.abs().max(q.rel_rmse.abs()))
            })
    };
    let mut out = Vec::new();
    for i in 0..curves.len() {
        for j in i + 1..curves.len() {
            if same(&curves[i], &curves[j]) {
                out.push((i, j));
            }
        }
    }
    out
}

/// The sentence the plot's caption and `converge.md` carry for [`identical`] curves, or `None`.
#[must_use]
pub fn identical_text(curves: &[Curve]) -> Option<String> {
    let pairs = identical(curves);
    if pairs.is_empty() {
        return None;
    }
    let names: Vec<String> = pairs
        .iter()
        .map(|(i, j)| format!("{} = {}", curves[*i].name, curves[*j].name))
        .collect();
    Some(format!(
        "Identical series (the same rel-RMSE at every spp, so one line hides the other; the markers differ): {}.",
        names.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let pts: Vec<_> = [1.0, 2.0, 4.0, 8.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(-0.5)))
            .collect();
        assert!((loglog_slope(&pts).unwrap() + 0.5).abs() < 1e-12);
        assert_eq!(loglog_slope(&pts[..1]), None);
        assert_eq!(loglog_slope(&[(1.0, 1.0), (1.0, 2.0)]), None);
    }

    #[test]
    fn rel_rmse_stays_finite_when_its_squares_overflow() {
        let img = |v: f64| Image {
            width: 2,
            height: 1,
            pixels: vec![Rgb::splat(v); 2],
        };
        let e = rel_rmse(&img(1e200), &img(0.0)).unwrap();
        assert!((e / 1e202 - 1.0).abs() < 1e-12, "{e}");
    }

    #[test]
    fn rel_rmse_is_relative_to_the_reference_plus_an_offset() {
        let img = |v: f64| Image {
            width: 2,
            height: 1,
            pixels: vec![Rgb::splat(v); 2],
        };
        assert_eq!(rel_rmse(&img(1.0), &img(1.0)), Some(0.0));
        let e = rel_rmse(&img(1.5), &img(0.99)).unwrap();
        assert!((e - 0.51).abs() < 1e-12, "{e}");
        let small = Image {
            width: 1,
            height: 1,
            pixels: vec![Rgb::ZERO],
        };
        assert_eq!(rel_rmse(&small, &img(1.0)), None);
    }

    #[test]
    fn series_names_round_trip_and_bad_names_are_refused() {
        for s in [
            Series::Default,
            Series::LightOnly,
            Series::BsdfOnly,
            Series::Sobol,
            Series::Stratified,
            Series::RrDepth(3),
            Series::Denoised,
        ] {
            assert_eq!(Series::parse(&s.name()), Ok(s));
        }
        let e = Series::parse("mis-off").unwrap_err();
        assert!(e.contains("mis-off") && e.contains("rr:N"), "{e}");
        assert!(Series::parse("rr:x").is_err());
    }

    #[test]
    fn identical_curves_are_found_and_named() {
        let curve = |name: &str, v: &[f64]| Curve {
            series: Series::Default,
            name: name.into(),
            points: v
                .iter()
                .enumerate()
                .map(|(k, &r)| Point {
                    spp: 1 << k,
                    seconds: 0.1 * (k + 1) as f64,
                    rel_rmse: r,
                })
                .collect(),
            slope_spp: None,
            slope_seconds: None,
        };
        let c = [
            curve("default", &[0.4, 0.3, 0.2]),
            curve("light-only", &[0.4, 0.3, 0.2]),
            curve("bsdf-only", &[0.4, 0.3, 0.21]),
            curve("sobol", &[0.4, 0.3]),
        ];
        assert_eq!(identical(&c), [(0, 1)]);
        let t = identical_text(&c).unwrap();
        assert!(t.contains("default = light-only"), "{t}");
        assert_eq!(identical_text(&c[1..]), None);
    }
}
