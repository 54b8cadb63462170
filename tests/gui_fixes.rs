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

// Issue 32 item 6: the smaller defects, each checked on what was painted (the frame's text
// shapes, their screen rectangles and clip rectangles).

const CAUSTIC: &str = include_str!("../fixtures/caustic.json");

/// The caustic fixture at 96x72 with `spp` samples, rendered.
fn caustic(spp: u32) -> Harness<'static, InspectorApp> {
    read_only_inspector(
        CAUSTIC,
        Box::new(move |s: &mut raytree::Scene| {
            s.settings.spp = spp;
            s.camera = s.camera.with_size(96, 72);
            Ok(())
        }),
    )
}

/// One painted text: its galley, where it was painted and the rectangle it was clipped to.
struct Painted {
    galley: Arc<egui::Galley>,
    pos: egui::Pos2,
    clip: egui::Rect,
}

impl Painted {
    fn rect(&self) -> egui::Rect {
        self.galley.rect.translate(self.pos.to_vec2())
    }
    fn text(&self) -> &str {
        self.galley.text()
    }
    /// The screen x of the first glyph of `needle` and of the right edge of its last, on the
    /// first row holding it.
    fn span_of(&self, needle: &str) -> Option<(f32, f32)> {
        for row in &self.galley.rows {
            let chars: String = row.row.glyphs.iter().map(|g| g.chr).collect();
            if let Some(at) = chars.find(needle) {
                let k = chars[..at].chars().count();
                let n = needle.chars().count();
                let first = &row.row.glyphs[k];
                let last = &row.row.glyphs[k + n - 1];
                let x = self.pos.x + row.pos.x;
                return Some((x + first.pos.x, x + last.pos.x + last.advance_width));
            }
        }
        None
    }
}

/// Every text the last frame painted.
fn painted(h: &Harness<'static, InspectorApp>) -> Vec<Painted> {
    fn walk(shape: &egui::Shape, clip: egui::Rect, out: &mut Vec<Painted>) {
        match shape {
            egui::Shape::Text(t) => out.push(Painted {
                galley: t.galley.clone(),
                pos: t.pos,
                clip,
            }),
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, clip, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for c in &h.output().shapes {
        walk(&c.shape, c.clip_rect, &mut out);
    }
    out
}

/// The Whitted vs path class table's columns line up: each class's expression starts at the
/// same x and each luminance ends at the same x (they were one proportional-font text, since
/// `.monospace().small()` is the small proportional style).
#[test]
fn the_whitted_vs_path_class_table_is_aligned() {
    let mut h = caustic(4);
    h.get_by_label("Compare integrators").click();
    h.run();
    h.get_by_label("compare Whitted and path").click();
    while h.state().versus().0.is_none() {
        h.step(); // the spinner repaints every frame
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    h.run();
    let scene = h.state().session.doc.scene.clone();
    let v = raytree::aov::versus(&scene, None, &|_| {}).unwrap();
    let texts = painted(&h);
    let mut starts = Vec::new();
    let mut ends = Vec::new();
    for c in &v.classes {
        let lpe = texts.iter().find_map(|t| t.span_of(c.lpe));
        let value = format!("{:.4}", c.luminance);
        let lum = texts
            .iter()
            .filter(|t| t.text().contains(c.lpe) || t.text().trim() == value)
            .find_map(|t| t.span_of(&value));
        starts.push(lpe.expect(c.lpe).0);
        ends.push(lum.expect("its luminance").1);
    }
    for (what, xs) in [("expressions start", &starts), ("luminances end", &ends)] {
        let (lo, hi) = xs
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), x| {
                (a.min(*x), b.max(*x))
            });
        assert!(hi - lo < 0.5, "{what} at {xs:?}");
    }
}

/// The sample list's last row is painted whole, above the Explain header (the list's height
/// left out a point of spacing per row, so its last row's bottom was clipped).
#[test]
fn the_last_sample_row_is_not_hidden_under_the_explain_header() {
    let mut h = caustic(8);
    // Tall enough that the Samples section is on screen whole.
    h.set_size(egui::vec2(1500.0, 1700.0));
    h.run();
    click_pixel(&mut h, 48, 50);
    h.run();
    let rows = h.state().samples_view().shown_rows().len();
    assert_eq!(rows, 8, "every row fits without scrolling");
    let last = h.state().samples_view().shown_rows()[rows - 1].index;
    let tree = h.state().session.doc.tree.as_ref().unwrap();
    let record = tree.samples[last].index;
    let texts = painted(&h);
    let prefix = format!("sample {record:<3} ");
    let row = texts
        .iter()
        .find(|t| t.text().starts_with(&prefix) && t.text().contains("len "))
        .expect("the last row is painted");
    let r = row.rect();
    assert!(
        row.clip.min.y <= r.min.y + 0.5 && r.max.y <= row.clip.max.y + 0.5,
        "row {r:?} clipped to {:?}",
        row.clip
    );
    let header = texts
        .iter()
        .find(|t| t.text() == "Explain")
        .expect("the Explain header");
    assert!(
        r.max.y <= header.rect().min.y,
        "{r:?} under {:?}",
        header.rect()
    );
}

/// The noise legend's lines wrap inside their strip in a narrow image panel (at 200 points the
/// colour bar and "... and above (99th percentile)" ran past the strip and were cut).
#[test]
fn the_noise_legend_fits_a_narrow_panel() {
    let mut h = caustic(4);
    h.set_size(egui::vec2(960.0, 950.0));
    let mut view = h.state().session.doc.view;
    view.debug = DebugView::Noise;
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SetView(view));
    h.run();
    h.run();
    let strip = h.state().placement().unwrap().legend.expect("a legend");
    assert!(strip.width() < 260.0, "a narrow panel: {strip:?}");
    let texts = painted(&h);
    let inside: Vec<&Painted> = texts
        .iter()
        .filter(|t| t.rect().intersects(strip) && t.clip == strip)
        .collect();
    assert!(
        inside.iter().any(|t| t.text().contains("noise")),
        "the legend's title is painted"
    );
    for t in inside {
        let r = t.rect();
        assert!(
            strip.expand(0.5).contains_rect(r),
            "{:?} at {r:?} cut by the strip {strip:?}",
            t.text()
        );
    }
}

