//! The left panel: scene file, tracer settings, view options and exports.

use crate::gui::model::document::{Command, Document};
use crate::gui::model::export::ExportKind;
use crate::gui::model::stats::DebugView;
use crate::gui::style::{ERROR, SELECTED, WARNING, dot, kind_colour};
use crate::math::FresnelModel;
use crate::scene::{Antialiasing, IntegratorKind, OffsetStrategy, ShadowMode};
use crate::tree::RayKind;
use egui::{RichText, Slider};

/// Scene file field, open, reload and edit; returns whether **edit** was clicked (the app
/// opens the scene's text in its window).
pub fn scene_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) -> bool {
    let mut open_editor = false;
    ui.label(RichText::new(doc.source.label()).strong());
    let mut path = doc.path_field.clone();
    let label = ui.label("scene file");
    let edit = ui.text_edit_singleline(&mut path).labelled_by(label.id);
    if path != doc.path_field {
        cmds.push(Command::SetPathField(path.clone()));
    }
    let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    ui.horizontal(|ui| {
        if (ui.button("Open").clicked() || enter) && !path.trim().is_empty() {
            cmds.push(Command::Open(path.trim().into()));
        }
        if ui.button("Reload").clicked() {
            cmds.push(Command::Reload);
        }
        open_editor = ui
            .button("Edit")
            .on_hover_text(
                "the scene's text in a window: edit it and apply it (the file is not written)",
            )
            .clicked();
    });
    if let Some(e) = &doc.error {
        ui.add(egui::Label::new(RichText::new(e).color(ERROR)).wrap());
    }
    // Kept, greyed, while the next render runs: the space stays reserved (issue 32: the line
    // vanished while rendering and every control below moved up by about 40 px).
    if let Some(g) = &doc.progress.growth {
        let text = RichText::new(g).small();
        let text = if doc.progress.growth_current {
            text
        } else {
            text.weak()
        };
        ui.add(egui::Label::new(text).wrap());
    }
    open_editor
}

/// How each offset strategy places a secondary ray's origin.
fn offset_label(o: OffsetStrategy) -> &'static str {
    match o {
        OffsetStrategy::Normal => "normal: P ± εN",
        OffsetStrategy::Ray => "ray: t_min = ε",
        OffsetStrategy::Scaled => "scaled: P ± ε·max(1,|P|)N",
        OffsetStrategy::Robust => "robust: error bounds",
    }
}

/// Tracer settings; any change re-renders and re-traces the selected pixel.
pub fn settings_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let old = doc.scene.settings;
    let mut s = old;
    integrator_ui(ui, &mut s);
    samples_ui(ui, doc, &mut s);
    offset_ui(ui, &mut s);
    whitted_ui(ui, doc, &mut s);
    stochastic_ui(ui, doc, &mut s);
    roulette_ui(ui, doc, &mut s);
    if s != old {
        cmds.push(Command::SetSettings(s));
    }
    super::progressive::progressive_ui(ui, doc, cmds);
}

/// The integrator, and where its Russian roulette starts (not for Whitted).
fn integrator_ui(ui: &mut egui::Ui, s: &mut crate::scene::Settings) {
    egui::ComboBox::from_label("integrator")
        .selected_text(s.integrator.name())
        .show_ui(ui, |ui| {
            for k in IntegratorKind::ALL {
                ui.selectable_value(&mut s.integrator, k, k.name());
            }
        });
    if s.integrator != IntegratorKind::Whitted {
        ui.add(
            Slider::new(&mut s.path.rr_depth, 0..=64)
                .clamping(egui::SliderClamping::Never)
                .text("roulette from bounce"),
        );
    }
}

/// Max depth, samples per pixel and automatic antialiasing.
fn samples_ui(ui: &mut egui::Ui, doc: &Document, s: &mut crate::scene::Settings) {
    // `Never`: the slider's range is where dragging ends, not a limit. A scene's own value
    // beyond it (max_depth 64, spp 256) stays as it is (egui's default clamped it at the first
    // frame), and a value typed beyond it is taken (`Edits` turned a typed 64 into 32); the
    // session validates it as the command line does and says when it refuses one.
    ui.add(
        Slider::new(&mut s.max_depth, 0..=32)
            .clamping(egui::SliderClamping::Never)
            .text("max depth"),
    );
    ui.add(
        Slider::new(&mut s.spp, 1..=64)
            .clamping(egui::SliderClamping::Never)
            .logarithmic(true)
            .text("samples / pixel"),
    );
    // Automatic antialiasing: edge pixels take spp samples, the others a first pass (where the
    // image depends on the film position alone; the hover says whether it applies).
    let mut auto = s.antialiasing == Antialiasing::Auto;
    ui.checkbox(&mut auto, "antialias edges only")
        .on_hover_ui(|ui| {
            let integrator = crate::integrator::SceneIntegrator::new(&doc.scene);
            ui.label(crate::render::antialiasing_note(&integrator));
        });
    s.antialiasing = if auto {
        Antialiasing::Auto
    } else {
        Antialiasing::Uniform
    };
}

