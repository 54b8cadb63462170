//! Bias, not only RMSE (issue 32, item 15): the mean signed difference of two images per
//! channel with a 95 % confidence interval, over the whole image or a pixel region, for
//! `raytree compare`. An energy-loss hunt needs the sign and whether it is more than noise;
//! RMSE gives neither.
//!
//! The interval comes from **block means**: the region is tiled by [`BLOCK`] x [`BLOCK`]
//! pixel blocks (the last row and column of blocks may be smaller), each block's mean
//! difference is one observation, and the half-width is `t(0.975, m - 1) s / sqrt(m)` for `m`
//! blocks with sample standard deviation `s` (the batch-means method: neighbouring pixels'
//! errors are correlated by the filter, the denoiser and shared samples, block means much
//! less). A region with fewer than [`MIN_BLOCKS`] blocks uses single pixels as blocks (the
//! per-pixel spread) and says so. The point estimate is the plain pixel mean.

use crate::math::Rgb;
use crate::render::Image;
use serde::Serialize;

/// Side of the blocks whose means give the interval, in pixels.
pub const BLOCK: u32 = 8;
/// Fewest blocks for a block interval; below it, pixels are the blocks.
pub const MIN_BLOCKS: usize = 16;

/// A pixel region `[x0, x1) x [y0, y1)` (x1 and y1 exclusive, as pbrt's pixel bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Region {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Region {
    /// The whole `width x height` image.
    #[must_use]
    pub fn whole(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Parse `X0,Y0,X1,Y1` for a `width x height` image: four integers, `X0 < X1 <= width`,
    /// `Y0 < Y1 <= height`. The error says which rule failed.
    pub fn parse(s: &str, width: u32, height: u32) -> Result<Self, String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if parts.len() != 4 {
            return Err(format!(
                "expected X0,Y0,X1,Y1 (four integers; X1 and Y1 exclusive), got {} value(s)",
                parts.len()
            ));
        }
        let mut v = [0u32; 4];
        for (i, (p, name)) in parts.iter().zip(["X0", "Y0", "X1", "Y1"]).enumerate() {
            v[i] = p.parse().map_err(|_| {
                format!("{name} must be a pixel coordinate (an integer >= 0), got {p:?}")
            })?;
        }
        let [x0, y0, x1, y1] = v;
        if x0 >= x1 || y0 >= y1 {
            return Err(format!(
                "the region {x0},{y0},{x1},{y1} is empty: X0 < X1 and Y0 < Y1 (X1, Y1 exclusive)"
            ));
        }
        if x1 > width || y1 > height {
            return Err(format!(
                "the region {x0},{y0},{x1},{y1} leaves the {width}x{height} image (X1 <= {width}, Y1 <= {height})"
            ));
        }
        Ok(Self { x0, y0, x1, y1 })
    }

    /// Width and height.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.x1 - self.x0, self.y1 - self.y0)
    }

    /// The part of `img` inside the region, as an image of its own.
    #[must_use]
    pub fn crop(&self, img: &Image) -> Image {
        let (w, h) = self.size();
        let mut pixels = Vec::with_capacity((w * h) as usize);
        for y in self.y0..self.y1 {
            for x in self.x0..self.x1 {
                pixels.push(img.get(x, y));
            }
        }
        Image {
            width: w,
            height: h,
            pixels,
        }
    }
}

/// The mean signed difference `a - b` of two equally sized images, per channel.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SignedDifference {
    /// Mean of `a - b` per channel (R, G, B), linear.
    pub mean: [f64; 3],
    /// Half-width of the 95 % interval per channel: the interval is `mean +/- half_width`.
    pub half_width: [f64; 3],
    /// Side of the blocks the interval came from (1: single pixels).
    pub block: u32,
    /// Number of blocks.
    pub blocks: usize,
}

impl SignedDifference {
    /// Whether channel `c`'s interval excludes 0 (a difference beyond the noise, at 95 %).
    #[must_use]
    pub fn significant(&self, c: usize) -> bool {
        self.mean[c].abs() > self.half_width[c]
    }
}

