//! The "Samples" section of the right panel: the LPE filter field, a histogram of the pixel's
//! sample values on a log scale (click a bar to list only its samples), the firefly
//! explanation of the selected sample, and the sample list sorted by value (click a row to
//! select that sample's path in the tree, the overlay and the diagram).

mod histogram;

use crate::analysis::firefly::{self, Firefly};
use crate::analysis::samples::{Histogram, SampleRow, histogram, sample_rows};
use crate::gui::model::document::{Command, Document};
use crate::gui::style::{ERROR, SELECTED, WARNING, rgb, square, swatch};
use egui::RichText;

/// Least height of one row of the sample list (a row is as tall as a button of the style).
const ROW_HEIGHT: f32 = 18.0;
/// Rows of the list shown before it scrolls.
const ROWS_SHOWN: usize = 8;

/// A histogram bar chosen by a click: the list shows only its samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bar {
    /// Bar `k` of [`Histogram::bins`].
    Bin(usize),
    /// The samples of value 0.
    Zero,
    /// The non-finite samples.
    NonFinite,
}

/// The section's own state: rows and histogram of the current tree, and the chosen bar.
#[derive(Default)]
pub struct SamplesView {
    version: Option<u64>,
    rows: Vec<SampleRow>,
    hist: Histogram,
    /// The bar whose samples the list shows (`None`: all).
    pub bar: Option<Bar>,
    /// The explanation of the selected sample (sample index, explanation).
    firefly: Option<(usize, Option<Firefly>)>,
}

impl SamplesView {
    fn sync(&mut self, doc: &Document) {
        if self.version == Some(doc.tree_version) {
            return;
        }
        self.version = Some(doc.tree_version);
        self.bar = None;
        self.firefly = None;
        match &doc.tree {
            Some(t) => {
                self.rows = sample_rows(t);
                self.hist = histogram(t);
            }
            None => {
                self.rows.clear();
                self.hist = Histogram::default();
            }
        }
    }

    /// The rows the list shows (all, or the chosen bar's), largest first.
    #[must_use]
    pub fn shown_rows(&self) -> Vec<&SampleRow> {
        let members: Option<&[usize]> = match self.bar {
            None => None,
            Some(Bar::Bin(k)) => self.hist.bins.get(k).map(|b| b.samples.as_slice()),
            Some(Bar::Zero) => Some(&self.hist.zero),
            Some(Bar::NonFinite) => Some(&self.hist.non_finite),
        };
        self.rows
            .iter()
            .filter(|r| members.is_none_or(|m| m.contains(&r.index)))
            .collect()
    }

    /// The firefly explanation of the selected sample, if it is one.
    #[must_use]
    pub fn firefly(&self) -> Option<&Firefly> {
        self.firefly.as_ref()?.1.as_ref()
    }
}

/// Select sample `index` (its camera ray) and make the diagram follow it.
fn select_sample(doc: &Document, index: usize, cmds: &mut Vec<Command>) {
    let Some(s) = doc.tree.as_ref().and_then(|t| t.samples.get(index)) else {
        return;
    };
    cmds.push(Command::SelectNode(Some(s.root)));
    if doc.view.diagram.sample.is_some() {
        let mut v = doc.view;
        v.diagram.sample = None;
        cmds.push(Command::SetView(v));
    }
}

/// The section.
pub fn samples_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    view: &mut SamplesView,
    cmds: &mut Vec<Command>,
) {
    lpe_ui(ui, doc, cmds);
    view.sync(doc);
    let Some(tree) = &doc.tree else {
        return;
    };
    if tree.samples.len() < 2 {
        // One sample: no spread to show (a histogram of one bar, a list of one row).
        ui.small("one sample per pixel: raise samples / pixel to compare samples");
        return;
    }
    let selected = doc
        .node
        .and_then(|id| crate::gui::model::diagram::sample_of(doc, id));
    histogram::histogram_ui(ui, doc, view, selected, cmds);
    if let Some(s) = selected {
        if view.firefly.as_ref().is_none_or(|f| f.0 != s) {
            view.firefly = Some((s, firefly::explain(tree, s)));
        }
        firefly_ui(ui, doc, view, s, cmds);
    }
    list_ui(ui, doc, view, selected, cmds);
}

/// The filter field, its parse error (red, with a caret under the column) and what matched.
fn lpe_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let st = &doc.lpe;
    ui.horizontal(|ui| {
        let label = ui.label("LPE filter");
        let mut text = st.field.clone();
        let r = ui
            .add(
                egui::TextEdit::singleline(&mut text)
                    .id_salt("lpe-filter")
                    .hint_text("e.g. C<RD>S+L")
                    .font(egui::TextStyle::Monospace)
                    .desired_width(f32::INFINITY),
            )
            .labelled_by(label.id)
            .on_hover_text(
                "keep only the paths matching this light path expression (OSL grammar, as raytree trace --lpe); empty: all. Applied on Enter, or on leaving the field",
            );
        if r.changed() {
            cmds.push(Command::EditLpe(text.clone()));
        }
        // Applied once typed (Enter or leaving the field), never a half-typed prefix.
        if r.lost_focus() {
            cmds.push(Command::SetLpe(text));
        }
    });
    if st.pending() {
        let in_force = st.active.as_ref().map_or("none", |l| l.as_str());
        ui.small(format!(
            "in force: {in_force} (press Enter to apply the field)"
        ));
    }
    if let Some(e) = &st.error {
        let caret = format!("{}^", " ".repeat(e.column.saturating_sub(1)));
        ui.label(RichText::new(e.to_string()).color(ERROR));
        ui.label(
            RichText::new(format!("{}\n{caret}", st.field.trim()))
                .monospace()
                .color(ERROR),
        );
    }
    if let (Some(lpe), Some(s)) = (&st.active, &st.summary) {
        let colour = if st.inapplicable {
            WARNING
        } else {
            ui.visuals().text_color()
        };
        ui.label(RichText::new(format!("{}: {s}", lpe.as_str())).color(colour));
    }
}

