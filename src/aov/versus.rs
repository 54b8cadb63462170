//! Whitted vs path tracing of one scene: both images, and the difference broken down by the
//! light transport classes ([`super::CLASSES`]) the path tracer's paths fall into.
//!
//! Over a region (the whole image by default) the path-traced luminance is the sum of its
//! classes' AOVs. The classes Whitted cannot render (environment light on diffuse surfaces,
//! caustics, indirect light) are what it misses; the classes both render (emission, background,
//! direct light) still differ by Whitted's approximations (ambient, Blinn-Phong highlights,
//! translucent shadows) and by Monte Carlo noise: that difference, `shared - whitted`, is
//! reported as one more term. Shares are of the sum of the magnitudes of these terms.

use super::{AovError, AovRender, AovSteps, CLASSES, render_aovs, standard_classes};
use crate::bsdf::luminance;
use crate::integrator::SceneIntegrator;
use crate::render::steps::Steps;
use crate::render::{Image, RenderStats, Rendered};
use crate::scene::{IntegratorKind, Scene};

/// One class's part of the difference.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassShare {
    /// The class's name ([`super::Class::name`]).
    pub name: &'static str,
    /// Its expression.
    pub lpe: &'static str,
    /// Whether Whitted renders it too.
    pub whitted: bool,
    /// Summed luminance of the class's AOV over the region.
    pub luminance: f64,
}

/// The comparison ([`versus`]).
#[derive(Clone, Debug)]
pub struct Versus {
    /// The Whitted render.
    pub whitted: Image,
    /// Its counts.
    pub whitted_stats: RenderStats,
    /// The path-traced render with one AOV per class (in [`CLASSES`] order).
    pub path: AovRender,
    /// The region `[x0, y0, x1, y1)` the sums are over.
    pub region: [u32; 4],
    /// Summed luminance of the Whitted image over the region.
    pub whitted_luminance: f64,
    /// Summed luminance of the path-traced image over the region.
    pub path_luminance: f64,
    /// Each class's summed luminance.
    pub classes: Vec<ClassShare>,
}

impl Versus {
    /// What the classes Whitted also renders differ by: their path-traced luminance minus
    /// Whitted's (its approximations and the noise).
    #[must_use]
    pub fn shared_difference(&self) -> f64 {
        let shared: f64 = self
            .classes
            .iter()
            .filter(|c| c.whitted)
            .map(|c| c.luminance)
            .sum();
        shared - self.whitted_luminance
    }

    /// The terms of the breakdown: each class Whitted misses with its luminance, then
    /// `("shared", shared_difference)`; and the share of each (its magnitude over the sum of
    /// the magnitudes; all 0 when nothing differs).
    #[must_use]
    pub fn breakdown(&self) -> Vec<(&'static str, f64, f64)> {
        let mut terms: Vec<(&'static str, f64)> = self
            .classes
            .iter()
            .filter(|c| !c.whitted)
            .map(|c| (c.name, c.luminance))
            .collect();
        terms.push(("shared", self.shared_difference()));
        let total: f64 = terms.iter().map(|t| t.1.abs()).sum();
        terms
            .into_iter()
            .map(|(n, v)| (n, v, if total > 0.0 { v.abs() / total } else { 0.0 }))
            .collect()
    }
}

impl Versus {
    /// The breakdown in words: the region's luminances, what Whitted misses by class, what
    /// differs in what both render, then one line per class.
    #[must_use]
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let [x0, y0, x1, y1] = self.region;
        let mut s = format!(
            "region {x0},{y0}..{x1},{y1}: Whitted luminance {:.4}, path {:.4} (sums over pixels)\n",
            self.whitted_luminance, self.path_luminance
        );
        let terms = self.breakdown();
        let parts: Vec<String> = terms
            .iter()
            .filter(|t| t.0 != "shared")
            .map(|(n, _, share)| format!("{:.0}% {n}", 100.0 * share))
            .collect();
        let _ = write!(s, "what Whitted misses here: {}", parts.join(", "));
        if let Some((_, d, share)) = terms.iter().find(|t| t.0 == "shared") {
            let _ = write!(
                s,
                "; {:.0}% differs in what both render (path - Whitted = {d:+.4}: ambient, Phong highlights, translucent shadows, noise)",
                100.0 * share
            );
        }
        s.push_str("\nclass        expression            luminance  Whitted renders it\n");
        for c in &self.classes {
            let _ = writeln!(
                s,
                "{:<12} {:<21} {:>10.4}  {}",
                c.name,
                c.lpe,
                c.luminance,
                if c.whitted { "yes" } else { "no" }
            );
        }
        s.trim_end().to_owned()
    }

