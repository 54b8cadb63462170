//! The page's app: the desktop inspector ([`InspectorApp`], unchanged) under a bar with the
//! scene picker, the file picker and the page's messages; the URL fragment; uploads and drops;
//! the state the test hooks read. The browser itself is behind [`Host`].

use crate::files::{self, MemFiles};
use crate::fragment::Fragment;
use raytree::gui::model::export::ExportKind;
use raytree::gui::{Command, InspectorApp, Session};
use std::path::PathBuf;

/// What the page's JavaScript asks for between frames.
#[derive(Debug)]
pub enum Action {
    /// The URL fragment changed (a link followed, the address bar edited).
    Fragment(String),
    /// Files chosen in the file picker or dropped on the page (name, bytes); the first scene
    /// among them is opened.
    Upload(Vec<(String, Vec<u8>)>),
    /// A message from the page (a file refused before it was read).
    Message(String),
    /// An export, as its button does (for the browser test).
    Export(ExportKind),
    /// Forget the worst frame time so far.
    ResetFrames,
    /// Start a background job as its button does (`versus`, `strategies`, `denoise`, `acne`;
    /// for the browser test).
    Start(String),
}

/// The browser, as the app sees it.
pub trait Host {
    /// Milliseconds since the page started.
    fn now_ms(&self) -> f64;
    /// What the page asked for since the last frame.
    fn take_actions(&self) -> Vec<Action>;
    /// Show `fragment` in the address bar (without reapplying it).
    fn set_hash(&self, fragment: &str);
    /// Open the browser's file picker.
    fn pick_files(&self);
    /// Publish the state for the test hooks.
    fn publish(&self, state: &Published);
}

/// What the hooks read: the selected tree (as the tree JSON export writes it), the page's
/// state, and where image pixels are on the canvas.
#[derive(Clone, Debug, Default)]
pub struct Published {
    /// The selected tree's JSON (`None`: no pixel selected, or a non-finite tree).
    pub tree_json: Option<String>,
    /// A JSON object with the scene, render progress, frame times and messages.
    pub state_json: String,
    /// Canvas points of the centres of pixels (0, 0) and (1, 1) as drawn last frame.
    pub pixel_frame: Option<[[f32; 2]; 2]>,
}

/// Frame times of the app's own work (layout, render slices, background tasks).
#[derive(Clone, Debug, Default)]
struct Frames {
    count: u64,
    worst_ms: f64,
    last_ms: f64,
    /// The slowest frames (over 40 ms) and what happened in them, slowest first (at most 8).
    slow: Vec<(f64, String)>,
}

/// The page.
pub struct WebApp {
    inner: InspectorApp,
    files: MemFiles,
    host: Box<dyn Host>,
    /// The fragment last applied or written.
    hash: String,
    /// The page's own message (uploads, fragment).
    message: Option<String>,
    frames: Frames,
    first_image_ms: Option<f64>,
    published_tree: Option<u64>,
    published: Published,
}

impl WebApp {
    /// The page at `hash` (the URL fragment), rendering through `repaint`.
    pub fn new(host: Box<dyn Host>, sink: files::Sink, hash: &str, repaint: Repaint) -> Self {
        let files = MemFiles::new(sink);
        let first = PathBuf::from(crate::fixtures::path_of(crate::fixtures::DEFAULT));
        let session = Session::new(
            Some(first),
            Box::new(files.clone()),
            Box::new(files::check_size),
            repaint,
        );
        let mut app = Self {
            inner: InspectorApp::new(session),
            files,
            host,
            hash: String::new(),
            message: None,
            frames: Frames::default(),
            first_image_ms: None,
            published_tree: None,
            published: Published::default(),
        };
        app.apply_fragment(hash);
        app
    }

    /// The inspector inside (for tests).
    #[must_use]
    pub fn inspector(&self) -> &InspectorApp {
        &self.inner
    }

    /// The page's own message, if any.
    #[must_use]
    pub fn message(&self) -> Option<&str> {
        self.message.as_deref()
    }

    /// Apply a URL fragment: the fixture, then the settings, then the pixel.
    pub fn apply_fragment(&mut self, text: &str) {
        self.hash = text.trim_start_matches('#').to_owned();
        let f = match Fragment::parse(text) {
            Ok(f) => f,
            Err(e) => {
                self.message = Some(e);
                return;
            }
        };
        self.message = None;
        let s = &mut self.inner.session;
        if let Some(name) = &f.scene {
            let path = PathBuf::from(crate::fixtures::path_of(name));
            if s.doc.source.path.as_ref() != Some(&path) {
                s.apply(Command::Open(path));
            }
        }
        let settings = f.settings(s.doc.scene.settings);
        if settings != s.doc.scene.settings {
            s.apply(Command::SetSettings(settings));
        }
        if let Some([x, y]) = f.pixel {
            let (w, h) = (s.doc.image.width, s.doc.image.height);
            if x < w && y < h {
                s.apply(Command::SelectPixel([x, y]));
            } else {
                self.message = Some(format!(
                    "URL fragment: pixel={x},{y} is outside the {w}x{h} image"
                ));
            }
        }
    }