/// Pin and compare reads the default roulette depth as 5, not "none", and both header lines
/// give the integrator and the roulette depth.
#[test]
fn pin_and_compare_names_the_roulette_depth() {
    let mut h = caustic(2);
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SelectPixel([48, 50]));
    h.run();
    h.get_by_label("pin this tree").click();
    h.run();
    let mut s = h.state().session.doc.scene.settings;
    assert_eq!(s.path.rr_depth, 5);
    s.path.rr_depth = 2;
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SetSettings(s));
    settle(&mut h);
    assert!(has(&h, "settings.rr_depth: 5 -> 2"));
    assert!(!has(&h, "settings.rr_depth: none"));
    // The pinned tree's line (rr_depth 5) and the current one's (2).
    assert!(has(&h, "pinned:  pixel 48,50"));
    assert!(has(&h, "current: pixel 48,50"));
    assert!(has(
        &h,
        ": path, depth 16, spp 2, roulette from bounce 5, offset"
    ));
    assert!(has(
        &h,
        ": path, depth 16, spp 2, roulette from bounce 2, offset"
    ));
}

const GLOSSY: &str = include_str!("../fixtures/glossy.json");

/// Issue 32 item 1: the settings in force are the scene's and the command line's, beyond the
/// sliders' ranges too (depth 0..=32, spp and samples 1..=64 clamped them at the first frame,
/// and a typed 64 became 32); what the command line refuses is refused and said.
#[test]
fn settings_beyond_the_sliders_are_kept_and_refusals_are_said() {
    let settings = |h: &Harness<'static, InspectorApp>| h.state().session.doc.scene.settings;
    // The path tracer's depth, samples and roulette depth (`view caustic.json --spp 128`).
    let mut h = read_only_inspector(
        CAUSTIC,
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(8, 6);
            s.settings.max_depth = 64;
            s.settings.spp = 128;
            s.settings.path.rr_depth = 100;
            Ok(())
        }),
    );
    h.state_mut()
        .session
        .apply(raytree::gui::Command::SelectPixel([4, 3]));
    settle(&mut h);
    let s = settings(&h);
    assert_eq!(
        (s.max_depth, s.spp, s.path.rr_depth),
        (64, 128, 100),
        "kept"
    );
    let tree = h.state().session.doc.tree.clone().expect("a traced pixel");
    assert_eq!(
        (tree.settings.max_depth, tree.settings.spp),
        (64, 128),
        "the tree records what was traced"
    );

    // Whitted's area-light and glossy samples (a lamp and rough balls).
    let mut h = read_only_inspector(
        GLOSSY,
        Box::new(|s: &mut raytree::Scene| {
            s.camera = s.camera.with_size(4, 2);
            s.settings.max_depth = 2;
            s.settings.whitted.light_samples = Some(100);
            s.settings.whitted.glossy_samples = 100;
            Ok(())
        }),
    );
    assert!(has(&h, "light samples"), "the area-light slider is shown");
    assert!(has(&h, "glossy samples"), "the glossy slider is shown");
    let s = settings(&h);
    assert_eq!(
        (s.whitted.light_samples, s.whitted.glossy_samples),
        (Some(100), 100),
        "kept"
    );

    // Typed values beyond the slider's end are taken...
    h.get_by_role_and_label(Role::Slider, "max depth")
        .set_value_accesskit(48.0);
    settle(&mut h);
    assert_eq!(settings(&h).max_depth, 48);
    // ...and those the command line refuses (`--max-depth 2000`: at most 1024) are said,
    // leaving the settings in force as they were.
    h.get_by_role_and_label(Role::Slider, "max depth")
        .set_value_accesskit(2000.0);
    settle(&mut h);
    assert_eq!(settings(&h).max_depth, 48, "refused, not clamped");
    assert!(
        has(
            &h,
            "not applied: settings.max_depth: must be at most 1024, got 2000"
        ),
        "the refusal is shown"
    );
    // The next accepted change clears the refusal.
    h.get_by_role_and_label(Role::Slider, "max depth")
        .set_value_accesskit(2.0);
    settle(&mut h);
    assert_eq!(settings(&h).max_depth, 2);
    assert!(!has(&h, "not applied:"));
}
