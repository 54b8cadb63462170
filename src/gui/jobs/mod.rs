//! Background work, off the UI thread natively and in slices between frames on wasm32: the
//! render [`worker`] (image, statistics, growth), [`progressive`] passes, the [`acne_lab`]'s
//! sweep, the [`denoise`]d image, and the [`background`] threads and lanes they run on. No egui
//! here: jobs read the model and send plain deliveries that the session folds in.

pub mod acne_lab;
pub mod background;
pub mod delivery;
pub mod denoise;
pub mod progressive;
pub mod worker;
