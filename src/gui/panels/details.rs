//! The details pane (every recorded field of the selected node, with the teacher-facing
//! numbers of [`crate::analysis::teach`]: angles in degrees, the critical angle, the weight's
//! factors, medium names) and the contribution breakdown.

use super::tree::TreeView;
use crate::analysis::teach;
use crate::gui::model::breakdown::{Term, pixel_contribution};
use crate::gui::model::document::{Command, Document};
use crate::gui::style::{SELECTED, amount, kind_colour, num, rgb, vec3};
use crate::math::Rgb;
use crate::tree::RayKind;
use egui::RichText;

/// Breakdown terms listed one by one; the rest are summed in one line.
const TERMS_SHOWN: usize = 24;

/// Every recorded field of the selected node.
pub fn details_ui(ui: &mut egui::Ui, doc: &Document) {
    let scene = &doc.scene;
    let (Some(tree), Some(id)) = (&doc.tree, doc.node) else {
        ui.label("Select a node to see its fields.");
        return;
    };
    let n = tree.node(id);
    ui.colored_label(
        kind_colour(n.kind),
        RichText::new(format!("#{} {} ray", n.id.0, n.kind.name())).strong(),
    );
    egui::Grid::new("details")
        .striped(true)
        .num_columns(2)
        .max_col_width((ui.available_width() - 110.0).max(120.0))
        .show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.add(egui::Label::new(RichText::new(v).monospace()).wrap());
                ui.end_row();
            };
            row("depth", n.depth.to_string());
            row(
                "parent",
                n.parent.map_or("-".into(), |p| format!("#{}", p.0)),
            );
            row(
                "children",
                n.children
                    .iter()
                    .map(|c| format!("#{}", c.0))
                    .collect::<Vec<_>>()
                    .join(" "),
            );
            row("spawn point", vec3(n.spawn_point));
            row("offset", vec3(n.offset));
            row("origin", vec3(n.origin));
            row("direction", vec3(n.direction));
            row("t_min", num(n.t_min));
            if let Some(h) = &n.hit {
                row(
                    "hit object",
                    format!("{} (#{}) [{}]", h.object_name, h.object, h.material),
                );
                row("hit t", num(h.t));
                row("hit point", vec3(h.point));
                row("hit normal", vec3(h.normal));
                row("entering", h.entering.to_string());
                row("cos_i", with_deg(h.cos_i, "theta_i"));
            }
            if let Some(i) = &n.interface {
                row("n1 -> n2", format!("{} -> {}", num(i.n1), num(i.n2)));
                row(
                    "cos_i / cos_t",
                    format!(
                        "{} / {}",
                        with_deg(i.cos_i, "theta_i"),
                        i.cos_t.map_or("- (TIR)".into(), |c| with_deg(c, "theta_t"))
                    ),
                );
                row("angles", teach::incidence_text(i));
                row(
                    "Fresnel R / T",
                    format!("{} / {}", num(i.fresnel.r), num(i.fresnel.t)),
                );
                row("TIR", i.tir.to_string());
                if let Some(c) = i.roulette {
                    row(
                        "roulette",
                        format!(
                            "followed the {} ray only, p {} (its weight / p)",
                            c.ray(),
                            num(c.probability)
                        ),
                    );
                }
            }
            if let Some(a) = &n.attenuation {
                row(
                    "medium",
                    format!("{} (#{})", teach::medium_name(scene, a.medium), a.medium),
                );
                row("distance", num(a.distance));
                row("absorption", rgb(a.absorption));
                row("Beer factor", rgb(a.factor));
            }
            if let Some(g) = &n.glossy {
                row(
                    "sampled from",
                    format!(
                        "{} ({} of {}{})",
                        g.lobe.name(),
                        g.sample + 1,
                        g.count,
                        if g.transmitted { ", through" } else { "" }
                    ),
                );
                row("pdf", num(g.pdf));
                row("BSDF / cos", format!("{} / {}", rgb(g.bsdf), num(g.cos)));
            }
            row(
                "weight",
                teach::weight_factors(scene, tree, id).unwrap_or_else(|| rgb(n.weight)),
            );
            row("throughput", rgb(n.throughput));
            row("emitted", rgb(n.emitted));
            row("ambient", rgb(n.ambient));
            row("local", rgb(n.local));
            row("radiance", rgb(n.radiance));
            row("share of the pixel", rgb(pixel_contribution(tree, id)));
            row("truncated", rgb(n.truncated));
            row("end", crate::text::end_text(n.end).to_string());
            if let Some(pi) = &n.path {
                // What the path integrator recorded (docs/path-tracing.md).
                row("light path (LPE)", pi.lpe.clone());
                if let Some(lobe) = pi.lobe {
                    row("sampled lobe", lobe.name().to_string());
                }
                if let Some(pdf) = &pi.pdf {
                    row(
                        "pdf",
                        match pdf {
                            crate::tree::Pdf::Density(p) => format!("{} /sr", num(*p)),
                            crate::tree::Pdf::Delta(_) => "delta".to_owned(),
                        },
                    );
                }
                if let Some(w) = pi.bsdf_cos_pdf {
                    row("f cos / pdf", rgb(w));
                }
                if let Some(m) = pi.mis_weight {
                    row("MIS weight", num(m));
                }
                if let Some(r) = &pi.roulette {
                    let outcome = if r.survived { "survived" } else { "killed" };
                    row(
                        "Russian roulette",
                        format!("q {} {outcome}", num(r.probability)),
                    );
                }
                row("contribution", rgb(pi.contribution));
            }
            if let Some(s) = &n.shadow {
                row("light", format!("{} (#{})", s.light_name, s.light));
                row("light distance", num(s.distance));
                row("cos theta", with_deg(s.cos_theta, "theta"));
                row("BRDF", rgb(s.brdf));
                if let Some(a) = &s.area {
                    // An area-light sample: the emitted radiance, its solid-angle pdf and the
                    // Monte Carlo weight L / pdf (not an irradiance).
                    row("sampled point", vec3(a.point));
                    row("emitted radiance L", rgb(a.radiance));
                    row("pdf (solid angle)", num(a.pdf));
                    row("L / pdf", rgb(s.irradiance));
                } else {
                    row("irradiance", rgb(s.irradiance));
                }
                row("transmittance", rgb(s.transmittance));
                for b in &s.blockers {
                    row(
                        "blocker",
                        format!(
                            "{} t={} chord={} factor={}",
                            b.object_name,
                            num(b.t),
                            num(b.chord),
                            rgb(b.factor)
                        ),
                    );
                }
            }
        });
}

