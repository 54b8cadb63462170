//! The inspector's samples section (issue 16) through egui_kittest: the sample list sorted by
//! value, selecting a sample everywhere, the log-scale histogram and its bars, the firefly
//! explanation, the LPE filter field, and the diagram's "all samples" option.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::analysis::samples::{histogram, sample_rows};
use raytree::gui::model::diagram::{build_display_list, diagram_options};
use raytree::gui::model::document::Command;
use raytree::gui::{InspectorApp, Session};
use raytree::lpe::{Lpe, filter_tree_all_samples};
use std::sync::Arc;

mod gui_support;
use gui_support::*;

const CAUSTIC: &str = include_str!("../fixtures/caustic.json");
const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// `text` at `path` with `spp` samples, pixel (x, y) selected; the render finished.
fn harness(path: &str, text: &str, spp: u32, [x, y]: [u32; 2]) -> Harness<'static, InspectorApp> {
    let files = MemFiles::default();
    files.put(path, text);
    let adjust = Box::new(move |s: &mut raytree::Scene| {
        s.settings.spp = spp;
        // The sample stream these tests were written against (the caustic is sample 6 of 16):
        // stratified, not the path integrator's default Sobol sampler.
        s.settings.sampler = Some(raytree::scene::SamplerKind::Stratified);
        Ok(())
    });
    let session = Session::new(Some(path.into()), Box::new(files), adjust, Arc::new(|| {}));
    let mut h = Harness::builder()
        .with_size([1600.0, 1000.0])
        .with_max_steps(16)
        .build_ui_state(
            |ui, app: &mut InspectorApp| app.show(ui),
            InspectorApp::new(session),
        );
    h.run();
    h.state_mut().session.wait_render();
    h.state_mut().session.apply(Command::SelectPixel([x, y]));
    h.run();
    h
}

/// The caustic pixel under the glass ball at spp 16: sample 6 is the caustic firefly.
fn caustic() -> Harness<'static, InspectorApp> {
    harness("scenes/caustic.json", CAUSTIC, 16, [98, 112])
}

/// The sample the selected node belongs to.
fn selected_sample(h: &Harness<'static, InspectorApp>) -> Option<usize> {
    let doc = &h.state().session.doc;
    let tree = doc.tree.as_ref()?;
    let mut id = doc.node?;
    while let Some(p) = tree.node(id).parent {
        id = p;
    }
    tree.samples.iter().position(|s| s.root == id)
}

/// The panel's diagram equals a fresh build of its options.
fn diagram_is_current(h: &Harness<'static, InspectorApp>) -> raytree::diagram::DiagramOptions {
    let (size, prims) = h.state().diagram_display_list().expect("a diagram");
    let doc = &h.state().session.doc;
    assert!(prims == build_display_list(doc, size).unwrap().as_slice());
    diagram_options(doc, size)
}

#[test]
fn the_sample_list_is_sorted_and_a_row_selects_its_sample_everywhere() {
    let mut h = caustic();
    let tree = h.state().session.doc.tree.clone().unwrap();
    let rows = h
        .state()
        .samples_view()
        .shown_rows()
        .iter()
        .map(|r| r.index)
        .collect::<Vec<_>>();
    assert_eq!(
        rows,
        sample_rows(&tree)
            .iter()
            .map(|r| r.index)
            .collect::<Vec<_>>()
    );
    assert_eq!(rows.len(), 16);
    assert_eq!(rows[0], 6, "the caustic sample first");
    assert_eq!(selected_sample(&h), Some(0));
    h.get_by_label_contains("sample 6 ").click();
    h.run();
    h.run();
    let root = tree.samples[6].root;
    assert_eq!(h.state().session.doc.node, Some(root));
    // The diagram draws it, the overlay draws its rays, the tree shows its row.
    assert_eq!(diagram_is_current(&h).sample, 6);
    let in_image = h.state().overlay_rays();
    assert!(in_image > 0);
    let row = format!("#{} camera -> floor", root.0);
    assert!(
        h.query_all_by_label_contains(&row).count() >= 1,
        "the tree shows {row}"
    );
    // The row shows the sample's dominant path.
    let label = format!(
        "sample 6   {:>10}  len 4  C<RD><TS><TS>L",
        format!("{:.4}", sample_rows(&tree)[0].value)
    );
    let _ = h.get_by_label_contains(&label);
}

