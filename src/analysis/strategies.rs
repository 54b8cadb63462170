//! Veach's per-strategy images (issue 30, `raytree strategies`; Veach 1997, figure 10.3): a
//! bidirectional render split by the strategy `(s, t)` that made each contribution, weighted
//! (they add up to the render) and unweighted (each strategy alone, MIS off: an unbiased
//! estimate of its path length wherever the strategy can make the path).
//!
//! One pass over the same samples as the render: every camera sample through
//! [`Bdpt::trace_camera_observed`] (the same random numbers, the same NaN rule), every light
//! subpath through the render's light pass, its `t = 1` splats kept apart by `s`. So the
//! weighted images plus the background and the longer paths sum to the rendered image up to
//! the order of the additions.

use crate::integrator::{Bdpt, Integrator, NoopRecorder, RayCounts, Splat, StrategyPart};
use crate::math::Rgb;
use crate::render::pixel_loop::Camera;
use crate::render::splat::{light_rounds, light_sampler};
use crate::sampling::SceneSampler;
use crate::scene::Scene;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// What a part of the image is: a strategy, the background the camera saw, or a strategy of a
/// path longer than the split keeps apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Part {
    /// The background (or environment) a camera subpath escaped to.
    Background,
    /// Strategy `(s, t)`: `s` light-subpath and `t` camera-subpath vertices.
    Strategy {
        /// Light-subpath vertices (the emitter's counted).
        s: u32,
        /// Camera-subpath vertices (the lens counted).
        t: u32,
    },
    /// Every strategy of a path with more than the split's bounces, together.
    Longer,
}

impl Part {
    /// Bounces of the strategy's path (`s + t - 2` scattering vertices; 0 = an emitter the
    /// camera sees).
    #[must_use]
    pub fn bounces(self) -> Option<u32> {
        match self {
            Self::Strategy { s, t } => Some(s + t - 2),
            _ => None,
        }
    }

    /// `s=1 t=2`, `background` or `longer`.
    #[must_use]
    pub fn label(self) -> String {
        match self {
            Self::Background => "background".to_string(),
            Self::Strategy { s, t } => format!("s={s} t={t}"),
            Self::Longer => "longer".to_string(),
        }
    }

    /// A file stem: `s1-t2`, `background`, `longer`.
    #[must_use]
    pub fn stem(self) -> String {
        match self {
            Self::Strategy { s, t } => format!("s{s}-t{t}"),
            p => p.label(),
        }
    }
}

/// One part's images (row-major linear radiance, the render's size).
#[derive(Clone, Debug, PartialEq)]
pub struct PartImage {
    /// Which part.
    pub part: Part,
    /// Its MIS-weighted contributions, as they enter the render.
    pub weighted: Vec<Rgb>,
    /// The same contributions before their MIS weights (the background's are its own).
    pub unweighted: Vec<Rgb>,
    /// Contributions it made (non-zero), over the whole image.
    pub contributions: u64,
}

/// A render split by strategy.
#[derive(Clone, Debug)]
pub struct Split {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Strategies of paths with up to this many bounces have their own part.
    pub max_bounces: u32,
    /// The parts that contributed, in [`Part`] order (background, strategies by `(s, t)`,
    /// longer).
    pub parts: Vec<PartImage>,
    /// Camera samples dropped because their sum was not finite (as the render drops them).
    pub dropped: u64,
    /// Rays traced.
    pub rays: RayCounts,
}

impl Split {
    /// The sum of the weighted parts: the rendered image up to rounding.
    #[must_use]
    pub fn total(&self) -> Vec<Rgb> {
        let mut sum = vec![Rgb::ZERO; (self.width * self.height) as usize];
        for p in &self.parts {
            for (a, b) in sum.iter_mut().zip(&p.weighted) {
                *a += *b;
            }
        }
        sum
    }

