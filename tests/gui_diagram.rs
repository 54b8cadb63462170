//! The diagram panel's controls (issue 17) through egui_kittest: zoom and pan, draw depth,
//! ray kinds, label depth, contribution threshold, plane through the selected ray, sample
//! choice, export without the selection highlight.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raytree::RayKind;
use raytree::diagram::{Diagram, PlaneSpec};
use raytree::gui::model::diagram::{diagram_options, export_options};
use raytree::gui::model::export::ExportKind;
use raytree::gui::{InspectorApp, Session};
use std::sync::Arc;

mod gui_support;
use gui_support::*;

const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// The classic scene at 320x180 with `spp` samples; (200, 100) is on the glass ball.
fn harness(files: &MemFiles, spp: u32) -> Harness<'static, InspectorApp> {
    files.put("scenes/classic.json", CLASSIC);
    let adjust = Box::new(move |s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(320, 180);
        s.settings.spp = spp;
        Ok(())
    });
    let session = Session::new(
        Some("scenes/classic.json".into()),
        Box::new(files.clone()),
        adjust,
        Arc::new(|| {}),
    );
    let mut h = inspector(session);
    settle(&mut h);
    click_pixel(&mut h, 200, 100);
    h
}

/// The panel shows what a fresh build of its options gives, and that build.
fn shown(h: &Harness<'static, InspectorApp>) -> Diagram {
    let (size, prims) = h.state().diagram_display_list().expect("a diagram");
    let doc = &h.state().session.doc;
    let fresh = raytree::gui::model::diagram::build_display_list(doc, size).unwrap();
    assert!(prims == fresh.as_slice(), "the panel shows its options");
    Diagram::build(
        &doc.scene,
        doc.tree.as_ref().unwrap(),
        &diagram_options(doc, size),
    )
    .unwrap()
}

/// A point in the middle of the figure (below the panel's controls).
fn figure_point(h: &Harness<'static, InspectorApp>) -> egui::Pos2 {
    let top = h.get_by_label("highlight in exports").rect().bottom();
    egui::pos2(750.0, (top + 950.0) * 0.5)
}

#[test]
fn scroll_zooms_about_the_cursor_drag_pans_double_click_resets() {
    let files = MemFiles::default();
    let mut h = harness(&files, 1);
    let before = shown(&h);
    let p = figure_point(&h);
    h.hover_at(p);
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 120.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Unknown,
        modifiers: egui::Modifiers::NONE,
    });
    for _ in 0..10 {
        h.step();
    }
    h.run();
    let v = h.state().session.doc.view.diagram;
    assert!(v.zoom > 1.2, "zoom {}", v.zoom);
    let zoomed = shown(&h);
    assert!(zoomed.frame.scale > 1.2 * before.frame.scale);
    // Drag pans: the figure moves with the pointer.
    let q = zoomed.frame.canvas_center;
    h.drag_at(p);
    h.hover_at(p + egui::vec2(100.0, 0.0));
    h.run();
    h.drop_at(p + egui::vec2(100.0, 0.0));
    h.run();
    let panned = shown(&h);
    let moved = panned.frame.plane_to_canvas(zoomed.frame.plane_center) - q;
    assert!(
        (moved.x - 100.0).abs() < 25.0 && moved.y.abs() < 5.0,
        "{moved}"
    );
    // "reset view" (and double-click) go back to the automatic framing.
    h.get_by_label("reset view").click();
    h.run();
    let v = h.state().session.doc.view.diagram;
    assert_eq!((v.zoom, v.pan), (1.0, [0.0, 0.0]));
    assert_eq!(shown(&h).frame, before.frame);
}

#[test]
fn depth_kinds_labels_and_threshold_controls_change_the_figure() {
    let files = MemFiles::default();
    let mut h = harness(&files, 1);
    let d = shown(&h);
    assert!(d.rays.iter().any(|r| r.kind == RayKind::Refracted));
    assert!(d.dropped_rays > 0, "the default threshold leaves rays out");
    // Ray kinds.
    h.get_by_role_and_label(Role::CheckBox, "refracted").click();
    h.run();
    let d = shown(&h);
    assert!(!d.rays.iter().any(|r| r.kind == RayKind::Refracted));
    h.get_by_role_and_label(Role::CheckBox, "refracted").click();
    h.run();
    // Draw depth.
    h.get_by_label("limit depth").click();
    h.run();
    h.get_by_role_and_label(Role::Slider, "draw depth")
        .set_value_accesskit(0.0);
    h.run();
    let d = shown(&h);
    assert!(d.rays.iter().all(|r| r.depth == 0) && !d.rays.is_empty());
    h.get_by_label("limit depth").click();
    h.run();
    // Label depth: no angle labels at 0 below the camera ray.
    let angles = |d: &Diagram| d.labels.iter().filter(|l| l.text.starts_with("θ")).count();
    let many = angles(&shown(&h));
    h.get_by_role_and_label(Role::Slider, "label depth")
        .set_value_accesskit(0.0);
    h.run();
    assert!(angles(&shown(&h)) < many, "{many}");
    // Threshold 0: every ray.
    h.get_by_role_and_label(Role::Slider, "min share %")
        .set_value_accesskit(0.0);
    h.run();
    let d = shown(&h);
    let nodes = h.state().session.doc.tree.as_ref().unwrap().nodes.len();
    assert_eq!((d.rays.len(), d.dropped_rays), (nodes, 0));
}

