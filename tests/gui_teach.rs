//! The inspector's teaching panels (issue 17, "new capabilities") driven through
//! egui_kittest: Explain, the teacher-facing Details, pin and compare, step along a ray and the
//! acne lab. Real `InspectorApp`, in-memory files, the worker waited on (no sleeps).

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raytree::gui::{Command, InspectorApp, Session};
use raytree::tree::{NodeId, RayKind};
use std::sync::Arc;

mod gui_support;
use gui_support::*;

const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// `scene` (JSON text) at 320x180 in the inspector, rendered.
fn harness_on(scene: &str) -> Harness<'static, InspectorApp> {
    let files = MemFiles::default();
    files.put("scenes/s.json", scene);
    let session = Session::new(
        Some("scenes/s.json".into()),
        Box::new(files),
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(320, 180);
            Ok(())
        }),
        Arc::new(|| {}),
    );
    let mut h = inspector(session);
    settle(&mut h);
    h
}

fn select_pixel(h: &mut Harness<'static, InspectorApp>, x: u32, y: u32) {
    h.state_mut().session.apply(Command::SelectPixel([x, y]));
    h.run();
}

fn select_node(h: &mut Harness<'static, InspectorApp>, id: NodeId) {
    h.state_mut().session.apply(Command::SelectNode(Some(id)));
    h.run();
    h.run();
}

/// Scroll the widget labelled `label` into view and click it.
fn click(h: &mut Harness<'static, InspectorApp>, label: &str) {
    h.get_by_label(label).scroll_to_me();
    h.run();
    h.get_by_label(label).click();
    h.run();
}

