//! The tree panel (the ray tree as a flat list of visible rows, only the rows on screen laid
//! out), the details pane (every recorded field of the selected node) and the contribution
//! breakdown.

use crate::gui::model::breakdown::{Term, breakdown, pixel_contribution};
use crate::gui::model::document::{Command, Document};
use crate::gui::style::{SELECTED, amount, kind_colour, num, rgb, square, swatch, weight};
use crate::tree::{EndReason, NodeId, RayNode, RayTree};
use egui::text::{LayoutJob, TextWrapping};
use egui::{FontId, Rect, RichText, Sense, pos2, vec2};

/// Trees open by default down to this depth.
const OPEN_DEPTH: u32 = 3;
/// Height of one tree row (points).
const ROW_HEIGHT: f32 = 18.0;
/// Indentation per level (points).
const INDENT: f32 = 14.0;
/// Width of each of the `w=` and `c=` columns (points).
const NUMBER_COLUMN: f32 = 84.0;

/// What a node's ray reached, with its Fresnel split: the start of its tree row.
#[must_use]
pub fn node_name(n: &RayNode) -> String {
    let target = match (&n.hit, &n.shadow) {
        // The light's name as the scene spells it, and how the shadow ray ended in words.
        (_, Some(s)) => format!("{} ({})", s.light_name, shadow_end(n.end)),
        (Some(h), None) => format!("{} t={}", h.object_name, num(h.t)),
        (None, None) => "miss".to_string(),
    };
    let rt = n
        .interface
        .as_ref()
        .map(|i| {
            let roulette = if i.roulette.is_some() {
                " roulette"
            } else {
                ""
            };
            if i.tir {
                "  TIR".to_string()
            } else {
                format!("  R={:.3} T={:.3}{roulette}", i.fresnel.r, i.fresnel.t)
            }
        })
        .unwrap_or_default();
    format!("#{} {} -> {target}{rt}", n.id.0, n.kind.name())
}

/// How a shadow ray ended, in the tree's few words: `unblocked`, `attenuated`, `blocked`,
/// `light behind`.
fn shadow_end(end: EndReason) -> String {
    match end {
        EndReason::LightBehind => "light behind".to_string(),
        e => format!("{e:?}").to_lowercase(),
    }
}

/// The `w=` and `c=` columns: the weight relative to the parent (as `raytree trace` prints it)
/// and the contribution to the pixel ([`pixel_contribution`]), max channel.
#[must_use]
pub fn node_numbers(tree: &RayTree, id: NodeId) -> [String; 2] {
    let n = tree.node(id);
    [
        format!("w={}", weight(n.weight.max_element())),
        format!("c={}", amount(pixel_contribution(tree, id).max_element())),
    ]
}

/// One line describing a node: the label the tree shows (and tests and screen readers query).
#[must_use]
pub fn node_label(tree: &RayTree, id: NodeId) -> String {
    let [w, c] = node_numbers(tree, id);
    format!("{}  {w}  {c}", node_name(tree.node(id)))
}

/// A line of the tree panel.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Row {
    /// A sample's heading (shown when there are several).
    Sample(usize),
    /// A ray.
    Node(NodeId),
}

/// The tree panel's own state: which nodes are open, the visible rows (rebuilt only when the
/// tree or the open set changes), and the breakdown terms of the current tree.
#[derive(Default)]
pub struct TreeView {
    /// Pixel and node count the open flags belong to (kept across re-traces of the same tree).
    shape: Option<([u32; 2], usize)>,
    open: Vec<bool>,
    /// `doc.tree_version` the rows and terms were built for.
    version: Option<u64>,
    rows: Vec<Row>,
    rows_dirty: bool,
    /// The selection last seen: a different one (from the breakdown, the keys, a new pixel) is
    /// revealed: its ancestors opened and the list scrolled to it.
    seen_node: Option<NodeId>,
    reveal: Option<NodeId>,
    /// Rows on screen last frame.
    shown: std::ops::Range<usize>,
    terms: Vec<Term>,
}

impl TreeView {
    /// The breakdown terms of the current tree, largest first.
    pub(super) fn terms(&self) -> &[Term] {
        &self.terms
    }
}