    /// The signed luminance difference path - Whitted in false colour (8-bit RGB), row-major:
    /// red where the path tracer is brighter (light Whitted misses), blue where Whitted is;
    /// full colour at the 99th percentile of the magnitude, which is returned with it.
    #[must_use]
    pub fn difference_rgb8(&self) -> (Vec<[u8; 3]>, f64) {
        super::pair::signed_rgb8(&self.whitted, &self.path.beauty)
    }
}

/// Sum of `f(pixel)` over `region` of `image`.
fn region_sum(image: &Image, [x0, y0, x1, y1]: [u32; 4]) -> f64 {
    (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| luminance(image.get(x, y)))
        .sum()
}

/// Render `scene` with both integrators (the scene's other settings unchanged) and break the
/// difference over `region` (`[x0, y0, x1, y1)`, clamped to the image; the whole image when
/// `None`) down by light transport class.
///
/// # Errors
/// None in practice ([`render_aovs`] under the path integrator with the six classes).
pub fn versus(
    scene: &Scene,
    region: Option<[u32; 4]>,
    progress: &(dyn Fn(u32) + Sync),
) -> Result<Versus, AovError> {
    let [whitted_scene, path_scene] = sides(scene);
    let whitted = crate::render::render(
        &SceneIntegrator::new(&whitted_scene),
        &crate::render::RenderOptions::new(),
        progress,
    );
    let lpes = standard_classes();
    let path = render_aovs(&SceneIntegrator::new(&path_scene), &lpes, progress)?;
    Ok(compared(region, whitted, path))
}

/// `scene` under Whitted and under the path tracer.
fn sides(scene: &Scene) -> [Scene; 2] {
    [IntegratorKind::Whitted, IntegratorKind::Path].map(|kind| {
        let mut s = scene.clone();
        s.settings.integrator = kind;
        s
    })
}

/// The comparison of the two renders over `region` (clamped; the whole image when `None`).
fn compared(region: Option<[u32; 4]>, whitted: Rendered, path: AovRender) -> Versus {
    let (w, h) = (whitted.image.width, whitted.image.height);
    let region = region.map_or([0, 0, w, h], |[x0, y0, x1, y1]| {
        [x0.min(w), y0.min(h), x1.min(w), y1.min(h)]
    });
    let classes = CLASSES
        .iter()
        .zip(&path.aovs)
        .map(|(c, img)| ClassShare {
            name: c.name,
            lpe: c.lpe,
            whitted: c.whitted,
            luminance: region_sum(img, region),
        })
        .collect();
    Versus {
        whitted_luminance: region_sum(&whitted.image, region),
        path_luminance: region_sum(&path.beauty, region),
        whitted: whitted.image,
        whitted_stats: whitted.stats,
        path,
        region,
        classes,
    }
}

/// [`versus`] a piece at a time ([`crate::render::steps`]; the web page has no threads): the
/// same comparison, bit for bit.
pub struct VersusSteps {
    region: Option<[u32; 4]>,
    scenes: [Scene; 2],
    whitted: Steps<()>,
    /// The Whitted render, once its steps are done.
    whitted_done: Option<Rendered>,
    path: AovSteps,
}

impl VersusSteps {
    /// The comparison of `scene` over `region`, as [`versus`] takes them.
    #[must_use]
    pub fn new(scene: &Scene, region: Option<[u32; 4]>) -> Self {
        let scenes = sides(scene);
        let whitted = Steps::new(&SceneIntegrator::new(&scenes[0]), false);
        let path = AovSteps::new(&SceneIntegrator::new(&scenes[1]), standard_classes())
            .expect("the path tracer takes the six classes");
        Self {
            region,
            scenes,
            whitted,
            whitted_done: None,
            path,
        }
    }

    /// Trace pixels (the Whitted render's, then the path tracer's) while `more_time` says so,
    /// at least one; returns whether more is to come.
    pub fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        if self.whitted_done.is_none() {
            let integrator = SceneIntegrator::new(&self.scenes[0]);
            if self.whitted.step_plain(&integrator, more_time) {
                return true;
            }
            let steps = std::mem::replace(&mut self.whitted, Steps::new(&integrator, false));
            self.whitted_done = Some(steps.rendered());
            if !more_time() {
                return true;
            }
        }
        self.path
            .step(&SceneIntegrator::new(&self.scenes[1]), more_time)
    }

    /// The comparison (once [`VersusSteps::step`] returned `false`).
    #[must_use]
    pub fn finish(self) -> Versus {
        let whitted = self.whitted_done.unwrap_or_else(|| self.whitted.rendered());
        compared(self.region, whitted, self.path.finish())
    }
}