fn has(h: &Harness<'static, InspectorApp>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}

/// A glass-ball pixel of the classic scene at 320x180 (400,200 at 640x360).
const GLASS: [u32; 2] = [200, 100];

#[test]
fn explain_sentences_select_and_reveal_their_nodes() {
    let mut h = harness_on(CLASSIC);
    assert!(has(&h, "Click a pixel to explain it."));
    select_pixel(&mut h, GLASS[0], GLASS[1]);
    let e = h.state().explanation().expect("explained").clone();
    let tree = h.state().session.doc.tree.clone().unwrap();
    assert_eq!(
        e,
        raytree::analysis::explain::explain(&tree, &h.state().session.doc.scene)
    );
    assert!(has(&h, "what it sees") && has(&h, "where energy went"));
    // The floor seen through the glass: a deep node, collapsed in the tree at first.
    let s = e
        .sentences
        .iter()
        .find(|s| s.text.starts_with("floor seen through the glass ball"))
        .expect("the floor through the glass");
    let target = s.nodes[0];
    assert!(tree.node(target).depth >= 2, "a ray below the camera ray");
    h.get_by_role_and_label(Role::Button, "collapse all")
        .click();
    h.run();
    let row = format!("#{} {} -> ", target.0, tree.node(target).kind.name());
    assert!(!has(&h, &row), "hidden before the click");
    let link = format!("{}  (#{})", s.text, target.0);
    h.get_by_label(&link).scroll_to_me();
    h.run();
    h.get_by_label(&link).click();
    h.run();
    h.run();
    assert_eq!(h.state().session.doc.node, Some(target));
    let rect = h.get_by_label_contains(&row).rect();
    let list = h.get_by_label("expand all below").rect();
    assert!(
        rect.top() > list.bottom() && rect.bottom() < 950.0,
        "{rect:?} revealed"
    );
    // The blocked shadow rays' sentence lists its ids as buttons; one selects that ray.
    let blocked = e
        .sentences
        .iter()
        .find(|s| s.text.contains("shadow rays blocked"))
        .expect("blocked shadow rays");
    let second = blocked.nodes[1];
    h.get_by_label(&format!("#{}", second.0)).scroll_to_me();
    h.run();
    h.get_by_label(&format!("#{}", second.0)).click();
    h.run();
    assert_eq!(h.state().session.doc.node, Some(second));
    assert_eq!(tree.node(second).kind, RayKind::Shadow);
}

#[test]
fn details_give_degrees_the_critical_angle_weight_factors_and_medium_names() {
    let mut h = harness_on(CLASSIC);
    select_pixel(&mut h, GLASS[0], GLASS[1]);
    // The glass ball's reflected ray: its weight is R x transmissivity.
    select_node(&mut h, NodeId(2));
    assert!(has(&h, "#2 reflected ray"));
    assert!(has(&h, "0.0380 = R 0.0400 x transmissivity 0.9500"));
    select_node(&mut h, NodeId(0));
    let tree = h.state().session.doc.tree.clone().unwrap();
    let i = tree.nodes[0].interface.clone().unwrap();
    let deg = |c: f64| c.acos().to_degrees();
    let want = format!("{:.4} (theta_i {:.2} deg)", i.cos_i, deg(i.cos_i));
    assert!(has(&h, &want), "degrees beside the cosine: {want}");
    assert!(has(
        &h,
        &format!("theta_t {:.2} deg", deg(i.cos_t.unwrap()))
    ));
    assert!(has(&h, "(n 1.000 -> 1.500, no critical angle)"));

    // Total internal reflection in the TIR block, with the critical angle.
    let mut h = harness_on(include_str!("../fixtures/tir-block.json"));
    select_pixel(&mut h, 160, 115);
    let tree = h.state().session.doc.tree.clone().unwrap();
    let tir = tree
        .nodes
        .iter()
        .find(|n| n.interface.as_ref().is_some_and(|i| i.tir))
        .expect("TIR at the block's side");
    select_node(&mut h, tir.id);
    assert!(has(&h, "> theta_c 41.8 deg: total internal reflection"));

    // Beer's law names its medium.
    let mut h = harness_on(include_str!("../fixtures/absorption.json"));
    let doc = &h.state().session.doc;
    let (w, hh) = (doc.image.width, doc.image.height);
    let scene = doc.scene.clone();
    let found = (0..hh)
        .step_by(6)
        .flat_map(|y| (0..w).step_by(6).map(move |x| (x, y)))
        .find_map(|(x, y)| {
            let t = raytree::trace_pixel(&scene, x, y)?;
            let n = t.nodes.iter().find(|n| {
                n.attenuation
                    .as_ref()
                    .is_some_and(|a| a.factor != raytree::math::Rgb::ONE)
            })?;
            Some(([x, y], n.id, n.attenuation.as_ref()?.medium))
        });
    let ([x, y], id, medium) = found.expect("a Beer segment");
    select_pixel(&mut h, x, y);
    select_node(&mut h, id);
    let name = &scene.objects[medium].name;
    assert!(has(&h, &format!("{name} (#{medium})")), "{name}");
}

#[test]
fn pin_and_compare_shows_the_first_divergence_and_the_changed_numbers() {
    let mut h = harness_on(CLASSIC);
    select_pixel(&mut h, GLASS[0], GLASS[1]);
    h.get_by_label("pin this tree").click();
    h.run();
    assert!(h.state().session.doc.pin.is_some());
    assert!(has(&h, "Pin and compare"));
    assert!(has(&h, "no difference: the trees are identical"));
    // Schlick instead of the exact Fresnel: the camera ray's R diverges first.
    let mut s = h.state().session.doc.scene.settings;
    s.whitted.fresnel = raytree::math::FresnelModel::Schlick;
    h.state_mut().session.apply(Command::SetSettings(s));
    settle(&mut h);
    let d = h.state().compare_diff().expect("a diff").clone();
    let f = d.first_divergence.as_ref().expect("they differ");
    assert_eq!((f.a, f.b, f.level), (NodeId(0), NodeId(0), 0));
    assert!(has(&h, "settings.fresnel: exact -> schlick"));
    assert!(has(&h, "first divergence: camera #0 (level 0)"));
    let first_row = h.get_by_label_contains("[first divergence,");
    let label = first_row
        .accesskit_node()
        .label()
        .unwrap_or_default()
        .to_string();
    assert!(label.starts_with("#0 camera -> glass ball"), "{label}");
    // Its changed numbers, pinned -> current, the Fresnel R among them.
    assert!(has(&h, "interface.fresnel.r"));
    let pinned = h.state().session.doc.pin.as_ref().unwrap().tree.nodes[0]
        .interface
        .clone()
        .unwrap();
    assert!(has(&h, &format!("{:.6}", pinned.fresnel.r)));
    // Max depth 1: subtrees only the pinned tree has; a row of one is marked so.
    let mut s = h.state().session.doc.scene.settings;
    s.max_depth = 1;
    h.state_mut().session.apply(Command::SetSettings(s));
    settle(&mut h);
    let d = h.state().compare_diff().unwrap();
    assert!(!d.only_a.is_empty() && d.only_b.is_empty());
    assert!(has(&h, "[only pinned]"));
    // Another pixel against the pinned one; then unpin closes the window.
    select_pixel(&mut h, 10, 10);
    assert!(has(&h, "pixel[0]: 200 -> 10"));
    h.get_by_label("unpin").click();
    h.run();
    assert!(h.state().session.doc.pin.is_none());
    assert!(!has(&h, "Pin and compare"));
}

#[test]
fn step_along_a_ray_moves_a_point_and_reveals_one_depth_at_a_time() {
    let mut h = harness_on(CLASSIC);
    select_pixel(&mut h, GLASS[0], GLASS[1]);
    select_node(&mut h, NodeId(0));
    h.get_by_label("Step along a ray").scroll_to_me();
    h.run();
    h.get_by_label("Step along a ray").click();
    h.run();
    h.get_by_label("show the point on the overlay and the diagram")
        .scroll_to_me();
    h.run();
    h.get_by_label("show the point on the overlay and the diagram")
        .click();
    h.run();
    let doc = &h.state().session.doc;
    assert_eq!(doc.step.at, Some(1.0), "starts at the hit");
    let tree = doc.tree.clone().unwrap();
    let hit = tree.nodes[0].hit.clone().unwrap();
    let (p, t, end) = raytree::gui::panels::step::step_point(doc).unwrap();
    assert_eq!((t, end), (hit.t, hit.t));
    assert!((p - hit.point).length() < 1e-9);
    assert!(has(&h, "at t_hit"));
    assert!(has(&h, "(n 1.000 -> 1.500, no critical angle)"));
    // Halfway: R(t) = A + t d, no hit yet.
    h.get_by_role_and_label(Role::Slider, "t")
        .set_value_accesskit(hit.t / 2.0);
    h.run();
    h.run();
    let doc = &h.state().session.doc;
    let at = doc.step.at.unwrap();
    assert!((at - 0.5).abs() < 1e-9, "{at}");
    let (p, t, _) = raytree::gui::panels::step::step_point(doc).unwrap();
    let n = &tree.nodes[0];
    assert!((p - (n.origin + n.direction * t)).length() < 1e-12);
    assert!(!has(&h, "at t_hit"));
    // The recursion, one depth at a time, on the overlay and in the diagram.
    let all = h.state().overlay_rays();
    click(&mut h, "step >");
    assert_eq!(h.state().session.doc.step.depth, Some(0));
    // The camera ray and the shadow rays of its hit (they share its depth).
    let depth0 = tree.nodes.iter().filter(|n| n.depth == 0).count();
    assert!(depth0 >= 2 && tree.nodes[1].kind == RayKind::Shadow);
    assert_eq!(h.state().overlay_rays(), depth0);
    let mut last = depth0;
    for depth in 1..=2 {
        click(&mut h, "step >");
        assert_eq!(h.state().session.doc.step.depth, Some(depth));
        let drawn = h.state().overlay_rays();
        assert!(drawn > last && drawn <= all, "{drawn} at depth {depth}");
        last = drawn;
        let (size, prims) = h.state().diagram_display_list().expect("a diagram");
        let fresh =
            raytree::gui::model::diagram::build_display_list(&h.state().session.doc, size).unwrap();
        assert!(
            prims == fresh.as_slice(),
            "the diagram is cut at depth {depth}"
        );
    }
    click(&mut h, "all");
    assert_eq!(h.state().session.doc.step.depth, None);
    assert_eq!(h.state().overlay_rays(), all);
}

#[test]
fn the_acne_lab_counts_affected_pixels_and_plots_the_sweep_off_the_ui_thread() {
    let mut h = harness_on(CLASSIC);
    click(&mut h, "Acne lab");
    click(&mut h, "run the acne lab");
    h.state_mut().session.wait_lab();
    h.run();
    let lab = h.state().session.doc.lab.clone();
    assert!(lab.done && lab.started);
    assert_eq!(lab.sweep.len() + 1, raytree::gui::jobs::acne_lab::job_len());
    let c = lab.current.clone().expect("the count");
    // The scene where it is, with its own epsilon (1e-4): no acne (one pixel leaks).
    assert_eq!(c.self_hit_pixels, 0, "{c:?}");
    assert!(has(
        &h,
        &format!(
            "normal: 0 of 14400 pixels with acne (0.0%), {} with leaks",
            c.leak_pixels
        )
    ));
    assert!(has(&h, "acne sweep plot: 40 renders"));
    // A billion units out, epsilon 1e-9: acne, counted as `raytree acne` counts it.
    h.get_by_role_and_label(Role::Slider, "scene scale")
        .set_value_accesskit(1e6);
    h.run();
    h.get_by_role_and_label(Role::Slider, "distance from origin")
        .set_value_accesskit(1e3);
    h.run();
    h.get_by_role_and_label(Role::Slider, "lab epsilon")
        .set_value_accesskit(1e-9);
    h.run();
    h.state_mut().session.wait_lab();
    h.run();
    let lab = h.state().session.doc.lab.clone();
    let p = lab.params;
    assert_eq!((p.scale, p.shift, p.epsilon), (1e6, 1e3, 1e-9));
    let c = lab.current.clone().unwrap();
    let scene = h.state().session.doc.scene.clone();
    let sized = raytree::Scene {
        camera: scene.camera.with_size(160, 90),
        ..(*scene).clone()
    };
    let want = raytree::analysis::acne::cell(
        &raytree::analysis::acne::scaled_scene(&sized, 1e6, 1e3),
        p.strategy,
        1e-9,
        1e6,
    );
    assert_eq!(c.self_hit_pixels, want.self_hit_pixels);
    assert!(c.self_hit_pixels > 0, "acne far from the origin");
    assert!(has(
        &h,
        &format!("{} of 14400 pixels with acne", c.self_hit_pixels)
    ));
    // The robust strategy stays clean at every epsilon of the sweep there.
    let robust = lab
        .sweep
        .iter()
        .filter(|c| c.strategy == raytree::scene::OffsetStrategy::Robust);
    assert_eq!(robust.clone().count(), 10);
    assert!(robust.clone().all(|c| c.clean()));
}
