//! Pin and compare (issue 17): pin the selected pixel's tree, change any setting or pick another
//! pixel, and see the pinned and the current tree side by side in a window, matched row by row
//! as `raytree diff` matches them ([`crate::analysis::diff`]), the first divergent pair
//! highlighted, every changed pair marked with its count of changed fields, and the changed
//! numbers of the chosen pair listed `pinned -> current`.

use super::tree::{node_name, node_numbers};
use crate::analysis::diff::align::{AlignedRow, align};
use crate::analysis::diff::{TreeDiff, diff};
use crate::gui::model::document::{Command, Document, tree_label};
use crate::gui::style::{SELECTED, WARNING, kind_colour};
use crate::tree::{NodeId, RayTree};
use egui::text::{LayoutJob, TextWrapping};
use egui::{Color32, FontId, RichText, Sense, pos2, vec2};
use std::collections::HashMap;

const ROW_HEIGHT: f32 = 18.0;
const INDENT: f32 = 12.0;
/// Background of a changed pair.
const CHANGED_BG: Color32 = Color32::from_rgba_premultiplied(48, 36, 6, 48);
/// Background of a ray only one tree has.
const ONLY_BG: Color32 = Color32::from_rgba_premultiplied(20, 32, 64, 64);
/// Background of the first divergent pair.
const FIRST_BG: Color32 = Color32::from_rgba_premultiplied(96, 20, 72, 112);

/// The comparison of the pinned and the current tree, rebuilt when either changes.
#[derive(Default)]
pub struct CompareView {
    key: Option<(u64, u64)>,
    diff: Option<TreeDiff>,
    rows: Vec<AlignedRow>,
    /// Index into `diff.changed` of each changed pair.
    changes: HashMap<(NodeId, NodeId), usize>,
    first_row: Option<usize>,
    selected: Option<usize>,
    scroll_to: Option<usize>,
}

impl CompareView {
    /// The difference shown (for tests).
    #[must_use]
    pub fn diff(&self) -> Option<&TreeDiff> {
        self.diff.as_ref()
    }

    fn sync(&mut self, doc: &Document) {
        let (Some(pin), Some(tree)) = (&doc.pin, &doc.tree) else {
            *self = Self::default();
            return;
        };
        let key = (doc.tree_version, pin.version);
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        let d = diff(&pin.tree, tree);
        self.rows = align(&pin.tree, tree);
        self.changes = d
            .changed
            .iter()
            .enumerate()
            .map(|(i, c)| ((c.a, c.b), i))
            .collect();
        self.first_row = d.first_divergence.as_ref().and_then(|f| {
            self.rows
                .iter()
                .position(|r| r.a == Some(f.a) && r.b == Some(f.b))
        });
        self.selected = self.first_row;
        self.scroll_to = self.first_row;
        self.diff = Some(d);
    }

    fn change_of(&self, r: &AlignedRow) -> Option<usize> {
        self.changes.get(&(r.a?, r.b?)).copied()
    }
}

/// The pin button (or what is pinned, with re-pin and unpin), above the tree.
pub fn pin_bar(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    ui.horizontal_wrapped(|ui| match &doc.pin {
        None => {
            let resp = ui
                .add_enabled(doc.tree.is_some(), egui::Button::new("pin this tree"))
                .on_hover_text("keep this tree; change settings or pixel to compare");
            if resp.clicked() {
                cmds.push(Command::Pin);
            }
        }
        Some(p) => {
            ui.small(format!("pinned: {}", p.label));
            if ui.small_button("re-pin").clicked() {
                cmds.push(Command::Pin);
            }
            if ui.small_button("unpin").clicked() {
                cmds.push(Command::Unpin);
            }
        }
    });
}

