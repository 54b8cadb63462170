//! The inspector driven through egui_kittest: real `InspectorApp`, in-memory files, the render
//! worker waited on synchronously (no sleeps).

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use raytree::gui::export::ExportKind;
use raytree::gui::stats::DebugView;
use raytree::gui::{InspectorApp, Session};
use raytree::math::Rgb;
use std::path::Path;
use std::sync::Arc;

mod gui_support;
use gui_support::*;

const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// The classic scene at 320x180 (pixel (150, 100) hits the mirror ball).
fn harness(files: &MemFiles) -> Harness<'static, InspectorApp> {
    files.put("scenes/classic.json", CLASSIC);
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.camera = s.camera.with_size(320, 180);
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
    h
}

fn has(h: &Harness<'static, InspectorApp>, text: &str) -> bool {
    h.query_all_by_label_contains(text).next().is_some()
}

#[test]
fn clicking_a_pixel_shows_its_ray_tree() {
    let files = MemFiles::default();
    let mut h = harness(&files);
    assert!(h.state().session.doc.rendered());
    assert!(has(&h, "Click a pixel"));
    click_pixel(&mut h, 150, 100);
    assert_eq!(h.state().session.doc.selection, Some([150, 100]));
    assert!(has(&h, "#0 camera -> mirror ball"), "camera node");
    assert!(has(&h, "reflected -> floor"), "reflected node");
    assert!(has(&h, "shadow -> key light"), "shadow node");
    assert!(!has(&h, "Click a pixel"));
    // Selecting a node shows its fields in the details pane.
    h.get_by_label_contains("reflected -> floor").click();
    h.run();
    assert!(has(&h, "#2 reflected ray"));
    // Arrow keys move the selection.
    h.key_press(egui::Key::ArrowRight);
    h.run();
    assert_eq!(h.state().session.doc.selection, Some([151, 100]));
}

#[test]
fn the_diagram_panel_keeps_its_height_before_a_pixel_is_picked() {
    // egui keeps a bottom panel's height from its content: with one line of text before the
    // first click it used to stay one line tall, hiding every diagram after it.
    let files = MemFiles::default();
    let mut h = harness(&files);
    // (Measured at the panel's header: its controls take three rows above the message.)
    assert!(has(&h, "Select a pixel to see its diagram."));
    let top = |h: &Harness<'static, InspectorApp>| h.get_by_label("Diagram").rect().top();
    let before = top(&h);
    assert!(before < 950.0 - 300.0, "diagram panel starts at {before}");
    // Still that tall a few frames on, and the diagram, once there, fills it.
    h.run();
    assert_eq!(top(&h), before);
    click_pixel(&mut h, 150, 100);
    let header = top(&h);
    assert!(header <= before + 1.0, "{header} vs {before}");
}

#[test]
fn lowering_max_depth_prunes_the_tree() {
    let files = MemFiles::default();
    let mut h = harness(&files);
    click_pixel(&mut h, 150, 100);
    assert!(has(&h, "reflected -> floor"));
    let before = h.state().session.doc.tree.as_ref().unwrap().nodes.len();
    h.get_by_role_and_label(Role::Slider, "max depth")
        .set_value_accesskit(0.0);
    settle(&mut h);
    let doc = &h.state().session.doc;
    assert_eq!(doc.scene.settings.max_depth, 0);
    let after = doc.tree.as_ref().unwrap().nodes.len();
    assert!(after < before, "{after} < {before}");
    assert!(!has(&h, "reflected -> floor"));
    assert!(has(&h, "#0 camera -> mirror ball"));
    // The re-render used the new depth: the image equals a direct render at depth 0.
    let mut scene = (*h.state().session.doc.scene).clone();
    scene.settings.max_depth = 0;
    let (image, _) = raytree::render(&scene, &|_| {});
    assert!(h.state().session.doc.image.pixels == image.pixels);
}

