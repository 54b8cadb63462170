//! Step along a ray (issue 17, the lecture's interactive figure): `R(t) = A + t d` with a slider
//! for `t` moves a point along the selected ray, in this panel's numbers, on the image overlay
//! and in the diagram; at `t_hit` the panel gives the normal and the angles
//! ([`crate::analysis::teach`]). A step control shows the recursion one depth at a time (the
//! overlay and the diagram draw rays down to that depth only).

use crate::analysis::teach;
use crate::gui::model::document::{Command, Document, Step};
use crate::gui::style::{SELECTED, num, vec3};
use crate::tree::{RayNode, RayTree};
use egui::{Color32, Pos2, RichText, Slider, Stroke, pos2};
use glam::DVec3;

/// The range of `t` of a miss: as far as the tree's longest hit, at least 1.
fn miss_length(tree: &RayTree) -> f64 {
    tree.nodes
        .iter()
        .filter_map(|n| n.hit.as_ref().map(|h| h.t))
        .filter(|t| t.is_finite())
        .fold(1.0, f64::max)
}

/// The point the slider stands at on the selected ray, its `t` and the ray's `t` range.
#[must_use]
pub fn step_point(doc: &Document) -> Option<(DVec3, f64, f64)> {
    let at = doc.step.at?;
    let tree = doc.tree.as_ref()?;
    let n = tree.nodes.get(doc.node?.index())?;
    let end = teach::t_end(n, miss_length(tree));
    let t = at.clamp(0.0, 1.0) * end;
    let p = teach::point_at(n, t);
    p.is_finite().then_some((p, t, end))
}

/// Whether the point stands at the ray's hit (the slider at its end, the ray hit something).
fn at_hit(at: Option<f64>, n: &RayNode) -> bool {
    at.is_some_and(|a| a >= 1.0) && n.hit.is_some()
}

/// The panel: the formula, the `t` slider and the point, the hit's normal and angles, and the
/// recursion step control.
pub fn step_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let old = doc.step;
    let mut step = old;
    let (Some(tree), Some(id)) = (&doc.tree, doc.node) else {
        ui.label("Select a ray to step along it.");
        return;
    };
    let Some(n) = tree.nodes.get(id.index()) else {
        return;
    };
    ui.label(
        RichText::new(
            "R(t) = A + t d   (A: origin, d: unit direction; the lecture's A + (P - A) t)",
        )
        .monospace(),
    );
    let mut on = step.at.is_some();
    ui.checkbox(&mut on, "show the point on the overlay and the diagram");
    let end = teach::t_end(n, miss_length(tree));
    let mut t = step.at.unwrap_or(1.0).clamp(0.0, 1.0) * end;
    ui.spacing_mut().slider_width = (ui.available_width() - 110.0).max(80.0);
    let resp = ui.add_enabled(
        on,
        Slider::new(&mut t, 0.0..=end)
            .text("t")
            .custom_formatter(|v, _| num(v)),
    );
    step.at = on.then(|| if end > 0.0 { t / end } else { 1.0 });
    if resp.changed() && end > 0.0 {
        step.at = Some(t / end);
    }
    numbers_ui(ui, n, t);
    if at_hit(step.at, n) {
        hit_ui(ui, n);
    }
    ui.separator();
    recursion_ui(ui, tree, &mut step);
    if step != old {
        cmds.push(Command::SetStep(step));
    }
}

/// The formula's numbers at `t` on ray `n`, and where the ray ends.
fn numbers_ui(ui: &mut egui::Ui, n: &RayNode, t: f64) {
    egui::Grid::new("step-grid")
        .num_columns(2)
        .min_col_width(90.0)
        .striped(true)
        .show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.add(egui::Label::new(RichText::new(v).monospace()).wrap());
                ui.end_row();
            };
            row("A (origin)", vec3(n.origin));
            row("d (direction)", vec3(n.direction));
            row("t", num(t));
            row("R(t)", vec3(teach::point_at(n, t)));
            match (&n.hit, &n.shadow) {
                (Some(h), _) => row("t_hit", format!("{} ({})", num(h.t), h.object_name)),
                (None, Some(s)) => row("light at t", num(s.distance)),
                (None, None) => row("t_hit", "none: the ray misses".into()),
            }
        });
}