#[test]
fn the_plane_follows_the_selected_ray() {
    let files = MemFiles::default();
    let mut h = harness(&files, 1);
    h.get_by_label("selected ray").click();
    h.run();
    // Select a refracted ray below the camera ray's: the plane goes through it.
    let tree = h.state().session.doc.tree.clone().unwrap();
    let id = tree
        .nodes
        .iter()
        .find(|n| n.kind == RayKind::Refracted && n.depth == 2)
        .expect("a depth-2 refracted ray")
        .id;
    let row = format!("#{} refracted -> ", id.0);
    h.state_mut().expand_all();
    h.run();
    h.get_by_label_contains(&row).scroll_to_me();
    h.run();
    h.get_by_label_contains(&row).click();
    h.run();
    assert_eq!(h.state().session.doc.node, Some(id));
    let doc = &h.state().session.doc;
    assert_eq!(diagram_options(doc, [900, 300]).plane, PlaneSpec::Ray(id));
    let d = shown(&h);
    let r = d.rays.iter().find(|r| r.node == id).expect("drawn");
    assert!(r.plane_distance.iter().all(|x| x.abs() < 1e-6));
    assert!(
        d.plane_text.contains(&format!("ray #{}", id.0)),
        "{}",
        d.plane_text
    );
}

#[test]
fn sample_choice_and_export_without_the_highlight() {
    use raytree::gui::model::document::Command;
    let files = MemFiles::default();
    let mut h = harness(&files, 4);
    let tree = h.state().session.doc.tree.clone().unwrap();
    assert_eq!(tree.samples.len(), 4);
    // The figure follows the selection's sample.
    let sel = tree.samples[2].root;
    h.state_mut().session.apply(Command::SelectNode(Some(sel)));
    h.run();
    let d = shown(&h);
    assert_eq!(d.rays[0].node, sel, "the figure draws sample 2");
    assert!(d.rays.iter().any(|r| r.highlighted));
    // Export: the selection is highlighted in the panel, not in the exported figure...
    let doc = &h.state().session.doc;
    assert_eq!(export_options(doc).highlight, None);
    assert_eq!(export_options(doc).sample, 2);
    h.state_mut()
        .session
        .apply(Command::Export(ExportKind::DiagramSvg));
    h.run();
    let svg = files
        .get("scenes/classic-diagram-200-100.svg")
        .expect("exported");
    // ... unless asked for (the checkbox itself: `the_export_highlight_checkbox_sets_it`).
    let mut v = h.state().session.doc.view;
    v.diagram.export_highlight = true;
    h.state_mut().session.apply(Command::SetView(v));
    h.run();
    assert_eq!(export_options(&h.state().session.doc).highlight, Some(sel));
    h.state_mut()
        .session
        .apply(Command::Export(ExportKind::DiagramSvg));
    h.run();
    let marked = files.get("scenes/classic-diagram-200-100.svg").unwrap();
    assert_ne!(marked, svg, "the highlight changes the export");
    // The sample slider picks another sample.
    h.get_by_role_and_label(Role::Slider, "sample")
        .set_value_accesskit(1.0);
    h.run();
    assert_eq!(h.state().session.doc.view.diagram.sample, Some(1));
    assert_eq!(shown(&h).rays[0].node, tree.samples[1].root);
}

#[test]
fn the_export_highlight_checkbox_sets_it() {
    let files = MemFiles::default();
    let mut h = harness(&files, 1);
    assert!(!h.state().session.doc.view.diagram.export_highlight);
    h.get_by_label("highlight in exports").click();
    h.run();
    assert!(h.state().session.doc.view.diagram.export_highlight);
}

/// The settings panel switches to the path tracer; its sampled diffuse bounces (the fifth ray
/// kind) are drawn in the diagram and have their own kind checkbox (the panel once kept four
/// kinds and dropped them).
#[test]
fn the_path_integrator_is_chosen_in_the_panel_and_its_diffuse_rays_drawn() {
    let files = MemFiles::default();
    let mut h = harness(&files, 1);
    // The Whitted integrator's own settings: enabled under Whitted, disabled under path.
    // (The min weight's "auto" box; the roulette's, shown under Whitted only, comes after it.)
    let disabled = |h: &Harness<'static, InspectorApp>| {
        let auto = h.get_all_by_role_and_label(Role::CheckBox, "auto").next();
        [
            h.get_by_label("Fresnel").accesskit_node().is_disabled(),
            h.get_by_label("translucent").accesskit_node().is_disabled(),
            auto.expect("the min weight's auto box")
                .accesskit_node()
                .is_disabled(),
        ]
    };
    assert_eq!(disabled(&h), [false, false, false]);
    h.get_by_label("integrator").click();
    h.run();
    h.get_by_label("path").click();
    settle(&mut h);
    assert_eq!(disabled(&h), [true, true, true]);
    assert_eq!(
        h.state().session.doc.scene.settings.integrator,
        raytree::scene::IntegratorKind::Path
    );
    let _ = h.get_by_role_and_label(Role::Slider, "roulette from bounce");
    click_pixel(&mut h, 200, 100);
    let tree = h.state().session.doc.tree.clone().expect("a tree");
    assert!(tree.nodes.iter().any(|n| n.path.is_some()));
    let diffuse = tree.count_by_kind()[RayKind::Diffuse as usize];
    assert!(diffuse > 0, "the glass pixel's path bounces off the floor");
    h.get_by_role_and_label(Role::Slider, "min share %")
        .set_value_accesskit(0.0);
    h.run();
    let d = shown(&h);
    assert_eq!(
        d.rays.iter().filter(|r| r.kind == RayKind::Diffuse).count(),
        diffuse
    );
    h.get_by_role_and_label(Role::CheckBox, "diffuse").click();
    h.run();
    assert!(!shown(&h).rays.iter().any(|r| r.kind == RayKind::Diffuse));
}