#[test]
fn a_bad_scene_shows_its_error_and_keeps_the_last_good_image() {
    let files = MemFiles::default();
    let mut h = harness(&files);
    let good: Vec<Rgb> = h.state().session.doc.image.pixels.clone();
    assert!(good.iter().any(|p| *p != Rgb::ZERO));
    files.put("scenes/bad.json", r#"{"camera": {"position": [0, 0, 0]}}"#);
    h.get_by_role_and_label(Role::TextInput, "scene file")
        .set_text_value_accesskit("scenes/bad.json");
    h.run();
    h.get_by_label("Open").click();
    settle(&mut h);
    assert!(has(&h, "scenes/bad.json:"), "error names the file");
    let doc = &h.state().session.doc;
    assert_eq!(
        doc.source.path.as_deref(),
        Some(Path::new("scenes/classic.json"))
    );
    assert!(doc.image.pixels == good, "the last good image stays");

    // Editing the file on disk reloads it; the error goes away.
    let wider = CLASSIC.replace("\"fov_y\": 40.0", "\"fov_y\": 60.0");
    assert_ne!(wider, CLASSIC);
    files.put("scenes/classic.json", &wider);
    assert!(h.state_mut().session.poll_reload());
    settle(&mut h);
    let doc = &h.state().session.doc;
    assert!(doc.error.is_none());
    assert_eq!(doc.scene.camera.fov_y, 60.0);
    assert!(doc.image.pixels != good, "re-rendered after the reload");
    assert!(!h.state_mut().session.poll_reload(), "no change, no reload");
}

#[test]
fn exports_write_next_to_the_export_base() {
    let files = MemFiles::default();
    let mut h = harness(&files);
    click_pixel(&mut h, 150, 100);
    h.get_by_label("tree JSON").click();
    h.run();
    h.get_by_label("image PNG").click();
    h.run();
    h.get_by_label("diagram SVG").click();
    h.run();
    let svg = files
        .get("scenes/classic-diagram-150-100.svg")
        .expect("diagram written");
    assert!(svg.contains("<svg") && svg.contains("mirror ball"));
    let json = files
        .get("scenes/classic-tree-150-100.json")
        .expect("tree written");
    assert!(json.contains("raytree.tree/2"));
    assert!(files.get("scenes/classic.png").is_some());
    assert!(has(&h, "wrote scenes/classic-diagram-150-100.svg"));
}

#[test]
fn a_mesh_scene_reads_its_obj_through_the_file_hook() {
    let files = MemFiles::default();
    let scene = CLASSIC.replace(
        "\"objects\": [",
        r#""objects": [{"type": "mesh", "name": "tri", "file": "meshes/t.obj", "material": "mirror"},"#,
    );
    assert_ne!(scene, CLASSIC);
    files.put("scenes/m.json", &scene);
    let open = |files: &MemFiles| {
        let mut s = Session::new(
            Some("scenes/m.json".into()),
            Box::new(files.clone()),
            Box::new(|_| Ok(())),
            Arc::new(|| {}),
        );
        s.wait_render();
        s
    };
    // Missing OBJ: the error names it (relative to the scene's directory), classic stays.
    let s = open(&files);
    let err = s.doc.error.clone().unwrap_or_default();
    assert!(
        err.contains("objects[0].file") && err.contains("t.obj"),
        "{err}"
    );
    files.put(
        "scenes/meshes/t.obj",
        "v -1 0 -1\nv 1 0 -1\nv 0 2 -1\nf 1 2 3\n",
    );
    let s = open(&files);
    assert!(s.doc.error.is_none(), "{:?}", s.doc.error);
    assert!(matches!(
        s.doc.scene.objects[0].shape,
        raytree::geometry::Shape::Mesh(_)
    ));
    // The traversal heat map: picked in the view menu, the mesh's pixels cost BVH work.
    let mut h = inspector(s);
    settle(&mut h);
    h.get_by_label("show").click();
    h.run();
    h.get_by_label("BVH traversal cost").click();
    settle(&mut h);
    let doc = &h.state().session.doc;
    assert_eq!(doc.view.debug, DebugView::Traversal);
    // Each pixel's value is the BVH work of every ray in its recorded tree.
    for (x, y) in [(100, 100), (320, 180), (500, 300), (10, 10)] {
        let tree = raytree::trace_pixel(&doc.scene, x, y).unwrap();
        let work: u32 = tree.nodes.iter().map(|n| n.traversal.total()).sum();
        assert!(work > 0);
        assert_eq!(DebugView::Traversal.value(&doc.stats_at(x, y)), work as f32);
    }
}

/// The classic scene at 320x180 with `adjust` applied too.
fn harness_with(
    files: &MemFiles,
    scene: &str,
    adjust: impl Fn(&mut raytree::Scene) + Send + 'static,
) -> Harness<'static, InspectorApp> {
    files.put("scenes/classic.json", scene);
    let session = Session::new(
        Some("scenes/classic.json".into()),
        Box::new(files.clone()),
        Box::new(move |s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(320, 180);
            adjust(s);
            Ok(())
        }),
        Arc::new(|| {}),
    );
    let mut h = inspector(session);
    settle(&mut h);
    h
}

/// A glass-ball pixel at 320x180 (400,200 at 640x360): a deep tree with a blocked shadow ray.
const GLASS: (u32, u32) = (200, 100);

