//! Helpers shared by the inspector's kittest files (`tests/gui*.rs`): files in memory and the
//! steps that wait for the render worker or click the image. Each test file is its own crate
//! and none uses every helper.
#![allow(dead_code)]

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::gui::{Files, InspectorApp, Session};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

/// Files in memory; each write bumps the file's modification time. Writes can be made to fail
/// as the binary's hook does, with a message that names the file.
#[derive(Clone, Default)]
pub struct MemFiles(
    Arc<Mutex<HashMap<PathBuf, (String, u64)>>>,
    Arc<Mutex<Option<String>>>,
);

impl MemFiles {
    /// From now on every write fails with `why`.
    pub fn fail_writes(&self, why: &str) {
        *self.1.lock().unwrap() = Some(why.to_string());
    }
    /// Write `text` at `path` (a new modification time).
    pub fn put(&self, path: &str, text: &str) {
        let mut m = self.0.lock().unwrap();
        let version = m.get(Path::new(path)).map_or(1, |(_, v)| v + 1);
        m.insert(path.into(), (text.to_string(), version));
    }
    /// The text at `path`, if any.
    pub fn get(&self, path: &str) -> Option<String> {
        self.0
            .lock()
            .unwrap()
            .get(Path::new(path))
            .map(|(t, _)| t.clone())
    }
}

impl Files for MemFiles {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .lock()
            .unwrap()
            .get(path)
            .map(|(t, _)| t.clone())
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"))
    }
    fn modified(&self, path: &Path) -> Option<SystemTime> {
        let v = self.0.lock().unwrap().get(path)?.1;
        Some(SystemTime::UNIX_EPOCH + Duration::from_secs(v))
    }
    fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        if let Some(why) = self.1.lock().unwrap().as_ref() {
            let msg = format!("cannot write {}: {why}", path.display());
            return Err(std::io::Error::other(msg));
        }
        self.put(&path.display().to_string(), &String::from_utf8_lossy(bytes));
        Ok(())
    }
}

/// The inspector on `session` in a 1500x950 harness. Up to 16 steps to settle: a frame can see
/// the worker's deliveries (image, then statistics) one at a time, and on a loaded machine they
/// arrive at different frames (4, kittest's default, was once too few under CI).
pub fn inspector(session: raytree::gui::Session) -> Harness<'static, InspectorApp> {
    Harness::builder()
        .with_size([1500.0, 950.0])
        .with_max_steps(16)
        .build_ui_state(
            |ui, app: &mut InspectorApp| app.show(ui),
            InspectorApp::new(session),
        )
}

/// Wait for the worker, then let the UI settle.
pub fn settle(h: &mut Harness<'static, InspectorApp>) {
    h.run();
    h.state_mut().session.wait_render();
    h.run();
}

/// Click image pixel (x, y) and let the UI take it.
pub fn click_pixel(h: &mut Harness<'static, InspectorApp>, x: u32, y: u32) {
    let pos = h.state().screen_of_pixel(x, y).expect("image drawn");
    h.hover_at(pos);
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run();
}

/// One scene, read-only: every path reads `text`, writes fail.
pub struct ReadOnly(pub &'static str);

impl Files for ReadOnly {
    fn read(&self, _: &Path) -> std::io::Result<String> {
        Ok(self.0.to_owned())
    }
    fn modified(&self, _: &Path) -> Option<SystemTime> {
        Some(SystemTime::UNIX_EPOCH)
    }
    fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
        Err(std::io::Error::other("read-only"))
    }
}

/// The inspector on the read-only scene `text` (adjusted by `adjust`), its render finished.
pub fn read_only_inspector(
    text: &'static str,
    adjust: raytree::gui::Adjust,
) -> Harness<'static, InspectorApp> {
    let session = raytree::gui::Session::new(
        Some("scene.json".into()),
        Box::new(ReadOnly(text)),
        adjust,
        Arc::new(|| {}),
    );
    let mut h = inspector(session);
    settle(&mut h);
    h
}

/// The classic scene (`fixtures/classic.json`).
pub const CLASSIC: &str = include_str!("../../fixtures/classic.json");

/// A glass-ball pixel at 320x180 (400,200 at 640x360): a deep tree with a blocked shadow ray.
pub const GLASS: (u32, u32) = (200, 100);

/// The classic scene at 320x180 (pixel (150, 100) hits the mirror ball), its render finished.
pub fn classic_harness(files: &MemFiles) -> Harness<'static, InspectorApp> {
    classic_harness_with(files, CLASSIC, |_| {})
}

/// `scene` (the classic scene or an edit of it) as `scenes/classic.json` at 320x180 with
/// `adjust` applied too, its render finished.
pub fn classic_harness_with(
    files: &MemFiles,
    scene: &str,
    adjust: impl Fn(&mut raytree::Scene) + Send + 'static,
) -> Harness<'static, InspectorApp> {
    files.put("scenes/classic.json", scene);
    let session = Session::new(
        Some("scenes/classic.json".into()),
        Box::new(files.clone()),
        Box::new(move |s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(320, 180);
            adjust(s);
            Ok(())
        }),
        Arc::new(|| {}),
    );
    let mut h = inspector(session);
    settle(&mut h);
    h
}

/// Whether a widget's label contains `text`.
pub fn has(h: &Harness<'static, InspectorApp>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}
