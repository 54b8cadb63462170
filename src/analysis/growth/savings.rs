//! What the bounded-error cut saves, measured on a grid of pixels.

use crate::integrator::bound::carried::effective_roulette_below;
use crate::integrator::bound::effective_min_weight;
use crate::integrator::{NoopRecorder, RayCounts};
use crate::scene::{Scene, Settings};

/// Rays of the default (automatic `min_weight`) tree against the exhaustive one on a grid of
/// pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutSavings {
    /// Grid columns and rows (pixel centres of equal cells, one sample each).
    pub grid: [u32; 2],
    /// The automatic cut used.
    pub min_weight: f64,
    /// The automatic roulette weight used (0: every dielectric hit split).
    pub roulette_below: f64,
    /// Rays of every kind with the cut.
    pub cut_rays: u64,
    /// Rays of every kind with `min_weight` 0 (bounded per sample by `settings.max_rays`).
    pub exhaustive_rays: u64,
    /// Samples of the exhaustive run that reached `max_rays` (then `exhaustive_rays` is a
    /// lower bound).
    pub budget_samples: u64,
}

impl CutSavings {
    /// `exhaustive_rays / cut_rays`.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.exhaustive_rays as f64 / self.cut_rays.max(1) as f64
    }

    /// "the automatic cut traces N rays where the exhaustive tree would trace M (x fewer) on a
    /// 16x9 sample".
    #[must_use]
    pub fn sentence(&self) -> String {
        let at_least = if self.budget_samples > 0 {
            "at least "
        } else {
            ""
        };
        let budget = if self.budget_samples > 0 {
            format!(
                "; {} samples reached the ray budget max_rays",
                self.budget_samples
            )
        } else {
            String::new()
        };
        let ratio = self.ratio();
        let fewer = if ratio < 1.05 && self.budget_samples == 0 {
            "no saving".to_string()
        } else {
            format!("{at_least}{ratio:.1}x fewer")
        };
        let what = if self.roulette_below > 0.0 {
            format!(
                "the automatic cut (min_weight {:.2e}) and roulette (below weight {:.2e}) trace",
                self.min_weight, self.roulette_below
            )
        } else {
            format!(
                "the automatic cut (min_weight {:.2e}) traces",
                self.min_weight
            )
        };
        format!(
            "{what} {} rays where the exhaustive tree would trace {at_least}{} ({fewer}) on a \
             {}x{} sample of pixel centres{budget}",
            self.cut_rays, self.exhaustive_rays, self.grid[0], self.grid[1]
        )
    }
}

/// The pixels of a `cols x rows` grid over a `w x h` image: the centre pixel of each cell.
#[must_use]
pub fn grid_pixels(w: u32, h: u32, cols: u32, rows: u32) -> Vec<(u32, u32)> {
    let cell = |i: u32, n: u32, len: u32| {
        ((2 * u64::from(i) + 1) * u64::from(len) / (2 * u64::from(n))).min(u64::from(len) - 1)
            as u32
    };
    if w == 0 || h == 0 {
        return Vec::new();
    }
    (0..rows)
        .flat_map(|r| (0..cols).map(move |c| (cell(c, cols, w), cell(r, rows, h))))
        .collect()
}

/// Trace the grid's pixels (one sample at each centre) with the scene's automatic cut and
/// roulette and with the exhaustive tree, and count the rays. `min_weight` and `roulette_below`
/// set in the scene are ignored: the question is what the default saves. `cancelled` is polled between pixels; `None` if it said
/// so.
#[must_use]
pub fn cut_savings(
    scene: &Scene,
    cols: u32,
    rows: u32,
    cancelled: &dyn Fn() -> bool,
) -> Option<CutSavings> {
    let with = |min_weight, roulette_below| Scene {
        settings: Settings {
            whitted: crate::scene::WhittedSettings {
                min_weight,
                roulette_below,
                ..scene.settings.whitted
            },
            spp: 1,
            ..scene.settings
        },
        ..scene.clone()
    };
    let (cut, full) = (with(None, None), with(Some(0.0), Some(0.0)));
    let pixels = grid_pixels(scene.camera.width, scene.camera.height, cols, rows);
    let count = |s: &Scene| {
        let tracer = crate::integrator::Whitted::new(s);
        let mut counts = RayCounts::default();
        for &(x, y) in &pixels {
            if cancelled() {
                return None;
            }
            crate::render::render_pixel(
                &tracer,
                &mut crate::sampling::SceneSampler::for_settings(&tracer.scene().settings),
                (x, y),
                &mut NoopRecorder,
                &mut counts,
                |_| {},
            );
        }
        Some(counts)
    };
    let a = count(&cut)?;
    let b = count(&full)?;
    Some(CutSavings {
        grid: [cols, rows],
        min_weight: effective_min_weight(&cut),
        roulette_below: effective_roulette_below(&cut),
        cut_rays: a.total(),
        exhaustive_rays: b.total(),
        budget_samples: b.budget_samples,
    })
}