#[test]
fn the_diagram_panel_shows_the_reloaded_scene() {
    // Issue 17.1: the panel's cache key restarted with the rebuilt document, so after a reload
    // it kept the old scene's figure while the export showed the new one.
    let files = MemFiles::default();
    let mut h = harness(&files);
    click_pixel(&mut h, GLASS.0, GLASS.1);
    let same = |h: &Harness<'static, InspectorApp>| {
        let (size, prims) = h.state().diagram_display_list().expect("a diagram");
        let fresh = raytree::gui::diagram_ui::build_display_list(&h.state().session.doc, size)
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
    let mut h = harness_with(&files, CLASSIC, |s| {
        s.settings.offset.epsilon = 0.0;
        s.settings.offset.strategy = raytree::scene::OffsetStrategy::Ray;
    });
    h.run();
    let doc = &h.state().session.doc;
    assert_eq!(doc.scene.settings.offset.epsilon, 0.0, "kept at 0");
    let self_hits: u32 = doc.stats.iter().map(|s| s.self_hits).sum();
    assert!(self_hits > 1000, "acne: {self_hits} self-hits");

    // From a positive epsilon, 0 can be set on the slider (its value field takes 0 typed).
    let mut h = harness(&files);
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
    let mut h = harness(&files);
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
        let want = raytree::gui::breakdown::pixel_contribution(tree, n.id).max_element();
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
    let mut h = harness_with(&files, &scene, |_| {});
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
    let mut h = harness(&files);
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
    let terms = raytree::gui::breakdown::breakdown(&tree);
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
    let mut h = harness_with(&files, CLASSIC, |s| s.settings.spp = 4);
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
    let mut h = harness(&files);
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

/// Export as the button does. Through the session, not a click: a click right after a render
/// can be lost when a late delivery adds a line above the buttons and shifts their ids.
fn export(h: &mut Harness<'static, InspectorApp>, kind: ExportKind) {
    h.state_mut()
        .session
        .apply(raytree::gui::Command::Export(kind));
    h.run();
}

#[test]
fn exports_warn_or_refuse_as_the_command_line_does_for_non_finite_values() {
    // A light of 1e42: the EXR export clamps beyond f32 and says so, as `render` does.
    let files = MemFiles::default();
    let hot = CLASSIC.replace(
        "\"intensity\": [120.0, 120.0, 120.0]",
        "\"intensity\": [1e42, 1e42, 1e42]",
    );
    assert_ne!(hot, CLASSIC);
    let mut h = harness_with(&files, &hot, |_| {});
    export(&mut h, ExportKind::ImageExr);
    let status = h.state().session.doc.status.clone();
    assert!(
        status.starts_with("wrote scenes/classic.exr; warning: ")
            && status.ends_with(
                "pixels had a channel beyond the 32-bit float range (3.4e38) and were clamped to it"
            ),
        "{status}"
    );
    assert!(has(&h, "were clamped to it"), "shown under the buttons");
    assert!(files.get("scenes/classic.exr").is_some());
    // The PNG of the same image needs no warning (sRGB clamps by design).
    export(&mut h, ExportKind::ImagePng);
    assert_eq!(h.state().session.doc.status, "wrote scenes/classic.png");

    // A tree with a NaN (the inspector's epsilon slider stops far below the 1e308 that makes
    // one, so it is put there): the JSON export refuses it, as `trace --json` does, and writes
    // nothing.
    click_pixel(&mut h, GLASS.0, GLASS.1);
    let doc = &mut h.state_mut().session.doc;
    doc.tree.as_mut().expect("a tree").nodes[1].radiance.y = f64::NAN;
    export(&mut h, ExportKind::TreeJson);
    let err = h
        .state()
        .session
        .doc
        .export_error
        .clone()
        .unwrap_or_default();
    assert!(
        err.contains("non-finite number at nodes[1].radiance[1]"),
        "{err}"
    );
    assert!(has(&h, "JSON cannot carry it"), "shown");
    assert!(files.get("scenes/classic-tree-200-100.json").is_none());

    // A sphere of radius 1e300: shapes left out of the SVG, with the count, as `diagram` does.
    let files = MemFiles::default();
    let big = CLASSIC.replace("\"radius\": 1.0,", "\"radius\": 1e300,");
    assert_ne!(big, CLASSIC);
    let mut h = harness_with(&files, &big, |_| {});
    click_pixel(&mut h, 0, 0);
    export(&mut h, ExportKind::DiagramSvg);
    let status = h.state().session.doc.status.clone();
    assert!(
        status.starts_with("wrote scenes/classic-diagram-0-0.svg; warning: ")
            && status.contains(
                "shapes with non-finite coordinates (not a number or infinite) were left out"
            ),
        "{status}"
    );
    let svg = files
        .get("scenes/classic-diagram-0-0.svg")
        .expect("written");
    assert!(!svg.contains("NaN") && !svg.contains("inf\""), "finite SVG");
}
