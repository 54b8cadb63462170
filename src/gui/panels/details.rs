//! The details pane (every recorded field of the selected node, with the teacher-facing
//! numbers of [`crate::analysis::teach`]: angles in degrees, the critical angle, the weight's
//! factors, medium names) and the contribution breakdown.

use super::tree::TreeView;
use crate::analysis::teach;
use crate::gui::model::breakdown::{Term, pixel_contribution};
use crate::gui::model::document::{Command, Document};
use crate::gui::style::{SELECTED, amount, kind_colour, num, rgb, vec3};
use crate::math::Rgb;
use crate::tree::{GlossySample, HitInfo, Interface, PathInfo, RayKind, RayNode, ShadowInfo};
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
            let mut r = Rows { ui };
            ray_rows(&mut r, n);
            if let Some(h) = &n.hit {
                hit_rows(&mut r, h);
            }
            if let Some(i) = &n.interface {
                interface_rows(&mut r, i);
            }
            if let Some(a) = &n.attenuation {
                r.row(
                    "medium",
                    format!("{} (#{})", teach::medium_name(scene, a.medium), a.medium),
                );
                r.row("distance", num(a.distance));
                r.row("absorption", rgb(a.absorption));
                r.row("Beer factor", rgb(a.factor));
            }
            if let Some(g) = &n.glossy {
                glossy_rows(&mut r, g);
            }
            r.row(
                "weight",
                teach::weight_factors(scene, tree, id).unwrap_or_else(|| rgb(n.weight)),
            );
            r.row("throughput", rgb(n.throughput));
            r.row("emitted", rgb(n.emitted));
            r.row("ambient", rgb(n.ambient));
            r.row("local", rgb(n.local));
            r.row("radiance", rgb(n.radiance));
            r.row("share of the pixel", rgb(pixel_contribution(tree, id)));
            r.row("truncated", rgb(n.truncated));
            r.row("end", crate::text::end_text(n.end).to_string());
            if let Some(pi) = &n.path {
                path_rows(&mut r, pi);
            }
            if let Some(s) = &n.shadow {
                shadow_rows(&mut r, s);
            }
        });
}

/// The rows of the details grid: a name and its value (monospace, wrapped).
struct Rows<'u> {
    ui: &'u mut egui::Ui,
}

impl Rows<'_> {
    /// One row: `k`, then `v`.
    fn row(&mut self, k: &str, v: String) {
        self.ui.label(k);
        self.ui
            .add(egui::Label::new(RichText::new(v).monospace()).wrap());
        self.ui.end_row();
    }
}

/// Where the ray is in the tree and where it starts, in which direction.
fn ray_rows(r: &mut Rows, n: &RayNode) {
    r.row("depth", n.depth.to_string());
    r.row(
        "parent",
        n.parent.map_or("-".into(), |p| format!("#{}", p.0)),
    );
    r.row(
        "children",
        n.children
            .iter()
            .map(|c| format!("#{}", c.0))
            .collect::<Vec<_>>()
            .join(" "),
    );
    r.row("spawn point", vec3(n.spawn_point));
    r.row("offset", vec3(n.offset));
    r.row("origin", vec3(n.origin));
    r.row("direction", vec3(n.direction));
    r.row("t_min", num(n.t_min));
}

/// The surface the ray hit.
fn hit_rows(r: &mut Rows, h: &HitInfo) {
    r.row(
        "hit object",
        format!("{} (#{}) [{}]", h.object_name, h.object, h.material),
    );
    r.row("hit t", num(h.t));
    r.row("hit point", vec3(h.point));
    r.row("hit normal", vec3(h.normal));
    r.row("entering", h.entering.to_string());
    r.row("cos_i", with_deg(h.cos_i, "theta_i"));
}

/// The interface the ray was born at: indices, angles, Fresnel, the roulette's choice.
fn interface_rows(r: &mut Rows, i: &Interface) {
    r.row("n1 -> n2", format!("{} -> {}", num(i.n1), num(i.n2)));
    r.row(
        "cos_i / cos_t",
        format!(
            "{} / {}",
            with_deg(i.cos_i, "theta_i"),
            i.cos_t.map_or("- (TIR)".into(), |c| with_deg(c, "theta_t"))
        ),
    );
    r.row("angles", teach::incidence_text(i));
    r.row(
        "Fresnel R / T",
        format!("{} / {}", num(i.fresnel.r), num(i.fresnel.t)),
    );
    r.row("TIR", i.tir.to_string());
    if let Some(c) = i.roulette {
        r.row(
            "roulette",
            format!(
                "followed the {} ray only, p {} (its weight / p)",
                c.ray(),
                num(c.probability)
            ),
        );
    }
}

/// The glossy lobe the ray was sampled from.
fn glossy_rows(r: &mut Rows, g: &GlossySample) {
    r.row(
        "sampled from",
        format!(
            "{} ({} of {}{})",
            g.lobe.name(),
            g.sample + 1,
            g.count,
            if g.transmitted { ", through" } else { "" }
        ),
    );
    r.row("pdf", num(g.pdf));
    r.row("BSDF / cos", format!("{} / {}", rgb(g.bsdf), num(g.cos)));
}

/// What the path integrator recorded (docs/path-tracing.md).
fn path_rows(r: &mut Rows, pi: &PathInfo) {
    r.row("light path (LPE)", pi.lpe.clone());
    if let Some(lobe) = pi.lobe {
        r.row("sampled lobe", lobe.name().to_string());
    }
    if let Some(pdf) = &pi.pdf {
        r.row(
            "pdf",
            match pdf {
                crate::tree::Pdf::Density(p) => format!("{} /sr", num(*p)),
                crate::tree::Pdf::Delta(_) => "delta".to_owned(),
            },
        );
    }
    if let Some(w) = pi.bsdf_cos_pdf {
        r.row("f cos / pdf", rgb(w));
    }
    if let Some(m) = pi.mis_weight {
        r.row("MIS weight", num(m));
    }
    if let Some(ro) = &pi.roulette {
        let outcome = if ro.survived { "survived" } else { "killed" };
        r.row(
            "Russian roulette",
            format!("q {} {outcome}", num(ro.probability)),
        );
    }
    r.row("contribution", rgb(pi.contribution));
}

/// A shadow ray: its light, the sample and what blocked it.
fn shadow_rows(r: &mut Rows, s: &ShadowInfo) {
    r.row("light", format!("{} (#{})", s.light_name, s.light));
    r.row("light distance", num(s.distance));
    r.row("cos theta", with_deg(s.cos_theta, "theta"));
    r.row("BRDF", rgb(s.brdf));
    if let Some(a) = &s.area {
        // An area-light sample: the emitted radiance, its solid-angle pdf and the
        // Monte Carlo weight L / pdf (not an irradiance).
        r.row("sampled point", vec3(a.point));
        r.row("emitted radiance L", rgb(a.radiance));
        r.row("pdf (solid angle)", num(a.pdf));
        r.row("L / pdf", rgb(s.irradiance));
    } else {
        r.row("irradiance", rgb(s.irradiance));
    }
    r.row("transmittance", rgb(s.transmittance));
    for b in &s.blockers {
        r.row(
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
