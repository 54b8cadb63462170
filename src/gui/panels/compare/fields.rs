//! The compare window's lower part: the changed fields of the chosen pair, pinned -> current.

use super::{CompareView, pair_ids, side_text};
use crate::analysis::diff::FieldChange;
use crate::gui::style::WARNING;
use crate::tree::RayTree;
use egui::RichText;
use serde_json::Value;

/// The changed fields of the chosen pair: field, pinned, current, and for numbers the change.
pub(super) fn fields_ui(ui: &mut egui::Ui, view: &CompareView, a: &RayTree, b: &RayTree) {
    let Some(r) = view.selected.and_then(|i| view.rows.get(i)) else {
        ui.small("Click a row to see what changed in it.");
        return;
    };
    let fields: &[FieldChange] = match (view.change_of(r), &view.diff) {
        (Some(k), Some(d)) => &d.changed[k].fields,
        _ => &[],
    };
    match (r.a, r.b) {
        (Some(x), None) => {
            ui.label(format!(
                "only in the pinned tree: {} (subtree of {} rays)",
                side_text(a, Some(x)),
                a.depth_first(x).len()
            ));
        }
        (None, Some(y)) => {
            ui.label(format!(
                "only in the current tree: {} (subtree of {} rays)",
                side_text(b, Some(y)),
                b.depth_first(y).len()
            ));
        }
        (Some(x), Some(y)) if fields.is_empty() => {
            ui.label(format!("{}: no field changed", pair_ids(x, y)));
        }
        (Some(x), Some(y)) => {
            ui.label(format!(
                "{} {}: {} changed field{}",
                a.node(x).kind.name(),
                pair_ids(x, y),
                fields.len(),
                if fields.len() == 1 { "" } else { "s" }
            ));
            egui::ScrollArea::vertical()
                .id_salt("compare-fields")
                .show(ui, |ui| {
                    egui::Grid::new("compare-fields-grid")
                        .striped(true)
                        .num_columns(4)
                        .max_col_width(260.0)
                        .show(ui, |ui| {
                            ui.strong("field");
                            ui.strong("pinned");
                            ui.strong("current");
                            ui.strong("current - pinned");
                            ui.end_row();
                            for f in fields {
                                ui.monospace(&f.field);
                                ui.monospace(value_text(&f.a));
                                ui.label(
                                    RichText::new(value_text(&f.b)).monospace().color(WARNING),
                                );
                                match (f.a.as_f64(), f.b.as_f64()) {
                                    (Some(x), Some(y)) => ui.monospace(format!("{:+.3e}", y - x)),
                                    _ => ui.label(""),
                                };
                                ui.end_row();
                            }
                        });
                });
        }
        (None, None) => {}
    }
}

/// A JSON leaf as text: strings bare, `null` as "none", numbers to 6 significant digits.
pub(super) fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => "none".into(),
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() && (x == 0.0 || (1e-3..1e5).contains(&x.abs())) => {
                format!("{x:.6}")
            }
            Some(x) if n.is_f64() => format!("{x:.4e}"),
            _ => n.to_string(),
        },
        v => v.to_string(),
    }
}
