//! The progressive mode's controls, its live noise estimate and what that estimate is made of
//! (in the Settings section).

use crate::gui::model::document::{Command, Document};
use crate::gui::model::progressive::{Options, Report, Stop};
use egui::{DragValue, Slider};

/// One line for a report: the estimate, the samples so far, the time, and why it stopped.
#[must_use]
pub fn status(report: &Report, options: &Options) -> String {
    let mut line = format!(
        "noise {:.2}% at {} spp, {:.1} s",
        report.error * 100.0,
        report.spp,
        report.seconds
    );
    line += &match report.stop {
        None => " (refining)".to_string(),
        Some(Stop::Target) => format!("; stopped: below the target {}%", options.target * 100.0),
        Some(Stop::Cap) => format!("; stopped: cap of {} spp reached", options.cap),
    };
    line
}

/// The checkbox, the target and the cap, and the live estimate.
pub fn progressive_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let old = doc.progressive.options;
    let mut o = old;
    ui.checkbox(&mut o.on, "progressive").on_hover_text(
        "render passes of 4, 8, 16, ... samples per pixel until the noise estimate falls \
         below the target; the selected pixel's tree stays at the scene's samples / pixel",
    );
    if o.on {
        ui.horizontal(|ui| {
            let mut pct = o.target * 100.0;
            let label = ui.label("stop at error");
            ui.add(
                DragValue::new(&mut pct)
                    .range(0.0..=100.0)
                    .speed(0.05)
                    .suffix(" %"),
            )
            .labelled_by(label.id);
            if pct != old.target * 100.0 {
                o.target = pct / 100.0;
            }
        });
        ui.add(
            Slider::new(&mut o.cap, 4..=16384)
                .logarithmic(true)
                .text("max samples / pixel"),
        );
        let line = match &doc.progressive.report {
            Some(r) => status(r, &o),
            None => "noise: first pass...".to_string(),
        };
        ui.label(line);
        // What the estimate is made of (issue 32): which pixels carry it, and why it
        // plateaus when a few rare-event pixels do.
        if let Some(c) = doc.progressive.report.and_then(|r| r.composition) {
            let text = egui::RichText::new(c.sentence()).small();
            ui.label(if c.dominated() {
                text.color(crate::gui::style::WARNING)
            } else {
                text
            });
        }
    }
    if o != old {
        cmds.push(Command::SetProgressive(o));
    }
}

/// In the title bar, while progressive rendering is on: the estimate and the samples so far.
pub fn title_ui(ui: &mut egui::Ui, doc: &Document) {
    if let Some(r) = &doc.progressive.report {
        ui.separator();
        let state = if r.stop.is_some() {
            "stopped"
        } else {
            "refining"
        };
        ui.label(format!(
            "progressive: {} spp, noise {:.2}%, {state}",
            r.spp,
            r.error * 100.0
        ));
    }
}
