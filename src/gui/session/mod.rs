//! The controller: a [`Document`] plus the render [`Worker`] and the file hook. Applies
//! commands, folds worker deliveries into the image, and reloads scenes. No egui here, so tests
//! and benchmarks can drive it directly.

use super::{Adjust, Files};
use crate::gui::jobs::acne_lab::LabWorker;
use crate::gui::jobs::worker::{Repaint, Worker};
use crate::gui::model::document::{Command, Document, Source};
use crate::gui::model::export::{self, ExportKind};
use crate::render::Image;
use crate::scene::Scene;
use crate::trace_pixel;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How a settings change the session refused begins: "not applied: settings.spp: must be in
/// 1..=65536, got 0" (the next accepted change clears it).
pub const REFUSED: &str = "not applied: ";

/// The inspector without its widgets.
pub struct Session {
    /// What the panels show.
    pub doc: Document,
    worker: Worker,
    files: Box<dyn Files>,
    adjust: Adjust,
    repaint: Repaint,
    /// The acne lab's thread, started on first use.
    lab: Option<LabWorker>,
}

impl Session {
    /// Open `path` (or the built-in scene) and start rendering. A bad scene file leaves the
    /// built-in scene loaded with the error shown.
    pub fn new(
        path: Option<PathBuf>,
        files: Box<dyn Files>,
        adjust: Adjust,
        repaint: Repaint,
    ) -> Self {
        let mut builtin = Scene::default_scene();
        let builtin_err = adjust(&mut builtin).err();
        let doc = Document::new(builtin, Source::default());
        let mut s = Self {
            doc,
            worker: Worker::new(Arc::clone(&repaint)),
            files,
            adjust,
            repaint,
            lab: None,
        };
        s.doc.error = builtin_err;
        match path {
            Some(p) => {
                if s.open(&p).is_err() {
                    // Keep the name in the field, so fixing the file is one Open away.
                    s.doc.path_field = p.display().to_string();
                    s.doc.status = format!("{} did not load: built-in scene shown", p.display());
                    s.rerender();
                }
            }
            None => s.rerender(),
        }
        s
    }

    /// Read, validate and adjust the scene at `path`.
    fn read(&self, path: &Path) -> Result<(Scene, Source, Vec<crate::formats::Note>), String> {
        let label = path.display();
        // A binary glTF (`.glb`) is read as bytes; every other scene is text.
        let binary = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
        let src = if binary {
            self.files.read_bytes(path)
        } else {
            self.files.read(path).map(String::into_bytes)
        }
        .map_err(|e| format!("cannot read scene {label}: {e}"))?;
        self.parse(path, &src)
    }