impl TreeView {
    /// Number of rows the tree shows (open levels only).
    #[must_use]
    pub fn row_count(&self) -> usize {
        self.rows.len()
    }

    fn sync(&mut self, doc: &Document) {
        let Some(tree) = &doc.tree else {
            *self = Self::default();
            return;
        };
        // A different tree under the same version would index past its nodes: rebuild then too.
        if self.version != Some(doc.tree_version) || self.open.len() != tree.nodes.len() {
            self.version = Some(doc.tree_version);
            let shape = (tree.pixel, tree.nodes.len());
            if self.shape != Some(shape) {
                self.shape = Some(shape);
                self.open = tree.nodes.iter().map(|n| n.depth < OPEN_DEPTH).collect();
                self.seen_node = None;
            }
            self.terms = breakdown(tree);
            self.rows_dirty = true;
        }
        if doc.node != self.seen_node {
            self.seen_node = doc.node;
            if let Some(id) = doc.node.filter(|id| id.index() < tree.nodes.len()) {
                let mut p = tree.node(id).parent;
                while let Some(a) = p {
                    self.open[a.index()] = true;
                    p = tree.node(a).parent;
                }
                self.reveal = Some(id);
                self.rows_dirty = true;
            }
        }
        if self.rows_dirty {
            self.rows_dirty = false;
            self.rows.clear();
            for (i, s) in tree.samples.iter().enumerate() {
                if tree.samples.len() > 1 {
                    self.rows.push(Row::Sample(i));
                }
                self.push_rows(tree, s.root);
            }
        }
    }

    fn push_rows(&mut self, tree: &RayTree, id: NodeId) {
        self.rows.push(Row::Node(id));
        if self.open[id.index()] {
            for &c in &tree.node(id).children {
                self.push_rows(tree, c);
            }
        }
    }

    /// Open `id` and everything below it.
    pub fn expand_below(&mut self, tree: &RayTree, id: NodeId) {
        for d in tree.depth_first(id) {
            self.open[d.index()] = true;
        }
        self.rows_dirty = true;
    }

    fn collapse_all(&mut self) {
        self.open.iter_mut().for_each(|o| *o = false);
        self.rows_dirty = true;
    }
}

/// The tree of every sample: a header, then one row per visible ray, in a list of fixed height
/// of which only the rows on screen are laid out.
pub fn tree_ui(ui: &mut egui::Ui, doc: &Document, view: &mut TreeView, cmds: &mut Vec<Command>) {
    view.sync(doc);
    let Some(tree) = &doc.tree else {
        ui.label("Click a pixel to trace its ray tree.");
        return;
    };
    header_ui(ui, doc, tree, view);
    view.sync(doc);
    let area = rows_area(ui, view);
    let rows = std::mem::take(&mut view.rows);
    let mut toggled = None;
    area.show_rows(ui, ROW_HEIGHT, rows.len(), |ui, range| {
        view.shown = range.clone();
        for &row in &rows[range] {
            match row {
                Row::Sample(i) => sample_row(ui, tree, i, cmds),
                Row::Node(id) => {
                    if node_row(ui, tree, id, view.open[id.index()], doc.node, cmds) {
                        toggled = Some(id);
                    }
                }
            }
        }
    });
    view.rows = rows;
    if let Some(id) = toggled {
        view.open[id.index()] = !view.open[id.index()];
        view.rows_dirty = true;
    }
    for c in cmds.iter() {
        if let Command::SelectNode(n) = c {
            // Selected here, so already on screen: no scrolling.
            view.seen_node = *n;
        }
    }
}

