//! The thin `eframe::App`: lays out the panels, owns the image texture, applies commands.

use crate::gui::model::document::{Command, Document};
use crate::gui::model::stats::{self, DebugView};
use crate::gui::panels::compare::{CompareView, compare_window, pin_bar};
use crate::gui::panels::diagram::{DiagramCache, diagram_ui};
use crate::gui::panels::explain::{ExplainCache, explain_ui};
use crate::gui::panels::image::{ImagePlacement, OverlayCache, image_ui};
use crate::gui::panels::tree::TreeView;
use crate::gui::panels::{details, settings, tree};
use crate::gui::session::Session;
use crate::gui::style::ERROR;
use egui::{Color32, ColorImage, Key, RichText, TextureHandle, TextureOptions};

/// Seconds between checks of the scene file's modification time.
const POLL_SECONDS: f64 = 1.0;

/// The inspector window.
pub struct InspectorApp {
    /// The controller (document, worker, files).
    pub session: Session,
    texture: Option<TextureHandle>,
    texture_version: Option<(u64, bool)>,
    denoise: crate::gui::jobs::denoise::DenoiseView,
    denoise_state: Option<crate::gui::jobs::denoise::DenoiseState>,
    last_poll: f64,
    placement: Option<ImagePlacement>,
    diagram: DiagramCache,
    tree_view: TreeView,
    overlay: OverlayCache,
    explain: ExplainCache,
    compare: CompareView,
    samples: crate::gui::panels::samples::SamplesView,
    versus: crate::gui::panels::versus::VersusPanel,
    strategies: crate::gui::panels::strategies::StrategiesPanel,
    editor: crate::gui::panels::editor::SceneEditor,
}

impl InspectorApp {
    /// Wrap a session.
    #[must_use]
    pub fn new(session: Session) -> Self {
        Self {
            session,
            texture: None,
            texture_version: None,
            denoise: crate::gui::jobs::denoise::DenoiseView::default(),
            denoise_state: None,
            last_poll: 0.0,
            placement: None,
            diagram: DiagramCache::default(),
            tree_view: TreeView::default(),
            overlay: OverlayCache::default(),
            explain: ExplainCache::default(),
            compare: CompareView::default(),
            samples: Default::default(),
            versus: Default::default(),
            strategies: Default::default(),
            editor: Default::default(),
        }
    }

    /// The denoised image toggle's state (`None` while it is off or a debug view is shown).
    #[must_use]
    pub fn denoise_state(&self) -> Option<&crate::gui::jobs::denoise::DenoiseState> {
        self.denoise_state.as_ref()
    }

    /// The scene text window: whether it is open, and its text.
    #[must_use]
    pub fn scene_editor(&self) -> (bool, &str) {
        (self.editor.is_open(), self.editor.text())
    }

    /// The Strategies section's captions (`s=1 t=2: 41.3%`), and whether a split is running.
    #[must_use]
    pub fn strategies(&self) -> (Vec<String>, bool) {
        (self.strategies.captions(), self.strategies.running())
    }

    /// The comparison section's last summary, and whether a comparison is running.
    #[must_use]
    pub fn versus(&self) -> (Option<&str>, bool) {
        (self.versus.summary(), self.versus.running())
    }

    /// Start the comparison of the integrators chosen (Whitted and path unless changed), as
    /// its button does (for the web page's test hook).
    pub fn start_versus(&mut self, ctx: &egui::Context) {
        self.versus.start(ctx, &self.session.doc);
    }

    /// Start the split by strategy, as its button does (for the web page's test hook).
    pub fn start_strategies(&mut self, ctx: &egui::Context) {
        self.strategies.start(ctx, &self.session.doc);
    }

    /// Whether the texture on screen is the denoised image.
    #[must_use]
    pub fn shows_denoised(&self) -> bool {
        self.texture_version.is_some_and(|v| v.1)
    }

    /// Where the image was drawn last frame (for tests).
    #[must_use]
    pub fn placement(&self) -> Option<ImagePlacement> {
        self.placement
    }

    /// The diagram panel's display list as last drawn and its size (for tests: it must equal
    /// a fresh build).
    #[must_use]
    pub fn diagram_display_list(&self) -> Option<([u32; 2], &[crate::diagram::paint::Prim])> {
        self.diagram.display_list()
    }

