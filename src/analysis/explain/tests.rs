//! Tests of `explain`.

use super::*;
use crate::trace_pixel;
use crate::tree::EndReason;

fn fixture(name: &str) -> Scene {
    let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn texts(e: &Explanation, kind: SentenceKind) -> Vec<&str> {
    e.sentences
        .iter()
        .filter(|s| s.kind == kind)
        .map(|s| s.text.as_str())
        .collect()
}

fn close(a: Rgb, b: Rgb) -> bool {
    (a - b).abs().max_element() <= 1e-12 * (1.0 + a.abs().max_element())
}

#[test]
fn the_glass_pixel_sees_the_floor_through_the_glass_ball() {
    let scene = fixture("classic.json");
    let tree = trace_pixel(&scene, 400, 200).unwrap();
    let e = explain(&tree, &scene);
    let top = &e.shares[0];
    assert_eq!(top.path, "floor seen through the glass ball", "{e:#?}");
    assert!(top.fraction > 0.5, "{}", top.fraction);
    let sees = texts(&e, SentenceKind::Sees);
    assert!(
        sees[0].starts_with("floor seen through the glass ball: "),
        "{sees:?}"
    );
    // The background reflected off the ball's front is a path of its own.
    assert!(
        e.shares
            .iter()
            .any(|s| s.path == "background reflected in the glass ball"),
        "{e:#?}"
    );
    // Each share's nodes are exactly the nodes whose terms it sums.
    for s in &e.shares {
        let sum = s
            .nodes
            .iter()
            .fold(Rgb::ZERO, |a, id| a + node_term(&tree, tree.node(*id)));
        assert!(close(sum, s.value), "{}: {sum} vs {}", s.path, s.value);
    }
    // The opaque glass blocks the floor's shadow rays behind it? Not at this pixel; but a
    // blocked shadow ray from inside the ball is reported, with its node.
    let energy = e
        .sentences
        .iter()
        .find(|s| s.text.contains("shadow ray"))
        .expect("the glass blocks shadow rays from inside the ball");
    assert!(energy.nodes.iter().all(|id| {
        tree.node(*id).end == EndReason::Blocked || tree.node(*id).end == EndReason::Attenuated
    }));
}

#[test]
fn the_shares_add_up_to_the_pixel_value() {
    let mut checked = 0;
    for (name, pixels) in [
        (
            "classic.json",
            vec![(400, 200), (300, 200), (5, 5), (250, 300)],
        ),
        ("nested.json", vec![(320, 150), (320, 230)]),
        ("tir-block.json", vec![(320, 230)]),
        ("absorption.json", vec![(100, 250), (500, 250)]),
        ("translucent-shadow.json", vec![(320, 300)]),
    ] {
        let mut scene = fixture(name);
        for spp in [1, 4] {
            scene.settings.spp = spp;
            for &(x, y) in &pixels {
                let tree = trace_pixel(&scene, x, y).unwrap();
                let e = explain(&tree, &scene);
                let sum = e.shares.iter().fold(Rgb::ZERO, |a, s| a + s.value);
                assert!(
                    close(sum, tree.radiance),
                    "{name} {x},{y} spp {spp}: {sum} vs {}",
                    tree.radiance
                );
                if tree.radiance.element_sum() > 0.0 {
                    let f: f64 = e.shares.iter().map(|s| s.fraction).sum();
                    assert!((f - 1.0).abs() < 1e-9, "{name} {x},{y}: {f}");
                    checked += 1;
                }
                // Every node id named exists.
                for s in &e.sentences {
                    assert!(s.nodes.iter().all(|n| n.index() < tree.nodes.len()));
                    assert!(!s.nodes.is_empty(), "{}", s.text);
                }
            }
        }
    }
    assert!(checked > 10, "only {checked} lit pixels checked");
}

#[test]
fn tir_in_the_block_is_mentioned() {
    let scene = fixture("tir-block.json");
    let tree = trace_pixel(&scene, 320, 230).unwrap();
    let e = explain(&tree, &scene);
    let ev = e
        .sentences
        .iter()
        .find(|s| s.kind == SentenceKind::Event)
        .expect("a TIR sentence");
    assert!(ev.text.contains("total internal reflection"), "{}", ev.text);
    assert!(
        ev.text.contains("glass block") && ev.text.contains("41.8"),
        "{}",
        ev.text
    );
    assert!(
        ev.nodes
            .iter()
            .all(|id| tree.node(*id).interface.as_ref().is_some_and(|i| i.tir))
    );
}

#[test]
fn max_depth_one_on_nested_is_a_cut() {
    let mut scene = fixture("nested.json");
    scene.settings.max_depth = 1;
    let tree = trace_pixel(&scene, 320, 150).unwrap();
    let e = explain(&tree, &scene);
    let cut = e
        .sentences
        .iter()
        .find(|s| s.text.starts_with("cut by max depth 1"))
        .unwrap_or_else(|| panic!("{:#?}", e.sentences));
    assert_eq!(cut.kind, SentenceKind::Energy);
    assert!(
        cut.nodes
            .iter()
            .all(|id| tree.node(*id).end == EndReason::MaxDepth)
    );
    // At the default depth nothing there is cut by max depth.
    scene.settings.max_depth = 16;
    let tree = trace_pixel(&scene, 320, 150).unwrap();
    let e = explain(&tree, &scene);
    assert!(
        !e.sentences
            .iter()
            .any(|s| s.text.starts_with("cut by max depth"))
    );
}

#[test]
fn beer_absorbs_red_more_than_blue_in_the_water() {
    let scene = fixture("absorption.json");
    let tree = trace_pixel(&scene, 320, 180).unwrap();
    let e = explain(&tree, &scene);
    let s = e
        .sentences
        .iter()
        .find(|s| s.text.starts_with("absorbed by Beer's law in the water 1"))
        .unwrap_or_else(|| panic!("{:#?}", e.sentences));
    assert!(
        s.nodes
            .iter()
            .all(|id| tree.node(*id).attenuation.is_some())
    );
    // The water's absorption is [0.9, 0.25, 0.06]: red is lost most ("deeper water looks
    // blue").
    let inside = &s.text[s.text.find('[').unwrap() + 1..s.text.find(']').unwrap()];
    let v: Vec<f64> = inside.split(", ").map(|x| x.parse().unwrap()).collect();
    assert!(v[0] > v[1] && v[1] > v[2] && v[2] > 0.0, "{}", s.text);
}

/// Suspicious cases built on a real tree: each must be reported, and a clean tree has none.
#[test]
fn suspicious_values_are_reported() {
    let scene = fixture("classic.json");
    let clean = trace_pixel(&scene, 400, 200).unwrap();
    assert!(texts(&explain(&clean, &scene), SentenceKind::Suspicious).is_empty());

    let mut t = clean.clone();
    t.radiance = Rgb::new(1.5, 0.2, 0.1);
    let s = texts(&explain(&t, &scene), SentenceKind::Suspicious).join("|");
    assert!(s.contains("above 1 in R") && s.contains("clips"), "{s}");

    let mut t = clean.clone();
    t.nodes[3].radiance = Rgb::new(f64::NAN, 0.0, 0.0);
    let e = explain(&t, &scene);
    let s = e
        .sentences
        .iter()
        .find(|s| s.text.starts_with("non-finite"))
        .expect("NaN reported");
    assert_eq!(s.nodes, vec![NodeId(3)]);

    let mut t = clean.clone();
    t.nodes[2].self_hit = true;
    t.nodes[5].self_hit = true;
    let e = explain(&t, &scene);
    let s = e
        .sentences
        .iter()
        .find(|s| s.text.contains("self-intersection"))
        .unwrap();
    assert_eq!(s.nodes, vec![NodeId(2), NodeId(5)]);
    assert!(s.text.starts_with("2 rays"), "{}", s.text);
}

#[test]
fn a_tir_chain_cut_at_max_depth_is_suspicious() {
    let mut scene = fixture("tir-block.json");
    let tree = trace_pixel(&scene, 320, 230).unwrap();
    let e = explain(&tree, &scene);
    assert!(
        !texts(&e, SentenceKind::Suspicious)
            .iter()
            .any(|s| s.contains("chain"))
    );
    // Cut the recursion right at the first TIR event.
    let first_tir = tree
        .nodes
        .iter()
        .find(|n| n.interface.as_ref().is_some_and(|i| i.tir))
        .unwrap();
    scene.settings.max_depth = first_tir.depth;
    let tree = trace_pixel(&scene, 320, 230).unwrap();
    let e = explain(&tree, &scene);
    let s = e
        .sentences
        .iter()
        .find(|s| {
            s.text.contains("total internal reflection") && s.kind == SentenceKind::Suspicious
        })
        .unwrap_or_else(|| panic!("{:#?}", e.sentences));
    assert!(s.text.contains("ends at max depth"), "{}", s.text);
}

#[test]
fn text_lists_node_ids() {
    let scene = fixture("classic.json");
    let tree = trace_pixel(&scene, 400, 200).unwrap();
    let text = explanation_text(&explain(&tree, &scene));
    assert!(text.starts_with("pixel (400, 200)"), "{text}");
    assert!(
        text.contains("- floor seen through the glass ball: "),
        "{text}"
    );
    assert!(text.contains("(#"), "{text}");
    assert_eq!(node_list(&[NodeId(12), NodeId(14)]), "#12, #14");
    let many: Vec<NodeId> = (0..15).map(NodeId).collect();
    assert!(node_list(&many).ends_with("#11, and 3 more"));
}

#[test]
fn a_path_traced_pixel_is_explained_by_light_path_classes_that_add_up() {
    let mut scene = fixture("cornell-box.json");
    scene.settings.spp = 16;
    let tree = trace_pixel(&scene, 128, 200).unwrap();
    let e = explain(&tree, &scene);
    // Classes from the light path expressions, not Whitted's "reflected in the wall" words.
    assert!(
        e.shares
            .iter()
            .any(|s| s.path.starts_with("direct light on the ")),
        "{e:#?}"
    );
    assert!(
        e.shares
            .iter()
            .any(|s| s.path.starts_with("indirect light on the ")),
        "{e:#?}"
    );
    assert!(e.shares.iter().all(|s| !s.path.contains("reflected in")));
    let sum = e.shares.iter().fold(Rgb::ZERO, |a, s| a + s.value);
    assert!(close(sum, tree.radiance), "{sum:?} vs {:?}", tree.radiance);
    let events = texts(&e, SentenceKind::Event).join("\n");
    assert!(events.contains("by light sampling"), "{events}");
    assert!(events.contains("diffuse"), "{events}");
    let energy = texts(&e, SentenceKind::Energy).join("\n");
    assert!(energy.contains("relative standard error"), "{energy}");
}

#[test]
fn light_samples_blocked_by_glass_point_to_caustic_paths() {
    let mut scene = fixture("caustic.json");
    scene.settings.spp = 16;
    let tree = trace_pixel(&scene, 110, 125).unwrap();
    let e = explain(&tree, &scene);
    let energy = texts(&e, SentenceKind::Energy).join("\n");
    assert!(
        energy.contains("blocked by the glass ball: shadow rays stop at glass"),
        "{energy}"
    );
    // The same pixel under Whitted keeps Whitted's words.
    scene.settings.integrator = crate::scene::IntegratorKind::Whitted;
    let whitted = explain(&trace_pixel(&scene, 110, 125).unwrap(), &scene);
    assert!(
        texts(&whitted, SentenceKind::Energy)
            .iter()
            .all(|t| !t.contains("shadow rays stop at glass")),
        "{whitted:#?}"
    );
}

fn class_of(lpe: &str) -> &'static str {
    path::class(&path::events(lpe)).0
}

#[test]
fn classes_read_from_the_light_path_expression() {
    assert_eq!(class_of("CL"), "an emitter seen directly");
    assert_eq!(class_of("CB"), "background seen directly");
    assert_eq!(class_of("C<RS>B"), "background seen in mirrors and glass");
    assert_eq!(class_of("C<RD>L"), "direct light");
    assert_eq!(class_of("C<TS><TS><RD>L"), "direct light");
    assert_eq!(
        class_of("C<RD><TS><TS>L"),
        "caustic: light through or off specular surfaces"
    );
    assert_eq!(class_of("C<RD><RD>L"), "indirect light");
    assert_eq!(class_of("C<RD><RG><TS>L"), "indirect light with a caustic");
    assert_eq!(class_of("C<RD>B"), "light from the background");
    // The surface named is the first rough vertex.
    assert_eq!(path::class(&path::events("C<RS><RD>L")).1, Some(1));
}