/// Above the rows: the pixel and its value, the rays by kind, and the expand and collapse
/// buttons.
fn header_ui(ui: &mut egui::Ui, doc: &Document, tree: &RayTree, view: &mut TreeView) {
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("pixel {}, {}", tree.pixel[0], tree.pixel[1])).strong());
        square(ui, swatch(tree.radiance));
        ui.monospace(rgb(tree.radiance));
    });
    let [c, r, t, s, d, l, k] = tree.count_by_kind();
    ui.horizontal(|ui| {
        let optional = |n: usize, what: &str| {
            if n > 0 {
                format!(", {n} {what}")
            } else {
                String::new()
            }
        };
        ui.small(format!(
            "{} rays: {c} camera, {r} reflected, {t} refracted, {s} shadow{}{}{}",
            tree.nodes.len(),
            optional(d, "diffuse"),
            optional(l, "light-path"),
            optional(k, "to the camera"),
        ));
    });
    ui.horizontal(|ui| {
        let below = doc.node.unwrap_or(NodeId(0));
        if ui
            .small_button("expand all below")
            .on_hover_text("open the selected ray and every level under it")
            .clicked()
        {
            view.expand_below(tree, below);
            view.reveal = Some(below);
        }
        if ui.small_button("collapse all").clicked() {
            view.collapse_all();
        }
        ui.small("w: weight from the parent, c: share of the pixel");
    });
}

/// The scrolled list of rows, scrolled to the ray to reveal unless it is already on screen.
fn rows_area(ui: &egui::Ui, view: &mut TreeView) -> egui::ScrollArea {
    let spacing = ui.spacing().item_spacing.y;
    let height = (ui.available_height() * 0.45).max(6.0 * ROW_HEIGHT);
    let mut area = egui::ScrollArea::vertical()
        .id_salt("tree-scroll")
        .auto_shrink([false, false])
        .min_scrolled_height(height)
        .max_height(height);
    if let Some(target) = view.reveal.take()
        && let Some(row) = view.rows.iter().position(|r| *r == Row::Node(target))
    {
        let inside = view.shown.start < row && row + 1 < view.shown.end;
        if !inside {
            let offset = row as f32 * (ROW_HEIGHT + spacing) - height / 3.0;
            area = area.vertical_scroll_offset(offset.max(0.0));
        }
    }
    area
}

/// The row of sample `i` (when the tree has several): a click selects its camera ray.
fn sample_row(ui: &mut egui::Ui, tree: &RayTree, i: usize, cmds: &mut Vec<Command>) {
    let sample = &tree.samples[i];
    let text = format!(
        "sample {} at ({:.3}, {:.3})",
        sample.index, sample.film[0], sample.film[1]
    );
    let resp = ui.add_sized(
        vec2(ui.available_width(), ROW_HEIGHT),
        egui::Button::selectable(false, RichText::new(text).small()),
    );
    if resp.clicked() {
        cmds.push(Command::SelectNode(Some(sample.root)));
    }
}

/// One ray's row: toggle, kind dot, name (cut with an ellipsis when too long), then the `w=`
/// and `c=` columns, right-aligned and never cut. Returns whether the toggle was clicked.
fn node_row(
    ui: &mut egui::Ui,
    tree: &RayTree,
    id: NodeId,
    open: bool,
    selected: Option<NodeId>,
    cmds: &mut Vec<Command>,
) -> bool {
    let n = tree.node(id);
    let (rect, _) = ui.allocate_exact_size(vec2(ui.available_width(), ROW_HEIGHT), Sense::hover());
    let extra = if tree.samples.len() > 1 { 1.0 } else { 0.0 };
    let x0 = rect.left() + (n.depth as f32 + extra) * INDENT;
    let toggle_rect = Rect::from_min_size(pos2(x0, rect.top()), vec2(INDENT, ROW_HEIGHT));
    let body = Rect::from_min_max(pos2(toggle_rect.right(), rect.top()), rect.max);
    let is_sel = selected == Some(id);
    let label = node_label(tree, id);
    let resp = ui.interact(
        body,
        ui.make_persistent_id(("ray-row", id.0)),
        Sense::click(),
    );
    resp.widget_info(|| egui::WidgetInfo::selected(egui::Role::Button, true, is_sel, &label));
    if resp.clicked() {
        cmds.push(Command::SelectNode(Some(id)));
    }
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    if is_sel {
        painter.rect_filled(body, 2.0, visuals.selection.bg_fill.gamma_multiply(0.6));
    } else if resp.hovered() {
        painter.rect_filled(body, 2.0, visuals.widgets.hovered.weak_bg_fill);
    }
    let toggle_clicked = !n.children.is_empty() && toggle_ui(ui, &painter, toggle_rect, id, open);
    painter.circle_filled(
        pos2(body.left() + 5.0, rect.center().y),
        4.5,
        kind_colour(n.kind),
    );
    let text_colour = if is_sel {
        SELECTED
    } else {
        visuals.text_color()
    };
    paint_row_text(&painter, rect, body.left() + 14.0, tree, id, text_colour);
    toggle_clicked
}