#[test]
fn a_histogram_bar_lists_its_samples_and_the_firefly_is_explained() {
    let mut h = caustic();
    let tree = h.state().session.doc.tree.clone().unwrap();
    let hist = histogram(&tree);
    // 33.1 (the caustic's luminance): the bar [1.5, 2).
    let k = hist.bin_of(6).unwrap();
    assert_eq!((hist.bins[k].lo, hist.bins[k].hi), (1.5, 2.0));
    h.get_by_label_contains("bar 1e1.5 to 1e2.0").click();
    h.run();
    h.run();
    let shown: Vec<usize> = h
        .state()
        .samples_view()
        .shown_rows()
        .iter()
        .map(|r| r.index)
        .collect();
    assert_eq!(shown, hist.bins[k].samples);
    assert_eq!(
        selected_sample(&h),
        Some(6),
        "the bar's largest sample is selected"
    );
    // The firefly sentence names the caustic and links to the diffuse floor bounce.
    let f = h
        .state()
        .samples_view()
        .firefly()
        .expect("sample 6 is a firefly")
        .clone();
    assert_eq!(tree.node(f.node).kind, raytree::RayKind::Diffuse);
    h.get_by_label_contains("Firefly. Sample 6").click();
    h.run();
    assert_eq!(h.state().session.doc.node, Some(f.node));
    // The zero bar lists the black samples; "show all" lists every one again.
    h.get_by_label_contains("bar value 0").click();
    h.run();
    assert_eq!(h.state().samples_view().shown_rows().len(), hist.zero.len());
    h.get_by_label("show all").click();
    h.run();
    assert_eq!(h.state().samples_view().shown_rows().len(), 16);
}

#[test]
fn the_lpe_filter_keeps_the_matching_paths_and_shows_a_bad_expression_in_red() {
    let mut h = caustic();
    let full = h.state().session.doc.tree.clone().unwrap();
    let field = h.get_by_label("LPE filter");
    field.focus();
    field.type_text("C<RD><TS><TS>L");
    h.run();
    // Issue 32: typed, not applied (a half-typed expression must not filter the tree), and the
    // panel says what is in force.
    assert_eq!(h.state().session.doc.tree.as_ref(), Some(&full));
    assert!(h.state().session.doc.lpe.active.is_none());
    let _ = h.get_by_label_contains("in force: none");
    h.key_press(egui::Key::Enter);
    h.run();
    h.run();
    let expected =
        filter_tree_all_samples(&full, &[Lpe::parse("C<RD><TS><TS>L").unwrap()]).unwrap();
    let doc = &h.state().session.doc;
    assert_eq!(doc.tree.as_ref(), Some(&expected.tree));
    assert!(expected.tree.nodes.len() < full.nodes.len());
    assert!(expected.matched >= 1);
    assert_eq!(expected.tree.samples.len(), full.samples.len());
    // The count and share, the samples and the diagram of the filtered tree.
    let _ = h.get_by_label_contains(&expected.summary());
    assert_eq!(
        h.state().samples_view().shown_rows().len(),
        expected.tree.samples.len()
    );
    diagram_is_current(&h);
    // A bad expression: the error with its column, in red, while it is typed and after Enter;
    // the last good filter stays.
    let field = h.get_by_label("LPE filter");
    field.focus();
    field.type_text("<");
    h.run();
    h.key_press(egui::Key::Enter);
    h.run();
    let doc = &h.state().session.doc;
    let err = doc
        .lpe
        .error
        .clone()
        .expect("C<RD><TS><TS>L< does not parse");
    let _ = h.get_by_label_contains(&format!("column {}", err.column));
    assert_eq!(doc.tree.as_ref(), Some(&expected.tree));
    let _ = h.get_by_label_contains("in force: C<RD><TS><TS>L");
    // Cleared: the whole tree again.
    h.state_mut().session.apply(Command::SetLpe(String::new()));
    h.run();
    assert_eq!(h.state().session.doc.tree.as_ref(), Some(&full));
}

