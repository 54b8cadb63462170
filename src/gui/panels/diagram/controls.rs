//! The diagram panel's options ([`DiagramView`]) and controls: plane (automatic, incidence,
//! camera, through the selected ray, axis planes), draw depth, ray kinds, label depth,
//! contribution threshold, sample, spawn-point insets, whether exports highlight the
//! selection; zoom about the cursor and pan by dragging.

use crate::diagram::{DiagramOptions, MIN_SHARE, PlaneFrame, PlaneSpec};
use crate::gui::model::document::Document;
use crate::tree::{NodeId, RayKind};

/// Which plane the panel slices with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlaneChoice {
    /// [`PlaneSpec::Auto`].
    Auto,
    /// [`PlaneSpec::Incidence`].
    Incidence,
    /// [`PlaneSpec::Camera`].
    Camera,
    /// The plane through the selected ray and its parent ([`PlaneSpec::Ray`]); follows the
    /// selection.
    SelectedRay,
    /// `x`, `y` or `z` = the selected ray's hit coordinate (fixed when chosen).
    Axis {
        /// 0, 1 or 2.
        axis: usize,
        /// The coordinate.
        value: f64,
    },
}

/// The diagram panel's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagramView {
    /// The slicing plane.
    pub plane: PlaneChoice,
    /// Insets magnifying the spawn points (offset epsilon).
    pub zoom_offsets: bool,
    /// Draw rays up to this depth only (`None`: all).
    pub draw_depth: Option<u32>,
    /// Kinds drawn, in [`RayKind::ALL`] order.
    pub kinds: [bool; RayKind::COUNT],
    /// Labels on depths up to this one.
    pub label_depth: u32,
    /// The contribution threshold (a share of the pixel, 0 = every ray).
    pub min_share: f64,
    /// The sample drawn; `None` follows the selected node's sample.
    pub sample: Option<usize>,
    /// Draw every other sample too, faded by its value ([`crate::diagram::all_samples`]).
    pub all_samples: bool,
    /// Magnification on the automatic framing.
    pub zoom: f64,
    /// Shift from the automatic framing in plane units.
    pub pan: [f64; 2],
    /// Whether exports highlight the selected ray (off: slides without the magenta ray).
    pub export_highlight: bool,
}

impl Default for DiagramView {
    fn default() -> Self {
        let d = DiagramOptions::default();
        Self {
            plane: PlaneChoice::Auto,
            zoom_offsets: false,
            draw_depth: None,
            kinds: [true; RayKind::COUNT],
            label_depth: d.label_depth,
            min_share: MIN_SHARE,
            sample: None,
            all_samples: false,
            zoom: 1.0,
            pan: [0.0, 0.0],
            export_highlight: false,
        }
    }
}

/// The sample holding node `id` (the overlay's rule).
pub(crate) fn sample_of(doc: &Document, id: NodeId) -> Option<usize> {
    let tree = doc.tree.as_ref()?;
    let mut cur = id;
    while let Some(p) = tree.nodes.get(cur.index())?.parent {
        cur = p;
    }
    tree.samples.iter().position(|s| s.root == cur)
}

impl DiagramView {
    /// The sample drawn.
    #[must_use]
    pub fn sample(&self, doc: &Document) -> usize {
        self.sample
            .or_else(|| doc.node.and_then(|id| sample_of(doc, id)))
            .unwrap_or(0)
    }

    /// Library options for `doc` at `size`, the selection highlighted or not.
    #[must_use]
    pub fn options(&self, doc: &Document, size: [u32; 2], highlight: bool) -> DiagramOptions {
        let sample = self.sample(doc);
        let root = doc
            .tree
            .as_ref()
            .and_then(|t| t.samples.get(sample))
            .map_or(NodeId(0), |s| s.root);
        let plane = match self.plane {
            PlaneChoice::Auto => PlaneSpec::Auto,
            PlaneChoice::Incidence => PlaneSpec::Incidence,
            PlaneChoice::Camera => PlaneSpec::Camera,
            PlaneChoice::SelectedRay => PlaneSpec::Ray(doc.node.unwrap_or(root)),
            PlaneChoice::Axis { axis, value } => PlaneSpec::Axis { axis, value },
        };
        DiagramOptions {
            plane,
            width: size[0],
            height: size[1],
            // The panel's draw depth, and no deeper than the step-along-a-ray control shows.
            max_depth: match (self.draw_depth, doc.step.depth) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
            kinds: RayKind::ALL
                .into_iter()
                .zip(self.kinds)
                .filter_map(|(k, on)| on.then_some(k))
                .collect(),
            sample,
            zoom_offsets: self.zoom_offsets,
            highlight: if highlight { doc.node } else { None },
            label_depth: self.label_depth,
            min_share: self.min_share,
            zoom: self.zoom,
            pan: self.pan,
            all_samples: self.all_samples,
            ..DiagramOptions::default()
        }
    }
}

