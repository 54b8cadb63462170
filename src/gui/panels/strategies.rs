//! Veach's figure in the inspector (issue 30): the scene's bidirectional render split by the
//! strategy `(s, t)` that made each contribution, on a thread of its own
//! ([`crate::analysis::strategies::split`], what `raytree strategies` runs), shown as a grid of
//! thumbnails, one per strategy, each captioned with its share of the image's luminance; with
//! "unweighted", each strategy with MIS off (each alone estimates all the light of its path
//! length where it can make the path).

use crate::Scene;
use crate::analysis::strategies::{Part, Split, SplitSteps, split};
use crate::gui::jobs::background::{Inbox, Work, deliver};
use crate::gui::model::document::Document;
use crate::render::Image;
use egui::{ColorImage, TextureHandle, TextureOptions};
use std::sync::Arc;

/// Bounces kept apart in the split (longer paths are one `longer` part), as the command's
/// default.
const BOUNCES: u32 = 3;

/// A finished split as the panel shows it: per part its caption and both sRGB images.
struct Sheet {
    scene: Arc<Scene>,
    width: u32,
    /// (part, share of the image's luminance, weighted sRGB, unweighted sRGB), by bounces then
    /// strategy.
    cells: Vec<(Part, f64, Vec<u8>, Vec<u8>)>,
}

/// The panel's shown sheet with its textures.
struct Shown {
    sheet: Sheet,
    textures: Vec<[TextureHandle; 2]>,
}

/// The "Strategies" section: its running job and its last sheet.
#[derive(Default)]
pub struct StrategiesPanel {
    pending: Option<Inbox<Sheet>>,
    shown: Option<Shown>,
    unweighted: bool,
}

fn srgb(s: &Split, pixels: &[crate::math::Rgb]) -> Vec<u8> {
    Image {
        width: s.width,
        height: s.height,
        pixels: pixels.to_vec(),
    }
    .to_srgb8()
}

/// Every part of split `s` of `scene` converted for display (on the job's thread).
fn sheet(scene: Arc<Scene>, s: &Split) -> Sheet {
    let shares = s.shares();
    let mut cells: Vec<_> = s
        .parts
        .iter()
        .zip(shares)
        .map(|(p, (_, share))| (p.part, share, srgb(s, &p.weighted), srgb(s, &p.unweighted)))
        .collect();
    // Rows by bounces (s from 0 along a row), then the background and longer paths.
    cells.sort_by_key(|c| match c.0 {
        Part::Strategy { s, t } => (0, s + t - 2, s),
        Part::Background => (1, 0, 0),
        Part::Longer => (2, 0, 0),
    });
    Sheet {
        scene,
        width: s.width,
        cells,
    }
}

/// The split as a background job: [`split`] whole natively; on wasm32 a pixel at a time
/// ([`SplitSteps`]: the same split).
struct Splitting {
    scene: Arc<Scene>,
    steps: Option<SplitSteps>,
}

impl Work for Splitting {
    type Out = Sheet;

    fn whole(self) -> Sheet {
        let s = split(&self.scene, BOUNCES, &|_| {});
        sheet(self.scene, &s)
    }

    fn piece(&mut self, more_time: &dyn Fn() -> bool) -> Option<Sheet> {
        let scene = &self.scene;
        let steps = self
            .steps
            .get_or_insert_with(|| SplitSteps::new(scene, BOUNCES));
        if steps.step(scene, more_time) {
            return None;
        }
        let s = self.steps.take()?.finish();
        Some(sheet(Arc::clone(&self.scene), &s))
    }
}

impl StrategiesPanel {
    /// Whether a split is running.
    #[must_use]
    pub fn running(&self) -> bool {
        self.pending.is_some()
    }

    /// The captions of the sheet shown (`s=1 t=2: 41.3%`), by bounces then strategy.
    #[must_use]
    pub fn captions(&self) -> Vec<String> {
        self.shown.as_ref().map_or_else(Vec::new, |s| {
            s.sheet.cells.iter().map(|c| caption(c.0, c.1)).collect()
        })
    }

