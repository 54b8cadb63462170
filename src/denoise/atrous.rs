//! The edge-avoiding a-trous wavelet filter (Dammertz, Sewtz, Hanika, Lensch 2010, "Edge-Avoiding
//! A-Trous Wavelet Transform for fast Global Illumination Filtering", HPG): `iterations` passes
//! of the 5x5 B3-spline kernel `h = [1/16, 1/4, 3/8, 1/4, 1/16]` with holes (step `2^i`), each
//! tap weighted by edge-stopping functions of the guide features. As in SVGF (Schied et al.
//! 2017, "Spatiotemporal Variance-Guided Filtering", HPG; here for one frame) the filter runs
//! on the illumination (colour divided by albedo, multiplied back at the end), the luminance
//! weight is `exp(-|l_p - l_q| / (sigma_l sqrt(g(var_p)) + eps))` with `g` a 3x3 Gaussian of
//! the variance, and each pass also filters the variance (weights squared) so the next, wider
//! pass trusts the smoothed signal more. Where the albedo is itself noisy (a lens blurs a
//! texture) its edge stop widens by the albedos' variance and the albedo is filtered with the
//! same weights; elsewhere the weights leave it as it is. With one sample per pixel the
//! variance is estimated over the 5x5 neighbours of similar features, leaving out the brightest
//! (so a firefly is not spread into its dark neighbours).

use super::Features;
use crate::bsdf::luminance;
use crate::math::Rgb;
use crate::render::Image;
use glam::DVec3;
use rayon::prelude::*;

/// The filter's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseParams {
    /// A-trous passes (the footprint is `4 * 2^iterations - 3` pixels wide).
    pub iterations: u32,
    /// Luminance edge stopping, in standard deviations of the mean (SVGF: 4).
    pub sigma_luminance: f64,
    /// Normal edge stopping: weight `exp(-|n_p - n_q|^2 / sigma^2)` (Dammertz et al.).
    pub sigma_normal: f64,
    /// Albedo edge stopping: weight `exp(-|a_p - a_q|^2 / sigma^2)`.
    pub sigma_albedo: f64,
}

impl Default for DenoiseParams {
    fn default() -> Self {
        Self {
            iterations: 5,
            sigma_luminance: 4.0,
            sigma_normal: 0.3,
            sigma_albedo: 0.1,
        }
    }
}

/// Below this an albedo channel is treated as 1 (no demodulation: emitters, black surfaces).
const MIN_ALBEDO: f64 = 0.01;
/// Keeps the luminance weight finite where the variance is 0.
const EPS_LUMINANCE: f64 = 1e-10;
/// Renders with fewer samples per pixel estimate the variance spatially (SVGF does so for the
/// first frames of a pixel's history).
const MIN_SPP_FOR_SAMPLE_VARIANCE: u32 = 4;

/// Pixels whose emitter coverage ([`Features::emitter`]) differs by this much weigh each other
/// `1/e`: a lamp (1), its edge (between) and its surroundings (0) are filtered apart.
const SIGMA_EMITTER: f64 = 0.02;

/// B3 spline taps for offsets 0, 1, 2.
const H: [f64; 3] = [3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];

/// The albedo used to demodulate: channels below [`MIN_ALBEDO`] become 1.
fn demod(a: Rgb) -> Rgb {
    Rgb::from_array(a.to_array().map(|c| if c >= MIN_ALBEDO { c } else { 1.0 }))
}

/// Denoise `image` with its `features` (same size). A pixel whose weights all vanish keeps its
/// value; the output is finite wherever the input is.
///
/// # Panics
/// If the features are not of the image's size (a programming error).
#[must_use]
pub fn denoise(image: &Image, features: &Features, p: &DenoiseParams) -> Image {
    let mut f = DenoiseSteps::new(image, features);
    while f.iteration < p.iterations {
        let n = f.w * f.h;
        let pass = f.pass(features, p);
        // Pixels in parallel.
        let out: Vec<(Rgb, f64, Rgb)> = (0..n).into_par_iter().map(|c| pass.pixel(c)).collect();
        f.out = out;
        f.next_pass();
    }
    f.finish(image, features)
}

/// [`denoise`] a piece at a time (the web page has no threads): the same image, bit for bit.
/// Each pass's pixels one after another, each pixel computed as [`denoise`]'s parallel pass
/// computes it.
pub struct DenoiseSteps {
    w: usize,
    h: usize,
    /// The illumination, its variance and the albedo, as the last pass left them.
    illum: Vec<Rgb>,
    var: Vec<f64>,
    albedo: Vec<Rgb>,
    /// The pass under way, its blurred variance (made at its first pixel) and its pixels so
    /// far.
    iteration: u32,
    blurred: Option<Vec<f64>>,
    out: Vec<(Rgb, f64, Rgb)>,
}