/// The controls above the figure (three rows).
pub(super) fn controls_ui(ui: &mut egui::Ui, doc: &Document, v: &mut DiagramView) {
    ui.horizontal_wrapped(|ui| {
        ui.strong("Diagram");
        ui.separator();
        ui.label("plane");
        ui.radio_value(&mut v.plane, PlaneChoice::Auto, "auto")
            .on_hover_text(
                "plane of incidence, or the plane of a first-bounce ray holding more of the pixel",
            );
        ui.radio_value(&mut v.plane, PlaneChoice::Incidence, "incidence");
        ui.radio_value(&mut v.plane, PlaneChoice::Camera, "camera");
        ui.radio_value(&mut v.plane, PlaneChoice::SelectedRay, "selected ray")
            .on_hover_text("the plane through the selected ray and its parent");
        for (axis, name) in [(0, "x"), (1, "y"), (2, "z")] {
            let value = doc.node.and_then(|id| {
                doc.tree
                    .as_ref()?
                    .node(id)
                    .hit
                    .as_ref()
                    .map(|h| h.point[axis])
            });
            let on = matches!(v.plane, PlaneChoice::Axis { axis: a, .. } if a == axis);
            if ui
                .radio(on, format!("{name} = const"))
                .on_hover_text("through the selected node's hit point")
                .clicked()
            {
                v.plane = PlaneChoice::Axis {
                    axis,
                    value: value.unwrap_or(0.0),
                };
            }
        }
        ui.separator();
        ui.checkbox(&mut v.zoom_offsets, "zoom on spawn points");
    });
    ui.horizontal_wrapped(|ui| {
        // Short sliders: the panel shares its width with the tree.
        ui.spacing_mut().slider_width = 56.0;
        let mut limited = v.draw_depth.is_some();
        ui.checkbox(&mut limited, "limit depth");
        let mut depth = v.draw_depth.unwrap_or(doc.scene.settings.max_depth);
        let r = ui.add_enabled(
            limited,
            egui::Slider::new(&mut depth, 0..=32).text("draw depth"),
        );
        if r.changed() {
            limited = true;
        }
        v.draw_depth = limited.then_some(depth);
        ui.separator();
        for (on, kind) in v.kinds.iter_mut().zip(RayKind::ALL) {
            ui.checkbox(on, kind.name());
        }
    });
    // A row of its own: a slider with its text does not wrap.
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().slider_width = 56.0;
        ui.add(egui::Slider::new(&mut v.label_depth, 0..=16).text("label depth"))
            .on_hover_text("angles, n, R/T and Beer labels on depths up to this one");
        ui.separator();
        let mut pct = v.min_share * 100.0;
        ui.add(egui::Slider::new(&mut pct, 0.0..=20.0).text("min share %"))
            .on_hover_text("leave out rays carrying less of the pixel (0 = all)");
        v.min_share = (pct / 100.0).clamp(0.0, 1.0);
        if let Some(tree) = doc.tree.as_ref().filter(|t| t.samples.len() > 1) {
            ui.separator();
            let mut follow = v.sample.is_none();
            ui.checkbox(&mut follow, "sample of the selection");
            let mut k = v.sample(doc);
            let r = ui.add(egui::Slider::new(&mut k, 0..=tree.samples.len() - 1).text("sample"));
            if r.changed() {
                follow = false;
            }
            v.sample = (!follow).then_some(k);
            ui.checkbox(&mut v.all_samples, "all samples")
                .on_hover_text("draw every sample of the pixel, faded by its value");
        }
        ui.separator();
        ui.checkbox(&mut v.export_highlight, "highlight in exports");
        if (v.zoom != 1.0 || v.pan != [0.0, 0.0]) && ui.button("reset view").clicked() {
            v.zoom = 1.0;
            v.pan = [0.0, 0.0];
        }
    });
}

/// Zoom (scroll, about the cursor), pan (drag) and reset (double-click) on the figure drawn
/// in `area` with `frame`. The new options when they change.
pub(super) fn navigate(
    ui: &egui::Ui,
    response: &egui::Response,
    area: egui::Rect,
    frame: &PlaneFrame,
    v: DiagramView,
) -> Option<DiagramView> {
    let mut out = v;
    if response.double_clicked() {
        out.zoom = 1.0;
        out.pan = [0.0, 0.0];
        return (out != v).then_some(out);
    }
    if response.dragged() {
        let d = response.drag_delta();
        if d != egui::Vec2::ZERO {
            out.pan[0] -= f64::from(d.x) / frame.scale;
            out.pan[1] += f64::from(d.y) / frame.scale;
        }
    }
    let scroll = ui.input(|i| i.smooth_scroll_delta.y);
    if response.hovered()
        && scroll != 0.0
        && let Some(p) = response.hover_pos()
    {
        let f = f64::from((scroll / 200.0).exp()).clamp(0.2, 5.0);
        let zoom = (v.zoom * f).clamp(0.1, 200.0);
        let f = zoom / v.zoom;
        let c = glam::DVec2::new(f64::from(p.x - area.min.x), f64::from(p.y - area.min.y));
        // Keep the plane point under the cursor where it is.
        let q = frame.canvas_to_plane(c);
        let s = frame.scale * f;
        let d = (c - frame.canvas_center) / s;
        let centre = q - glam::DVec2::new(d.x, -d.y);
        let shift = centre - frame.plane_center;
        out.zoom = zoom;
        out.pan[0] += shift.x;
        out.pan[1] += shift.y;
    }
    (out != v && out.pan.iter().all(|x| x.is_finite())).then_some(out)
}
