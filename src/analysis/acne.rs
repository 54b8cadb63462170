//! The self-intersection sweep behind `raytree acne`: render one scene for every offset
//! strategy x epsilon x scene scale with the diagnostics on, and count self-hit (acne) and
//! leak pixels. Pure: the CLI writes the report, heat maps and plot.

use crate::render::{DiagnosticMap, Image, render};
use crate::scene::{OffsetStrategy, Scene, transformed};
use glam::DVec3;
use serde::Serialize;
use std::fmt::Write;

/// What to sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AcneConfig {
    /// Offset strategies.
    pub strategies: Vec<OffsetStrategy>,
    /// Epsilons (absolute world units; `scaled` makes them relative, `robust` ignores them).
    pub epsilons: Vec<f64>,
    /// Scene scales: the scene becomes `scale * x + scale * shift * (1, 1, 1)`.
    pub scales: Vec<f64>,
    /// Distance the scene is moved from the origin, per unit scale and axis, so that its
    /// coordinates are `shift` times larger than its features at every scale.
    pub shift: f64,
    /// Image width of each render.
    pub width: u32,
    /// Image height of each render.
    pub height: u32,
}

impl Default for AcneConfig {
    fn default() -> Self {
        Self {
            strategies: OffsetStrategy::ALL.to_vec(),
            epsilons: (-7..=-1).map(|e| 10f64.powi(e)).collect(),
            scales: (-3..=6).map(|e| 10f64.powi(e)).collect(),
            shift: 1e3,
            width: 48,
            height: 36,
        }
    }
}

/// One render of the sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AcneCell {
    /// Strategy.
    pub strategy: OffsetStrategy,
    /// Epsilon.
    pub epsilon: f64,
    /// Scene scale.
    pub scale: f64,
    /// Pixels in the image.
    pub pixels: u64,
    /// Pixels with a self-hit ray.
    pub self_hit_pixels: u64,
    /// Pixels with a leaking ray.
    pub leak_pixels: u64,
    /// Self-hit rays.
    pub self_hit_rays: u64,
    /// Leaking rays.
    pub leak_rays: u64,
    /// Rays traced.
    pub rays: u64,
    /// The rendered image (not serialized).
    #[serde(skip)]
    pub image: Image,
    /// Per-pixel counts (not serialized).
    #[serde(skip)]
    pub map: DiagnosticMap,
}

impl AcneCell {
    /// No self-hit and no leak anywhere.
    #[must_use]
    pub fn clean(&self) -> bool {
        self.self_hit_pixels == 0 && self.leak_pixels == 0
    }
}

/// The whole sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AcneReport {
    /// Always `raytree.acne/1`.
    pub schema: String,
    /// What was swept.
    pub config: AcneConfig,
    /// One cell per strategy x epsilon x scale, in that nesting order.
    pub cells: Vec<AcneCell>,
}

/// The scene of the sweep at `scale`: scaled about the origin and moved `scale * shift` away.
#[must_use]
pub fn scaled_scene(scene: &Scene, scale: f64, shift: f64) -> Scene {
    transformed(scene, scale, DVec3::splat(scale * shift))
}

/// One render of the sweep: `scaled` (already at the cell's size, scale and place, see
/// [`scaled_scene`]) with `strategy` and `epsilon`, diagnosed; `scale` is recorded as given.
#[must_use]
pub fn cell(scaled: &Scene, strategy: OffsetStrategy, epsilon: f64, scale: f64) -> AcneCell {
    let sc = with_offset(scaled, strategy, epsilon);
    let rendered = render(
        &crate::integrator::SceneIntegrator::new(&sc),
        &crate::render::RenderOptions::diagnosed(),
        &|_| {},
    );
    cell_of(&sc, scale, rendered)
}

/// `scaled` with the offset `strategy` and `epsilon`.
fn with_offset(scaled: &Scene, strategy: OffsetStrategy, epsilon: f64) -> Scene {
    let mut sc = scaled.clone();
    sc.settings.offset.strategy = strategy;
    sc.settings.offset.epsilon = epsilon;
    sc
}