    /// Each part's share of the image's luminance (weighted; the shares sum to 1 when the
    /// image is not black, otherwise all are 0).
    #[must_use]
    pub fn shares(&self) -> Vec<(Part, f64)> {
        let sums: Vec<f64> = self
            .parts
            .iter()
            .map(|p| p.weighted.iter().map(|&c| crate::bsdf::luminance(c)).sum())
            .collect();
        let total: f64 = sums.iter().sum();
        self.parts
            .iter()
            .zip(sums)
            .map(|(p, s)| {
                let share = if total > 0.0 && total.is_finite() {
                    s / total
                } else {
                    0.0
                };
                (p.part, share)
            })
            .collect()
    }
}

/// Per-part sums of one row or of the whole image: weighted, unweighted, contributions.
type Sums = BTreeMap<Part, (Vec<Rgb>, Vec<Rgb>, u64)>;

/// `part`'s sums in images of `n` pixels, black where it is new.
fn entry(sums: &mut Sums, n: usize, part: Part) -> &mut (Vec<Rgb>, Vec<Rgb>, u64) {
    sums.entry(part)
        .or_insert_with(|| (vec![Rgb::ZERO; n], vec![Rgb::ZERO; n], 0))
}

/// Add `part` at pixel `i` of an image of `n` pixels.
fn add(sums: &mut Sums, n: usize, part: Part, i: usize, unweighted: Rgb, weight: f64) {
    let e = entry(sums, n, part);
    e.0[i] += unweighted * weight;
    e.1[i] += unweighted;
    if unweighted != Rgb::ZERO {
        e.2 += 1;
    }
}

/// The part of strategy `[s, t]` (or the background) under a split at `max_bounces`.
fn part_of(strategy: Option<[u32; 2]>, max_bounces: u32) -> Part {
    match strategy {
        None => Part::Background,
        Some([s, t]) if s + t - 2 <= max_bounces => Part::Strategy { s, t },
        Some(_) => Part::Longer,
    }
}

/// Split `scene`'s bidirectional render (its settings, whatever `settings.integrator` says) by
/// strategy, keeping strategies of paths with up to `max_bounces` bounces apart. `progress`
/// gets the rows finished (camera pass, then light pass: `2 * height` in all).
#[must_use]
pub fn split(scene: &Scene, max_bounces: u32, progress: &(dyn Fn(u32) + Sync)) -> Split {
    let bdpt = Bdpt::new(scene);
    let h = scene.camera.height;
    let done = std::sync::atomic::AtomicU32::new(0);
    let tick = || progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map(|y| {
            let row = camera_row(&bdpt, y, max_bounces);
            tick();
            row
        })
        .collect();
    let mut out = empty(scene, max_bounces);
    let mut sums = Sums::new();
    for (y, row) in (0..h).zip(rows) {
        add_row((out.width, h), &mut sums, &mut out.rays, y, row);
    }
    out.dropped = out.rays.dropped_samples;
    out.rays += light_rows(&bdpt, max_bounces, &mut sums, &|rows| progress(h + rows));
    with_parts(out, sums)
}

/// `scene`'s split with no parts yet, no rays, nothing dropped.
fn empty(scene: &Scene, max_bounces: u32) -> Split {
    Split {
        width: scene.camera.width,
        height: scene.camera.height,
        spp: scene.settings.spp.max(1),
        max_bounces,
        parts: Vec::new(),
        dropped: 0,
        rays: RayCounts::default(),
    }
}

/// `split` with its parts: the image's sums over `spp`, the parts that contributed.
fn with_parts(mut split: Split, sums: Sums) -> Split {
    let spp = f64::from(split.spp);
    split.parts = sums
        .into_iter()
        .filter(|(_, (_, _, contributions))| *contributions > 0)
        .map(|(part, (wt, un, contributions))| PartImage {
            part,
            weighted: wt.into_iter().map(|c| c / spp).collect(),
            unweighted: un.into_iter().map(|c| c / spp).collect(),
            contributions,
        })
        .collect();
    split
}

/// A row being traced: its sampler (made at the row's start, as the render's loops make it),
/// its camera samples' per-part sums (images one row wide) and its rays.
#[derive(Debug)]
struct Row {
    sampler: SceneSampler,
    sums: Sums,
    counts: RayCounts,
}

impl Row {
    /// A camera row of `scene`.
    fn camera(scene: &Scene) -> Self {
        Self::with(SceneSampler::for_settings(&scene.settings))
    }

