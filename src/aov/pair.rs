//! Two integrators of one scene side by side (`raytree versus --pair A,B` for the pairs other
//! than Whitted and path, which [`super::versus`] breaks down by light transport class): both
//! images, their mean luminance over a region, and the mean signed difference `B - A` per
//! channel with its 95 % interval over 8x8-pixel blocks
//! ([`crate::analysis::bias::signed_difference`]). Path tracing, light tracing and BDPT are
//! unbiased estimators of the same image wherever each can reach the light, so a difference
//! beyond the noise is a bias in one of them, or light one of them cannot carry (light tracing
//! does not see what the camera sees only through specular surfaces).

use crate::analysis::bias::{Region, SignedDifference, signed_difference};
use crate::bsdf::luminance;
use crate::integrator::SceneIntegrator;
use crate::render::steps::Steps;
use crate::render::{Image, RenderStats, Rendered};
use crate::scene::{IntegratorKind, Scene};

/// One side of a [`Pair`].
#[derive(Clone, Debug)]
pub struct Side {
    /// Its integrator.
    pub kind: IntegratorKind,
    /// Its render.
    pub image: Image,
    /// Its counts.
    pub stats: RenderStats,
    /// Mean luminance per pixel over the region.
    pub mean_luminance: f64,
}

/// The comparison ([`pair`]).
#[derive(Clone, Debug)]
pub struct Pair {
    /// Side A.
    pub a: Side,
    /// Side B.
    pub b: Side,
    /// The region `[x0, y0, x1, y1)` the numbers are over.
    pub region: [u32; 4],
    /// `B - A` per channel with its 95 % interval (`None` for an empty region).
    pub difference: Option<SignedDifference>,
}

/// Render `scene` with each of `kinds` (the scene's other settings unchanged; `render` calls
/// [`crate::render::render`] in the CLI and a test, which may time it) and compare them over
/// `region` (`[x0, y0, x1, y1)`, clamped; the whole image when `None`).
pub fn pair(
    scene: &Scene,
    kinds: [IntegratorKind; 2],
    region: Option<[u32; 4]>,
    render: &mut dyn FnMut(&Scene) -> Rendered,
) -> Pair {
    let [a, b] = sides(scene, kinds).map(|s| render(&s));
    paired(kinds, region, a, b)
}

/// `scene` under each of `kinds`.
fn sides(scene: &Scene, kinds: [IntegratorKind; 2]) -> [Scene; 2] {
    kinds.map(|kind| {
        let mut s = scene.clone();
        s.settings.integrator = kind;
        s
    })
}

/// The comparison of render `a` by `kinds[0]` and `b` by `kinds[1]` over `region` (clamped;
/// the whole image when `None`).
fn paired(kinds: [IntegratorKind; 2], region: Option<[u32; 4]>, a: Rendered, b: Rendered) -> Pair {
    let (w, h) = (a.image.width, a.image.height);
    let region = region.map_or([0, 0, w, h], |[x0, y0, x1, y1]| {
        [x0.min(w), y0.min(h), x1.min(w), y1.min(h)]
    });
    let side = |kind, r: Rendered| Side {
        kind,
        mean_luminance: mean_luminance(&r.image, region),
        image: r.image,
        stats: r.stats,
    };
    let (a, b) = (side(kinds[0], a), side(kinds[1], b));
    let [x0, y0, x1, y1] = region;
    let difference = (x0 < x1 && y0 < y1)
        .then(|| signed_difference(&b.image, &a.image, Region { x0, y0, x1, y1 }))
        .flatten();
    Pair {
        a,
        b,
        region,
        difference,
    }
}

/// [`pair`] rendered by [`crate::render::render`], a piece at a time
/// ([`crate::render::steps`]; the web page has no threads): the same comparison, bit for bit.
pub struct PairSteps {
    kinds: [IntegratorKind; 2],
    region: Option<[u32; 4]>,
    scenes: [Scene; 2],
    /// Side A's steps, then side B's.
    steps: Steps<()>,
    /// Side A's render, once its steps are done.
    a: Option<Rendered>,
}

