//! Whitted vs path tracing in the inspector (issue 16): the scene rendered by both integrators
//! on a thread of its own ([`crate::aov::versus`], as `raytree versus`), shown side by side
//! with the signed difference, and the difference broken down by light transport class ("what
//! Whitted misses here: 79% caustics, 21% indirect").

use crate::Scene;
use crate::aov::{ClassShare, Versus, versus};
use crate::gui::model::document::Document;
use egui::{ColorImage, TextureHandle, TextureOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, channel};

/// What a comparison was made from: the scene file and the scene as set.
#[derive(Clone)]
struct Made {
    path: Option<PathBuf>,
    scene: Arc<Scene>,
}

/// The comparison the panel shows.
struct Done {
    made: Made,
    summary: String,
    /// The summary's class table as rows (class, expression, luminance, Whitted renders it),
    /// shown in a grid rather than as spaced text (issue 32: it was misaligned).
    classes: Vec<ClassShare>,
    textures: [TextureHandle; 3],
    /// The render generation its staleness was last checked at, and whether it was stale then.
    checked: Option<(u64, bool)>,
}

/// The "Whitted vs path" section: its running job and its last result.
#[derive(Default)]
pub struct VersusPanel {
    pending: Option<(Made, Receiver<Result<Versus, String>>)>,
    done: Option<Done>,
}

/// Whether a comparison made from `a` still shows `b`: the same scene in every respect but the
/// integrator (the comparison renders both, so switching the integrator leaves it current; a
/// sampler left to the integrator's default is the same too).
fn same_comparison(a: &Scene, b: &Scene) -> bool {
    if std::ptr::eq(a, b) {
        return true;
    }
    let mut settings = a.settings;
    settings.integrator = b.settings.integrator;
    settings == b.settings
        && a.camera == b.camera
        && a.background == b.background
        && a.ambient == b.ambient
        && a.materials == b.materials
        && a.objects == b.objects
        && a.lights == b.lights
}

fn texture(ctx: &egui::Context, name: &str, w: u32, rgb: &[u8]) -> TextureHandle {
    let h = rgb.len() / 3 / (w as usize).max(1);
    let image = ColorImage::from_rgb([w as usize, h], rgb);
    ctx.load_texture(name, image, TextureOptions::NEAREST)
}

impl VersusPanel {
    /// Whether a comparison is running.
    #[must_use]
    pub fn running(&self) -> bool {
        self.pending.is_some()
    }

    /// The last comparison's summary, if any.
    #[must_use]
    pub fn summary(&self) -> Option<&str> {
        self.done.as_ref().map(|d| d.summary.as_str())
    }

    /// Forget a comparison (finished or running) made from another scene file than the one
    /// open now (issue 32: after opening another scene the panel kept the previous scene's
    /// images and numbers).
    fn forget_other_files(&mut self, doc: &Document) {
        let path = &doc.source.path;
        if self.done.as_ref().is_some_and(|d| &d.made.path != path) {
            self.done = None;
        }
        if self.pending.as_ref().is_some_and(|p| &p.0.path != path) {
            self.pending = None;
        }
    }

    /// Whether the comparison shown was made from another scene than the one set now (checked
    /// once per render generation).
    fn stale(&mut self, doc: &Document) -> bool {
        let generation = doc.progress.generation;
        let Some(done) = &mut self.done else {
            return false;
        };
        match done.checked {
            Some((g, stale)) if g == generation => stale,
            _ => {
                let stale = !same_comparison(&done.made.scene, &doc.scene);
                done.checked = Some((generation, stale));
                stale
            }
        }
    }

