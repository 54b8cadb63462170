//! The inspector's defects found in issue 17 (items 1-6 and 8), each pinned by a kittest that
//! failed before its fix: the diagram panel after a reload, epsilon 0, the tree's `c=` column,
//! panel sizes, deep rows, the overlay, the hover readout and legend, a scene that fails on
//! start. Real `InspectorApp`, in-memory files, the worker waited on (no sleeps).

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raytree::gui::model::stats::DebugView;
use raytree::gui::{InspectorApp, Session};
use std::sync::Arc;

mod gui_support;
use gui_support::*;

#[test]
fn the_diagram_panel_shows_the_reloaded_scene() {
    // Issue 17.1: the panel's cache key restarted with the rebuilt document, so after a reload
    // it kept the old scene's figure while the export showed the new one.
    let files = MemFiles::default();
    let mut h = classic_harness(&files);
    click_pixel(&mut h, GLASS.0, GLASS.1);
    let same = |h: &Harness<'static, InspectorApp>| {
        let (size, prims) = h.state().diagram_display_list().expect("a diagram");
        let fresh = raytree::gui::model::diagram::build_display_list(&h.state().session.doc, size)
            .expect("builds");
        prims == fresh.as_slice()
    };
    assert!(same(&h));
    let clear = CLASSIC.replace("\"ior\": 1.5", "\"ior\": 1.0");
    assert_ne!(clear, CLASSIC);
    files.put("scenes/classic.json", &clear);
    assert!(h.state_mut().session.poll_reload());
    settle(&mut h);
    assert_eq!(h.state().session.doc.selection, Some([GLASS.0, GLASS.1]));
    assert!(same(&h), "the panel shows the reloaded scene's diagram");
}

#[test]
fn epsilon_zero_is_kept_and_the_self_hits_view_shows_the_acne() {
    // Issue 17.2: the slider clamped at 1e-9 and reset `--epsilon 0 --offset ray` to 1e-9.
    let files = MemFiles::default();
    let mut h = classic_harness_with(&files, CLASSIC, |s| {
        s.settings.offset.epsilon = 0.0;
        s.settings.offset.strategy = raytree::scene::OffsetStrategy::Ray;
    });
    h.run();
    let doc = &h.state().session.doc;
    assert_eq!(doc.scene.settings.offset.epsilon, 0.0, "kept at 0");
    let self_hits: u32 = doc.stats.iter().map(|s| s.self_hits).sum();
    assert!(self_hits > 1000, "acne: {self_hits} self-hits");

    // From a positive epsilon, 0 can be set on the slider (its value field takes 0 typed).
    let mut h = classic_harness(&files);
    assert!(h.state().session.doc.scene.settings.offset.epsilon > 0.0);
    h.get_by_role_and_label(Role::Slider, "epsilon")
        .set_value_accesskit(0.0);
    settle(&mut h);
    assert_eq!(h.state().session.doc.scene.settings.offset.epsilon, 0.0);
}

/// The number after `key=` in a tree row's label.
fn field(label: &str, key: &str) -> f64 {
    let at = label
        .find(key)
        .unwrap_or_else(|| panic!("{key} in {label}"))
        + key.len();
    let rest = &label[at..];
    let end = rest.find(' ').unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|_| panic!("{key} in {label}"))
}

#[test]
fn tree_rows_give_each_rays_share_of_the_pixel() {
    // Issue 17.3: shadow rows showed the light's irradiance (2.08 for a 0.25 pixel), and
    // weights printed rounding residues such as 4.279e-30.
    let files = MemFiles::default();
    let mut h = classic_harness(&files);
    click_pixel(&mut h, GLASS.0, GLASS.1);
    h.state_mut().expand_all();
    h.run();
    let doc = &h.state().session.doc;
    let tree = doc.tree.as_ref().unwrap();
    let pixel = tree.radiance.max_element();
    let mut shadows = 0;
    for n in tree.nodes.iter().take(12) {
        let label = format!("#{} {} -> ", n.id.0, n.kind.name());
        let node = h.get_by_label_contains(&label);
        let text = node.accesskit_node().label().unwrap_or_default();
        assert!(!text.contains("e-30"), "{text}");
        let c = field(&text, "c=");
        let want = raytree::gui::model::breakdown::pixel_contribution(tree, n.id).max_element();
        assert!((c - want).abs() <= 1e-4 * want.max(1.0), "{text}: {want}");
        assert!(
            c <= pixel + 1e-4,
            "{text}: no ray gives more than the pixel {pixel}"
        );
        assert!((field(&text, "w=") - n.weight.max_element()).abs() < 1e-4);
        shadows += usize::from(n.kind == raytree::tree::RayKind::Shadow);
    }
    assert!(shadows >= 2);
}