    /// A light-pass seeding row of `bdpt` (the light paths' sampler, as the render's).
    fn light(bdpt: &Bdpt<'_>) -> Self {
        Self::with(light_sampler(bdpt))
    }

    fn with(sampler: SceneSampler) -> Self {
        Self {
            sampler,
            sums: Sums::new(),
            counts: RayCounts::default(),
        }
    }
}

/// Add camera row `y`'s sums into the image's `sums` and its rays into `rays` (in row order,
/// as [`split`] adds them) of an image of `w x h` pixels.
fn add_row((w, h): (u32, u32), sums: &mut Sums, rays: &mut RayCounts, y: u32, row: Row) {
    let (w, n) = (w as usize, w as usize * h as usize);
    let at = y as usize * w;
    for (part, (wt, un, k)) in row.sums {
        let e = entry(sums, n, part);
        for x in 0..w {
            e.0[at + x] += wt[x];
            e.1[at + x] += un[x];
        }
        e.2 += k;
    }
    *rays += row.counts;
}

/// Row `y`'s camera samples, split ([`camera_pixel`] along the row).
fn camera_row(bdpt: &Bdpt<'_>, y: u32, max_bounces: u32) -> Row {
    let scene = Integrator::scene(bdpt);
    let cam = Camera::new(bdpt);
    let mut row = Row::camera(scene);
    for x in 0..scene.camera.width {
        camera_pixel(bdpt, &cam, &mut row, (x, y), max_bounces);
    }
    row
}

/// Pixel `(x, y)`'s camera samples, split into `row`: the render's sampler and film positions,
/// a sample whose sum is not finite dropped whole (as the render's pixel loop drops it).
fn camera_pixel(
    bdpt: &Bdpt<'_>,
    cam: &Camera<'_>,
    row: &mut Row,
    (x, y): (u32, u32),
    max_bounces: u32,
) {
    let scene = Integrator::scene(bdpt);
    let (w, spp) = (scene.camera.width, scene.settings.spp.max(1));
    let mut parts: Vec<StrategyPart> = Vec::new();
    for s in 0..spp {
        let (_, ray) = cam.sample(&mut row.sampler, x, y, s);
        parts.clear();
        let (l, _) = bdpt.trace_camera_observed(
            ray,
            &mut row.sampler,
            &mut NoopRecorder,
            &mut row.counts,
            |p| {
                parts.push(p);
            },
        );
        if !row.counts.keep_sample(l, false, (x, y, s)) {
            continue;
        }
        for p in &parts {
            let part = part_of(p.strategy, max_bounces);
            add(
                &mut row.sums,
                w as usize,
                part,
                x as usize,
                p.unweighted,
                p.weight,
            );
        }
    }
}

/// A splat as the split keeps it: pixel index, part, unweighted value, MIS weight.
type SplitSplat = (usize, Part, Rgb, f64);

/// Splat `sp`, landing in pixel `i` (row-major), as the split keeps it.
fn keep_splat(i: usize, sp: &Splat, max_bounces: u32) -> SplitSplat {
    let part = part_of(Some([sp.vertices, 1]), max_bounces);
    (i, part, sp.unweighted, sp.mis_weight)
}

/// Add a kept splat to the image's `sums` (`n` pixels).
fn add_splat(sums: &mut Sums, n: usize, (i, part, un, weight): SplitSplat) {
    add(sums, n, part, i, un, weight);
}

/// The light pass ([`light_rounds`], as the render's), its `t = 1` splats added to `sums` by
/// strategy, in path order; `progress` gets the seeding rows finished.
fn light_rows(
    bdpt: &Bdpt<'_>,
    max_bounces: u32,
    sums: &mut Sums,
    progress: &(dyn Fn(u32) + Sync),
) -> RayCounts {
    let scene = Integrator::scene(bdpt);
    let n = (scene.camera.width * scene.camera.height) as usize;
    light_rounds(
        bdpt,
        |i, sp| keep_splat(i, &sp, max_bounces),
        |s| add_splat(sums, n, s),
        progress,
    )
}