/// The comparison window, open while a tree is pinned (closing it unpins).
pub fn compare_window(
    ctx: &egui::Context,
    doc: &Document,
    view: &mut CompareView,
    cmds: &mut Vec<Command>,
) {
    view.sync(doc);
    let Some(pin) = &doc.pin else { return };
    let mut open = true;
    egui::Window::new("Pin and compare")
        .open(&mut open)
        // Over the image, clear of the side panels at their default widths.
        .default_pos(pos2(320.0, 40.0))
        .default_size(vec2(700.0, 520.0))
        .max_width(960.0)
        .max_height(800.0)
        .resizable(true)
        .show(ctx, |ui| {
            ui.small(format!("pinned:  {}", pin.label));
            let Some(tree) = &doc.tree else {
                ui.label("Click a pixel to compare it with the pinned tree.");
                return;
            };
            ui.small(format!(
                "current: {}",
                tree_label(&doc.source.label(), tree)
            ));
            summary_ui(ui, view);
            ui.separator();
            rows_ui(ui, doc, view, &pin.tree, tree, cmds);
            ui.separator();
            fields_ui(ui, view, &pin.tree, tree);
        });
    if !open {
        cmds.push(Command::Unpin);
    }
}

fn summary_ui(ui: &mut egui::Ui, view: &mut CompareView) {
    let Some(d) = &view.diff else { return };
    for f in &d.settings {
        ui.monospace(format!(
            "{}: {} -> {}",
            f.field,
            value_text(&f.a),
            value_text(&f.b)
        ));
    }
    if d.trees_equal() {
        ui.label(format!(
            "no difference: the trees are identical ({} rays matched)",
            d.matched
        ));
    } else {
        if let Some(f) = &d.first_divergence {
            let text = format!(
                "first divergence: {} {} (level {}): {} field{} changed",
                f.kind.name(),
                pair_ids(f.a, f.b),
                f.level,
                f.fields.len(),
                if f.fields.len() == 1 { "" } else { "s" }
            );
            if ui
                .add(egui::Button::selectable(
                    view.selected == view.first_row,
                    RichText::new(text).color(SELECTED),
                ))
                .clicked()
            {
                view.selected = view.first_row;
                view.scroll_to = view.first_row;
            }
        }
        ui.label(format!(
            "changed rays: {} of {} matched; only pinned: {} rays, only current: {} rays",
            d.changed.len(),
            d.matched,
            view.rows.iter().filter(|r| r.b.is_none()).count(),
            view.rows.iter().filter(|r| r.a.is_none()).count(),
        ));
    }
    ui.monospace(format!(
        "pixel pinned {}  current {}  difference {}",
        rgb6(d.radiance_a),
        rgb6(d.radiance_b),
        rgb6(d.difference)
    ));
}

fn pair_ids(a: NodeId, b: NodeId) -> String {
    if a == b {
        format!("#{}", a.0)
    } else {
        format!("#{} / #{}", a.0, b.0)
    }
}

fn rgb6(c: crate::math::Rgb) -> String {
    format!("[{:.6}, {:.6}, {:.6}]", c.x, c.y, c.z)
}

/// One side's text of a row: name, weight and share of the pixel.
fn side_text(t: &RayTree, id: Option<NodeId>) -> String {
    id.map_or(String::new(), |id| {
        let [w, c] = node_numbers(t, id);
        format!("{}  {w}  {c}", node_name(t.node(id)))
    })
}

fn rows_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    view: &mut CompareView,
    a: &RayTree,
    b: &RayTree,
    cmds: &mut Vec<Command>,
) {
    ui.columns(2, |c| {
        c[0].strong("pinned");
        c[1].strong("current");
    });
    let spacing = ui.spacing().item_spacing.y;
    let height = (ui.available_height() * 0.55).max(8.0 * ROW_HEIGHT);
    let mut area = egui::ScrollArea::vertical()
        .id_salt("compare-rows")
        .auto_shrink([false, false])
        .max_height(height);
    if let Some(row) = view.scroll_to.take() {
        let offset = row as f32 * (ROW_HEIGHT + spacing) - height / 3.0;
        area = area.vertical_scroll_offset(offset.max(0.0));
    }
    let rows = Rows {
        view,
        trees: [a, b],
        selected_node: doc.node,
    };
    let mut clicked = None;
    area.show_rows(ui, ROW_HEIGHT, rows.view.rows.len(), |ui, range| {
        for i in range {
            if row_ui(ui, &rows, i) {
                clicked = Some(i);
            }
        }
    });
    if let Some(i) = clicked {
        view.selected = Some(i);
        if let Some(id) = view.rows[i].b {
            cmds.push(Command::SelectNode(Some(id)));
        }
    }
}