    fn poll(&mut self, ctx: &egui::Context) {
        let Some((made, rx)) = &self.pending else {
            return;
        };
        let Ok(result) = rx.try_recv() else {
            return;
        };
        let made = made.clone();
        self.pending = None;
        self.done = Some(match result {
            Ok(v) => {
                let w = v.whitted.width;
                let diff: Vec<u8> = v.difference_rgb8().0.into_iter().flatten().collect();
                Done {
                    made,
                    checked: None,
                    summary: v.summary(),
                    classes: v.classes.clone(),
                    textures: [
                        texture(ctx, "versus-whitted", w, &v.whitted.to_srgb8()),
                        texture(ctx, "versus-path", w, &v.path.beauty.to_srgb8()),
                        texture(ctx, "versus-difference", w, &diff),
                    ],
                }
            }
            Err(e) => Done {
                made,
                checked: None,
                summary: format!("the comparison failed: {e}"),
                classes: Vec::new(),
                textures: std::array::from_fn(|_| texture(ctx, "versus-empty", 1, &[0, 0, 0])),
            },
        });
    }

    /// The section: a button that (re)starts the comparison for the scene as set, then the
    /// three images (Whitted, path, path - Whitted) and the breakdown.
    pub fn ui(&mut self, ui: &mut egui::Ui, doc: &Document) {
        let ctx = ui.ctx().clone();
        self.forget_other_files(doc);
        self.poll(&ctx);
        let stale = self.stale(doc);
        ui.horizontal_wrapped(|ui| {
            let label = match &self.done {
                Some(_) if !stale => "compare again",
                _ => "compare Whitted and path",
            };
            if ui
                .add_enabled(!self.running(), egui::Button::new(label))
                .on_hover_text(
                    "render the scene with both integrators (the path tracer at the scene's spp)",
                )
                .clicked()
            {
                let scene = Arc::clone(&doc.scene);
                let (tx, rx) = channel();
                let repaint = ctx.clone();
                let spawned = crate::gui::jobs::background::spawn(
                    "raytree-versus",
                    Some(crate::integrator::THREAD_STACK_BYTES),
                    move || {
                        let r = versus(&scene, None, &|_| {}).map_err(|e| e.to_string());
                        if tx.send(r).is_ok() {
                            repaint.request_repaint();
                        }
                    },
                );
                if spawned.is_ok() {
                    let made = Made {
                        path: doc.source.path.clone(),
                        scene: Arc::clone(&doc.scene),
                    };
                    self.pending = Some((made, rx));
                }
            }
            if self.running() {
                ui.spinner();
                ui.label("rendering both...");
            }
        });
        let Some(done) = &self.done else {
            return;
        };
        if stale {
            ui.small("(made before the last settings change)");
        }
        let width = (ui.available_width() / 3.0 - 6.0).max(40.0);
        ui.horizontal(|ui| {
            for (t, caption) in done
                .textures
                .iter()
                .zip(["Whitted", "path", "path - Whitted"])
            {
                ui.vertical(|ui| {
                    let size = t.size_vec2();
                    let scale = width / size.x.max(1.0);
                    ui.image((t.id(), size * scale));
                    ui.small(caption);
                });
            }
        });
        ui.small("difference: red where the path tracer is brighter, blue where Whitted is");
        // The summary's sentences wrap; its table is a grid, one cell per column.
        let prose = done
            .summary
            .split("\nclass ")
            .next()
            .unwrap_or(&done.summary);
        ui.small(prose);
        classes_ui(ui, &done.classes);
    }
}

/// The class table: class, expression, luminance (right-aligned), whether Whitted renders it.
fn classes_ui(ui: &mut egui::Ui, classes: &[ClassShare]) {
    if classes.is_empty() {
        return;
    }
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
    let mono = |t: String| egui::RichText::new(t).monospace();
    egui::Grid::new("versus-classes")
        .striped(true)
        .num_columns(4)
        .show(ui, |ui| {
            for h in ["class", "expression", "luminance", "Whitted renders it"] {
                ui.label(egui::RichText::new(h).strong());
            }
            ui.end_row();
            for c in classes {
                ui.label(c.name);
                ui.label(mono(c.lpe.to_string()));
                // Monospace and padded: the decimal points line up.
                ui.label(mono(format!("{:>12.4}", c.luminance)));
                ui.label(if c.whitted { "yes" } else { "no" });
                ui.end_row();
            }
        });
}
