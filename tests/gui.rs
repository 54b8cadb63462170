//! The inspector driven through egui_kittest: real `InspectorApp`, in-memory files, the render
//! worker waited on synchronously (no sleeps).

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::gui::stats::DebugView;
use raytree::gui::{Files, InspectorApp, Session};
use raytree::math::Rgb;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// Files in memory; each write bumps the file's modification time.
#[derive(Clone, Default)]
struct MemFiles(Arc<Mutex<HashMap<PathBuf, (String, u64)>>>);

impl MemFiles {
    fn put(&self, path: &str, text: &str) {
        let mut m = self.0.lock().unwrap();
        let version = m.get(Path::new(path)).map_or(1, |(_, v)| v + 1);
        m.insert(path.into(), (text.to_string(), version));
    }
    fn get(&self, path: &str) -> Option<String> {
        self.0
            .lock()
            .unwrap()
            .get(Path::new(path))
            .map(|(t, _)| t.clone())
    }
}

impl Files for MemFiles {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .lock()
            .unwrap()
            .get(path)
            .map(|(t, _)| t.clone())
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"))
    }
    fn modified(&self, path: &Path) -> Option<SystemTime> {
        let v = self.0.lock().unwrap().get(path)?.1;
        Some(SystemTime::UNIX_EPOCH + Duration::from_secs(v))
    }
    fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        self.put(&path.display().to_string(), &String::from_utf8_lossy(bytes));
        Ok(())
    }
}

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

/// The inspector on `session` in a harness. Up to 16 steps to settle: a frame can see the
/// worker's deliveries (image, then statistics) one at a time, and on a loaded machine they
/// arrive at different frames (4, kittest's default, was once too few under CI).
fn inspector(session: Session) -> Harness<'static, InspectorApp> {
    Harness::builder()
        .with_size([1500.0, 950.0])
        .with_max_steps(16)
        .build_ui_state(
            |ui, app: &mut InspectorApp| app.show(ui),
            InspectorApp::new(session),
        )
}

/// Wait for the worker, then let the UI settle.
fn settle(h: &mut Harness<'static, InspectorApp>) {
    h.run();
    h.state_mut().session.wait_render();
    h.run();
}

fn click_pixel(h: &mut Harness<'static, InspectorApp>, x: u32, y: u32) {
    let pos = h.state().screen_of_pixel(x, y).expect("image drawn");
    h.hover_at(pos);
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run();
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
    let top = |h: &Harness<'static, InspectorApp>| {
        h.get_by_label("Select a pixel to see its diagram.")
            .rect()
            .top()
    };
    let before = top(&h);
    assert!(before < 950.0 - 300.0, "diagram panel starts at {before}");
    // Still that tall a few frames on, and the diagram, once there, fills it.
    h.run();
    assert_eq!(top(&h), before);
    click_pixel(&mut h, 150, 100);
    let header = h.get_by_label("Diagram").rect().bottom();
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
    assert!(json.contains("raytree.tree/1"));
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