    /// Rows the ray tree shows (its open levels).
    #[must_use]
    pub fn tree_rows(&self) -> usize {
        self.tree_view.row_count()
    }

    /// Rays the overlay draws (one sample's, inside the image).
    #[must_use]
    pub fn overlay_rays(&self) -> usize {
        self.overlay.rays
    }

    /// The explanation the Explain panel shows (for tests).
    #[must_use]
    pub fn explanation(&self) -> Option<&crate::analysis::explain::Explanation> {
        self.explain.explanation()
    }

    /// The samples section's state: its rows, histogram, chosen bar, firefly (for tests).
    #[must_use]
    pub fn samples_view(&self) -> &crate::gui::panels::samples::SamplesView {
        &self.samples
    }

    /// The pinned-versus-current difference the compare window shows (for tests).
    #[must_use]
    pub fn compare_diff(&self) -> Option<&crate::analysis::diff::TreeDiff> {
        self.compare.diff()
    }

    /// Open every level of the selected tree (as the "expand all below" button on the root).
    pub fn expand_all(&mut self) {
        if let Some(tree) = &self.session.doc.tree {
            for s in &tree.samples {
                self.tree_view.expand_below(tree, s.root);
            }
        }
    }

    /// Screen position of the centre of pixel (x, y) as drawn last frame (for tests).
    #[must_use]
    pub fn screen_of_pixel(&self, x: u32, y: u32) -> Option<egui::Pos2> {
        self.placement.map(|p| p.screen_of(x, y))
    }

    /// Draw one frame and apply the commands it produced.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        self.pump(ui, &ctx);
        self.update_texture(&ctx);
        // A comparison or split started while its section is closed (the web page's hook)
        // still arrives.
        self.versus.poll(&ctx);
        self.strategies.poll(&ctx);
        let doc = &self.session.doc;
        let mut cmds = Vec::new();
        egui::Panel::top("title").show(ui, |ui| title_ui(ui, doc));
        // Fixed limits on every panel: content never widens them (long rows are cut or wrapped
        // inside), so the image does not move under the cursor.
        let edit = controls_panel(ui, doc, self.denoise_state.as_ref(), &mut cmds);
        let panels = TreePanels {
            tree_view: &mut self.tree_view,
            explain: &mut self.explain,
            samples: &mut self.samples,
            versus: &mut self.versus,
            strategies: &mut self.strategies,
        };
        tree_panel(ui, doc, panels, &mut cmds);
        let cache = &mut self.diagram;
        // Tall enough by default that the figure is not squeezed under its three rows of
        // controls (at 330 px a glass ball was 20-80 px across).
        egui::Panel::bottom("diagram")
            .resizable(true)
            .default_size(430.0)
            .size_range(200.0..=640.0)
            .show(ui, |ui| diagram_ui(ui, doc, cache, &mut cmds));
        let tex = self.texture.as_ref().map(TextureHandle::id);
        let mut placement = None;
        let overlay = &mut self.overlay;
        egui::CentralPanel::default().show(ui, |ui| {
            placement = Some(image_ui(ui, doc, tex, overlay, &mut cmds));
        });
        self.placement = placement;
        compare_window(&ctx, doc, &mut self.compare, &mut cmds);
        let session = &self.session;
        if edit {
            self.editor.open_with(session.scene_text());
        }
        self.editor
            .ui(&ctx, doc, || session.scene_text(), &mut cmds);
        keys_ui(ui, doc, &mut cmds);
        for c in cmds {
            self.session.apply(c);
        }
        // On wasm32 the background tasks (diagram, comparison, split, denoiser, acne lab) are
        // stepped here for a slice of the frame; natively they have threads and this does
        // nothing.
        let budget = crate::gui::jobs::background::SLICE_BUDGET_MS;
        if crate::gui::jobs::background::run_pending(budget) {
            ctx.request_repaint();
        }
    }

    /// Fold in the worker's deliveries, and check the scene file for changes every
    /// [`POLL_SECONDS`] (asking for a frame then while there is a file).
    fn pump(&mut self, ui: &egui::Ui, ctx: &egui::Context) {
        self.session.pump();
        let now = ui.input(|i| i.time);
        if now - self.last_poll >= POLL_SECONDS {
            self.last_poll = now;
            self.session.poll_reload();
        }
        if self.session.doc.source.path.is_some() {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(POLL_SECONDS));
        }
    }

    fn update_texture(&mut self, ctx: &egui::Context) {
        let doc = &self.session.doc;
        let denoised = if doc.view.denoise && doc.view.debug == DebugView::Off {
            let repaint = ctx.clone();
            let (image, state) = self.denoise.image(doc, move || repaint.request_repaint());
            self.denoise_state = Some(state);
            image
        } else {
            self.denoise_state = None;
            None
        };
        let version = (doc.image_version, denoised.is_some());
        if self.texture_version == Some(version) {
            return;
        }
        self.texture_version = Some(version);
        let image = match denoised {
            Some(d) => ColorImage::from_rgb([d.width as usize, d.height as usize], &d.to_srgb8()),
            None => texture_image(doc),
        };
        match &mut self.texture {
            Some(t) => t.set(image, TextureOptions::NEAREST),
            None => {
                self.texture =
                    Some(ctx.load_texture("raytree-image", image, TextureOptions::NEAREST))
            }
        }
    }
}