impl PairSteps {
    /// The comparison of `scene` under `kinds` over `region`, as [`pair`] takes them.
    #[must_use]
    pub fn new(scene: &Scene, kinds: [IntegratorKind; 2], region: Option<[u32; 4]>) -> Self {
        let scenes = sides(scene, kinds);
        let steps = Steps::new(&SceneIntegrator::new(&scenes[0]), false);
        Self {
            kinds,
            region,
            scenes,
            steps,
            a: None,
        }
    }

    /// Trace pixels (side A's render, then side B's) while `more_time` says so, at least one;
    /// returns whether more is to come.
    pub fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        let side = usize::from(self.a.is_some());
        let integrator = SceneIntegrator::new(&self.scenes[side]);
        if self.steps.step_plain(&integrator, more_time) {
            return true;
        }
        if side == 1 {
            return false;
        }
        let b = Steps::new(&SceneIntegrator::new(&self.scenes[1]), false);
        self.a = Some(std::mem::replace(&mut self.steps, b).rendered());
        true
    }

    /// The comparison (once [`PairSteps::step`] returned `false`).
    #[must_use]
    pub fn finish(self) -> Pair {
        let b = self.steps.rendered();
        let a = self.a.unwrap_or_else(|| b.clone());
        paired(self.kinds, self.region, a, b)
    }
}

impl Pair {
    /// The channels whose difference lies beyond the noise (95 %), by name.
    #[must_use]
    pub fn significant(&self) -> Vec<&'static str> {
        let Some(d) = &self.difference else {
            return Vec::new();
        };
        ["R", "G", "B"]
            .into_iter()
            .enumerate()
            .filter(|&(c, _)| d.significant(c))
            .map(|(_, n)| n)
            .collect()
    }

    /// The comparison in words.
    #[must_use]
    pub fn summary(&self) -> String {
        let (a, b) = (self.a.kind.name(), self.b.kind.name());
        let [x0, y0, x1, y1] = self.region;
        let mut s = format!(
            "{a} vs {b} over pixels {x0},{y0}..{x1},{y1}: mean luminance {a} {}, {b} {}\n",
            crate::text::sci(self.a.mean_luminance, Some(3)),
            crate::text::sci(self.b.mean_luminance, Some(3))
        );
        let Some(d) = &self.difference else {
            s.push_str("empty region: nothing to compare\n");
            return s;
        };
        let unit = if d.block == 1 { "pixels" } else { "blocks" };
        s.push_str(&format!(
            "{b} - {a} per channel, 95 % interval over {} {unit} of {}x{}:",
            d.blocks, d.block, d.block
        ));
        for (c, n) in ["R", "G", "B"].iter().enumerate() {
            s.push_str(&format!(
                " {n} {} +- {}",
                crate::text::sci(d.mean[c], Some(2)),
                crate::text::sci(d.half_width[c], Some(2))
            ));
        }
        s.push('\n');
        let beyond = self.significant();
        if beyond.is_empty() {
            s.push_str(
                "within the noise in every channel: no evidence that the two estimate \
                 different images (more samples narrow the interval)",
            );
        } else {
            let has = |k| self.a.kind == k || self.b.kind == k;
            let mut why = vec!["a bias in one of them"];
            if has(IntegratorKind::Light) {
                why.push(
                    "light that light tracing cannot carry (it does not see what the camera sees \
                     only through specular surfaces: emitters, glass, mirrors)",
                );
            }
            if has(IntegratorKind::Whitted) {
                why.push(
                    "Whitted's approximations (no indirect light or caustics; ambient, \
                     highlights and translucent shadows of its own)",
                );
            }
            s.push_str(&format!(
                "beyond the noise in {}: the two estimate different images here ({})",
                beyond.join(", "),
                why.join(", or ")
            ));
        }
        s
    }

    /// The signed luminance difference `B - A` as RGB (red where B is brighter, blue where
    /// darker), full at the 99th percentile of its magnitude, and that scale.
    #[must_use]
    pub fn difference_rgb8(&self) -> (Vec<[u8; 3]>, f64) {
        signed_rgb8(&self.a.image, &self.b.image)
    }
}