/// The cell of `sc` (a lab scene with its offset set) from its diagnosed render.
fn cell_of(sc: &Scene, scale: f64, rendered: crate::render::Rendered) -> AcneCell {
    let (image, stats, map) = rendered.into_parts();
    AcneCell {
        strategy: sc.settings.offset.strategy,
        epsilon: sc.settings.offset.epsilon,
        scale,
        pixels: u64::from(sc.camera.width) * u64::from(sc.camera.height),
        self_hit_pixels: stats.self_hit_pixels,
        leak_pixels: stats.leak_pixels,
        self_hit_rays: stats.rays.self_hits,
        leak_rays: stats.rays.leaks,
        rays: stats.rays.total(),
        image,
        map,
    }
}

/// [`cell`] a piece at a time ([`crate::render::steps`]; the web page has no threads): the
/// same cell, bit for bit.
pub struct CellSteps {
    scene: Scene,
    scale: f64,
    steps: crate::render::steps::Steps<()>,
}

impl CellSteps {
    /// The cell [`cell`] makes of these arguments.
    #[must_use]
    pub fn new(scaled: &Scene, strategy: OffsetStrategy, epsilon: f64, scale: f64) -> Self {
        let scene = with_offset(scaled, strategy, epsilon);
        let steps = crate::render::steps::Steps::new(
            &crate::integrator::SceneIntegrator::new(&scene),
            true,
        );
        Self {
            scene,
            scale,
            steps,
        }
    }

    /// Trace pixels while `more_time` says so, at least one; returns whether more is to come.
    pub fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        let integrator = crate::integrator::SceneIntegrator::new(&self.scene);
        self.steps.step_plain(&integrator, more_time)
    }

    /// The cell (once [`CellSteps::step`] returned `false`).
    #[must_use]
    pub fn finish(self) -> AcneCell {
        cell_of(&self.scene, self.scale, self.steps.rendered())
    }
}

/// Run the sweep; `progress` receives the number of renders finished.
#[must_use]
pub fn sweep(scene: &Scene, config: &AcneConfig, progress: &(dyn Fn(usize) + Sync)) -> AcneReport {
    let mut cells = Vec::new();
    let base = Scene {
        camera: scene.camera.with_size(config.width, config.height),
        ..scene.clone()
    };
    let scenes: Vec<Scene> = config
        .scales
        .iter()
        .map(|&s| scaled_scene(&base, s, config.shift))
        .collect();
    for &strategy in &config.strategies {
        for &epsilon in &config.epsilons {
            for (scaled, &scale) in scenes.iter().zip(&config.scales) {
                cells.push(cell(scaled, strategy, epsilon, scale));
                progress(cells.len());
            }
        }
    }
    AcneReport {
        schema: "raytree.acne/1".to_string(),
        config: config.clone(),
        cells,
    }
}

/// `1e-3`-style label of a power of ten (or `{:e}` otherwise).
#[must_use]
pub fn sci(v: f64) -> String {
    format!("{v:e}")
}

impl AcneReport {
    /// Number of renders.
    #[must_use]
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the sweep is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The cells of one strategy and epsilon, in scale order.
    pub fn row(&self, strategy: OffsetStrategy, epsilon: f64) -> impl Iterator<Item = &AcneCell> {
        self.cells
            .iter()
            .filter(move |c| c.strategy == strategy && c.epsilon == epsilon)
    }

    /// Epsilons at which `strategy` is clean at every scale.
    #[must_use]
    pub fn clean_everywhere(&self, strategy: OffsetStrategy) -> Vec<f64> {
        let eps = &self.config.epsilons;
        eps.iter()
            .copied()
            .filter(|&e| self.row(strategy, e).all(AcneCell::clean))
            .collect()
    }