/// The filter renumbers nodes; the selection follows the ray, not the number.
#[test]
fn the_selection_follows_its_ray_through_lpe_filters() {
    let mut h = caustic();
    let full = h.state().session.doc.tree.clone().unwrap();
    let caustic_lpe = "C<RD><TS><TS>L";
    let end = full
        .nodes
        .iter()
        .rev()
        .find(|n| n.path.as_ref().is_some_and(|p| p.lpe == caustic_lpe))
        .expect("a caustic path")
        .id;
    let same_ray = |a: &raytree::tree::RayNode, b: &raytree::tree::RayNode| {
        a.origin == b.origin && a.direction == b.direction && a.kind == b.kind
    };
    h.state_mut().session.apply(Command::SelectNode(Some(end)));
    h.state_mut()
        .session
        .apply(Command::SetLpe(caustic_lpe.into()));
    h.run();
    let doc = &h.state().session.doc;
    let shown = doc.node.expect("a selection");
    assert_ne!(
        shown, end,
        "the filter renumbers (else this test proves nothing)"
    );
    assert!(same_ray(
        doc.tree.as_ref().unwrap().node(shown),
        full.node(end)
    ));
    // A filter without that path: its nearest kept ancestor (a strict one).
    h.state_mut()
        .session
        .apply(Command::SetLpe("C<RD>L".into()));
    h.run();
    let doc = &h.state().session.doc;
    let shown = doc.node.expect("a selection");
    let ancestor = doc.lpe.to_original(shown);
    let mut chain = std::iter::successors(full.node(end).parent, |&p| full.node(p).parent);
    assert!(
        chain.any(|p| p == ancestor),
        "{ancestor:?} is not above {end:?}"
    );
    // No filter: the same ray in the whole tree.
    h.state_mut().session.apply(Command::SetLpe(String::new()));
    h.run();
    assert_eq!(h.state().session.doc.node, Some(ancestor));
}

#[test]
fn the_lpe_filter_on_a_whitted_tree_says_it_does_not_apply() {
    let mut h = harness("scenes/classic.json", CLASSIC, 1, [400, 200]);
    let full = h.state().session.doc.tree.clone().unwrap();
    h.state_mut()
        .session
        .apply(Command::SetLpe("C<RD>L".into()));
    h.run();
    assert_eq!(h.state().session.doc.tree.as_ref(), Some(&full));
    let _ = h.get_by_label_contains("not applied: a Whitted tree");
    // One sample per pixel: no histogram of one bar, no list of one row.
    let _ = h.get_by_label_contains("one sample per pixel");
    assert!(h.query_by_label_contains("sample 0 ").is_none());
}

#[test]
fn all_samples_in_the_diagram() {
    let mut h = caustic();
    h.get_by_label("all samples").click();
    h.run();
    h.run();
    let opts = diagram_is_current(&h);
    assert!(opts.all_samples);
    let doc = &h.state().session.doc;
    let d =
        raytree::diagram::Diagram::build(&doc.scene, doc.tree.as_ref().unwrap(), &opts).unwrap();
    let one = raytree::diagram::Diagram::build(
        &doc.scene,
        doc.tree.as_ref().unwrap(),
        &raytree::diagram::DiagramOptions {
            all_samples: false,
            ..opts.clone()
        },
    )
    .unwrap();
    assert!(d.rays.len() > one.rays.len());
}

/// Issue 32: typing `C<RD>S+K` never applies its valid prefix `C<RD>S+` (which matched 0 of
/// 116 paths and hid the firefly sentence): after Enter the error shows and no filter is in
/// force.
#[test]
fn a_typo_never_applies_its_half_typed_prefix() {
    let mut h = caustic();
    let full = h.state().session.doc.tree.clone().unwrap();
    let field = h.get_by_label("LPE filter");
    field.focus();
    field.type_text("C<RD>S+K");
    h.run();
    h.key_press(egui::Key::Enter);
    h.run();
    let doc = &h.state().session.doc;
    assert!(doc.lpe.active.is_none(), "{:?}", doc.lpe.active);
    assert!(doc.lpe.error.is_some());
    assert_eq!(doc.tree.as_ref(), Some(&full));
}

/// Issue 32: the selection follows its sample, not its node number, when the tree is rebuilt
/// under another integrator: sample 4's camera ray under path is sample 4's camera ray under
/// Whitted (by number it was a depth-16 refracted ray there).
#[test]
fn the_selection_keeps_its_sample_across_integrators() {
    let mut h = caustic();
    let tree = h.state().session.doc.tree.clone().unwrap();
    let s4 = tree
        .samples
        .iter()
        .find(|s| s.index == 4)
        .expect("sample 4")
        .root;
    h.state_mut().session.apply(Command::SelectNode(Some(s4)));
    let mut settings = h.state().session.doc.scene.settings;
    settings.integrator = raytree::scene::IntegratorKind::Whitted;
    h.state_mut().session.apply(Command::SetSettings(settings));
    h.run();
    let doc = &h.state().session.doc;
    let t = doc.tree.as_ref().unwrap();
    let id = doc.node.expect("a selection");
    assert_eq!(t.node(id).kind, raytree::RayKind::Camera);
    let s = t
        .samples
        .iter()
        .find(|s| s.root == id)
        .expect("a sample's camera ray");
    assert_eq!(s.index, 4);
}