impl eframe::App for InspectorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }
}

/// The left panel: the scene, settings, view (with the denoiser's state), export and the acne
/// lab. Whether the scene text was asked for.
fn controls_panel(
    ui: &mut egui::Ui,
    doc: &Document,
    denoise_state: Option<&crate::gui::jobs::denoise::DenoiseState>,
    cmds: &mut Vec<Command>,
) -> bool {
    let mut edit = false;
    egui::Panel::left("controls")
        .resizable(true)
        .default_size(290.0)
        .size_range(240.0..=420.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                section(ui, "Scene", |ui| {
                    edit = settings::scene_ui(ui, doc, cmds);
                });
                section(ui, "Settings", |ui| settings::settings_ui(ui, doc, cmds));
                section(ui, "View", |ui| {
                    settings::view_ui(ui, doc, cmds);
                    if let Some(state) = denoise_state {
                        ui.small(denoise_words(state));
                    }
                });
                section(ui, "Export", |ui| settings::export_ui(ui, doc, cmds));
                egui::CollapsingHeader::new(RichText::new("Acne lab").strong())
                    .default_open(false)
                    .show(ui, |ui| crate::gui::panels::acne::acne_ui(ui, doc, cmds));
            });
        });
    edit
}

/// The right panel's own state, borrowed for one frame.
struct TreePanels<'a> {
    tree_view: &'a mut TreeView,
    explain: &'a mut ExplainCache,
    samples: &'a mut crate::gui::panels::samples::SamplesView,
    versus: &'a mut crate::gui::panels::versus::VersusPanel,
    strategies: &'a mut crate::gui::panels::strategies::StrategiesPanel,
}

/// The right panel: the pin bar, the ray tree, and under it the sections about the selection.
fn tree_panel(ui: &mut egui::Ui, doc: &Document, mut panels: TreePanels, cmds: &mut Vec<Command>) {
    egui::Panel::right("tree")
        .resizable(true)
        .default_size(470.0)
        .size_range(380.0..=640.0)
        .show(ui, |ui| {
            ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
            ui.heading("Ray tree");
            pin_bar(ui, doc, cmds);
            tree::tree_ui(ui, doc, panels.tree_view, cmds);
            ui.separator();
            egui::ScrollArea::vertical()
                .id_salt("details-scroll")
                .show(ui, |ui| {
                    sections_ui(ui, doc, &mut panels, cmds);
                });
        });
}

/// The sections under the ray tree: samples, explanation, details, stepping, the breakdown,
/// integrators compared and the BDPT strategies.
fn sections_ui(ui: &mut egui::Ui, doc: &Document, p: &mut TreePanels, cmds: &mut Vec<Command>) {
    egui::CollapsingHeader::new("Samples")
        .default_open(true)
        .show(ui, |ui| {
            crate::gui::panels::samples::samples_ui(ui, doc, p.samples, cmds);
        });
    egui::CollapsingHeader::new("Explain")
        .default_open(true)
        .show(ui, |ui| explain_ui(ui, doc, p.explain, cmds));
    egui::CollapsingHeader::new("Details")
        .default_open(true)
        .show(ui, |ui| {
            details::details_ui(ui, doc);
        });
    egui::CollapsingHeader::new("Step along a ray")
        .default_open(false)
        .show(ui, |ui| crate::gui::panels::step::step_ui(ui, doc, cmds));
    egui::CollapsingHeader::new("Contribution breakdown")
        .default_open(true)
        .show(ui, |ui| {
            details::breakdown_ui(ui, doc, p.tree_view, cmds);
        });
    egui::CollapsingHeader::new("Compare integrators")
        .default_open(false)
        .show(ui, |ui| p.versus.ui(ui, doc));
    egui::CollapsingHeader::new("Strategies (bdpt)")
        .default_open(false)
        .show(ui, |ui| p.strategies.ui(ui, doc));
}

