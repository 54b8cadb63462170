//! The inspector's state: the scene, the progressive image, the selection and its tree, and the
//! view options. Plain data; panels read it and emit [`Command`]s.

use super::export::ExportKind;
use super::stats::{DebugView, PixelStats};
use crate::math::Rgb;
use crate::render::Image;
use crate::scene::{Scene, Settings};
use crate::tree::{NodeId, RayTree};
use std::path::PathBuf;
use std::sync::Arc;

/// Where the scene came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Source {
    /// The file, or `None` for the built-in classic scene.
    pub path: Option<PathBuf>,
    /// Modification time when last read (for reload on change).
    pub modified: Option<std::time::SystemTime>,
}

impl Source {
    /// How to name the scene in the window.
    #[must_use]
    pub fn label(&self) -> String {
        self.path
            .as_ref()
            .map_or("<built-in classic>".into(), |p| p.display().to_string())
    }
}

/// How the image is shown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewOptions {
    /// Screen points per image pixel; `None` fits the image to the panel.
    pub zoom: Option<f32>,
    /// Offset of the image centre from the panel centre, in points.
    pub pan: [f32; 2],
    /// False-colour view.
    pub debug: DebugView,
    /// Draw the selected pixel's ray path on the image.
    pub overlay: bool,
    /// The diagram panel's options (plane, filters, zoom and pan, export highlight).
    pub diagram: super::diagram_view::DiagramView,
    /// Show the image denoised ([`crate::gui::jobs::denoise`]; trees, overlay, diagram and exports
    /// stay the raw samples).
    pub denoise: bool,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            zoom: None,
            pan: [0.0, 0.0],
            debug: DebugView::Off,
            overlay: true,
            diagram: super::diagram_view::DiagramView::default(),
            denoise: false,
        }
    }
}

/// The render in progress or finished.
#[derive(Clone, Debug)]
pub struct Progress {
    /// Generation of the render the image shows.
    pub generation: u64,
    /// Rows delivered for `generation`.
    pub rows: u32,
    /// Seconds of the last finished render.
    pub seconds: Option<f64>,
    /// Rays of the last finished render.
    pub rays: u64,
    /// Rows of debug statistics delivered for `generation` (gathered after the image).
    pub stats_rows: u32,
    /// Seconds of the last finished statistics pass.
    pub stats_seconds: Option<f64>,
    /// How the ray tree grows and what the automatic cut saves (after the statistics). Kept
    /// while the next render runs (marked by `growth_current`), so the Scene section does not
    /// shrink and move every control below it (issue 32).
    pub growth: Option<String>,
    /// Whether `growth` is of the current render.
    pub growth_current: bool,
}

/// Step along a ray: where the point stands on the selected ray and how deep the recursion is
/// shown.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Step {
    /// The point's place on the selected ray as a fraction of its `t` range (1 = at the hit);
    /// `None`: no point drawn.
    pub at: Option<f64>,
    /// Draw rays down to this depth only (overlay and diagram); `None`: all.
    pub depth: Option<u32>,
}

/// The acne lab: its parameters and what the lab's worker has delivered for them.
#[derive(Clone, Debug, Default)]
pub struct Lab {
    /// What is rendered.
    pub params: super::lab::LabParams,
    /// Whether the lab has been started (it re-runs on every scene or settings change then).
    pub started: bool,
    /// The lab job the results belong to.
    pub generation: u64,
    /// The chosen strategy and epsilon's render (affected pixels).
    pub current: Option<crate::analysis::acne::AcneCell>,
    /// The sweep's cells delivered so far.
    pub sweep: Vec<crate::analysis::acne::AcneCell>,
    /// Whether the job is complete.
    pub done: bool,
}

/// A tree kept aside to compare the current one with ("pin and compare").
#[derive(Clone, Debug)]
pub struct Pin {
    /// The pinned tree.
    pub tree: RayTree,
    /// What it was traced with, in words (pixel, scene, settings).
    pub label: String,
    /// Bumped on every pin, so caches see a new pin of the same tree.
    pub version: u64,
}

/// What a tree was traced with, in words: pixel, scene and the settings a teacher changes,
/// the integrator and its roulette among them (the path tracer's `rr_depth`; Whitted's
/// `roulette_below` when it is on).
#[must_use]
pub fn tree_label(scene_label: &str, tree: &RayTree) -> String {
    let s = &tree.settings;
    let name = |v: serde_json::Result<serde_json::Value>| {
        v.ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default()
    };
    let roulette = match (s.integrator, s.whitted.roulette_below) {
        (crate::scene::IntegratorKind::Path, _) => {
            format!(", roulette from bounce {}", s.path.rr_depth)
        }
        (_, Some(w)) if w > 0.0 => format!(", roulette below {w}"),
        _ => String::new(),
    };
    format!(
        "pixel {},{} of {scene_label}: {}, depth {}, spp {}{roulette}, offset {} {:e}, Fresnel {}, shadows {}",
        tree.pixel[0],
        tree.pixel[1],
        name(serde_json::to_value(s.integrator)),
        s.max_depth,
        s.spp,
        name(serde_json::to_value(s.offset.strategy)),
        s.offset.epsilon,
        name(serde_json::to_value(s.whitted.fresnel)),
        name(serde_json::to_value(s.whitted.shadows)),
    )
}