/// The 0.975 quantile of Student's t with `df` degrees of freedom: from the tables for
/// `df <= 4` (12.706, 4.303, 3.182, 2.776), beyond from the Cornish-Fisher expansion about the
/// normal quantile to the `1/df^4` term (Abramowitz and Stegun 26.7.5; within 3e-4 of the
/// tables at df = 5, 2e-5 from df = 8). NaN for `df = 0`.
#[must_use]
pub fn t_975(df: usize) -> f64 {
    const Z: f64 = 1.959_963_984_540_054;
    match df {
        0 => f64::NAN,
        1 => 12.706_204_736,
        2 => 4.302_652_730,
        3 => 3.182_446_305,
        4 => 2.776_445_105,
        _ => {
            let n = df as f64;
            let z = |k: i32| Z.powi(k);
            Z + (z(3) + Z) / (4.0 * n)
                + (5.0 * z(5) + 16.0 * z(3) + 3.0 * Z) / (96.0 * n * n)
                + (3.0 * z(7) + 19.0 * z(5) + 17.0 * z(3) - 15.0 * Z) / (384.0 * n.powi(3))
                + (79.0 * z(9) + 776.0 * z(7) + 1482.0 * z(5) - 1920.0 * z(3) - 945.0 * Z)
                    / (92160.0 * n.powi(4))
        }
    }
}

