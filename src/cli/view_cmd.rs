//! `raytree view`: the inspector window. The binary supplies the file hook (real files, written
//! atomically) and the command-line overrides.

use super::args::ViewArgs;
use super::load::{apply, pair};
use super::output::{Inputs, Pending};
use anyhow::{Result, anyhow};
use raytree::gui::{Files, InspectorApp, Session};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// Real files; exports never overwrite the scene (`.0`).
struct DiskFiles(Option<PathBuf>);

impl Files for DiskFiles {
    /// Bounded like the command line's reads; the session refuses a scene over
    /// [`raytree::input::MAX_SCENE_BYTES`] itself (the hook reads meshes too).
    fn read(&self, path: &Path) -> std::io::Result<String> {
        super::read::read_text(path, raytree::input::MAX_OBJ_BYTES)
    }

    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        super::read::read_limited(path, raytree::input::MAX_OBJ_BYTES)
            .map_err(std::io::Error::other)
    }

    fn modified(&self, path: &Path) -> Option<SystemTime> {
        std::fs::metadata(path).and_then(|m| m.modified()).ok()
    }

    fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        Pending::create(path, &Inputs::new(self.0.as_deref()))
            .and_then(|p| p.commit(bytes))
            .map_err(|e| std::io::Error::other(format!("{e:#}")))
    }
}

/// Open the window; returns when it is closed.
pub fn run(a: &ViewArgs) -> Result<()> {
    let overrides = a.overrides.clone();
    // Fail early on bad flags, before a window opens.
    apply(&mut raytree::Scene::default_scene(), &overrides)?;
    let pixel = a
        .pixel
        .as_deref()
        .map(|p| pair("pixel", p, ','))
        .transpose()?;
    let path = a.scene.clone();
    let title = format!(
        "raytree view - {}",
        path.as_deref()
            .map_or("<built-in classic>".into(), |p| p.display().to_string())
    );
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([1560.0, 940.0]),
        ..Default::default()
    };
    eframe::run_native(
        "raytree",
        options,
        Box::new(move |cc| {
            let ctx = cc.egui_ctx.clone();
            let adjust = Box::new(move |s: &mut raytree::Scene| {
                apply(s, &overrides).map_err(|e| format!("{e:#}"))
            });
            let mut session = Session::new(
                path.clone(),
                Box::new(DiskFiles(path)),
                adjust,
                Arc::new(move || ctx.request_repaint()),
            );
            if let Some((x, y)) = pixel {
                session.apply(raytree::gui::Command::SelectPixel([x, y]));
            }
            Ok(Box::new(InspectorApp::new(session)))
        }),
    )
    .map_err(|e| anyhow!("cannot open the window: {e}"))
}