    /// Take a finished job's outcome, if one has arrived (every frame, the section open or
    /// not).
    pub fn poll(&mut self, ctx: &egui::Context) {
        let Some(rx) = &self.pending else { return };
        let Some(sheet) = rx.try_recv() else { return };
        self.pending = None;
        let h = |rgb: &[u8]| rgb.len() / 3 / (sheet.width as usize).max(1);
        let tex = |name: String, rgb: &[u8]| {
            let image = ColorImage::from_rgb([sheet.width as usize, h(rgb)], rgb);
            ctx.load_texture(name, image, TextureOptions::NEAREST)
        };
        let textures = sheet
            .cells
            .iter()
            .enumerate()
            .map(|(i, c)| {
                [
                    tex(format!("strategy-{i}-w"), &c.2),
                    tex(format!("strategy-{i}-u"), &c.3),
                ]
            })
            .collect();
        self.shown = Some(Shown { sheet, textures });
    }

    /// Split the scene as set (as the section's button does).
    pub fn start(&mut self, ctx: &egui::Context, doc: &Document) {
        let scene = Arc::clone(&doc.scene);
        let repaint = ctx.clone();
        let spawned = deliver(
            "raytree-strategies",
            Some(crate::integrator::THREAD_STACK_BYTES),
            Splitting { scene, steps: None },
            move || repaint.request_repaint(),
        );
        if let Ok(rx) = spawned {
            self.pending = Some(rx);
        }
    }

    /// The section: a button that splits the scene as set, then the grid.
    pub fn ui(&mut self, ui: &mut egui::Ui, doc: &Document) {
        let ctx = ui.ctx().clone();
        let stale = self
            .shown
            .as_ref()
            .is_some_and(|s| !Arc::ptr_eq(&s.sheet.scene, &doc.scene));
        ui.horizontal_wrapped(|ui| {
            let text = if self.shown.is_some() && !stale {
                "split again"
            } else {
                "split by strategy"
            };
            if ui
                .add_enabled(!self.running(), egui::Button::new(text))
                .on_hover_text(format!(
                    "render the scene with BDPT (at its spp) and split the image by the \
                     strategy (s, t) of each contribution, paths of up to {BOUNCES} bounces apart"
                ))
                .clicked()
            {
                self.start(&ctx, doc);
            }
            if self.running() {
                ui.spinner();
                ui.label("rendering...");
            }
            ui.checkbox(&mut self.unweighted, "unweighted (MIS off)");
        });
        let Some(shown) = &self.shown else { return };
        if stale {
            ui.small("(made before the last change of the scene or its settings)");
        }
        grid_ui(ui, shown, self.unweighted);
    }
}

/// `s=1 t=2: 41.3%`.
fn caption(part: Part, share: f64) -> String {
    format!("{}: {:.1}%", part.label(), 100.0 * share)
}

/// One row per bounce count (then background and longer paths), one cell per strategy.
fn grid_ui(ui: &mut egui::Ui, shown: &Shown, unweighted: bool) {
    let cells = &shown.sheet.cells;
    let per_row = cells
        .iter()
        .filter_map(|c| c.0.bounces())
        .fold(0, |n, b| n.max(b + 2)) as usize;
    let width = (ui.available_width() / per_row.max(2) as f32 - 6.0).clamp(24.0, 160.0);
    let mut i = 0;
    while i < cells.len() {
        let bounces = cells[i].0.bounces();
        ui.horizontal(|ui| {
            while i < cells.len() && cells[i].0.bounces() == bounces {
                let c = &cells[i];
                let t = &shown.textures[i][usize::from(unweighted)];
                ui.vertical(|ui| {
                    let size = t.size_vec2();
                    ui.image((t.id(), size * (width / size.x.max(1.0))));
                    ui.small(caption(c.0, c.1));
                });
                i += 1;
            }
        });
    }
    ui.small(
        "weighted: the parts add up to the render; the share is of the image's luminance. \
         s light-subpath vertices, t camera-subpath vertices (raytree strategies, docs/bidirectional.md)",
    );
}