#[test]
fn panels_keep_their_size_with_long_rows() {
    // Issue 17.4: a long row widened the right panel over the others and moved the image.
    let files = MemFiles::default();
    let long = "glass ball whose name goes on and on well past the width of any panel";
    let scene = CLASSIC.replace("\"name\": \"glass ball\"", &format!("\"name\": \"{long}\""));
    assert_ne!(scene, CLASSIC);
    let mut h = classic_harness_with(&files, &scene, |_| {});
    let edge = |h: &Harness<'static, InspectorApp>| h.get_by_label("Ray tree").rect().left();
    let before = (edge(&h), h.state().placement().unwrap());
    click_pixel(&mut h, GLASS.0, GLASS.1);
    h.state_mut().expand_all();
    h.run();
    // Select the blocked shadow ray (its details name the long blocker) and a deep ray.
    let tree = h.state().session.doc.tree.clone().unwrap();
    let blocked = tree
        .nodes
        .iter()
        .find(|n| n.end == raytree::tree::EndReason::Blocked)
        .unwrap();
    for id in [blocked.id, raytree::NodeId(tree.nodes.len() as u32 - 1)] {
        h.state_mut()
            .session
            .apply(raytree::gui::Command::SelectNode(Some(id)));
        h.run();
        h.run();
        assert_eq!(edge(&h), before.0, "the tree panel keeps its width");
        assert_eq!(
            h.state().placement().unwrap(),
            before.1,
            "the image stays put"
        );
    }
    assert!(has(&h, long), "the long name is in the details");
}

#[test]
fn expand_all_below_and_breakdown_terms_reveal_deep_rays() {
    // Issue 17.5: a depth-16 chain took 16 clicks to open; a breakdown term selected a node
    // hidden in collapsed levels; the last row could not be clicked.
    let files = MemFiles::default();
    let mut h = classic_harness(&files);
    click_pixel(&mut h, GLASS.0, GLASS.1);
    let nodes = h.state().session.doc.tree.as_ref().unwrap().nodes.len();
    assert!(h.state().tree_rows() < nodes);
    h.get_by_label("collapse all").click();
    h.run();
    assert_eq!(h.state().tree_rows(), 1);
    h.get_by_label("expand all below").click();
    h.run();
    assert_eq!(
        h.state().tree_rows(),
        nodes,
        "every level open in one click"
    );

    // A breakdown term of a deep ray opens its levels and scrolls the tree to it.
    h.get_by_label("collapse all").click();
    h.run();
    let tree = h.state().session.doc.tree.clone().unwrap();
    let terms = raytree::gui::model::breakdown::breakdown(&tree);
    let deep = terms
        .iter()
        .take(20)
        .max_by_key(|t| tree.node(t.node).depth)
        .unwrap();
    assert!(tree.node(deep.node).depth >= 3);
    // (The breakdown is below the details: scroll it into view first.)
    h.get_by_label(&deep.label).scroll_to_me();
    h.run();
    h.get_by_label(&deep.label).click();
    h.run();
    h.run();
    assert_eq!(h.state().session.doc.node, Some(deep.node));
    let row = format!("#{} {} -> ", deep.node.0, tree.node(deep.node).kind.name());
    let rect = h.get_by_label_contains(&row).rect();
    let list = h.get_by_label("expand all below").rect();
    assert!(
        rect.top() > list.bottom() && rect.bottom() < 950.0,
        "{rect:?} on screen"
    );

    // The last row, scrolled to the bottom of the list with the wheel, takes the click.
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SelectNode(Some(raytree::NodeId(0))));
    h.run();
    h.get_by_label("expand all below").click();
    h.run();
    let last = raytree::NodeId(nodes as u32 - 1);
    let list = h.get_by_label_contains("#0 camera -> ").rect();
    h.hover_at(list.center());
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, -20_000.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Unknown,
        modifiers: egui::Modifiers::NONE,
    });
    h.run();
    let row = format!("#{} {} -> ", last.0, tree.node(last).kind.name());
    h.get_by_label_contains(&row).hover();
    h.run();
    h.get_by_label_contains(&row).click();
    h.run();
    assert_eq!(
        h.state().session.doc.node,
        Some(last),
        "the last row was clicked"
    );
}