impl DenoiseSteps {
    /// The filter of `image` by its `features`.
    ///
    /// # Panics
    /// As [`denoise`].
    #[must_use]
    pub fn new(image: &Image, features: &Features) -> Self {
        let (w, h) = (image.width as usize, image.height as usize);
        assert_eq!(
            (
                features.width as usize,
                features.height as usize,
                features.albedo.len()
            ),
            (w, h, w * h),
            "features of another image"
        );
        let albedo: Vec<Rgb> = features.albedo.iter().map(|&a| demod(a)).collect();
        // Directly seen emission stays out of the filter (issue 32: a filtered lamp's edge
        // turned jagged with bright speckles): the reflected part is filtered and the emission
        // added back.
        let illum: Vec<Rgb> = image
            .pixels
            .iter()
            .zip(&albedo)
            .enumerate()
            .map(|(i, (c, a))| (*c - emitted(features, i)) / *a)
            .collect();
        let var = variance(&illum, &albedo, features);
        Self {
            w,
            h,
            illum,
            var,
            albedo,
            iteration: 0,
            blurred: None,
            out: Vec::with_capacity(w * h),
        }
    }

    /// The pass under way (its blurred variance made if need be).
    fn pass<'a>(&'a mut self, features: &'a Features, p: &'a DenoiseParams) -> Pass<'a> {
        let (w, h) = (self.w, self.h);
        let blurred = self
            .blurred
            .get_or_insert_with(|| gaussian3(&self.var, w, h));
        Pass {
            w,
            h,
            step: 1usize << self.iteration,
            illum: &self.illum,
            var: &self.var,
            albedo: &self.albedo,
            blurred_var: blurred,
            features,
            p,
        }
    }

    /// The pass's pixels are all in `out`: they become the next pass's input.
    fn next_pass(&mut self) {
        let out = std::mem::take(&mut self.out);
        self.illum = out.iter().map(|o| o.0).collect();
        self.var = out.iter().map(|o| o.1).collect();
        self.albedo = out.iter().map(|o| o.2).collect();
        self.iteration += 1;
        self.blurred = None;
        self.out = Vec::with_capacity(self.w * self.h);
    }

    /// Filter pixels while `more_time` says so, at least one (the same `features` and `p` as
    /// [`DenoiseSteps::new`]'s); returns whether more is to come.
    pub fn step(
        &mut self,
        features: &Features,
        p: &DenoiseParams,
        more_time: &dyn Fn() -> bool,
    ) -> bool {
        let n = self.w * self.h;
        while self.iteration < p.iterations {
            let mut c = self.out.len();
            let mut out = std::mem::take(&mut self.out);
            let pass = self.pass(features, p);
            while c < n {
                out.push(pass.pixel(c));
                c += 1;
                if c < n && !more_time() {
                    self.out = out;
                    return true;
                }
            }
            self.out = out;
            self.next_pass();
            if !more_time() {
                return self.iteration < p.iterations;
            }
        }
        false
    }

    /// The denoised image (once [`DenoiseSteps::step`] returned `false`; `image` and
    /// `features` as [`DenoiseSteps::new`]'s).
    #[must_use]
    pub fn finish(self, image: &Image, features: &Features) -> Image {
        let pixels = self
            .illum
            .iter()
            .zip(&self.albedo)
            .zip(&image.pixels)
            .enumerate()
            .map(|(i, ((l, a), orig))| {
                let v = *l * *a + emitted(features, i);
                if v.is_finite() { v } else { *orig }
            })
            .collect();
        Image {
            width: image.width,
            height: image.height,
            pixels,
        }
    }
}

/// The emission seen directly at pixel `c` (none where the features do not say).
fn emitted(features: &Features, c: usize) -> Rgb {
    features.emitted.get(c).copied().unwrap_or(Rgb::ZERO)
}

/// The share of pixel `c` covered by an emitter (none where the features do not say).
fn coverage(features: &Features, c: usize) -> f64 {
    features.emitter.get(c).copied().unwrap_or(0.0)
}

/// One à-trous pass over a `w x h` image: its taps `step` pixels apart, reading the previous
/// pass's illumination, variance and albedo.
struct Pass<'a> {
    w: usize,
    h: usize,
    step: usize,
    illum: &'a [Rgb],
    var: &'a [f64],
    albedo: &'a [Rgb],
    /// The variance blurred by a 3x3 Gaussian (the luminance edge stop's scale).
    blurred_var: &'a [f64],
    features: &'a Features,
    p: &'a DenoiseParams,
}

