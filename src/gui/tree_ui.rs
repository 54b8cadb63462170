//! The tree panel (collapsible ray tree), the details pane (every recorded field of the selected
//! node) and the contribution breakdown.

use super::breakdown::breakdown;
use super::document::{Command, Document};
use super::style::{SELECTED, dot, kind_colour, num, rgb, square, swatch, vec3};
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use egui::RichText;
use egui::collapsing_header::CollapsingState;

/// Trees open by default down to this depth.
const OPEN_DEPTH: u32 = 3;

/// One line describing a node: the label the tree shows and tests query.
#[must_use]
pub fn node_label(n: &RayNode) -> String {
    let target = match (&n.hit, &n.shadow) {
        (_, Some(s)) => format!("{} ({:?})", s.light_name, n.end).to_lowercase(),
        (Some(h), None) => format!("{} t={}", h.object_name, num(h.t)),
        (None, None) => "miss".to_string(),
    };
    let rt = n
        .interface
        .as_ref()
        .map(|i| {
            if i.tir {
                "  TIR".to_string()
            } else {
                format!("  R={:.3} T={:.3}", i.fresnel.r, i.fresnel.t)
            }
        })
        .unwrap_or_default();
    format!(
        "#{} {} -> {target}{rt}  w={}  c={}",
        n.id.0,
        n.kind.name(),
        num(n.weight.max_element()),
        num(n.contribution().max_element())
    )
}

/// The collapsible tree of every sample.
pub fn tree_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let Some(tree) = &doc.tree else {
        ui.label("Click a pixel to trace its ray tree.");
        return;
    };
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("pixel {}, {}", tree.pixel[0], tree.pixel[1])).strong());
        square(ui, swatch(tree.radiance));
        ui.monospace(rgb(tree.radiance));
    });
    let [c, r, t, s] = tree.count_by_kind();
    ui.small(format!(
        "{} rays: {c} camera, {r} reflected, {t} refracted, {s} shadow",
        tree.nodes.len()
    ));
    egui::ScrollArea::both()
        .id_salt("tree-scroll")
        .auto_shrink([false, true])
        .max_height(ui.available_height() * 0.5)
        .show(ui, |ui| {
            for sample in &tree.samples {
                if tree.samples.len() > 1 {
                    ui.small(format!(
                        "sample {} at ({:.3}, {:.3})",
                        sample.index, sample.film[0], sample.film[1]
                    ));
                }
                node_ui(ui, tree, sample.root, doc.node, cmds);
            }
        });
}

fn node_ui(
    ui: &mut egui::Ui,
    tree: &RayTree,
    id: NodeId,
    selected: Option<NodeId>,
    cmds: &mut Vec<Command>,
) {
    let n = tree.node(id);
    let header = |ui: &mut egui::Ui, cmds: &mut Vec<Command>| {
        dot(ui, kind_colour(n.kind));
        let is_sel = selected == Some(id);
        let text = RichText::new(node_label(n)).monospace();
        let text = if is_sel { text.color(SELECTED) } else { text };
        if ui.selectable_label(is_sel, text).clicked() {
            cmds.push(Command::SelectNode(Some(id)));
        }
    };
    if n.children.is_empty() {
        ui.horizontal(|ui| {
            ui.add_space(ui.spacing().indent);
            header(ui, cmds);
        });
        return;
    }
    let key = ui.make_persistent_id(("ray-node", tree.pixel, id.0));
    CollapsingState::load_with_default_open(ui.ctx(), key, n.depth < OPEN_DEPTH)
        .show_header(ui, |ui| header(ui, cmds))
        .body(|ui| {
            for &c in &n.children {
                node_ui(ui, tree, c, selected, cmds);
            }
        });
}

/// Every recorded field of the selected node.
pub fn details_ui(ui: &mut egui::Ui, doc: &Document) {
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
        .show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.monospace(v);
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
                row("cos_i", num(h.cos_i));
            }
            if let Some(i) = &n.interface {
                row("n1 -> n2", format!("{} -> {}", num(i.n1), num(i.n2)));
                row(
                    "cos_i / cos_t",
                    format!(
                        "{} / {}",
                        num(i.cos_i),
                        i.cos_t.map_or("- (TIR)".into(), num)
                    ),
                );
                row(
                    "Fresnel R / T",
                    format!("{} / {}", num(i.fresnel.r), num(i.fresnel.t)),
                );
                row("TIR", i.tir.to_string());
            }
            if let Some(a) = &n.attenuation {
                row("medium", format!("#{}", a.medium));
                row("distance", num(a.distance));
                row("absorption", rgb(a.absorption));
                row("Beer factor", rgb(a.factor));
            }
            row("weight", rgb(n.weight));
            row("throughput", rgb(n.throughput));
            row("emitted", rgb(n.emitted));
            row("ambient", rgb(n.ambient));
            row("local", rgb(n.local));
            row("radiance", rgb(n.radiance));
            row("contribution", rgb(n.contribution()));
            row("truncated", rgb(n.truncated));
            row("end", format!("{:?}", n.end));
            if let Some(s) = &n.shadow {
                row("light", format!("{} (#{})", s.light_name, s.light));
                row("light distance", num(s.distance));
                row("cos theta", num(s.cos_theta));
                row("BRDF", rgb(s.brdf));
                row("irradiance", rgb(s.irradiance));
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

/// How the pixel value adds up; clicking a term selects its node.
pub fn breakdown_ui(ui: &mut egui::Ui, doc: &Document, cmds: &mut Vec<Command>) {
    let Some(tree) = &doc.tree else { return };
    let terms = breakdown(tree);
    let total = tree.radiance.element_sum().max(1e-12);
    egui::Grid::new("breakdown")
        .striped(true)
        .num_columns(3)
        .show(ui, |ui| {
            for t in &terms {
                let share = t.value.element_sum() / total;
                let kind = tree.node(t.node).kind;
                let colour = if doc.node == Some(t.node) {
                    SELECTED
                } else {
                    kind_colour(kind)
                };
                if ui
                    .selectable_label(
                        doc.node == Some(t.node),
                        RichText::new(&t.label).color(colour),
                    )
                    .clicked()
                {
                    cmds.push(Command::SelectNode(Some(t.node)));
                }
                ui.monospace(rgb(t.value));
                ui.label(format!("{:5.1}%", share * 100.0));
                ui.end_row();
            }
            ui.label(RichText::new("pixel").strong());
            ui.monospace(rgb(tree.radiance));
            ui.label("100%");
            ui.end_row();
        });
    let shadows = tree
        .nodes
        .iter()
        .filter(|n| n.kind == RayKind::Shadow)
        .count();
    ui.small(format!(
        "local = emitted + ambient + direct light from {shadows} shadow rays"
    ));
}
