//! raytree's inspector as a static web page: the library's `gui` module (the desktop
//! inspector, unchanged) built for wasm32 and run by eframe's web backend, with the fixtures
//! built in, uploads, downloads and hooks for the browser test. `web/build.sh` builds it.
//!
//! The platform-independent parts (fixture table, URL fragment, input limits, the app over a
//! [`app::Host`]) build and test natively too; [`browser`] is the wasm32 glue.

pub mod app;
pub mod files;
pub mod fixtures;
pub mod fragment;

#[cfg(target_arch = "wasm32")]
mod browser;