impl Pass<'_> {
    /// Pixel `c`'s (illumination, variance, albedo) after this pass; unchanged where the
    /// weights vanish or are not finite.
    fn pixel(&self, c: usize) -> (Rgb, f64, Rgb) {
        let Self {
            w,
            h,
            step,
            illum,
            var,
            albedo,
            features,
            p,
            ..
        } = *self;
        let (x, y) = (c % w, c / w);
        let lp = luminance(illum[c]);
        let sigma = p.sigma_luminance * self.blurred_var[c].max(0.0).sqrt() + EPS_LUMINANCE;
        let (np, ap) = (features.normal[c], features.albedo[c]);
        let vap = features.albedo_variance[c];
        let (mut sum, mut wsum, mut vsum, mut asum) = (Rgb::ZERO, 0.0, 0.0, Rgb::ZERO);
        for dy in -2i64..=2 {
            let yq = y as i64 + dy * step as i64;
            if yq < 0 || yq >= h as i64 {
                continue;
            }
            for dx in -2i64..=2 {
                let xq = x as i64 + dx * step as i64;
                if xq < 0 || xq >= w as i64 {
                    continue;
                }
                let q = yq as usize * w + xq as usize;
                let kernel = H[dx.unsigned_abs() as usize] * H[dy.unsigned_abs() as usize];
                let wl = (-(lp - luminance(illum[q])).abs() / sigma).exp();
                let wn = edge(np, features.normal[q], p.sigma_normal);
                // An albedo that is itself noisy (a lens, the pixel footprint) widens its
                // edge stop by the variance of the difference of the two means.
                let s2 = p.sigma_albedo * p.sigma_albedo + (vap + features.albedo_variance[q]);
                let wa = (-(ap - features.albedo[q]).length_squared() / s2).exp();
                let dc = coverage(features, c) - coverage(features, q);
                let we = (-(dc * dc) / (SIGMA_EMITTER * SIGMA_EMITTER)).exp();
                let wt = kernel * wl * wn * wa * we;
                sum += illum[q] * wt;
                wsum += wt;
                vsum += wt * wt * var[q];
                asum += albedo[q] * wt;
            }
        }
        if wsum > 0.0 && wsum.is_finite() && sum.is_finite() {
            (sum / wsum, vsum / (wsum * wsum), asum / wsum)
        } else {
            (illum[c], var[c], albedo[c])
        }
    }
}

/// `exp(-|a - b|^2 / sigma^2)`.
fn edge(a: DVec3, b: DVec3, sigma: f64) -> f64 {
    (-(a - b).length_squared() / (sigma * sigma)).exp()
}

/// The variance of each pixel's illumination luminance: from its samples when there are
/// enough (the colour's variance over the albedo's luminance squared), else the spread of the
/// illumination over the 5x5 neighbours of similar features (the neighbours stand in for the
/// missing samples), or 0 for a deterministic render of one sample.
fn variance(illum: &[Rgb], albedo: &[Rgb], f: &Features) -> Vec<f64> {
    let (w, h) = (f.width as usize, f.height as usize);
    if f.spp >= MIN_SPP_FOR_SAMPLE_VARIANCE || !f.stochastic {
        return f
            .variance
            .iter()
            .zip(albedo)
            .map(|(v, a)| v / luminance(*a).max(MIN_ALBEDO).powi(2))
            .collect();
    }
    let d = DenoiseParams::default();
    let mut out = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            let c = y * w + x;
            let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
            // The brightest neighbour (not the pixel itself) is left out: one rare bright
            // sample (a caustic firefly) would otherwise make its dark neighbours accept it
            // and spread it.
            let mut brightest = (0.0, 0.0, f64::NEG_INFINITY);
            for yq in y.saturating_sub(2)..(y + 3).min(h) {
                for xq in x.saturating_sub(2)..(x + 3).min(w) {
                    let q = yq * w + xq;
                    let wt = edge(f.normal[c], f.normal[q], d.sigma_normal)
                        * edge(f.albedo[c], f.albedo[q], d.sigma_albedo);
                    let l = luminance(illum[q]);
                    s0 += wt;
                    s1 += wt * l;
                    s2 += wt * l * l;
                    if q != c && l > brightest.2 {
                        brightest = (wt, wt * l, l);
                    }
                }
            }
            if brightest.2.is_finite() && s0 - brightest.0 > 0.0 {
                let (bw, bl, l) = brightest;
                s0 -= bw;
                s1 -= bl;
                s2 -= bl * l;
            }
            let m = s1 / s0;
            out[c] = (s2 / s0 - m * m).max(0.0);
        }
    }
    out
}

/// The variance blurred by the 3x3 Gaussian `[1/4, 1/2, 1/4]^2` (renormalised at the border).
fn gaussian3(v: &[f64], w: usize, h: usize) -> Vec<f64> {
    const K: [f64; 2] = [0.5, 0.25];
    let mut out = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            let (mut s, mut ws) = (0.0, 0.0);
            for yq in y.saturating_sub(1)..(y + 2).min(h) {
                for xq in x.saturating_sub(1)..(x + 2).min(w) {
                    let k = K[yq.abs_diff(y)] * K[xq.abs_diff(x)];
                    s += k * v[yq * w + xq];
                    ws += k;
                }
            }
            out[y * w + x] = s / ws;
        }
    }
    out
}
