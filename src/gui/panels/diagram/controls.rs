//! The diagram panel's controls over the document's [`DiagramView`]: plane (automatic,
//! incidence, camera, through the selected ray, axis planes), draw depth, ray kinds, label
//! depth, contribution threshold, sample, spawn-point insets, whether exports highlight the
//! selection; zoom about the cursor and pan by dragging.

use crate::diagram::PlaneFrame;
use crate::gui::model::diagram_view::{DiagramView, PlaneChoice};
use crate::gui::model::document::Document;
use crate::tree::RayKind;

/// The controls above the figure (three rows).
pub(super) fn controls_ui(ui: &mut egui::Ui, doc: &Document, v: &mut DiagramView) {
    ui.horizontal_wrapped(|ui| plane_row(ui, doc, v));
    ui.horizontal_wrapped(|ui| depth_row(ui, doc, v));
    // A row of its own: a slider with its text does not wrap.
    ui.horizontal_wrapped(|ui| labels_row(ui, doc, v));
}

/// The first row: the plane (automatic, incidence, camera, selected ray, an axis plane through
/// the selected hit) and the spawn-point insets.
fn plane_row(ui: &mut egui::Ui, doc: &Document, v: &mut DiagramView) {
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
}

/// The second row: the draw depth and the ray kinds drawn.
fn depth_row(ui: &mut egui::Ui, doc: &Document, v: &mut DiagramView) {
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
}

/// The third row: label depth, contribution threshold, the sample, exports' highlight and the
/// view's reset.
fn labels_row(ui: &mut egui::Ui, doc: &Document, v: &mut DiagramView) {
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