/// The open/close triangle of ray `id` in `toggle_rect` (`open`: pointing down); whether it
/// was clicked.
fn toggle_ui(
    ui: &egui::Ui,
    painter: &egui::Painter,
    toggle_rect: Rect,
    id: NodeId,
    open: bool,
) -> bool {
    let visuals = ui.visuals();
    let t = ui.interact(
        toggle_rect,
        ui.make_persistent_id(("ray-toggle", id.0)),
        Sense::click(),
    );
    t.widget_info(|| {
        let what = if open { "collapse" } else { "expand" };
        egui::WidgetInfo::labeled(egui::Role::Button, true, format!("{what} #{}", id.0))
    });
    let toggle_clicked = t.clicked();
    let c = toggle_rect.center();
    let colour = if t.hovered() {
        visuals.strong_text_color()
    } else {
        visuals.text_color()
    };
    let pts = if open {
        vec![
            c + vec2(-4.0, -2.5),
            c + vec2(4.0, -2.5),
            c + vec2(0.0, 3.5),
        ]
    } else {
        vec![
            c + vec2(-2.5, -4.0),
            c + vec2(3.5, 0.0),
            c + vec2(-2.5, 4.0),
        ]
    };
    painter.add(egui::Shape::convex_polygon(pts, colour, egui::Stroke::NONE));
    toggle_clicked
}

/// The text of ray `id`'s row in `rect`: the `w=` and `c=` columns at the right, its name from
/// `name_left`, cut to the room left.
fn paint_row_text(
    painter: &egui::Painter,
    rect: Rect,
    name_left: f32,
    tree: &RayTree,
    id: NodeId,
    text_colour: egui::Color32,
) {
    let font = FontId::monospace(12.0);
    let [w, c] = node_numbers(tree, id);
    let right = rect.right() - 4.0;
    for (text, x) in [(c, right), (w, right - NUMBER_COLUMN)] {
        painter.text(
            pos2(x, rect.center().y),
            egui::Align2::RIGHT_CENTER,
            text,
            font.clone(),
            text_colour,
        );
    }
    let name_width = (right - 2.0 * NUMBER_COLUMN - name_left).max(8.0);
    let mut job = LayoutJob::simple_singleline(node_name(tree.node(id)), font, text_colour);
    job.wrap = TextWrapping::truncate_at_width(name_width);
    let galley = painter.layout_job(job);
    let y = rect.center().y - galley.size().y / 2.0;
    painter.galley(pos2(name_left, y), galley, text_colour);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    /// A shadow ray's line keeps the light's name as the scene spells it and says how the ray
    /// ended in words (it once lowercased both: "key light (lightbehind)").
    #[test]
    fn shadow_lines_keep_the_light_name_and_say_how_they_ended() {
        let scene = Scene::from_json(
            r#"{"camera": {"position": [0, 2, 4], "look_at": [0, 0, 0], "fov_y": 40,
                "width": 8, "height": 6},
              "materials": {"m": {"diffuse": [0.5, 0.5, 0.5]}},
              "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
                "material": "m"}],
              "lights": [
                {"type": "point", "name": "Key Light", "position": [0, 5, 0],
                  "intensity": [10, 10, 10]},
                {"type": "point", "name": "Under Lamp", "position": [0, -5, 0],
                  "intensity": [10, 10, 10]}]}"#,
        )
        .unwrap();
        let tree = crate::render::trace_pixel(&scene, 4, 4).unwrap();
        let names: Vec<String> = tree.nodes.iter().map(node_name).collect();
        assert!(
            names
                .iter()
                .any(|n| n.ends_with("-> Key Light (unblocked)")),
            "{names:?}"
        );
        assert!(
            names
                .iter()
                .any(|n| n.ends_with("-> Under Lamp (light behind)")),
            "{names:?}"
        );
    }
}