/// Mean luminance per pixel of `image` over `region` (0 for an empty one).
fn mean_luminance(image: &Image, [x0, y0, x1, y1]: [u32; 4]) -> f64 {
    let n = f64::from(x1.saturating_sub(x0)) * f64::from(y1.saturating_sub(y0));
    if n == 0.0 {
        return 0.0;
    }
    let sum: f64 = (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| luminance(image.pixels[(y * image.width + x) as usize]))
        .sum();
    sum / n
}

/// The signed luminance difference `b - a` per pixel as RGB: red where `b` is brighter, blue
/// where darker, full at the 99th percentile of the magnitude; and that scale.
#[must_use]
pub fn signed_rgb8(a: &Image, b: &Image) -> (Vec<[u8; 3]>, f64) {
    let d: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(a, b)| luminance(*b) - luminance(*a))
        .collect();
    let mut mags: Vec<f64> = d.iter().map(|x| x.abs()).collect();
    let scale = if mags.is_empty() {
        1.0
    } else {
        let k = (mags.len() - 1) * 99 / 100;
        let m = *mags.select_nth_unstable_by(k, f64::total_cmp).1;
        if m > 0.0 && m.is_finite() { m } else { 1.0 }
    };
    let pixels = d
        .iter()
        .map(|x| {
            let t = ((x.abs() / scale).min(1.0) * 255.0).round() as u8;
            if *x >= 0.0 { [t, 0, 0] } else { [0, t / 3, t] }
        })
        .collect();
    (pixels, scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    fn flat(w: u32, h: u32, v: f64, noise: f64) -> Image {
        let mut rng = crate::sampling::SplitMix64::new((v * 1000.0) as u64 + 1);
        let pixels = (0..w * h)
            .map(|_| Rgb::splat(v + noise * (rng.next_f64() - 0.5)))
            .collect();
        Image {
            width: w,
            height: h,
            pixels,
        }
    }

    fn fake(images: [Image; 2]) -> impl FnMut(&Scene) -> crate::render::Rendered {
        let mut it = images.into_iter();
        move |_| crate::render::Rendered {
            image: it.next().unwrap(),
            stats: RenderStats::default(),
            map: crate::render::DiagnosticMap::default(),
        }
    }

    #[test]
    fn equal_images_are_within_the_noise_and_a_bias_is_not() {
        let mut scene = Scene::default_scene();
        scene.camera.width = 64;
        scene.camera.height = 64;
        let kinds = [IntegratorKind::Path, IntegratorKind::Bdpt];
        let same = pair(
            &scene,
            kinds,
            None,
            &mut fake([flat(64, 64, 0.5, 0.2), flat(64, 64, 0.5, 0.2)]),
        );
        assert!(same.significant().is_empty(), "{}", same.summary());
        assert!(same.summary().contains("within the noise"));
        // B 0.05 brighter against noise of +-0.1 per pixel: 64 blocks see it.
        let biased = pair(
            &scene,
            kinds,
            None,
            &mut fake([flat(64, 64, 0.5, 0.2), flat(64, 64, 0.55, 0.2)]),
        );
        assert_eq!(
            biased.significant(),
            ["R", "G", "B"],
            "{}",
            biased.summary()
        );
        assert!((biased.b.mean_luminance - biased.a.mean_luminance - 0.05).abs() < 0.01);
        assert!(biased.summary().contains("beyond the noise in R, G, B"));
        let (px, scale) = biased.difference_rgb8();
        assert_eq!(px.len(), 64 * 64);
        assert!(scale > 0.0 && scale.is_finite());
        // A region: clamped, and the numbers are over it only.
        let r = pair(
            &scene,
            kinds,
            Some([60, 60, 99, 99]),
            &mut fake([flat(64, 64, 0.5, 0.0), flat(64, 64, 0.5, 0.0)]),
        );
        assert_eq!(r.region, [60, 60, 64, 64]);
        let e = pair(
            &scene,
            kinds,
            Some([10, 10, 10, 20]),
            &mut fake([flat(64, 64, 0.5, 0.0), flat(64, 64, 0.5, 0.0)]),
        );
        assert!(e.difference.is_none() && e.summary().contains("empty region"));
    }
}