/// The offset strategy of secondary rays and its epsilon.
fn offset_ui(ui: &mut egui::Ui, s: &mut crate::scene::Settings) {
    egui::ComboBox::from_label("offset")
        .selected_text(offset_label(s.offset.strategy))
        .show_ui(ui, |ui| {
            for o in OffsetStrategy::ALL {
                ui.selectable_value(&mut s.offset.strategy, o, offset_label(o));
            }
        });
    // From 0 (no offset at all: the acne of docs/numerics.md) on a log scale whose first step
    // above 0 is 1e-9; the value field takes any number typed, 0 included.
    ui.add(
        Slider::new(&mut s.offset.epsilon, 0.0..=1e-1)
            .logarithmic(true)
            .smallest_positive(1e-9)
            .custom_formatter(|v, _| {
                if v == 0.0 {
                    "0".into()
                } else {
                    format!("{v:.0e}")
                }
            })
            .text("epsilon"),
    );
}

/// The Whitted integrator's own settings: shown under the path integrator too (they are
/// kept for a switch back) but disabled, as it does not read them.
fn whitted_ui(ui: &mut egui::Ui, doc: &Document, s: &mut crate::scene::Settings) {
    ui.add_enabled_ui(s.integrator == IntegratorKind::Whitted, |ui| {
        egui::ComboBox::from_label("Fresnel")
            .selected_text(format!("{:?}", s.whitted.fresnel))
            .show_ui(ui, |ui| {
                for m in [
                    FresnelModel::Exact,
                    FresnelModel::Schlick,
                    FresnelModel::None,
                ] {
                    ui.selectable_value(&mut s.whitted.fresnel, m, format!("{m:?}"));
                }
            });
        ui.horizontal(|ui| {
            ui.label("shadows");
            ui.radio_value(&mut s.whitted.shadows, ShadowMode::Opaque, "opaque");
            ui.radio_value(
                &mut s.whitted.shadows,
                ShadowMode::Translucent,
                "translucent",
            );
        });
        min_weight_ui(ui, doc, s);
    })
    .response
    .on_disabled_hover_text(format!(
        "the path integrator does not read these: {}",
        crate::scene::WhittedSettings::WHY_OTHERS_IGNORE
    ));
}

/// Area-light and glossy sampling of the Whitted integrator, shown only for scenes that have an
/// emitter to sample or a rough material.
fn stochastic_ui(ui: &mut egui::Ui, doc: &Document, s: &mut crate::scene::Settings) {
    let scene = &doc.scene;
    if s.integrator != IntegratorKind::Whitted {
        // The path tracer samples lights and lobes itself, one of each per hit.
        return;
    }
    if (0..scene.objects.len()).any(|i| scene.area_light(i).is_some()) {
        let mut on = s.whitted.light_samples.is_some();
        let mut n = s.whitted.light_samples.unwrap_or(1);
        ui.horizontal(|ui| {
            ui.checkbox(&mut on, "area lights")
                .on_hover_text("sample emissive objects with shadow rays (soft shadows)");
            ui.add_enabled(
                on,
                Slider::new(&mut n, 1..=64)
                    .clamping(egui::SliderClamping::Never)
                    .logarithmic(true)
                    .text("light samples"),
            );
        });
        s.whitted.light_samples = on.then_some(n);
    }
    if scene.used_materials().any(|m| m.roughness > 0.0) {
        ui.add(
            Slider::new(&mut s.whitted.glossy_samples, 1..=64)
                .clamping(egui::SliderClamping::Never)
                .logarithmic(true)
                .text("glossy samples"),
        );
    }
}

/// The min-weight cut: "auto" shows the cut chosen from the tolerance and the scene
/// ([`crate::integrator::bound`]); unticking starts the slider there; 0 is the exhaustive tree.
fn min_weight_ui(ui: &mut egui::Ui, doc: &Document, s: &mut crate::scene::Settings) {
    let auto_value = crate::integrator::bound::auto_min_weight(&doc.scene, s);
    s.whitted.min_weight = auto_weight_ui(
        ui,
        s.whitted.min_weight,
        auto_value,
        "min weight",
        "cut branches that could add less than the tolerance (1/510)",
    );
}