    /// Take uploaded (or dropped) files in, then open the scene among them
    /// ([`files::scene_among`]: a raytree JSON, glTF, Mitsuba or pbrt scene, with its meshes
    /// and includes opened together). Refused files are named in the message; the page goes
    /// on with what it had.
    pub fn open_uploads(&mut self, uploads: Vec<(String, Vec<u8>)>) {
        let mut errors = Vec::new();
        let mut taken = Vec::new();
        for (name, bytes) in uploads {
            // Only the name: a dropped path's directories mean nothing here.
            let name = name.rsplit(['/', '\\']).next().unwrap_or(&name).to_owned();
            match files::upload(&name, bytes, files::limit_for(&name)) {
                Ok(bytes) => taken.push((name, bytes)),
                Err(e) => errors.push(e),
            }
        }
        let scene = files::scene_among(&taken).map(|i| taken[i].0.clone());
        for (name, bytes) in taken {
            self.files
                .insert(PathBuf::from(format!("{}/{name}", files::UPLOADS)), bytes);
        }
        if scene.is_none() && errors.is_empty() {
            errors.push(
                "no scene among the files opened (a .json, .gltf, .glb, .xml or .pbrt); their \
                 meshes are kept for the scene opened next"
                    .to_string(),
            );
        }
        self.message = (!errors.is_empty()).then(|| errors.join("\n"));
        if let Some(name) = scene {
            let path = PathBuf::from(format!("{}/{name}", files::UPLOADS));
            self.inner.session.apply(Command::Open(path));
        }
    }

