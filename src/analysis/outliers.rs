//! The worst pixels of an image (issue 32, item 14; `raytree outliers`): each pixel's
//! luminance against a robust estimate of its neighbourhood, so a firefly on a smooth floor
//! ranks first and the edge of a lamp does not.
//!
//! For pixel `p` with luminance `l` (Rec. 709, linear) and the luminances of its neighbours
//! (the `w x w` window around it, `w` = 3 or 5, clipped at the image's border, `p` itself left
//! out), the estimate is their median `m` and the scale `s = max(1.4826 MAD, s_min)`, MAD the
//! median absolute deviation from `m`: 1.4826 MAD estimates a normal distribution's standard
//! deviation and, like the median, ignores up to half the window being wild (Hampel 1974;
//! Rousseeuw and Croux 1993, "Alternatives to the median absolute deviation"). `s_min` is
//! [`FLOOR`] of the image's mean luminance (a flat neighbourhood has MAD 0, and the score must
//! stay finite). The score is `(l - m) / s`, the excess in robust standard deviations; pixels
//! are ranked by it, largest first, and only pixels brighter than their neighbourhood's median
//! are listed (a firefly is bright; a dark hole is the other sign of the same test, not
//! listed here). A straight edge is no outlier (each side holds the majority of its own
//! pixels' windows), but the convex corner of a bright shape is: its pixel has bright
//! neighbours on only 3 of 8 sides, so the median is the dark side's. The listing shows the
//! median beside the value so a reader can tell, and the `trace` command settles it.
//!
//! Given the standard errors of the pixel means of a render ([`by_std_error`]), the pixels
//! can also be ranked by how uncertain their value is.

use crate::bsdf::luminance;
use crate::math::Rgb;
use crate::render::Image;
use serde::Serialize;

/// 1.4826: the MAD of a normal distribution times this is its standard deviation
/// (`1 / Phi^-1(3/4)`).
pub const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;
/// The smallest scale, as a share of the image's mean luminance.
pub const FLOOR: f64 = 0.01;

/// One ranked pixel.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outlier {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// The pixel's value (linear RGB).
    pub value: Rgb,
    /// Its luminance.
    pub luminance: f64,
    /// The median luminance of its neighbours.
    pub median: f64,
    /// The robust scale `s` (see the module docs).
    pub scale: f64,
    /// `(luminance - median) / scale`.
    pub score: f64,
    /// The standard error of the pixel's mean (from the render's samples), when known.
    pub std_error: Option<f64>,
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The luminances of `img`, with non-finite values as they are (they rank first: see [`rank`]).
fn luminances(img: &Image) -> Vec<f64> {
    img.pixels.iter().map(|c| luminance(*c)).collect()
}

/// The smallest scale for `img`: [`FLOOR`] of its mean finite luminance (never 0).
fn scale_floor(lum: &[f64]) -> f64 {
    let finite: Vec<f64> = lum.iter().copied().filter(|v| v.is_finite()).collect();
    let mean = finite.iter().map(|v| v / finite.len() as f64).sum::<f64>();
    (FLOOR * mean.abs()).max(1e-12)
}

/// Pixel `(x, y)` of `img` scored against its `window x window` neighbourhood.
fn score_at(img: &Image, lum: &[f64], (x, y): (u32, u32), window: u32, floor: f64) -> Outlier {
    let r = window / 2;
    let (w, h) = (img.width, img.height);
    let mut nb = Vec::with_capacity((window * window) as usize);
    for ny in y.saturating_sub(r)..=(y + r).min(h - 1) {
        for nx in x.saturating_sub(r)..=(x + r).min(w - 1) {
            let v = lum[(ny * w + nx) as usize];
            if (nx, ny) != (x, y) && v.is_finite() {
                nb.push(v);
            }
        }
    }
    let m = median(&mut nb);
    let mut dev: Vec<f64> = nb.iter().map(|v| (v - m).abs()).collect();
    let s = (MAD_TO_SIGMA * median(&mut dev)).max(floor);
    let l = lum[(y * w + x) as usize];
    let score = (l - m) / s;
    Outlier {
        x,
        y,
        value: img.get(x, y),
        luminance: l,
        median: m,
        scale: s,
        score: if score.is_finite() { score } else { f64::MAX },
        std_error: None,
    }
}

/// The `top` pixels of `img` brighter than their neighbourhood's median, ranked by their
/// score over a `window x window` neighbourhood (3 or 5; see the module docs), largest first,
/// ties in reading order. A pixel whose value is not finite scores `f64::MAX` (it is the worst
/// outlier there is), its luminance kept as it is for the caller to report.
///
/// # Panics
/// If `window` is not 3 or 5.
#[must_use]
pub fn rank(img: &Image, window: u32, top: usize) -> Vec<Outlier> {
    assert!(window == 3 || window == 5, "window 3 or 5, got {window}");
    if img.pixels.is_empty() {
        return Vec::new();
    }
    let lum = luminances(img);
    let floor = scale_floor(&lum);
    let mut all: Vec<Outlier> = (0..img.height)
        .flat_map(|y| (0..img.width).map(move |x| (x, y)))
        .map(|p| score_at(img, &lum, p, window, floor))
        .filter(|o| o.score > 0.0)
        .collect();
    all.sort_by(|a, b| b.score.total_cmp(&a.score));
    all.truncate(top);
    all
}

