//! The inspector's panels, each `*_ui(ui, &Document, &mut Vec<Command>)` with its cache where
//! drawing is costly. They read the model, draw with egui in the colours of `gui/style.rs`
//! and push commands; only [`InspectorApp`](crate::gui::InspectorApp) lays them out.

pub(super) mod acne;
pub mod compare;
pub(super) mod details;
pub mod diagram;
pub mod editor;
pub mod explain;
pub(super) mod image;
pub mod progressive;
pub mod samples;
pub(super) mod settings;
pub mod step;
pub mod strategies;
pub(super) mod tree;
pub mod versus;