    /// One frame: the page's actions, the bar, the inspector, the published state.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let start = self.host.now_ms();
        let before = self.progress();
        let actions = self.host.take_actions();
        let n_actions = actions.len();
        for a in actions {
            match a {
                Action::Fragment(f) => {
                    if f.trim_start_matches('#') != self.hash {
                        self.apply_fragment(&f);
                    }
                }
                Action::Upload(u) => self.open_uploads(u),
                Action::Message(m) => self.message = Some(m),
                Action::Export(kind) => self.inner.session.apply(Command::Export(kind)),
                Action::ResetFrames => self.reset_frames(),
                Action::Start(job) => self.start(ui.ctx(), &job),
            }
        }
        let mid = self.host.now_ms();
        egui::Panel::top("web-bar").show(ui, |ui| self.bar_ui(ui));
        self.inner.show(ui);
        self.sync_hash();
        let doc = &self.inner.session.doc;
        if self.first_image_ms.is_none() && doc.rendered() && doc.progress.seconds.is_some() {
            self.first_image_ms = Some(self.host.now_ms());
        }
        let ms = self.host.now_ms() - start;
        self.frames.count += 1;
        self.frames.last_ms = ms;
        self.frames.worst_ms = self.frames.worst_ms.max(ms);
        if ms > 40.0 {
            let after = self.progress();
            let what = format!(
                "{n_actions} actions ({:.0} ms); image rows {}->{}, statistics rows {}->{}, \
                 tree version {}->{}, generation {}->{}",
                mid - start,
                before[0],
                after[0],
                before[1],
                after[1],
                before[2],
                after[2],
                before[3],
                after[3]
            );
            let slow = &mut self.frames.slow;
            slow.push((ms, what));
            slow.sort_by(|a, b| b.0.total_cmp(&a.0));
            slow.truncate(8);
        }
        self.publish();
    }

    /// Image rows, statistics rows, tree version and generation (what a slow frame did).
    fn progress(&self) -> [u64; 4] {
        let d = &self.inner.session.doc;
        [
            u64::from(d.progress.rows),
            u64::from(d.progress.stats_rows),
            d.tree_version,
            d.progress.generation,
        ]
    }

    /// Forget the worst frame so far (the test measures one render at a time).
    pub fn reset_frames(&mut self) {
        self.frames = Frames::default();
    }

    fn bar_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let current = self.inner.session.doc.source.label();
            let name = current
                .strip_prefix("fixtures/")
                .and_then(|s| s.strip_suffix(".json"))
                .unwrap_or("(a file opened in this page)");
            ui.label("Scene:");
            let mut chosen = None;
            egui::ComboBox::from_id_salt("web-scene")
                .selected_text(name)
                .show_ui(ui, |ui| {
                    for (n, _) in crate::fixtures::FIXTURES {
                        if ui.selectable_label(*n == name, *n).clicked() {
                            chosen = Some(*n);
                        }
                    }
                });
            if let Some(n) = chosen {
                self.message = None;
                let path = PathBuf::from(crate::fixtures::path_of(n));
                self.inner.session.apply(Command::Open(path));
            }
            if ui
                .button("Open scene file...")
                .on_hover_text(
                    "a scene JSON with its OBJ meshes (select them together), or drop them on \
                     the page",
                )
                .clicked()
            {
                self.host.pick_files();
            }
            if let Some(m) = &self.message {
                ui.separator();
                ui.colored_label(egui::Color32::from_rgb(255, 110, 110), m);
            }
        });
    }

    /// Keep the address bar's fragment on the scene, pixel and settings shown, so the link can
    /// be copied.
    fn sync_hash(&mut self) {
        let doc = &self.inner.session.doc;
        let mut parts = Vec::new();
        if let Some(name) = doc
            .source
            .path
            .as_ref()
            .and_then(|p| p.to_str()?.strip_prefix("fixtures/")?.strip_suffix(".json"))
        {
            parts.push(format!("scene={name}"));
        }
        if let Some([x, y]) = doc.selection {
            parts.push(format!("pixel={x},{y}"));
        }
        let s = &doc.scene.settings;
        let integrator = serde_json::to_value(s.integrator)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        parts.push(format!("integrator={integrator}"));
        parts.push(format!("spp={}", s.spp));
        parts.push(format!("depth={}", s.max_depth));
        let hash = parts.join("&");
        if hash != self.hash {
            self.hash = hash;
            self.host.set_hash(&self.hash);
        }
    }

    /// Start background job `job` (`versus`, `strategies`, `denoise`: the denoised image,
    /// `acne`: the acne lab), as its button or checkbox does.
    fn start(&mut self, ctx: &egui::Context, job: &str) {
        let doc = &self.inner.session.doc;
        match job {
            "versus" => self.inner.start_versus(ctx),
            "strategies" => self.inner.start_strategies(ctx),
            "denoise" => {
                let mut view = doc.view;
                view.denoise = true;
                self.inner.session.apply(Command::SetView(view));
            }
            "acne" => {
                let params = doc.lab.params;
                self.inner.session.apply(Command::SetLab(params));
            }
            other => self.message = Some(format!("no background job named {other:?}")),
        }
    }

    fn publish(&mut self) {
        let doc = &self.inner.session.doc;
        if self.published_tree != Some(doc.tree_version) {
            self.published_tree = Some(doc.tree_version);
            self.published.tree_json = doc
                .tree
                .as_ref()
                .and_then(|t| raytree::gui::model::export::tree_json(t).ok())
                .and_then(|b| String::from_utf8(b).ok());
        }
        let p = &doc.progress;
        let s = &doc.scene.settings;
        let state = serde_json::json!({
            "scene": doc.source.label(),
            "width": doc.image.width,
            "height": doc.image.height,
            "integrator": serde_json::to_value(s.integrator).unwrap_or_default(),
            "spp": s.spp,
            "max_depth": s.max_depth,
            "generation": p.generation,
            "rendered": doc.rendered() && p.seconds.is_some(),
            "image_ms": p.seconds.map(|s| s * 1e3),
            "stats_ms": p.stats_seconds.map(|s| s * 1e3),
            "growth": p.growth.as_ref().filter(|_| p.growth_current),
            "selection": doc.selection,
            "tree_nodes": doc.tree.as_ref().map(|t| t.nodes.len()),
            "error": doc.error,
            "export_error": doc.export_error,
            "status": doc.status,
            "message": self.message,
            "first_image_ms": self.first_image_ms,
            "frames": self.frames.count,
            "worst_frame_ms": self.frames.worst_ms,
            "last_frame_ms": self.frames.last_ms,
            "slow_frames": self.frames.slow,
            "hash": self.hash,
            "versus": { "summary": self.inner.versus().0, "running": self.inner.versus().1 },
            "strategies": { "captions": self.inner.strategies().0, "running": self.inner.strategies().1 },
            "denoise": self.inner.denoise_state().map(|d| format!("{d:?}")),
            "lab": { "started": doc.lab.started, "done": doc.lab.done, "cells": doc.lab.sweep.len() + usize::from(doc.lab.current.is_some()) },
        });
        self.published.state_json = state.to_string();
        self.published.pixel_frame = self.inner.screen_of_pixel(0, 0).and_then(|a| {
            let b = self.inner.screen_of_pixel(1, 1)?;
            Some([[a.x, a.y], [b.x, b.y]])
        });
        self.host.publish(&self.published);
    }
}

/// Called after every delivery of the render (the page asks for a frame).
pub type Repaint = raytree::gui::jobs::worker::Repaint;

impl eframe::App for WebApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }
}