#[test]
fn the_overlay_draws_one_sample_inside_the_image() {
    // Issue 17.6: every ray of every sample was drawn, and past the image's edges.
    let files = MemFiles::default();
    let mut h = classic_harness_with(&files, CLASSIC, |s| s.settings.spp = 4);
    click_pixel(&mut h, GLASS.0, GLASS.1);
    h.run();
    let tree = h.state().session.doc.tree.clone().unwrap();
    assert_eq!(tree.samples.len(), 4);
    let first = tree.depth_first(tree.samples[0].root).len();
    let drawn = h.state().overlay_rays();
    assert!(drawn > 0 && drawn <= first, "{drawn} of {first}");
    // Selecting a ray of another sample draws that sample.
    let root = tree.samples[3].root;
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SelectNode(Some(root)));
    h.run();
    assert!(h.state().overlay_rays() <= tree.depth_first(root).len());
}

#[test]
fn the_hover_readout_legend_and_errors_stay_readable() {
    // Issue 17.8.
    let files = MemFiles::default();
    let mut h = classic_harness(&files);
    // The readout is laid out in its own box inside the image area.
    let pos = h.state().screen_of_pixel(100, 60).unwrap();
    h.hover_at(pos);
    h.run();
    let readout = h.get_by_label_contains("boxes + primitive tests").rect();
    let image = h.state().placement().unwrap().rect;
    assert!(readout.left() >= image.left() - 1.0 && readout.width() > 100.0);
    // The debug legend sits under the image, not over it.
    let mut view = h.state().session.doc.view;
    view.debug = DebugView::Depth;
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SetView(view));
    settle(&mut h);
    let place = h.state().placement().unwrap();
    let legend = place.legend.expect("a legend");
    let diagram = h.get_by_label("Diagram").rect().top();
    assert!(
        !legend.intersects(place.rect),
        "{legend:?} over {:?}",
        place.rect
    );
    assert!(legend.bottom() <= diagram, "{legend:?} vs {diagram}");
    // An export error is shown whole, once.
    files.fail_writes("read-only file system");
    h.get_by_label("image PNG").click();
    h.run();
    let err = h
        .state()
        .session
        .doc
        .export_error
        .clone()
        .expect("an error");
    assert_eq!(err.matches("cannot write").count(), 1, "{err}");
    assert!(has(&h, "read-only file system"));
}

#[test]
fn a_scene_that_fails_on_start_keeps_its_name_and_error() {
    let files = MemFiles::default();
    files.put("scenes/bad.json", "{ not json");
    let session = Session::new(
        Some("scenes/bad.json".into()),
        Box::new(files.clone()),
        Box::new(|_| Ok(())),
        Arc::new(|| {}),
    );
    assert_eq!(session.doc.path_field, "scenes/bad.json");
    let mut h = inspector(session);
    settle(&mut h);
    assert!(has(&h, "scenes/bad.json:1:"), "the error names the file");
    assert!(has(&h, "scenes/bad.json did not load"));
}

/// Issue 32 item 5: the Scene section's tree-growth line stays (greyed) while the next render
/// runs, so the controls below it do not move up and back (a click meant for one control hit
/// another).
#[test]
fn the_layout_does_not_jump_while_rendering() {
    let files = MemFiles::default();
    let mut h = classic_harness(&files);
    assert!(
        h.state().session.doc.progress.growth.is_some(),
        "a growth line"
    );
    let top = |h: &Harness<'static, InspectorApp>| h.get_by_label("integrator").rect().top();
    let before = top(&h);
    let mut settings = h.state().session.doc.scene.settings;
    settings.max_depth -= 1;
    h.state_mut()
        .session
        .apply(raytree::gui::model::document::Command::SetSettings(
            settings,
        ));
    h.step();
    let doc = &h.state().session.doc;
    assert!(
        doc.progress.growth.is_some(),
        "the line is kept while rendering"
    );
    assert!((top(&h) - before).abs() < 0.5, "{} -> {}", before, top(&h));
    settle(&mut h);
    assert!(h.state().session.doc.progress.growth_current);
}
