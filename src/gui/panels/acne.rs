//! The acne lab panel (issue 17): offset strategy, epsilon from 0, and the scene's scale and
//! distance from the origin (as `raytree acne` sweeps them); the count of pixels with acne
//! (self-hits) and leaks for that choice, and the sweep plot (every strategy against epsilon at
//! that scale and distance), both computed by the lab's worker
//! ([`crate::gui::jobs::acne_lab`]), never on the UI thread.

use crate::analysis::acne::AcneCell;
use crate::gui::jobs::acne_lab::{CURRENT_WIDTH, SWEEP_WIDTH, job_len, sweep_epsilons};
use crate::gui::model::document::{Command, Document};
use crate::gui::model::lab::LabParams;
use crate::scene::OffsetStrategy;
use egui::{Color32, FontId, Pos2, Rect, Sense, Shape, Slider, Stroke, pos2, vec2};

/// Height of the plot (points).
const PLOT_HEIGHT: f32 = 170.0;

/// A strategy's colour in the plot.
fn colour(s: OffsetStrategy) -> Color32 {
    match s {
        OffsetStrategy::Normal => Color32::from_rgb(255, 110, 110),
        OffsetStrategy::Ray => Color32::from_rgb(255, 190, 70),
        OffsetStrategy::Scaled => Color32::from_rgb(110, 200, 255),
        OffsetStrategy::Robust => Color32::from_rgb(120, 230, 120),
    }
}

fn eps_text(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.0e}")
    }
}

fn pct(n: u64, of: u64) -> f64 {
    100.0 * n as f64 / of.max(1) as f64
}

/// The lab: controls, the count and the sweep plot.
pub fn acne_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let lab = &doc.lab;
    if !lab.started {
        start_ui(ui, doc, cmds);
        return;
    }
    let p = params_ui(ui, lab.params, cmds);
    ui.small(format!(
        "scene at {:.0e} x, moved to ({d:.1e}, {d:.1e}, {d:.1e})",
        p.scale,
        d = p.scale * p.shift
    ));
    match &lab.current {
        Some(c) => count_ui(ui, c),
        None => {
            ui.label("counting…");
        }
    }
    let total = job_len() - 1;
    if !lab.done {
        ui.add(
            egui::ProgressBar::new(lab.sweep.len() as f32 / total as f32)
                .desired_width(200.0)
                .text(format!("sweep {}/{total}", lab.sweep.len())),
        );
    }
    plot(ui, &lab.sweep, &p);
}

/// Before the lab has run: what it does, and the button that starts it at the scene's offset.
fn start_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    ui.label(
        "Render this scene scaled and moved from the origin with the self-hit and leak \
         diagnostics, for one offset strategy and epsilon and as a sweep of all of them.",
    );
    if ui.button("run the acne lab").clicked() {
        let o = doc.scene.settings.offset;
        cmds.push(Command::SetLab(LabParams {
            strategy: o.strategy,
            epsilon: o.epsilon,
            ..LabParams::default()
        }));
    }
}

/// The lab's strategy, epsilon, scale and distance, from `old`; a change is sent as a
/// command. The parameters as shown.
fn params_ui(ui: &mut egui::Ui, old: LabParams, cmds: &mut Vec<Command>) -> LabParams {
    let mut p = old;
    egui::ComboBox::from_label("lab offset")
        .selected_text(p.strategy.name())
        .show_ui(ui, |ui| {
            for s in OffsetStrategy::ALL {
                ui.selectable_value(&mut p.strategy, s, s.name());
            }
        });
    ui.add(
        Slider::new(&mut p.epsilon, 0.0..=1e-1)
            .logarithmic(true)
            .smallest_positive(1e-9)
            .custom_formatter(|v, _| eps_text(v))
            .text("lab epsilon"),
    );
    ui.add(
        Slider::new(&mut p.scale, 1e-3..=1e6)
            .logarithmic(true)
            .custom_formatter(|v, _| format!("{v:.0e}"))
            .text("scene scale"),
    );
    ui.add(
        Slider::new(&mut p.shift, 0.0..=1e4)
            .logarithmic(true)
            .smallest_positive(1.0)
            .custom_formatter(|v, _| format!("{v:.0}"))
            .text("distance from origin"),
    )
    .on_hover_text("the scene is scaled about the origin, then moved scale x this along each axis");
    if p != old {
        cmds.push(Command::SetLab(p));
    }
    p
}

/// The count for the lab's own choice: pixels with acne and with leaks (in the warning colour
/// when there are any), then the rays.
fn count_ui(ui: &mut egui::Ui, c: &AcneCell) {
    let text = format!(
        "{}: {} of {} pixels with acne ({:.1}%), {} with leaks ({:.1}%)",
        c.strategy.name(),
        c.self_hit_pixels,
        c.pixels,
        pct(c.self_hit_pixels, c.pixels),
        c.leak_pixels,
        pct(c.leak_pixels, c.pixels)
    );
    let colour = if c.clean() {
        Color32::PLACEHOLDER
    } else {
        crate::gui::style::WARNING
    };
    let mut rt = egui::RichText::new(text).strong();
    if colour != Color32::PLACEHOLDER {
        rt = rt.color(colour);
    }
    ui.label(rt);
    ui.small(format!(
        "{} self-hit rays, {} leaking rays of {} ({CURRENT_WIDTH} px wide)",
        c.self_hit_rays, c.leak_rays, c.rays
    ));
}