/// At the hit: the normal, the angle of incidence and the interface's angles.
fn hit_ui(ui: &mut egui::Ui, n: &RayNode) {
    if let Some(h) = &n.hit {
        ui.label(RichText::new("at t_hit").strong().color(SELECTED));
        ui.monospace(format!("N = {}", vec3(h.normal)));
        ui.monospace(format!(
            "cos_i {} (theta_i {:.2} deg)",
            num(h.cos_i),
            teach::deg(h.cos_i)
        ));
        if let Some(i) = &n.interface {
            ui.add(egui::Label::new(RichText::new(teach::incidence_text(i)).monospace()).wrap());
        }
    }
}

/// The recursion step control: back, step, all, and the depths shown.
fn recursion_ui(ui: &mut egui::Ui, tree: &RayTree, step: &mut Step) {
    let max = tree.nodes.iter().map(|n| n.depth).max().unwrap_or(0);
    ui.horizontal_wrapped(|ui| {
        ui.label("recursion");
        if ui.small_button("< back").clicked() {
            step.depth = Some(step.depth.unwrap_or(max).saturating_sub(1));
        }
        if ui.small_button("step >").clicked() {
            step.depth = match step.depth {
                None => Some(0),
                Some(d) if d >= max => None,
                Some(d) => Some(d + 1),
            };
        }
        if ui.small_button("all").clicked() {
            step.depth = None;
        }
        ui.label(match step.depth {
            Some(d) => format!("depth 0..={d} of {max} shown"),
            None => format!("all {} depths shown", max + 1),
        });
    });
}

/// The marker: a ring at the point, and at a hit a short line along the normal.
fn marker(painter: &egui::Painter, p: Pos2, normal_end: Option<Pos2>) {
    if let Some(q) = normal_end {
        painter.line_segment([p, q], Stroke::new(3.0, Color32::BLACK));
        painter.line_segment([p, q], Stroke::new(1.5, Color32::from_rgb(120, 255, 140)));
    }
    painter.circle_filled(p, 5.0, Color32::BLACK);
    painter.circle_filled(p, 3.5, SELECTED);
    painter.circle_stroke(p, 7.0, Stroke::new(1.5, Color32::WHITE));
}

/// The normal to draw at the point, when it stands at a hit: from the point, a third of the
/// ray's `t` range long.
fn normal_segment(doc: &Document, p: DVec3, end: f64) -> Option<(DVec3, DVec3)> {
    let n = doc.tree.as_ref()?.nodes.get(doc.node?.index())?;
    if !at_hit(doc.step.at, n) {
        return None;
    }
    let h = n.hit.as_ref()?;
    Some((p, p + h.normal * (end / 3.0).min(1.0)))
}

/// Draw the step point on the image overlay (`to_screen` maps film pixels to the screen).
pub fn paint_on_image(
    painter: &egui::Painter,
    doc: &Document,
    to_screen: impl Fn([f64; 2]) -> Pos2,
) {
    let Some((p, _, end)) = step_point(doc) else {
        return;
    };
    let cam = &doc.scene.camera;
    let Some(at) = crate::gui::model::project::film_from_world(cam, p) else {
        return;
    };
    let normal = normal_segment(doc, p, end)
        .and_then(|(a, b)| crate::gui::model::project::film_segment(cam, a, b))
        .map(|s| to_screen(s[1]));
    marker(painter, to_screen(at), normal);
}

/// Draw the step point on the diagram whose canvas origin is at `origin` on screen.
pub fn paint_on_diagram(
    painter: &egui::Painter,
    doc: &Document,
    frame: &crate::diagram::PlaneFrame,
    origin: Pos2,
) {
    let Some((p, _, end)) = step_point(doc) else {
        return;
    };
    let at = |w: DVec3| {
        let c = frame.to_canvas(w);
        pos2(origin.x + c.x as f32, origin.y + c.y as f32)
    };
    let normal = normal_segment(doc, p, end).map(|(_, b)| at(b));
    marker(painter, at(p), normal);
}