/// The light paths seeded by pixel `(x, y)`'s samples, in path order (as the render's light
/// pass traces them along `row`, with `row`'s sampler), each kept splat added to `sums`.
fn light_pixel(
    bdpt: &Bdpt<'_>,
    row: &mut Row,
    (x, y): (u32, u32),
    max_bounces: u32,
    sums: &mut Sums,
) {
    let scene = Integrator::scene(bdpt);
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    crate::render::splat::light_pixel(
        bdpt,
        (x, y),
        &mut row.sampler,
        &mut NoopRecorder,
        &mut row.counts,
        |_, sp: Splat| {
            let (px, py) = sp.pixel;
            let kept = keep_splat(py as usize * w + px as usize, &sp, max_bounces);
            add_splat(sums, w * h, kept);
        },
    );
}

/// [`split`] a piece at a time (the web page's UI thread has no threads): the same `Split`, bit
/// for bit. Pixel by pixel: every pixel's camera samples in row order, then the light paths
/// seeded by every pixel, each in the order [`split`] adds them.
#[derive(Debug)]
pub struct SplitSteps {
    /// The split so far: size, `spp`, `max_bounces`, the camera rows' rays, and once the camera
    /// pass is done, the samples it dropped.
    out: Split,
    /// The light pass's rays, of the seeding rows finished.
    light_rays: RayCounts,
    /// The image's per-part sums.
    sums: Sums,
    /// The row being traced (`None` before its first pixel).
    row: Option<Row>,
    /// The next pixel: `0..n` the camera pass's, `n..2 n` the light pass's (row-major).
    next: u64,
}

impl SplitSteps {
    /// Start splitting `scene`'s render ([`split`]'s arguments, less its progress).
    #[must_use]
    pub fn new(scene: &Scene, max_bounces: u32) -> Self {
        Self {
            out: empty(scene, max_bounces),
            light_rays: RayCounts::default(),
            sums: Sums::new(),
            row: None,
            next: 0,
        }
    }

    /// Pixels in the image.
    fn pixels(&self) -> u64 {
        u64::from(self.out.width) * u64::from(self.out.height)
    }

    /// Trace pixels (camera samples of every pixel in row order, then the light paths seeded by
    /// each pixel, in the order [`split`] adds them) while `more_time()` says so, at least one
    /// pixel per call. Returns whether more is to come. `scene` must be the one given to
    /// [`SplitSteps::new`].
    pub fn step(&mut self, scene: &Scene, more_time: &dyn Fn() -> bool) -> bool {
        debug_assert_eq!(
            (scene.camera.width, scene.camera.height),
            (self.out.width, self.out.height)
        );
        let bdpt = Bdpt::new(scene);
        let cam = Camera::new(&bdpt);
        while self.next < 2 * self.pixels() {
            self.pixel(&bdpt, &cam);
            if !more_time() {
                break;
            }
        }
        self.next < 2 * self.pixels()
    }

    /// Trace the next pixel (camera or light pass), adding its row when it ends one.
    fn pixel(&mut self, bdpt: &Bdpt<'_>, cam: &Camera<'_>) {
        let (n, w) = (self.pixels(), u64::from(self.out.width));
        let camera = self.next < n;
        let i = self.next % n;
        let (x, y) = ((i % w) as u32, (i / w) as u32);
        let mb = self.out.max_bounces;
        let row = self.row.get_or_insert_with(|| {
            if camera {
                Row::camera(Integrator::scene(bdpt))
            } else {
                Row::light(bdpt)
            }
        });
        if camera {
            camera_pixel(bdpt, cam, row, (x, y), mb);
        } else {
            light_pixel(bdpt, row, (x, y), mb, &mut self.sums);
        }
        self.next += 1;
        if x + 1 < self.out.width {
            return;
        }
        let Some(row) = self.row.take() else { return };
        if camera {
            let size = (self.out.width, self.out.height);
            add_row(size, &mut self.sums, &mut self.out.rays, y, row);
            if self.next == n {
                self.out.dropped = self.out.rays.dropped_samples;
            }
        } else {
            self.light_rays += row.counts;
        }
    }

