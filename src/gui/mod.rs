//! The inspector (`raytree view`): an egui app over a [`Document`]. Each part below imports
//! only those above it (docs/inspector.md):
//!
//! - [`model`]: the [`Document`] and its plain data; no egui, no threads. `style.rs`: colours
//!   and number formatting.
//! - [`jobs`]: background work (the render worker, progressive passes, the acne lab, the
//!   denoiser) that reads the model and sends deliveries; no egui.
//! - [`Session`] is the controller (document + jobs + file hook); no egui.
//! - [`panels`] (`*_ui` functions) read the document and push [`Command`]s, applied after layout.
//! - [`InspectorApp`] is the thin `eframe::App`.
//!
//! The library does no I/O itself: reading and writing files goes through the [`Files`] hook
//! that the binary supplies.

mod app;
pub mod jobs;
pub mod model;
pub mod panels;
mod session;
mod style;

pub use app::InspectorApp;
pub use model::document::{Command, Document, ViewOptions};
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