/// The denoised image's state in words, under the View section's toggle.
fn denoise_words(state: &crate::gui::jobs::denoise::DenoiseState) -> String {
    use crate::gui::jobs::denoise::DenoiseState;
    match state {
        DenoiseState::Waiting => "denoise: after the render".into(),
        DenoiseState::Running => "denoising...".into(),
        DenoiseState::Ready(s) => format!("denoised in {s:.2} s (guide buffers and filter)"),
        DenoiseState::Unavailable(why) => format!("denoise: {why}"),
    }
}

/// The image or the selected debug view as an sRGB texture.
fn texture_image(doc: &Document) -> ColorImage {
    let size = [doc.image.width as usize, doc.image.height as usize];
    let view = doc.view.debug;
    if view == DebugView::Off {
        return ColorImage::from_rgb(size, &doc.image.to_srgb8());
    }
    let (_, max) = stats::range(view, &doc.stats);
    let pixels = doc
        .stats
        .iter()
        .map(|s| {
            let [r, g, b] = stats::false_colour(view, s, max);
            Color32::from_rgb(r, g, b)
        })
        .collect();
    ColorImage::new(size, pixels)
}

fn section(ui: &mut egui::Ui, title: &str, body: impl FnOnce(&mut egui::Ui)) {
    egui::CollapsingHeader::new(RichText::new(title).strong())
        .default_open(true)
        .show(ui, body);
}

fn title_ui(ui: &mut egui::Ui, doc: &Document) {
    ui.horizontal(|ui| {
        ui.label(RichText::new("raytree inspector").strong());
        ui.separator();
        ui.label(doc.source.label());
        ui.separator();
        let (w, h) = (doc.image.width, doc.image.height);
        let s = &doc.scene.settings;
        ui.label(format!("{w}x{h}  depth {}  spp {}", s.max_depth, s.spp));
        ui.separator();
        match doc.progress.seconds {
            Some(secs) if doc.rendered() => {
                ui.label(format!(
                    "rendered in {:.0} ms, {} rays",
                    secs * 1e3,
                    doc.progress.rays
                ));
                ui.separator();
                match doc.progress.stats_seconds {
                    Some(s) => ui.label(format!("debug statistics in {:.0} ms", s * 1e3)),
                    None => ui.add(
                        egui::ProgressBar::new(doc.progress.stats_rows as f32 / h.max(1) as f32)
                            .desired_width(160.0)
                            .text("debug statistics"),
                    ),
                };
            }
            _ => {
                let frac = doc.progress.rows as f32 / h.max(1) as f32;
                ui.add(
                    egui::ProgressBar::new(frac)
                        .desired_width(160.0)
                        .text("rendering"),
                );
            }
        }
        crate::gui::panels::progressive::title_ui(ui, doc);
        if let Some(e) = doc.error.as_ref().or(doc.export_error.as_ref()) {
            // The whole message is in the left panel; here its first line, cut to fit.
            ui.separator();
            ui.add(
                egui::Label::new(RichText::new(first_line(e)).color(ERROR))
                    .truncate()
                    .show_tooltip_when_elided(true),
            );
        }
    });
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

/// Arrow keys move the selected pixel (unless a text field has focus).
fn keys_ui(ui: &egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    if doc.selection.is_none() || ui.ctx().memory(|m| m.focused().is_some()) {
        return;
    }
    let moves = [
        (Key::ArrowLeft, [-1, 0]),
        (Key::ArrowRight, [1, 0]),
        (Key::ArrowUp, [0, -1]),
        (Key::ArrowDown, [0, 1]),
    ];
    for (key, d) in moves {
        if ui.input(|i| i.key_pressed(key)) {
            cmds.push(Command::MoveSelection(d));
        }
    }
}