    /// The split (call once [`SplitSteps::step`] returned `false`).
    #[must_use]
    pub fn finish(self) -> Split {
        debug_assert_eq!(
            self.next,
            2 * self.pixels(),
            "SplitSteps::finish before the end"
        );
        let mut out = self.out;
        out.rays += self.light_rays;
        with_parts(out, self.sums)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::IntegratorKind;
    use std::cell::Cell;

    /// `fixtures/<name>` under BDPT at 24 x 18 pixels, 3 samples a pixel.
    fn fixture(name: &str) -> Scene {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fixtures")
            .join(name);
        let mut scene = Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap();
        scene.camera = scene.camera.with_size(24, 18);
        scene.settings.integrator = IntegratorKind::Bdpt;
        scene.settings.spp = 3;
        scene
    }

    /// An image's bits.
    fn bits(image: &[Rgb]) -> Vec<u64> {
        image
            .iter()
            .flat_map(|c| [c.x, c.y, c.z])
            .map(f64::to_bits)
            .collect()
    }

    /// `a` and `b` field by field, images bit for bit.
    fn assert_same(a: &Split, b: &Split, what: &str) {
        assert_eq!(
            (a.width, a.height, a.spp, a.max_bounces),
            (b.width, b.height, b.spp, b.max_bounces),
            "{what}"
        );
        assert_eq!((a.dropped, a.rays), (b.dropped, b.rays), "{what}");
        let names = |s: &Split| s.parts.iter().map(|p| p.part).collect::<Vec<_>>();
        assert_eq!(names(a), names(b), "{what}");
        for (p, q) in a.parts.iter().zip(&b.parts) {
            assert_eq!(p.contributions, q.contributions, "{what} {:?}", p.part);
            assert!(
                bits(&p.weighted) == bits(&q.weighted),
                "{what} {:?}",
                p.part
            );
            assert!(
                bits(&p.unweighted) == bits(&q.unweighted),
                "{what} {:?}",
                p.part
            );
        }
    }

    /// Steps until done, `more_time` saying yes `per_step - 1` times a call: the split and the
    /// calls made.
    fn stepped(scene: &Scene, max_bounces: u32, per_step: u32) -> (Split, u64) {
        let mut steps = SplitSteps::new(scene, max_bounces);
        let mut calls = 0;
        loop {
            calls += 1;
            let asked = Cell::new(0);
            let more = || {
                asked.set(asked.get() + 1);
                asked.get() < per_step
            };
            if !steps.step(scene, &more) {
                break;
            }
        }
        (steps.finish(), calls)
    }

    /// A pixel a call, 7 a call (steps ending mid-row) and all in one call: `split`'s result.
    #[test]
    fn split_steps_make_the_same_split_bit_for_bit() {
        for (name, max_bounces) in [
            ("caustic.json", 1),
            ("cornell-box.json", 1),
            ("cornell-box.json", 3),
        ] {
            let scene = fixture(name);
            let whole = split(&scene, max_bounces, &|_| {});
            let what = format!("{name} at {max_bounces} bounces");
            assert!(whole.parts.iter().any(|p| p.part == Part::Longer), "{what}");
            let light = |p: &PartImage| matches!(p.part, Part::Strategy { t: 1, .. });
            assert!(whole.parts.iter().any(light), "{what}: no light tracing");
            assert!(whole.rays.light > 0 && whole.rays.camera > 0, "{what}");
            let pixels: u64 = 24 * 18;
            for (per_step, calls) in [
                (1, 2 * pixels),
                (7, (2 * pixels).div_ceil(7)),
                (u32::MAX, 1),
            ] {
                let (s, made) = stepped(&scene, max_bounces, per_step);
                assert_eq!(made, calls, "{what}, {per_step} a step");
                assert_same(&s, &whole, &format!("{what}, {per_step} a step"));
            }
        }
    }

    /// An empty image is done at once.
    #[test]
    fn split_steps_of_an_empty_image() {
        let mut scene = fixture("caustic.json");
        scene.camera = scene.camera.with_size(0, 0);
        let mut steps = SplitSteps::new(&scene, 2);
        assert!(!steps.step(&scene, &|| true));
        assert_same(&steps.finish(), &split(&scene, 2, &|_| {}), "empty");
    }
}