    /// The report as Markdown: a table of `acne / leak` pixel percentages per strategy and
    /// epsilon (rows) and scale (columns), then a verdict per strategy.
    #[must_use]
    pub fn markdown(&self, scene_label: &str) -> String {
        let c = &self.config;
        let mut s = format!(
            "# Self-intersection sweep: {scene_label}\n\n\
             {}x{} pixels per render; scene scaled by `s` about the origin and moved by \
             `s * {}` along each axis. Each cell: % of pixels with a self-hit ray (acne) / \
             % with a leaking ray (offset skipped a surface). `.` = clean.\n\n",
            c.width,
            c.height,
            sci(c.shift)
        );
        s.push_str("| strategy | epsilon |");
        for sc in &c.scales {
            let _ = write!(s, " s={} |", sci(*sc));
        }
        s.push_str("\n|---|---|");
        s.push_str(&"---|".repeat(c.scales.len()));
        s.push('\n');
        for &st in &c.strategies {
            for &e in &c.epsilons {
                let _ = write!(s, "| {} | {} |", st.name(), sci(e));
                for cell in self.row(st, e) {
                    let _ = write!(s, " {} |", cell_text(cell));
                }
                s.push('\n');
            }
        }
        s.push_str("\n## Verdict\n\n");
        for &st in &c.strategies {
            let ok = self.clean_everywhere(st);
            let verdict = if !st.uses_epsilon() && ok.len() == c.epsilons.len() {
                "clean at every scale (uses no epsilon)".to_string()
            } else if ok.is_empty() {
                "no epsilon is clean at every scale".to_string()
            } else {
                let list: Vec<String> = ok.iter().map(|e| sci(*e)).collect();
                format!("clean at every scale with epsilon {}", list.join(", "))
            };
            let _ = writeln!(s, "- `{}`: {verdict}", st.name());
        }
        s
    }
}

fn cell_text(c: &AcneCell) -> String {
    if c.clean() {
        return ".".to_string();
    }
    let pct = |n: u64| {
        if n == 0 {
            "-".to_string()
        } else {
            format!("{:.1}", 100.0 * n as f64 / c.pixels.max(1) as f64)
        }
    };
    format!("{} / {}", pct(c.self_hit_pixels), pct(c.leak_pixels))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiny_sweep_finds_acne_and_leaks_but_robust_is_clean() {
        let config = AcneConfig {
            strategies: vec![OffsetStrategy::Normal, OffsetStrategy::Robust],
            epsilons: vec![1e-9, 1e-1],
            scales: vec![1e-3, 1e6],
            width: 16,
            height: 12,
            ..AcneConfig::default()
        };
        let r = sweep(&Scene::default_scene(), &config, &|_| {});
        assert_eq!(r.len(), 8);
        let at = |st, e, s| {
            r.cells
                .iter()
                .find(|c| c.strategy == st && c.epsilon == e && c.scale == s)
                .unwrap()
        };
        // Too small for a scene a billion units from the origin: acne.
        assert!(at(OffsetStrategy::Normal, 1e-9, 1e6).self_hit_pixels > 0);
        // Too large for a millimetre scene: leaks.
        assert!(at(OffsetStrategy::Normal, 1e-1, 1e-3).leak_pixels > 0);
        assert_eq!(r.clean_everywhere(OffsetStrategy::Robust), vec![1e-9, 1e-1]);
        let md = r.markdown("classic");
        assert!(md.contains("| normal | 1e-9 |") && md.contains("`robust`: clean at every scale"));
    }

    #[test]
    fn a_stepped_cell_is_the_cell() {
        let scene = scaled_scene(&Scene::default_scene(), 1e6, 1e3);
        let scene = Scene {
            camera: scene.camera.with_size(12, 8),
            ..scene
        };
        let whole = cell(&scene, OffsetStrategy::Normal, 1e-9, 1e6);
        assert!(whole.self_hit_pixels > 0, "the test needs acne");
        let mut steps = CellSteps::new(&scene, OffsetStrategy::Normal, 1e-9, 1e6);
        let mut n = 1;
        while steps.step(&|| false) {
            n += 1;
        }
        assert_eq!(n, 12 * 8, "a pixel a step");
        assert_eq!(format!("{:?}", steps.finish()), format!("{whole:?}"));
    }
}