/// The `top` pixels with the largest standard error of their mean (`std_error`, one per pixel,
/// row-major), each scored as [`rank`] scores it too; ties in reading order. Pixels whose
/// error is 0 (a single sample, or a black pixel: not estimable) are not listed.
#[must_use]
pub fn by_std_error(img: &Image, std_error: &[f64], window: u32, top: usize) -> Vec<Outlier> {
    assert!(window == 3 || window == 5, "window 3 or 5, got {window}");
    if img.pixels.is_empty() || std_error.len() != img.pixels.len() {
        return Vec::new();
    }
    let lum = luminances(img);
    let floor = scale_floor(&lum);
    let mut order: Vec<usize> = (0..std_error.len())
        .filter(|i| std_error[*i] > 0.0 && std_error[*i].is_finite())
        .collect();
    order.sort_by(|a, b| std_error[*b].total_cmp(&std_error[*a]));
    order.truncate(top);
    order
        .into_iter()
        .map(|i| {
            let p = ((i as u32) % img.width, (i as u32) / img.width);
            Outlier {
                std_error: Some(std_error[i]),
                ..score_at(img, &lum, p, window, floor)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{splitmix64, unit};

    /// A noisy grey floor (0.5 +/- 0.05), a bright lamp (40) across the top six rows (its
    /// straight lower edge in view) and one firefly (a value of 3) at (20, 12).
    fn floor_with_firefly() -> Image {
        let (w, h) = (32u32, 24u32);
        let mut pixels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let noise = unit(splitmix64(u64::from(y * w + x))) - 0.5;
                let v = if y < 6 { 40.0 } else { 0.5 + 0.1 * noise };
                pixels.push(Rgb::splat(v));
            }
        }
        pixels[(12 * w + 20) as usize] = Rgb::splat(3.0);
        Image {
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn the_firefly_ranks_first_and_the_lamp_s_edge_does_not() {
        let img = floor_with_firefly();
        for window in [3, 5] {
            let top = rank(&img, window, 5);
            assert_eq!((top[0].x, top[0].y), (20, 12), "{top:?}");
            assert!((top[0].luminance - 3.0).abs() < 1e-12);
            assert!((top[0].median - 0.5).abs() < 0.05, "{}", top[0].median);
            // The excess of 2.5 over a scale of about 0.1: the floor of 1 % of the mean
            // luminance (10.4, the lamp's), above the floor's own spread (1.4826 MAD = 0.037).
            assert!(top[0].score > 20.0, "{}", top[0].score);
            assert!((top[0].scale - 0.01 * (6.0 * 40.0 + 18.0 * 0.5) / 24.0).abs() < 0.002);
            // The lamp's edge pixels (40 beside 0.5) have a wild neighbourhood: a large MAD.
            for o in &top[1..] {
                assert!(o.score < top[0].score / 4.0, "{o:?}");
            }
        }
    }

    #[test]
    fn the_median_ignores_the_firefly_and_flat_images_stay_finite() {
        let mut img = Image {
            width: 5,
            height: 5,
            pixels: vec![Rgb::splat(1.0); 25],
        };
        img.pixels[12] = Rgb::splat(101.0);
        let top = rank(&img, 3, 10);
        assert_eq!(top.len(), 1, "only the hot pixel is above its median");
        let o = top[0];
        assert_eq!((o.x, o.y, o.median), (2, 2, 1.0));
        // Flat neighbourhood: MAD 0, the scale is the floor (1 % of the mean luminance 5).
        assert!((o.scale - 0.05).abs() < 1e-12, "{}", o.scale);
        assert!((o.score - 2000.0).abs() < 1e-9, "{}", o.score);
        // An all-black image: nothing listed, nothing divided by zero.
        let black = Image {
            width: 4,
            height: 4,
            pixels: vec![Rgb::ZERO; 16],
        };
        assert!(rank(&black, 5, 10).is_empty());
    }

    #[test]
    fn a_non_finite_pixel_ranks_first_with_a_finite_score() {
        let mut img = floor_with_firefly();
        img.pixels[5 * 32 + 30] = Rgb::new(f64::INFINITY, 0.0, 0.0);
        let top = rank(&img, 3, 3);
        assert_eq!((top[0].x, top[0].y), (30, 5));
        assert!(
            top.iter()
                .all(|o| o.score.is_finite() && o.median.is_finite())
        );
        assert_eq!((top[1].x, top[1].y), (20, 12));
    }

    #[test]
    fn by_std_error_ranks_the_most_uncertain_pixels() {
        let img = floor_with_firefly();
        let mut se = vec![0.01; 32 * 24];
        se[3 * 32 + 7] = 0.5;
        se[12 * 32 + 20] = 0.9;
        se[0] = 0.0;
        let top = by_std_error(&img, &se, 3, 3);
        assert_eq!(
            top.iter().map(|o| (o.x, o.y)).collect::<Vec<_>>()[..2],
            [(20, 12), (7, 3)]
        );
        assert_eq!(top[0].std_error, Some(0.9));
        assert!(by_std_error(&img, &se[1..], 3, 3).is_empty());
    }
}