/// The selected sample's firefly sentence, a link to the blamed node.
fn firefly_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    view: &SamplesView,
    sample: usize,
    cmds: &mut Vec<Command>,
) {
    match view.firefly() {
        Some(f) => {
            let on = doc.node == Some(f.node);
            let text = RichText::new(format!("Firefly. {}", f.sentence())).color(if on {
                SELECTED
            } else {
                WARNING
            });
            if ui
                .add(egui::Button::selectable(on, text).wrap())
                .on_hover_text("select the blamed node in the tree")
                .clicked()
            {
                cmds.push(Command::SelectNode(Some(f.node)));
            }
        }
        None => {
            let ratio = doc.tree.as_ref().and_then(|t| {
                let (typ, by_median) = firefly::typical(t)?;
                let v = crate::analysis::samples::sample_value(t.samples.get(sample)?.radiance);
                Some((v / typ, if by_median { "median" } else { "mean" }))
            });
            let record = doc
                .tree
                .as_ref()
                .and_then(|t| t.samples.get(sample))
                .map_or(sample, |s| s.index as usize);
            if let Some((r, what)) = ratio {
                ui.small(format!(
                    "sample {record}: {r:.2}x the pixel's {what} (a firefly above {}x)",
                    firefly::FIREFLY_RATIO
                ));
            }
        }
    }
}

/// One row per sample (of the chosen bar), largest first.
fn list_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    view: &mut SamplesView,
    selected: Option<usize>,
    cmds: &mut Vec<Command>,
) {
    let rows = view.shown_rows();
    let mut show_all = false;
    ui.horizontal(|ui| {
        match view.bar {
            Some(_) => {
                ui.small(format!(
                    "{} of {} samples (the bar's)",
                    rows.len(),
                    view.rows.len()
                ));
                show_all = ui.small_button("show all").clicked();
            }
            None => {
                ui.small("sample, luminance, rays along the path, dominant path's LPE");
            }
        };
    });
    // Exactly the rows shown, each with the spacing `show_rows` puts under it (issue 32: 2
    // points a row instead of the style's 3 hid the last row's bottom under the next header).
    // Each row takes exactly `row` points (a button of the style) and `show_rows` puts the
    // style's spacing under it; the list is exactly the rows shown (issue 32: 18 + 2 points a
    // row against 20.4 + 3 drawn hid the last row under the next header).
    let gap = ui.spacing().item_spacing.y;
    let row = ROW_HEIGHT.max(ui.spacing().interact_size.y).max(
        ui.text_style_height(&egui::TextStyle::Monospace) + 2.0 * ui.spacing().button_padding.y,
    );
    let height = ROWS_SHOWN.min(rows.len()).max(1) as f32 * (row + gap) - gap;
    let Some(tree) = &doc.tree else { return };
    egui::ScrollArea::vertical()
        .id_salt("samples-scroll")
        .max_height(height)
        .auto_shrink([false, true])
        .show_rows(ui, row, rows.len(), |ui, range| {
            for r in &rows[range] {
                let on = selected == Some(r.index);
                let lpe = match (r.dominant(), r.paths.len()) {
                    (Some(p), 1) => p.label(),
                    (Some(p), n) => format!("{} (+{} paths)", p.label(), n - 1),
                    (None, 0) => "-".into(),
                    (None, n) => format!("no light ({n} paths)"),
                };
                let record = tree
                    .samples
                    .get(r.index)
                    .map_or(r.index, |s| s.index as usize);
                let line = format!(
                    "sample {record:<3} {:>10}  len {:<2} {lpe}",
                    value_text(r.value),
                    r.length
                );
                let (cell, _) = ui.allocate_exact_size(
                    egui::vec2(ui.available_width(), row),
                    egui::Sense::hover(),
                );
                let layout = egui::Layout::left_to_right(egui::Align::Center);
                ui.scope_builder(egui::UiBuilder::new().max_rect(cell).layout(layout), |ui| {
                    square(ui, swatch(r.radiance));
                    let text = RichText::new(line).monospace();
                    let text = if on { text.color(SELECTED) } else { text };
                    if ui
                        .add(egui::Button::selectable(on, text).truncate())
                        .on_hover_text(row_tip(r))
                        .clicked()
                    {
                        select_sample(doc, r.index, cmds);
                    }
                });
            }
        });
    if show_all {
        view.bar = None;
    }
}

/// A row's hover text: the radiance and every complete path with its contribution.
fn row_tip(r: &SampleRow) -> String {
    let mut t = format!("radiance {}", rgb(r.radiance));
    for p in &r.paths {
        t.push_str(&format!(
            "\n{} (#{}): {}",
            p.label(),
            p.node.0,
            rgb(p.contribution)
        ));
    }
    t
}

fn value_text(v: f64) -> String {
    if !v.is_finite() {
        format!("{v}")
    } else if v != 0.0 && !(1e-3..1e4).contains(&v) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}