    /// The text of the current scene as the editor starts from: its file's (a glTF binary
    /// cannot be edited as text), or the built-in scene's JSON.
    ///
    /// # Errors
    /// Why the file cannot be read as text.
    pub fn scene_text(&self) -> Result<String, String> {
        match &self.doc.source.path {
            None => Ok(crate::scene::DEFAULT_SCENE_JSON.to_string()),
            Some(p) if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb")) => {
                Err(format!("{}: a binary glTF is not text", p.display()))
            }
            Some(p) => self
                .files
                .read(p)
                .map_err(|e| format!("cannot read scene {}: {e}", p.display())),
        }
    }

    /// Parse, validate and adjust scene source `src` as the file `path` (its format detected
    /// from the name and the bytes; meshes and includes read beside it).
    fn parse(
        &self,
        path: &Path,
        src: &[u8],
    ) -> Result<(Scene, Source, Vec<crate::formats::Note>), String> {
        let label = path.display();
        if src.len() as u64 > crate::input::MAX_SCENE_BYTES {
            return Err(format!(
                "cannot read scene {label}: larger than the limit of {} MiB",
                crate::input::MAX_SCENE_BYTES >> 20
            ));
        }
        let format = crate::formats::Format::detect(&path.to_string_lossy(), src);
        let (mut scene, notes) = if format == crate::formats::Format::Json {
            let src = String::from_utf8_lossy(src);
            // Mesh files are read through the same hook, relative to the scene's directory.
            let dir = path.parent().unwrap_or(Path::new(""));
            let mut load_mesh = |file: &str| {
                let p = dir.join(file);
                crate::mesh::parse_obj_read(file, &p, self.files.read(&p))
            };
            let scene =
                Scene::from_json_with(&src, &mut load_mesh).map_err(|e| format!("{label}:{e}"))?;
            (scene, Vec::new())
        } else {
            self.read_foreign(path, format, src)?
        };
        (self.adjust)(&mut scene).map_err(|e| format!("{label}: {e}"))?;
        let source = Source {
            path: Some(path.to_path_buf()),
            modified: self.files.modified(path),
        };
        Ok((scene, source, notes))
    }

    /// A pbrt, Mitsuba or glTF scene: converted (its includes and meshes read through the hook,
    /// relative to the scene) and validated; the notes say what was approximated.
    fn read_foreign(
        &self,
        path: &Path,
        format: crate::formats::Format,
        src: &[u8],
    ) -> Result<(Scene, Vec<crate::formats::Note>), String> {
        let name = path.to_string_lossy().into_owned();
        let mut res = |f: &str| {
            self.files
                .read_bytes(Path::new(f))
                .map_err(|e| format!("cannot read {f}: {e}"))
        };
        let c = crate::formats::convert(format, &name, src, &[], &mut res)
            .map_err(|e| crate::input::escape_controls(&e.to_string()).into_owned())?;
        let scene = crate::scene::validate(&c.desc, "", &mut |_| Err(String::new()))
            .map_err(|e| format!("{name}: the converted scene is invalid: {e}"))?;
        Ok((scene, c.notes))
    }

    /// Load `path`; on error keep the current scene and show the error.
    fn open(&mut self, path: &Path) -> Result<(), ()> {
        let read = self.read(path);
        self.install(path, read, "loaded")
    }

    /// Load the edited text `text` as the current scene's file (the built-in scene's as JSON),
    /// without writing it; on error keep the current scene and show the error.
    fn apply_text(&mut self, text: &str) {
        let path = self
            .doc
            .source
            .path
            .clone()
            .unwrap_or_else(|| PathBuf::from("<built-in classic>.json"));
        let mut read = self.parse(&path, text.as_bytes());
        if let Ok((_, source, _)) = &mut read {
            // Reload only when the file itself changes again; the built-in scene has no file.
            source.path = self.doc.source.path.clone();
            source.modified = self
                .doc
                .source
                .path
                .as_ref()
                .and_then(|p| self.files.modified(p));
        }
        let _ = self.install(&path, read, "applied the edited text of");
    }

    /// Show a scene `read` from `path` (keeping the view, the selection, the pin, the step,
    /// the lab and the filter), or its error with the current scene kept.
    fn install(
        &mut self,
        path: &Path,
        read: Result<(Scene, Source, Vec<crate::formats::Note>), String>,
        verb: &str,
    ) -> Result<(), ()> {
        match read {
            Ok((scene, source, notes)) => {
                let view = self.doc.view;
                let selection = self.doc.selection;
                let versions = (self.doc.tree_version, self.doc.image_version);
                let (pin, step) = (self.doc.pin.take(), self.doc.step);
                let lab = std::mem::take(&mut self.doc.lab);
                let mut lpe = std::mem::take(&mut self.doc.lpe);
                lpe.full = None;
                self.doc = Document::new(scene, source);
                self.doc.lpe = lpe;
                self.doc.view = view;
                self.doc.pin = pin;
                self.doc.step = step;
                self.doc.lab = lab;
                // Versions keep counting: caches keyed on them must see a new document.
                self.doc.tree_version = versions.0;
                self.doc.image_version = versions.1 + 1;
                self.doc.status = match notes.first() {
                    None => format!("{verb} {}", path.display()),
                    Some(n) => format!(
                        "{verb} {} with {} approximation(s) (raytree effects lists them), first: {}",
                        path.display(),
                        notes.len(),
                        crate::input::escape_controls(&n.to_string())
                    ),
                };
                self.rerender();
                if let Some([x, y]) = selection {
                    self.select([x, y]);
                }
                Ok(())
            }
            Err(e) => {
                // Remember the time so a broken file is not re-read every poll.
                if self.doc.source.path.as_deref() == Some(path) {
                    self.doc.source.modified = self.files.modified(path);
                }
                self.doc.error = Some(e);
                Err(())
            }
        }
    }

    /// Re-read the scene if its file changed on disk. Returns whether it reloaded.
    pub fn poll_reload(&mut self) -> bool {
        let Some(path) = self.doc.source.path.clone() else {
            return false;
        };
        let now = self.files.modified(&path);
        if now.is_none() || now == self.doc.source.modified {
            return false;
        }
        self.open(&path).is_ok()
    }

    fn rerender(&mut self) {
        let (w, h) = (self.doc.scene.camera.width, self.doc.scene.camera.height);
        if self.doc.image.width != w || self.doc.image.height != h {
            self.doc.image = Image {
                width: w,
                height: h,
                pixels: vec![crate::math::Rgb::ZERO; (w * h) as usize],
            };
            self.doc.stats = vec![Default::default(); (w * h) as usize];
        }
        // With a debug view on screen its statistics matter most: gather them in the one pass
        // that also gives the image; otherwise show the image first.
        let image_first = self.doc.view.debug == crate::gui::model::stats::DebugView::Off;
        let scene = Arc::clone(&self.doc.scene);
        let options = self.doc.progressive.options;
        // Light tracing and BDPT splat across the image: their passes are whole renders.
        let progressive = options.on && !self.doc.scene.settings.integrator.splats();
        self.doc.progress.generation = if progressive {
            self.worker.start_progressive(scene, options)
        } else {
            self.worker.start(scene, image_first)
        };
        self.doc.progressive.report = None;
        self.doc.progress.rows = 0;
        self.doc.progress.seconds = None;
        self.doc.progress.stats_rows = 0;
        self.doc.progress.stats_seconds = None;
        self.doc.progress.growth_current = false;
        if self.doc.lab.started {
            self.start_lab();
        }
    }

    fn select(&mut self, [x, y]: [u32; 2]) {
        // Where the selected ray sits (its sample and its path from the sample's camera ray),
        // not its number: another integrator or setting numbers the rays differently (issue
        // 32: #19 was sample 4's camera ray under path, a depth-16 refracted ray under Whitted).
        let place = self
            .doc
            .node
            .and_then(|id| place_of(self.doc.tree.as_ref()?, id));
        self.doc.selection = Some([x, y]);
        self.doc.lpe.full = None;
        self.doc.tree = trace_pixel(&self.doc.scene, x, y);
        self.refilter();
        let n = self.doc.tree.as_ref().map_or(0, |t| t.nodes.len());
        let kept = place.and_then(|p| find_place(self.doc.tree.as_ref()?, &p));
        self.doc.node = kept.or(Some(crate::NodeId(0)).filter(|_| n > 0));
    }

    /// Apply the LPE filter to the selected pixel's unfiltered tree (a new tree version).
    fn refilter(&mut self) {
        let full = self.doc.lpe.full.take().or_else(|| self.doc.tree.take());
        self.doc.tree = self.doc.lpe.apply(full);
        self.doc.tree_version += 1;
    }

    /// Apply one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::SelectPixel(p) => {
                self.doc.node = None;
                self.select(p);
            }
            Command::MoveSelection(step) => self.move_selection(step),
            Command::SelectNode(id) => self.doc.node = id,
            Command::SetSettings(settings) => self.set_settings(settings),
            Command::SetProgressive(o) => {
                self.doc.progressive.options = o;
                self.rerender();
            }
            Command::SetView(v) => {
                if v.debug != self.doc.view.debug {
                    self.doc.image_version += 1;
                }
                self.doc.view = v;
            }
            Command::Open(path) => {
                self.doc.error = None;
                let _ = self.open(&path);
            }
            Command::ApplyText(text) => {
                self.doc.error = None;
                self.apply_text(&text);
            }
            Command::Reload => {
                self.doc.error = None;
                match self.doc.source.path.clone() {
                    Some(p) => {
                        let _ = self.open(&p);
                    }
                    None => self.rerender(),
                }
            }
            Command::Export(kind) => self.export(kind),
            Command::SetPathField(s) => self.doc.path_field = s,
            Command::SetExportField(s) => self.doc.export_field = s,
            Command::Pin => self.pin(),
            Command::Unpin => self.doc.pin = None,
            Command::SetStep(step) => self.doc.step = step,
            Command::EditLpe(text) => self.doc.lpe.edit(text),
            Command::SetLpe(text) => self.set_lpe(text),
            Command::SetLab(params) => {
                self.doc.lab.params = params;
                self.start_lab();
            }
        }
    }

    /// Select the pixel `[dx, dy]` from the selection (or from the top-left corner), clamped
    /// to the image.
    fn move_selection(&mut self, [dx, dy]: [i32; 2]) {
        let [x, y] = self.doc.selection.unwrap_or([0, 0]);
        let nx = (i64::from(x) + i64::from(dx)).clamp(0, i64::from(self.doc.image.width) - 1);
        let ny = (i64::from(y) + i64::from(dy)).clamp(0, i64::from(self.doc.image.height) - 1);
        self.doc.node = None;
        self.select([nx as u32, ny as u32]);
    }

    /// New settings: checked as the command line checks them, then rendered.
    fn set_settings(&mut self, settings: crate::scene::Settings) {
        // The command line's own validation: a refused value is said, and the
        // settings in force stay as they were (issue 32, item 1).
        if let Err((path, msg)) = crate::scene::check_settings(&settings) {
            self.doc.error = Some(format!("{REFUSED}{path}: {msg}"));
            return;
        }
        if self
            .doc
            .error
            .as_deref()
            .is_some_and(|e| e.starts_with(REFUSED))
        {
            self.doc.error = None;
        }
        let mut scene = (*self.doc.scene).clone();
        scene.settings = settings;
        self.doc.scene = Arc::new(scene);
        self.rerender();
        if let Some(p) = self.doc.selection {
            self.select(p);
        }
    }

    /// Pin the selected pixel's tree (a new pin version) for comparison.
    fn pin(&mut self) {
        if let Some(tree) = self.doc.tree.clone() {
            let version = self.doc.pin.as_ref().map_or(0, |p| p.version) + 1;
            let label = crate::gui::model::document::tree_label(&self.doc.source.label(), &tree);
            self.doc.pin = Some(crate::gui::model::document::Pin {
                tree,
                label,
                version,
            });
        }
    }

    /// A new LPE filter: refilter the tree and keep the selected ray where the filter does.
    fn set_lpe(&mut self, text: String) {
        if self.doc.lpe.set_text(text) {
            // The filter renumbers nodes: keep the same ray selected (or its nearest
            // ancestor the new filter keeps), else the first root.
            let original = self.doc.node.map(|id| self.doc.lpe.to_original(id));
            self.refilter();
            let n = self.doc.tree.as_ref().map_or(0, |t| t.nodes.len());
            let lpe = &self.doc.lpe;
            let kept = original
                .and_then(|id| lpe.from_original(lpe.unfiltered(self.doc.tree.as_ref())?, id));
            self.doc.node = kept.or(Some(crate::NodeId(0)).filter(|_| n > 0));
        }
    }

    fn export(&mut self, kind: ExportKind) {
        let doc = &self.doc;
        let name = kind.file_name(&doc.export_field, doc.selection);
        let no_warning = |b: Vec<u8>| (b, None);
        let bytes = match kind {
            ExportKind::ImagePng if doc.rendered() => export::png(&doc.image).map(no_warning),
            ExportKind::ImageExr if doc.rendered() => export::exr(&doc.image),
            ExportKind::ImagePng | ExportKind::ImageExr => {
                Err("the render has not finished".into())
            }
            ExportKind::TreeJson => doc
                .tree
                .as_ref()
                .ok_or_else(|| "select a pixel first".to_string())
                .and_then(export::tree_json)
                .map(no_warning),
            ExportKind::DiagramSvg | ExportKind::DiagramPng => diagram_bytes(doc, kind),
        };
        let result = bytes.and_then(|(b, warning)| {
            self.files
                .write(Path::new(&name), &b)
                .map(|()| warning)
                .map_err(|e| {
                    // The file hook may already name the file (the binary's does).
                    let e = e.to_string();
                    if e.contains(&name) {
                        e
                    } else {
                        format!("cannot write {name}: {e}")
                    }
                })
        });
        match result {
            Ok(warning) => {
                self.doc.export_error = None;
                self.doc.status = match warning {
                    // The same warning the command line gives for the same output.
                    Some(w) => format!("wrote {name}; warning: {w}"),
                    None => format!("wrote {name}"),
                };
            }
            Err(e) => self.doc.export_error = Some(e),
        }
    }
}

