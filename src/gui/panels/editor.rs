//! The scene's text in a window (issue 31): edit the scene file's JSON (or pbrt, or Mitsuba
//! XML) and apply it, without writing the file; an error names its line and column as a bad
//! file does, and the current scene stays. In the browser this is how a student changes a
//! built-in scene.

use crate::gui::model::document::{Command, Document};
use crate::gui::style::ERROR;
use egui::RichText;

/// The editor window's state: whether it is open, and its text (kept while it is closed, so
/// an edit in progress survives; **revert** takes the file's text again).
#[derive(Default)]
pub struct SceneEditor {
    open: bool,
    text: String,
    /// The error of the last apply, if it failed.
    error: Option<String>,
    /// Whether an apply is waiting for the session's answer (the next frame's document).
    applied: bool,
}

impl SceneEditor {
    /// Whether the window is open.
    #[must_use]
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// The text being edited.
    #[must_use]
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Open the window on `text` (the scene's), or report why there is none.
    pub fn open_with(&mut self, text: Result<String, String>) {
        match text {
            Ok(t) => {
                self.text = t;
                self.error = None;
            }
            Err(e) => self.error = Some(e),
        }
        self.open = true;
    }

    /// The window: the text, **apply** (load it as the scene, not saved), **revert** (the
    /// file's text again) and **close**; `file_text` gives the scene's text for revert.
    pub fn ui(
        &mut self,
        ctx: &egui::Context,
        doc: &Document,
        file_text: impl FnOnce() -> Result<String, String>,
        cmds: &mut Vec<Command>,
    ) {
        if !self.open {
            return;
        }
        if self.applied {
            // The session answered the apply in the frame before: its error, if any.
            self.error.clone_from(&doc.error);
            self.applied = false;
        }
        let mut open = true;
        let mut revert = false;
        egui::Window::new("Scene text")
            .open(&mut open)
            .default_size([520.0, 560.0])
            .show(ctx, |ui| {
                ui.small(format!(
                    "{}: applying loads this text as the scene; the file is not written",
                    doc.source.label()
                ));
                ui.horizontal(|ui| {
                    if ui.button("apply").clicked() {
                        cmds.push(Command::ApplyText(self.text.clone()));
                        self.applied = true;
                    }
                    revert = ui.button("revert").clicked();
                });
                if let Some(e) = &self.error {
                    ui.add(egui::Label::new(RichText::new(e).color(ERROR)).wrap());
                }
                let label = ui.small("scene text");
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.add(
                        egui::TextEdit::multiline(&mut self.text)
                            .code_editor()
                            .desired_width(f32::INFINITY)
                            .desired_rows(30),
                    )
                    .labelled_by(label.id);
                });
            });
        if revert {
            self.open_with(file_text());
        }
        self.open = open;
    }
}