/// Mean and 95 % half-width of the signed difference `a - b` over `region`; `None` if the
/// sizes differ or the region leaves the images. Sums are of differences divided by the
/// count as they are added, so finite images keep finite means unless a single difference
/// overflows (then the mean is reported as it is, not finite, and the caller says so).
#[must_use]
pub fn signed_difference(a: &Image, b: &Image, region: Region) -> Option<SignedDifference> {
    if (a.width, a.height) != (b.width, b.height) || region.x1 > a.width || region.y1 > a.height {
        return None;
    }
    let (w, h) = region.size();
    let whole = (w.div_ceil(BLOCK) * h.div_ceil(BLOCK)) as usize;
    let block = if whole >= MIN_BLOCKS { BLOCK } else { 1 };
    let (bw, bh) = (w.div_ceil(block), h.div_ceil(block));
    let mut means = Vec::with_capacity((bw * bh) as usize);
    let n = f64::from(w) * f64::from(h);
    let mut mean = Rgb::ZERO;
    for by in 0..bh {
        for bx in 0..bw {
            let xs = region.x0 + bx * block..(region.x0 + (bx + 1) * block).min(region.x1);
            let ys = region.y0 + by * block..(region.y0 + (by + 1) * block).min(region.y1);
            let count = f64::from((xs.end - xs.start) * (ys.end - ys.start));
            let mut m = Rgb::ZERO;
            for y in ys {
                for x in xs.clone() {
                    let d = a.get(x, y) - b.get(x, y);
                    m += d / count;
                    mean += d / n;
                }
            }
            means.push(m);
        }
    }
    let k = means.len();
    let centre = means.iter().fold(Rgb::ZERO, |s, m| s + *m / k as f64);
    let var = means.iter().fold(Rgb::ZERO, |s, m| {
        let d = *m - centre;
        s + d * d / (k.saturating_sub(1).max(1)) as f64
    });
    let t = if k >= 2 { t_975(k - 1) } else { f64::NAN };
    let hw = |v: f64| t * (v / k as f64).sqrt();
    Some(SignedDifference {
        mean: mean.to_array(),
        half_width: [hw(var.x), hw(var.y), hw(var.z)],
        block,
        blocks: k,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{splitmix64, unit};

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> Rgb) -> Image {
        let mut pixels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                pixels.push(f(x, y));
            }
        }
        Image {
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn t_quantiles_match_the_tables() {
        // Student's t, 0.975 quantile (e.g. NIST/SEMATECH e-Handbook, table 1.3.6.7.2).
        for (df, want) in [
            (1, 12.706),
            (2, 4.303),
            (3, 3.182),
            (4, 2.776),
            (5, 2.571),
            (8, 2.306),
            (10, 2.228),
            (15, 2.131),
            (30, 2.042),
            (100, 1.984),
        ] {
            let got = t_975(df);
            assert!((got - want).abs() < 1e-3, "df {df}: {got} vs {want}");
        }
        assert!((t_975(1_000_000) - 1.95996).abs() < 1e-4);
    }

    #[test]
    fn regions_parse_and_refuse_what_leaves_the_image() {
        assert_eq!(
            Region::parse("1, 2,5,6", 8, 8),
            Ok(Region {
                x0: 1,
                y0: 2,
                x1: 5,
                y1: 6
            })
        );
        assert_eq!(Region::parse("0,0,8,8", 8, 8), Ok(Region::whole(8, 8)));
        for bad in [
            "",
            "1,2,3",
            "1,2,3,4,5",
            "a,0,1,1",
            "-1,0,1,1",
            "2,0,2,1",
            "3,0,2,1",
            "0,0,9,1",
            "0,0,1,9",
            "0,0,1e1,1",
            "0,0,1.5,1",
        ] {
            assert!(Region::parse(bad, 8, 8).is_err(), "{bad:?}");
        }
        let img = image(4, 3, |x, y| Rgb::new(f64::from(x), f64::from(y), 0.0));
        let c = Region::parse("1,1,3,3", 4, 3).unwrap().crop(&img);
        assert_eq!((c.width, c.height), (2, 2));
        assert_eq!(c.get(0, 0), Rgb::new(1.0, 1.0, 0.0));
        assert_eq!(c.get(1, 1), Rgb::new(2.0, 2.0, 0.0));
    }

    #[test]
    fn a_constant_offset_is_its_own_mean_with_no_spread() {
        let a = image(64, 48, |x, y| Rgb::splat(f64::from(x + y) * 0.01));
        let b = image(64, 48, |x, y| {
            Rgb::new(0.25, -0.5, 0.0) + Rgb::splat(f64::from(x + y) * 0.01)
        });
        let d = signed_difference(&a, &b, Region::whole(64, 48)).unwrap();
        assert_eq!((d.block, d.blocks), (BLOCK, 48));
        for (c, want) in [-0.25, 0.5, 0.0].into_iter().enumerate() {
            assert!((d.mean[c] - want).abs() < 1e-12, "{:?}", d.mean);
            assert!(d.half_width[c] < 1e-12, "{:?}", d.half_width);
        }
        assert!(d.significant(0) && d.significant(1) && !d.significant(2));
        // A 3x3 region has one block of 8: single pixels are the blocks.
        let r = signed_difference(&a, &b, Region::parse("0,0,3,3", 64, 48).unwrap()).unwrap();
        assert_eq!((r.block, r.blocks), (1, 9));
    }

    /// Zero-mean noise: the 95 % interval covers 0 in about 95 % of seeded trials (binomial
    /// bounds for 400 trials: 0.95 +/- 3.5 standard deviations of 0.011).
    #[test]
    fn the_interval_covers_a_zero_bias_at_its_nominal_rate() {
        let trials = 400u64;
        let mut covered = 0;
        for t in 0..trials {
            let a = image(32, 32, |_, _| Rgb::ZERO);
            let noise: Vec<f64> = (0..32 * 32u64)
                .map(|i| unit(splitmix64(t * 4096 + i)) - 0.5)
                .collect();
            let b = image(32, 32, |x, y| Rgb::splat(noise[(y * 32 + x) as usize]));
            let d = signed_difference(&a, &b, Region::whole(32, 32)).unwrap();
            assert_eq!(d.blocks, 16);
            if !d.significant(0) {
                covered += 1;
            }
        }
        let rate = f64::from(covered) / trials as f64;
        assert!((rate - 0.95).abs() < 3.5 * 0.011, "coverage {rate}");
    }
}