/// What every row of the comparison is drawn from.
struct Rows<'a> {
    view: &'a CompareView,
    /// The pinned and the current tree.
    trees: [&'a RayTree; 2],
    /// The current tree's selected node.
    selected_node: Option<NodeId>,
}

/// Row `i`: both sides, its status for accessibility, its background and its count of changed
/// fields. Whether it was clicked.
fn row_ui(ui: &mut egui::Ui, rows: &Rows, i: usize) -> bool {
    let view = rows.view;
    let r = view.rows[i];
    let change = view.change_of(&r);
    let (rect, _) = ui.allocate_exact_size(vec2(ui.available_width(), ROW_HEIGHT), Sense::hover());
    let [a, b] = rows.trees;
    let (ta, tb) = (side_text(a, r.a), side_text(b, r.b));
    let fields = change.map_or(0, |k| {
        view.diff.as_ref().map_or(0, |d| d.changed[k].fields.len())
    });
    let first = Some(i) == view.first_row;
    let status = match (r.a, r.b) {
        _ if first => format!("first divergence, {fields} changed"),
        (Some(_), None) => "only pinned".to_string(),
        (None, Some(_)) => "only current".to_string(),
        _ if fields > 0 => format!("{fields} changed"),
        _ => "same".to_string(),
    };
    let resp = ui.interact(
        rect,
        ui.make_persistent_id(("compare-row", i)),
        Sense::click(),
    );
    let label = format!("{ta} | {tb} [{status}]");
    let is_sel = view.selected == Some(i);
    resp.widget_info(|| egui::WidgetInfo::selected(egui::Role::Button, true, is_sel, &label));
    let painter = ui.painter_at(rect);
    let bg = if first {
        Some(FIRST_BG)
    } else if r.a.is_none() || r.b.is_none() {
        Some(ONLY_BG)
    } else if fields > 0 {
        Some(CHANGED_BG)
    } else {
        None
    };
    if let Some(bg) = bg {
        painter.rect_filled(rect, 2.0, bg);
    }
    if is_sel {
        painter.rect_stroke(
            rect,
            2.0,
            egui::Stroke::new(1.5, SELECTED),
            egui::StrokeKind::Inside,
        );
    }
    paint_sides(ui, &painter, rect, rows, &r, [ta, tb]);
    if fields > 0 {
        let half = rect.width() / 2.0;
        painter.text(
            pos2(rect.left() + half - 4.0, rect.center().y),
            egui::Align2::RIGHT_CENTER,
            format!("Δ{fields}"),
            FontId::monospace(11.5),
            WARNING,
        );
    }
    resp.clicked()
}

/// The two halves of row `r` at `rect`: each side's ray, a dot of its kind's colour at its
/// depth and its text `texts`, truncated.
fn paint_sides(
    ui: &egui::Ui,
    painter: &egui::Painter,
    rect: egui::Rect,
    rows: &Rows,
    r: &AlignedRow,
    texts: [String; 2],
) {
    let half = rect.width() / 2.0;
    let font = FontId::monospace(11.5);
    let text_colour = ui.visuals().text_color();
    let [a, b] = rows.trees;
    let [ta, tb] = texts;
    for (side, (t, id, text)) in [(a, r.a, ta), (b, r.b, tb)].into_iter().enumerate() {
        let Some(id) = id else { continue };
        let x0 = rect.left() + side as f32 * half + 4.0 + r.depth as f32 * INDENT;
        painter.circle_filled(
            pos2(x0 + 4.0, rect.center().y),
            4.0,
            kind_colour(t.node(id).kind),
        );
        let colour = if side == 1 && rows.selected_node == Some(id) {
            SELECTED
        } else {
            text_colour
        };
        // Room for the Δ count at the end of the pinned side.
        let width = (rect.left() + (side as f32 + 1.0) * half - x0 - 48.0).max(8.0);
        let mut job = LayoutJob::simple_singleline(text, font.clone(), colour);
        job.wrap = TextWrapping::truncate_at_width(width);
        let g = painter.layout_job(job);
        painter.galley(
            pos2(x0 + 12.0, rect.center().y - g.size().y / 2.0),
            g,
            colour,
        );
    }
}

mod fields;
use fields::{fields_ui, value_text};
