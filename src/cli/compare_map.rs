//! The error maps of `raytree compare -o map.png`, each with a legend strip under the image:
//! the signed map (luminance of A - B on a diverging blue-grey-red ramp) and, with `--abs`,
//! the unsigned one (the largest channel's |A - B| from black through red and yellow to white).

use super::canvas::{Canvas, Rgb8};
use anyhow::Result;
use raytree::Image;
use raytree::bsdf::luminance;
use raytree::text::sci;

/// Height of the legend strip in canvas pixels.
const LEGEND_H: u32 = 52;
/// The narrowest map: smaller images are magnified by a whole factor (nearest neighbour) so the
/// legend's text fits under them.
const MIN_W: u32 = 420;

/// Moreland's cool-warm diverging map, its end and middle points ("Diverging Color Maps for
/// Scientific Visualization", 2009), interpolated linearly in sRGB (an approximation of his
/// Msh interpolation): -1 blue, 0 grey, +1 red.
fn diverging(v: f64) -> Rgb8 {
    const BLUE: [f64; 3] = [59.0, 76.0, 192.0];
    const GREY: [f64; 3] = [221.0, 221.0, 221.0];
    const RED: [f64; 3] = [180.0, 4.0, 38.0];
    let v = if v.is_finite() {
        v.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let (from, to, t) = if v < 0.0 {
        (GREY, BLUE, -v)
    } else {
        (GREY, RED, v)
    };
    std::array::from_fn(|i| (from[i] + (to[i] - from[i]) * t).round() as u8)
}

/// Black-body style ramp: 0 black, 1/3 red, 2/3 yellow, 1 white.
fn heat(v: f64) -> Rgb8 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let ch = |x: f64| ((x * 3.0).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    [ch(v), ch(v - 1.0 / 3.0), ch(v - 2.0 / 3.0)]
}

/// The full scale: `scale` if given, else the largest |value|; `None` when that is 0 (the
/// images are equal: the map is painted at scale 1, all in the zero colour).
fn full_scale(values: &[f64], scale: Option<f64>) -> Option<f64> {
    let s = scale.unwrap_or_else(|| values.iter().fold(0.0, |m: f64, v| m.max(v.abs())));
    (s > 0.0).then_some(s)
}

/// Paint `values` (one per pixel of `w x h`) through `colour(v / scale)`, magnified to at
/// least [`MIN_W`] wide, with the legend: a colour bar from `lo` to `hi` (in units of the
/// scale), its end and middle values, and `caption`.
fn paint(
    values: &[f64],
    (w, h): (u32, u32),
    scale: f64,
    (lo, hi): (f64, f64),
    colour: fn(f64) -> Rgb8,
    caption: &str,
) -> Result<Vec<u8>> {
    let k = MIN_W.div_ceil(w).max(1);
    let (cw, ch) = (w * k, h * k);
    let mut c = Canvas::new(cw, ch + LEGEND_H, [255, 255, 255])?;
    for y in 0..h {
        for x in 0..w {
            let col = colour(values[(y * w + x) as usize] / scale);
            c.rect((x * k) as f32, (y * k) as f32, k as f32, k as f32, col);
        }
    }
    let (x0, bar_w, top) = (10.0f32, cw as f32 - 20.0, ch as f32 + 6.0);
    let steps = bar_w.max(1.0) as u32;
    for i in 0..steps {
        let t = f64::from(i) / f64::from(steps.max(2) - 1);
        c.rect(x0 + i as f32, top, 1.0, 12.0, colour(lo + (hi - lo) * t));
    }
    let ink = [20, 20, 20];
    let label = |v: f64| {
        let x = v * scale;
        if x == 0.0 {
            "0".to_string()
        } else {
            sci(x, Some(2))
        }
    };
    let size = 12.0;
    let (l, m, r) = (label(lo), label((lo + hi) / 2.0), label(hi));
    c.text(x0, top + 26.0, size, &l, ink);
    let mw = c.text_width(&m, size);
    c.text(x0 + bar_w / 2.0 - mw / 2.0, top + 26.0, size, &m, ink);
    let rw = c.text_width(&r, size);
    c.text(x0 + bar_w - rw, top + 26.0, size, &r, ink);
    c.text(x0, top + 42.0, size, caption, ink);
    c.png()
}

/// The signed map of A - B (Rec. 709 luminance, linear) and its full scale (`None`: all equal).
pub fn signed_map(a: &Image, b: &Image, scale: Option<f64>) -> Result<(Vec<u8>, Option<f64>)> {
    let v: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| luminance(*p - *q))
        .collect();
    let s = full_scale(&v, scale);
    let png = paint(
        &v,
        (a.width, a.height),
        s.unwrap_or(1.0),
        (-1.0, 1.0),
        diverging,
        "luminance A - B: blue A darker, red A brighter",
    )?;
    Ok((png, s))
}

/// The unsigned map of the largest channel's |A - B| and its full scale (`None`: all equal).
pub fn abs_map(a: &Image, b: &Image, scale: Option<f64>) -> Result<(Vec<u8>, Option<f64>)> {
    let v: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .collect();
    let s = full_scale(&v, scale);
    let png = paint(
        &v,
        (a.width, a.height),
        s.unwrap_or(1.0),
        (0.0, 1.0),
        heat,
        "largest channel |A - B|",
    )?;
    Ok((png, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_diverging_ramp_is_grey_at_zero_and_signed_at_the_ends() {
        assert_eq!(diverging(0.0), [221, 221, 221]);
        assert_eq!(diverging(-1.0), [59, 76, 192]);
        assert_eq!(diverging(1.0), [180, 4, 38]);
        assert_eq!(diverging(-5.0), diverging(-1.0));
        let (neg, pos) = (diverging(-0.5), diverging(0.5));
        assert!(neg[2] > neg[0] && pos[0] > pos[2], "{neg:?} {pos:?}");
    }
}
