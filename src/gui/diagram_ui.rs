//! The diagram panel: the selected pixel's cross-section (from [`crate::diagram`]) painted with
//! egui's painter, the selected node highlighted, with a plane choice and spawn-point insets.

use super::document::{Command, Document};
use crate::diagram::model::Anchor;
use crate::diagram::paint::{Prim, Rgba};
use crate::diagram::{Diagram, DiagramOptions, PlaneSpec, Style, Theme, display_list};
use crate::tree::NodeId;
use egui::{Align2, Color32, FontId, Pos2, Shape, Stroke, pos2};

/// What a cached display list was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    tree_version: u64,
    node: Option<NodeId>,
    plane: PlaneSpec,
    zoom_offsets: bool,
    size: [u32; 2],
}

/// The last diagram built, reused while nothing it depends on changes.
pub struct DiagramCache {
    key: Option<Key>,
    prims: Result<Vec<Prim>, String>,
}

impl Default for DiagramCache {
    fn default() -> Self {
        Self {
            key: None,
            prims: Ok(Vec::new()),
        }
    }
}

/// Diagram options for the document's selection at `size` pixels.
#[must_use]
pub fn diagram_options(doc: &Document, size: [u32; 2]) -> DiagramOptions {
    DiagramOptions {
        plane: doc.view.plane,
        width: size[0],
        height: size[1],
        zoom_offsets: doc.view.zoom_offsets,
        highlight: doc.node,
        ..DiagramOptions::default()
    }
}

/// Build the display list of the selected pixel's diagram (what the panel paints).
pub fn build_display_list(doc: &Document, size: [u32; 2]) -> Result<Vec<Prim>, String> {
    let tree = doc.tree.as_ref().ok_or("select a pixel")?;
    let d =
        Diagram::build(&doc.scene, tree, &diagram_options(doc, size)).map_err(|e| e.to_string())?;
    Ok(display_list(&d, &Style::new(Theme::Dark)))
}

/// Plane choice, insets toggle and the painted diagram.
pub fn diagram_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    cache: &mut DiagramCache,
    cmds: &mut Vec<Command>,
) {
    let mut v = doc.view;
    ui.horizontal(|ui| {
        ui.strong("Diagram");
        ui.separator();
        ui.label("plane");
        ui.radio_value(&mut v.plane, PlaneSpec::Incidence, "incidence");
        ui.radio_value(&mut v.plane, PlaneSpec::Camera, "camera");
        for (axis, name) in [(0, "x"), (1, "y"), (2, "z")] {
            let value = doc.node.and_then(|id| {
                doc.tree
                    .as_ref()?
                    .node(id)
                    .hit
                    .as_ref()
                    .map(|h| h.point[axis])
            });
            let spec = PlaneSpec::Axis {
                axis,
                value: value.unwrap_or(0.0),
            };
            let on = matches!(v.plane, PlaneSpec::Axis { axis: a, .. } if a == axis);
            if ui
                .radio(on, format!("{name} = const"))
                .on_hover_text("through the selected node's hit point")
                .clicked()
            {
                v.plane = spec;
            }
        }
        ui.separator();
        ui.checkbox(&mut v.zoom_offsets, "zoom on spawn points");
    });
    if v != doc.view {
        cmds.push(Command::SetView(v));
    }
    if doc.tree.is_none() {
        ui.label("Select a pixel to see its diagram.");
        // Fill the panel: egui keeps a bottom panel's height from its content, so a panel
        // holding one line would stay one line tall once a diagram arrives.
        ui.allocate_space(ui.available_size());
        return;
    }
    let area = ui.available_rect_before_wrap();
    let size = [
        area.width().max(64.0) as u32,
        area.height().max(64.0) as u32,
    ];
    let key = Key {
        tree_version: doc.tree_version,
        node: doc.node,
        plane: doc.view.plane,
        zoom_offsets: doc.view.zoom_offsets,
        size,
    };
    if cache.key != Some(key) {
        cache.key = Some(key);
        cache.prims = build_display_list(doc, size);
    }
    ui.allocate_rect(area, egui::Sense::hover());
    let painter = ui.painter_at(area);
    match &cache.prims {
        Ok(prims) => paint(&painter, area.min, prims),
        Err(e) => {
            painter.text(
                area.center(),
                Align2::CENTER_CENTER,
                e,
                FontId::proportional(14.0),
                Color32::LIGHT_RED,
            );
        }
    }
}

fn colour(c: Rgba) -> Color32 {
    Color32::from_rgba_unmultiplied(c.0, c.1, c.2, c.3)
}

/// Paint a display list with its canvas origin at `origin` (one canvas pixel = one point).
pub fn paint(painter: &egui::Painter, origin: Pos2, prims: &[Prim]) {
    let at = |p: glam::DVec2| pos2(origin.x + p.x as f32, origin.y + p.y as f32);
    for prim in prims {
        match prim {
            Prim::Fill { points, color } => {
                let pts = points.iter().map(|p| at(*p)).collect();
                painter.add(Shape::convex_polygon(pts, colour(*color), Stroke::NONE));
            }
            Prim::Stroke {
                points,
                color,
                width,
                dash,
                closed,
            } => {
                let mut pts: Vec<Pos2> = points.iter().map(|p| at(*p)).collect();
                if *closed && let Some(first) = pts.first().copied() {
                    pts.push(first);
                }
                let stroke = Stroke::new(*width as f32, colour(*color));
                match dash {
                    Some([d, g]) => {
                        painter.extend(Shape::dashed_line(&pts, stroke, *d as f32, *g as f32))
                    }
                    None => {
                        painter.add(Shape::line(pts, stroke));
                    }
                }
            }
            Prim::Circle {
                center,
                radius,
                fill,
                stroke,
            } => {
                let s = stroke.map_or(Stroke::NONE, |(c, w)| Stroke::new(w as f32, colour(c)));
                let f = fill.map_or(Color32::TRANSPARENT, colour);
                painter.add(Shape::circle_filled(at(*center), *radius as f32, f));
                painter.add(Shape::circle_stroke(at(*center), *radius as f32, s));
            }
            Prim::Text {
                pos,
                text,
                size,
                color,
                anchor,
                ..
            } => {
                let align = match anchor {
                    Anchor::Start => Align2::LEFT_BOTTOM,
                    Anchor::Middle => Align2::CENTER_BOTTOM,
                    Anchor::End => Align2::RIGHT_BOTTOM,
                };
                // The baseline is a little above the bottom of egui's text box.
                let p = at(*pos) + egui::vec2(0.0, *size as f32 * 0.22);
                painter.text(
                    p,
                    align,
                    text,
                    FontId::proportional(*size as f32),
                    colour(*color),
                );
            }
        }
    }
}
