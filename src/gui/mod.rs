//! The inspector (`raytree view`): an egui app over a [`Document`].
//!
//! - [`Session`] is the controller (document + render worker + file hook); no egui.
//! - Panels (`*_ui` functions) read the document and push [`Command`]s, applied after layout.
//! - [`InspectorApp`] is the thin `eframe::App`.
//!
//! The library does no I/O itself: reading and writing files goes through the [`Files`] hook
//! that the binary supplies.

pub mod acne_lab;
mod acne_ui;
mod app;
pub mod background;
pub mod breakdown;
pub mod compare_ui;
pub mod denoise_view;
mod details_ui;
mod diagram_controls;
pub mod diagram_ui;
pub mod document;
pub mod explain_ui;
pub mod export;
mod image_ui;
pub mod lpe_filter;
pub mod progressive;
pub mod project;
pub mod samples_ui;
mod session;
mod settings_ui;
pub mod stats;
pub mod step_ui;
mod style;
mod tree_ui;
pub mod versus_ui;
pub mod worker;

pub use app::InspectorApp;
pub use document::{Command, Document, ViewOptions};
pub use session::Session;

use std::path::Path;
use std::time::SystemTime;

/// File access for the inspector, supplied by the binary (and faked by tests).
pub trait Files: Send {
    /// The whole file as text.
    fn read(&self, path: &Path) -> std::io::Result<String>;
    /// The whole file as bytes (binary PLY meshes of pbrt and Mitsuba scenes); by default the
    /// text of [`Files::read`].
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.read(path).map(String::into_bytes)
    }
    /// The file's modification time, if it exists.
    fn modified(&self, path: &Path) -> Option<SystemTime>;
    /// Write `bytes` to `path` (atomically where possible).
    fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()>;
}

/// Applied to every scene after it is parsed (the command line's overrides); an error is shown.
pub type Adjust = Box<dyn Fn(&mut crate::Scene) -> Result<(), String> + Send>;