/// Everything the panels show.
pub struct Document {
    /// The scene being traced (with the panel's settings).
    pub scene: Arc<Scene>,
    /// Where it came from.
    pub source: Source,
    /// Linear image; rows are replaced as bands arrive (old rows stay until then).
    pub image: Image,
    /// Debug statistics per pixel, same layout as `image`.
    pub stats: Vec<PixelStats>,
    /// Render progress.
    pub progress: Progress,
    /// Progressive rendering: its options and the last pass's noise estimate.
    pub progressive: super::progressive::State,
    /// Selected pixel.
    pub selection: Option<[u32; 2]>,
    /// The selected pixel's tree (re-traced synchronously on every change).
    pub tree: Option<RayTree>,
    /// Selected node of `tree`.
    pub node: Option<NodeId>,
    /// Bumped whenever `tree` is re-traced; it keeps counting across scene (re)loads, so a cache
    /// keyed on it never mistakes a new scene's tree for the old one's.
    pub tree_version: u64,
    /// View options.
    pub view: ViewOptions,
    /// The last error (bad scene, failed export); the last good scene stays loaded.
    pub error: Option<String>,
    /// The last failed export (shown whole under the export buttons).
    pub export_error: Option<String>,
    /// The last informational message.
    pub status: String,
    /// Text of the "open scene" field.
    pub path_field: String,
    /// Text of the export base field (file name without extension).
    pub export_field: String,
    /// Bumped whenever the image or debug data changed, so the app re-uploads its texture.
    pub image_version: u64,
    /// The pinned tree, compared with the current one (kept across settings, pixels and
    /// reloads).
    pub pin: Option<Pin>,
    /// Step along a ray.
    pub step: Step,
    /// The acne lab.
    pub lab: Lab,
    /// The light path expression filter (`tree` is the filtered tree while one applies).
    pub lpe: super::lpe_filter::LpeState,
}

impl Document {
    /// A document on `scene`, with a black image of the right size.
    #[must_use]
    pub fn new(scene: Scene, source: Source) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        let base = source
            .path
            .as_ref()
            .map(|p| p.with_extension("").display().to_string())
            .unwrap_or_else(|| "classic".into());
        Self {
            image: Image {
                width: w,
                height: h,
                pixels: vec![Rgb::ZERO; (w * h) as usize],
            },
            stats: vec![PixelStats::default(); (w * h) as usize],
            progress: Progress {
                generation: 0,
                rows: 0,
                seconds: None,
                rays: 0,
                stats_rows: 0,
                stats_seconds: None,
                growth: None,
                growth_current: false,
            },
            progressive: Default::default(),
            path_field: source
                .path
                .as_ref()
                .map_or(String::new(), |p| p.display().to_string()),
            export_field: base,
            scene: Arc::new(scene),
            source,
            selection: None,
            tree: None,
            node: None,
            tree_version: 0,
            view: ViewOptions::default(),
            error: None,
            export_error: None,
            status: String::new(),
            image_version: 0,
            pin: None,
            step: Step::default(),
            lab: Lab::default(),
            lpe: Default::default(),
        }
    }

    /// Whether the current render has finished.
    #[must_use]
    pub fn rendered(&self) -> bool {
        self.progress.rows >= self.image.height
    }

    /// The stats of pixel (x, y).
    #[must_use]
    pub fn stats_at(&self, x: u32, y: u32) -> PixelStats {
        self.stats[(y * self.image.width + x) as usize]
    }
}

/// A change requested by a panel, applied after layout by [`crate::gui::Session::apply`].
#[must_use]
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Select pixel (x, y) and trace its tree.
    SelectPixel([u32; 2]),
    /// Move the selection by (dx, dy), clamped to the image.
    MoveSelection([i32; 2]),
    /// Select a node of the tree (or none).
    SelectNode(Option<NodeId>),
    /// New tracer settings: re-render and re-trace.
    SetSettings(Settings),
    /// New view options.
    SetView(ViewOptions),
    /// Load a scene file.
    Open(PathBuf),
    /// Re-read the current scene file.
    Reload,
    /// Load the scene from this text, edited in the inspector, as if it were the current
    /// scene's file (its format, its meshes and includes beside it); the file on disk is not
    /// written. On error the current scene stays and the error names the line and column.
    ApplyText(String),
    /// Write an export next to the export base.
    Export(ExportKind),
    /// Edit the "open scene" field.
    SetPathField(String),
    /// Edit the export base field.
    SetExportField(String),
    /// Pin the current tree to compare later trees with it.
    Pin,
    /// Drop the pinned tree.
    Unpin,
    /// Move the step point or change the depth shown.
    SetStep(Step),
    /// Run the acne lab with these parameters (cancelling its last job).
    SetLab(super::lab::LabParams),
    /// Apply this text as the LPE filter (when it parses; empty: no filter).
    SetLpe(String),
    /// The LPE filter field's text while it is typed (its error shown, nothing applied).
    EditLpe(String),
    /// Progressive rendering's options (re-renders).
    SetProgressive(super::progressive::Options),
}