/// x of epsilon `e` on the plot's axis: 0 at the left, then one step per decade from 1e-9.
fn eps_x(e: f64) -> f64 {
    if e <= 0.0 {
        0.0
    } else {
        (e.log10() + 10.0).clamp(0.5, 9.0)
    }
}

/// The plot's frame: epsilon's axis position (0 to `xmax`) across `plot`, percent up it.
struct Axes {
    plot: Rect,
    xmax: f64,
}

impl Axes {
    /// The point of axis position `x` and `y` percent.
    fn at(&self, x: f64, y: f64) -> Pos2 {
        let plot = self.plot;
        pos2(
            plot.left() + (x / self.xmax) as f32 * plot.width(),
            plot.bottom() - (y / 100.0) as f32 * plot.height(),
        )
    }
}

/// Acne (solid) and leaks (dashed) in % of pixels against epsilon, one line per strategy; the
/// lab's epsilon marked.
fn plot(ui: &mut egui::Ui, cells: &[AcneCell], p: &LabParams) {
    let width = ui.available_width().max(160.0);
    let (rect, resp) = ui.allocate_exact_size(vec2(width, PLOT_HEIGHT), Sense::hover());
    let label = format!(
        "acne sweep plot: {} renders at {SWEEP_WIDTH} px wide, scale {:.0e}",
        cells.len(),
        p.scale
    );
    resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Image, true, &label));
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    painter.rect_filled(rect, 2.0, visuals.extreme_bg_color);
    let eps = sweep_epsilons();
    let axes = Axes {
        plot: Rect::from_min_max(rect.min + vec2(34.0, 8.0), rect.max - vec2(8.0, 30.0)),
        xmax: eps_x(*eps.last().unwrap_or(&0.1)),
    };
    let font = FontId::proportional(10.0);
    paint_axes(&painter, &axes, visuals, &font, &eps);
    // The lab's epsilon.
    let x = eps_x(p.epsilon);
    painter.line_segment(
        [axes.at(x, 0.0), axes.at(x, 100.0)],
        Stroke::new(1.5, crate::gui::style::SELECTED),
    );
    for s in OffsetStrategy::ALL {
        let line: Vec<&AcneCell> = cells.iter().filter(|c| c.strategy == s).collect();
        let acne: Vec<Pos2> = line
            .iter()
            .map(|c| axes.at(eps_x(c.epsilon), pct(c.self_hit_pixels, c.pixels)))
            .collect();
        let leaks: Vec<Pos2> = line
            .iter()
            .map(|c| axes.at(eps_x(c.epsilon), pct(c.leak_pixels, c.pixels)))
            .collect();
        let stroke = Stroke::new(1.8, colour(s));
        painter.add(Shape::line(acne.clone(), stroke));
        painter.extend(Shape::dashed_line(&leaks, stroke, 4.0, 3.0));
        for q in acne {
            painter.circle_filled(q, 2.5, colour(s));
        }
    }
    legend(&painter, rect, visuals, font);
}

/// The percent grid and its labels, epsilon's labels (every other one, and the last) and the
/// x axis.
fn paint_axes(
    painter: &egui::Painter,
    axes: &Axes,
    visuals: &egui::Visuals,
    font: &FontId,
    eps: &[f64],
) {
    let axis = Stroke::new(1.0, visuals.weak_text_color());
    for y in [0.0, 50.0, 100.0] {
        painter.line_segment(
            [axes.at(0.0, y), axes.at(axes.xmax, y)],
            Stroke::new(0.5, visuals.weak_text_color()),
        );
        painter.text(
            axes.at(0.0, y) - vec2(4.0, 0.0),
            egui::Align2::RIGHT_CENTER,
            format!("{y:.0}%"),
            font.clone(),
            visuals.text_color(),
        );
    }
    for (i, e) in eps.iter().enumerate() {
        if i % 2 == 0 || i + 1 == eps.len() {
            painter.text(
                axes.at(eps_x(*e), 0.0) + vec2(0.0, 3.0),
                egui::Align2::CENTER_TOP,
                eps_text(*e),
                font.clone(),
                visuals.text_color(),
            );
        }
    }
    painter.line_segment([axes.plot.left_bottom(), axes.plot.right_bottom()], axis);
}

/// The legend under the axis labels: each strategy's colour, and which line is which.
fn legend(painter: &egui::Painter, rect: Rect, visuals: &egui::Visuals, font: FontId) {
    let mut lx = rect.left() + 8.0;
    let ly = rect.bottom() - 8.0;
    for s in OffsetStrategy::ALL {
        painter.line_segment(
            [pos2(lx, ly), pos2(lx + 12.0, ly)],
            Stroke::new(2.0, colour(s)),
        );
        let r = painter.text(
            pos2(lx + 15.0, ly),
            egui::Align2::LEFT_CENTER,
            s.name(),
            font.clone(),
            visuals.text_color(),
        );
        lx = r.right() + 10.0;
    }
    painter.text(
        pos2(rect.right() - 6.0, ly),
        egui::Align2::RIGHT_CENTER,
        "acne solid, leaks dashed",
        font,
        visuals.weak_text_color(),
    );
}