/// The roulette below a weight at glass (Whitted scenes with a transmissive material): off by
/// default ("default" ticked: every glass hit splits, the image is deterministic); unticking
/// starts the slider at the weight suggested for the scene ([`crate::integrator::bound::carried`]).
fn roulette_ui(ui: &mut egui::Ui, doc: &Document, s: &mut crate::scene::Settings) {
    if s.integrator != IntegratorKind::Whitted
        || !doc.scene.used_materials().any(|m| m.is_transmissive())
    {
        return;
    }
    let suggested = crate::integrator::bound::carried::auto_roulette_below(&doc.scene, s);
    let hover = format!(
        "off by default: every glass hit splits and the image is deterministic. Unticked, glass \
         hits weaker than the weight follow one of their two rays (Russian roulette, exact in \
         expectation, noisy); suggested for this scene: {suggested:.2e}"
    );
    let mut default = s.whitted.roulette_below.is_none();
    let mut w = s.whitted.roulette_below.unwrap_or(suggested);
    ui.horizontal(|ui| {
        ui.add_enabled(
            !default,
            Slider::new(&mut w, 0.0..=1.0)
                .logarithmic(true)
                .smallest_positive(1e-9)
                .text("roulette below"),
        );
        ui.checkbox(&mut default, "default (off)")
            .on_hover_text(hover);
    });
    s.whitted.roulette_below = (!default).then_some(w);
}

/// A weight in `[0, 1]` on a log slider beside an "auto" box: `None` (automatic, the slider
/// showing `auto_value` and disabled) or the chosen weight (unticking starts it at
/// `auto_value`).
fn auto_weight_ui(
    ui: &mut egui::Ui,
    value: Option<f64>,
    auto_value: f64,
    label: &str,
    auto_hover: &str,
) -> Option<f64> {
    let mut auto = value.is_none();
    let mut w = value.unwrap_or(auto_value);
    ui.horizontal(|ui| {
        ui.add_enabled(
            !auto,
            Slider::new(&mut w, 0.0..=1.0)
                .logarithmic(true)
                .smallest_positive(1e-9)
                .text(label),
        );
        ui.checkbox(&mut auto, "auto").on_hover_text(auto_hover);
    });
    (!auto).then_some(w)
}

/// Debug view, overlay and zoom.
pub fn view_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let mut v = doc.view;
    egui::ComboBox::from_label("show")
        .selected_text(v.debug.label())
        .show_ui(ui, |ui| {
            for d in DebugView::ALL {
                ui.selectable_value(&mut v.debug, d, d.label());
            }
        });
    ui.checkbox(&mut v.overlay, "ray path overlay");
    ui.checkbox(&mut v.denoise, "denoised image").on_hover_text(
        "the finished render through the a-trous denoiser (docs/denoise.md); the tree, overlay, diagram and exports stay the raw samples",
    );
    ui.horizontal(|ui| {
        ui.label("zoom");
        if ui.button("fit").clicked() {
            v.zoom = None;
            v.pan = [0.0, 0.0];
        }
        for z in [1.0, 4.0, 16.0] {
            if ui.button(format!("{z}x")).clicked() {
                v.zoom = Some(z);
                v.pan = centre_on_selection(doc, z);
            }
        }
    });
    ui.horizontal_wrapped(|ui| {
        for k in RayKind::ALL {
            dot(ui, kind_colour(k));
            ui.label(k.name());
        }
        dot(ui, SELECTED);
        ui.label("selected");
    });
    if v != doc.view {
        cmds.push(Command::SetView(v));
    }
}

/// Pan that puts the selected pixel at the panel centre at zoom `z`.
fn centre_on_selection(doc: &Document, z: f32) -> [f32; 2] {
    let Some([x, y]) = doc.selection else {
        return [0.0, 0.0];
    };
    let dx = (doc.image.width as f32 * 0.5 - (x as f32 + 0.5)) * z;
    let dy = (doc.image.height as f32 * 0.5 - (y as f32 + 0.5)) * z;
    [dx, dy]
}

/// Export base and buttons.
pub fn export_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let mut base = doc.export_field.clone();
    let label = ui.label("export base (path without extension)");
    ui.text_edit_singleline(&mut base).labelled_by(label.id);
    if base != doc.export_field {
        cmds.push(Command::SetExportField(base));
    }
    ui.horizontal_wrapped(|ui| {
        for k in ExportKind::ALL {
            if ui.button(k.label()).clicked() {
                cmds.push(Command::Export(k));
            }
        }
    });
    if let Some(e) = &doc.export_error {
        ui.add(egui::Label::new(RichText::new(e).color(ERROR)).wrap());
    } else if doc.status.contains("warning:") {
        // An export that wrote its file but had to clamp or leave out non-finite values.
        ui.add(egui::Label::new(RichText::new(&doc.status).color(WARNING)).wrap());
    } else if !doc.status.is_empty() {
        ui.add(egui::Label::new(RichText::new(&doc.status).small()).wrap());
    }
}