/// The selected pixel's diagram at 1280x720 as SVG or PNG, with the panel's options (the
/// selection highlighted only when the panel asks for it).
/// The diagram's bytes, and the warning for shapes left out of an SVG.
fn diagram_bytes(doc: &Document, kind: ExportKind) -> Result<(Vec<u8>, Option<String>), String> {
    use crate::diagram::{Diagram, Style, Theme, to_png, to_svg_counting};
    let tree = doc.tree.as_ref().ok_or("select a pixel first")?;
    let opts = crate::gui::model::diagram::export_options(doc);
    let d = Diagram::build(&doc.scene, tree, &opts).map_err(|e| e.to_string())?;
    let style = Style::new(Theme::Light);
    Ok(match kind {
        ExportKind::DiagramPng => (to_png(&d, &style), None),
        _ => {
            let (svg, dropped) = to_svg_counting(&d, &style);
            (svg.into_bytes(), export::svg_warning(dropped))
        }
    })
}

mod deliveries;
mod lab;

/// Where a ray sits in a pixel's tree: its sample's index and, from that sample's camera ray
/// down, the child index and kind of each ray on the way.
struct Place {
    sample: u32,
    steps: Vec<(usize, crate::RayKind)>,
}

/// The place of node `id` in `tree`.
fn place_of(tree: &crate::RayTree, id: crate::NodeId) -> Option<Place> {
    let mut steps = Vec::new();
    let mut at = id;
    while let Some(parent) = tree.nodes.get(at.index())?.parent {
        let k = tree.node(parent).children.iter().position(|&c| c == at)?;
        steps.push((k, tree.node(at).kind));
        at = parent;
    }
    steps.reverse();
    let sample = tree.samples.iter().find(|s| s.root == at)?.index;
    Some(Place { sample, steps })
}

/// The ray at `place` in `tree`, or the deepest ray on its way that `tree` has (the same child
/// of the same kind at each step): at least the sample's camera ray, if the sample exists.
fn find_place(tree: &crate::RayTree, place: &Place) -> Option<crate::NodeId> {
    let mut at = tree.samples.iter().find(|s| s.index == place.sample)?.root;
    for &(k, kind) in &place.steps {
        match tree.node(at).children.get(k) {
            Some(&c) if tree.node(c).kind == kind => at = c,
            _ => break,
        }
    }
    Some(at)
}