/// A cosine with its angle: `0.9969 (theta_i 4.48 deg)`.
fn with_deg(cos: f64, name: &str) -> String {
    format!("{} ({name} {:.2} deg)", num(cos), teach::deg(cos))
}

/// How the pixel value adds up; clicking a term selects its node (and reveals it in the tree).
pub fn breakdown_ui(ui: &mut egui::Ui, doc: &Document, view: &TreeView, cmds: &mut Vec<Command>) {
    let Some(tree) = &doc.tree else { return };
    // Terms that would print 0 (residues such as 4.3e-30 of a zero BRDF) are not listed.
    let (terms, zero): (Vec<&Term>, Vec<&Term>) = view
        .terms()
        .iter()
        .partition(|t| amount(t.value.max_element()) != "0");
    let total = tree.radiance.element_sum().max(1e-12);
    // Numbers are never wrapped (a wrapping grid squeezed them to a few characters a line);
    // a long label is cut instead.
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
    egui::Grid::new("breakdown")
        .striped(true)
        .num_columns(3)
        .max_col_width(200.0)
        .show(ui, |ui| {
            for t in terms.iter().take(TERMS_SHOWN) {
                let share = t.value.element_sum() / total;
                let kind = tree.node(t.node).kind;
                let colour = if doc.node == Some(t.node) {
                    SELECTED
                } else {
                    kind_colour(kind)
                };
                if ui
                    .add(
                        egui::Button::selectable(
                            doc.node == Some(t.node),
                            RichText::new(&t.label).color(colour),
                        )
                        .truncate(),
                    )
                    .clicked()
                {
                    cmds.push(Command::SelectNode(Some(t.node)));
                }
                ui.monospace(amounts(t.value));
                ui.label(format!("{:5.1}%", share * 100.0));
                ui.end_row();
            }
            if terms.len() > TERMS_SHOWN {
                let rest = terms[TERMS_SHOWN..]
                    .iter()
                    .fold(crate::math::Rgb::ZERO, |acc, t| acc + t.value);
                ui.label(format!("{} smaller terms", terms.len() - TERMS_SHOWN));
                ui.monospace(amounts(rest));
                ui.label(format!("{:5.1}%", rest.element_sum() / total * 100.0));
                ui.end_row();
            }
            ui.label(RichText::new("pixel").strong());
            ui.monospace(rgb(tree.radiance));
            ui.label("100%");
            ui.end_row();
        });
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
    let shadows = tree
        .nodes
        .iter()
        .filter(|n| n.kind == RayKind::Shadow)
        .count();
    ui.small(format!(
        "local = emitted + ambient + direct light from {shadows} shadow rays"
    ));
    if !zero.is_empty() {
        let sum = zero.iter().fold(Rgb::ZERO, |acc, t| acc + t.value);
        ui.small(format!(
            "{} terms under 5e-10 not listed (together {:.1e})",
            zero.len(),
            sum.max_element()
        ));
    }
}

/// A term's value: one number for a grey, else three, each as [`amount`] prints it (so a
/// small term reads 3.1e-6, not 0.0000).
fn amounts(c: Rgb) -> String {
    if c.x == c.y && c.y == c.z {
        return amount(c.x);
    }
    format!("[{}, {}, {}]", amount(c.x), amount(c.y), amount(c.z))
}
