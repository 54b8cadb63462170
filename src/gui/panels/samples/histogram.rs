//! The histogram of the samples section: a bar per half decade of sample value, the zero and
//! non-finite samples in bars of their own; a click lists a bar's samples.

use super::{Bar, SamplesView, select_sample};
use crate::analysis::samples::Histogram;
use crate::gui::model::document::{Command, Document};
use crate::gui::style::{ERROR, SELECTED};
use egui::{Color32, Sense, pos2, vec2};

/// Height of the histogram (points).
const HIST_HEIGHT: f32 = 84.0;

/// The histogram: a bar per half decade of sample value, the zero (and non-finite) samples in
/// bars of their own at the left (right); the selected sample's bar outlined.
pub(super) fn histogram_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    view: &mut SamplesView,
    selected: Option<usize>,
    cmds: &mut Vec<Command>,
) {
    let h = &view.hist;
    let columns = columns(h);
    ui.small(format!(
        "{} samples by luminance, log scale (2 bars a decade, each labelled with its lower edge; 0 apart): click a bar to list its samples",
        view.rows.len()
    ));
    let (rect, _) = ui.allocate_exact_size(vec2(ui.available_width(), HIST_HEIGHT), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, ui.visuals().extreme_bg_color);
    let max = columns.iter().map(|c| c.count).max().unwrap_or(1).max(1);
    let n = columns.len().max(1) as f32;
    // Room for the axis labels below and the counts above the tallest bar.
    let plot_h = rect.height() - 16.0;
    let plot = Plot {
        rect,
        w: rect.width() / n,
        plot_h,
        bar_h: plot_h - 13.0,
        max,
        text: ui.visuals().text_color(),
        sel_bar: selected.and_then(|s| {
            if h.zero.contains(&s) {
                Some(Bar::Zero)
            } else if h.non_finite.contains(&s) {
                Some(Bar::NonFinite)
            } else {
                h.bin_of(s).map(Bar::Bin)
            }
        }),
    };
    for (i, column) in columns.iter().enumerate() {
        if bar_ui(ui, &painter, &plot, i, column, view) {
            toggle_bar(doc, view, column.bar, cmds);
        }
    }
}

/// One bar of the histogram: which, how many samples, its axis label.
struct Column {
    bar: Bar,
    count: usize,
    label: String,
}

/// The bars of `h`, left to right: zero, the bins, non-finite (the first and last only when
/// they have samples).
fn columns(h: &Histogram) -> Vec<Column> {
    let column = |bar, count, label| Column { bar, count, label };
    let mut columns = Vec::new();
    if !h.zero.is_empty() {
        columns.push(column(Bar::Zero, h.zero.len(), "0".into()));
    }
    for (k, b) in h.bins.iter().enumerate() {
        columns.push(column(Bar::Bin(k), b.samples.len(), edge(b.lo)));
    }
    if !h.non_finite.is_empty() {
        columns.push(column(Bar::NonFinite, h.non_finite.len(), "NaN".into()));
    }
    columns
}

/// Where the histogram is drawn and what every bar shares.
struct Plot {
    rect: egui::Rect,
    /// Width of a bar's cell.
    w: f32,
    /// Height of the bars' area (above the axis labels).
    plot_h: f32,
    /// Height of the tallest bar (below its count).
    bar_h: f32,
    /// The largest count (at least 1).
    max: usize,
    text: Color32,
    /// The bar of the selected sample.
    sel_bar: Option<Bar>,
}

/// Bar `i` of the histogram, `column`, with its count and axis label; whether it was clicked.
fn bar_ui(
    ui: &mut egui::Ui,
    painter: &egui::Painter,
    plot: &Plot,
    i: usize,
    column: &Column,
    view: &SamplesView,
) -> bool {
    let (rect, w, text) = (plot.rect, plot.w, plot.text);
    let Column { bar, count, label } = column;
    let h = &view.hist;
    let x0 = rect.left() + i as f32 * w;
    let cell = egui::Rect::from_min_size(pos2(x0, rect.top()), vec2(w, rect.height()));
    let bh = plot.bar_h * *count as f32 / plot.max as f32;
    let bar_rect = egui::Rect::from_min_max(
        pos2(x0 + 1.5, rect.top() + plot.plot_h - bh),
        pos2(x0 + w - 1.5, rect.top() + plot.plot_h),
    );
    let resp = ui.interact(
        cell,
        ui.make_persistent_id(("sample-bar", *bar)),
        Sense::click(),
    );
    let chosen = view.bar == Some(*bar);
    let what = match bar {
        Bar::Zero => "value 0".to_string(),
        Bar::NonFinite => "non-finite".to_string(),
        Bar::Bin(k) => format!("1e{:.1} to 1e{:.1}", h.bins[*k].lo, h.bins[*k].hi),
    };
    let name = format!("bar {what}: {count} samples");
    resp.widget_info(|| egui::WidgetInfo::selected(egui::Role::Button, true, chosen, &name));
    let fill = match (bar, chosen) {
        (_, true) => SELECTED,
        (Bar::NonFinite, _) => ERROR,
        (Bar::Zero, _) => Color32::from_gray(120),
        _ if resp.hovered() => Color32::from_rgb(140, 190, 255),
        _ => Color32::from_rgb(90, 150, 230),
    };
    if *count > 0 {
        painter.rect_filled(bar_rect, 1.0, fill);
    }
    if plot.sel_bar == Some(*bar) {
        painter.rect_stroke(
            bar_rect.expand(1.0),
            1.0,
            egui::Stroke::new(1.5, SELECTED),
            egui::StrokeKind::Outside,
        );
    }
    if *count > 0 {
        painter.text(
            pos2(cell.center().x, bar_rect.top() - 1.0),
            egui::Align2::CENTER_BOTTOM,
            count.to_string(),
            egui::FontId::proportional(10.0),
            text,
        );
    }
    // Axis labels on every other bar when they are narrow.
    if w >= 34.0 || i.is_multiple_of(2) || matches!(bar, Bar::Zero | Bar::NonFinite) {
        painter.text(
            pos2(cell.center().x, rect.bottom() - 1.0),
            egui::Align2::CENTER_BOTTOM,
            label,
            egui::FontId::proportional(10.0),
            text,
        );
    }
    let tip = format!("{name}; click to list them");
    resp.on_hover_text(tip).clicked()
}

/// A click on `bar`: the list shows only its samples (and its largest is selected), or all
/// of them again when it was already chosen.
fn toggle_bar(doc: &Document, view: &mut SamplesView, bar: Bar, cmds: &mut Vec<Command>) {
    if view.bar == Some(bar) {
        view.bar = None;
    } else {
        view.bar = Some(bar);
        // Select the bar's largest sample.
        if let Some(r) = view.shown_rows().first() {
            select_sample(doc, r.index, cmds);
        }
    }
}

/// A bar's lower edge `10^lo`, two significant digits.
fn edge(lo: f64) -> String {
    let v = 10f64.powf(lo);
    if (1e-3..1e4).contains(&v) {
        let digits = (1.0 - v.log10().floor()).max(0.0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.1e}")
    }
}
