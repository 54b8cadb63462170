//! Hard whole scenes checked through the traced tree: a 2e-7 thin glass shell (the robust
//! offset keeps it, a large epsilon leaks through it), nested dielectrics, TIR chains ending
//! exactly at max_depth, and the NaN/infinity guard on images.

use raytree::SceneIntegrator;
use raytree::analysis::invariants::tree_violations;
use raytree::render::RenderOptions;
use raytree::tree::{EndReason, RayKind};
use raytree::{Scene, render, trace_pixel};

fn scene(materials: &str, objects: &str, settings: &str) -> Scene {
    Scene::from_json(&format!(
        r#"{{"camera": {{"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30, "width": 9, "height": 9}},
            "background": [1, 1, 1], "materials": {{{materials}}}, "objects": [{objects}],
            "lights": [{{"type": "point", "position": [0, 5, 5], "intensity": [10, 10, 10]}}],
            "settings": {{{settings}}}}}"#
    ))
    .unwrap()
}

#[test]
fn thin_shell_is_not_skipped_by_the_robust_offset_but_is_by_a_large_epsilon() {
    let mats = r#""glass": {"transmissivity": [1, 1, 1], "ior": 1.5}"#;
    let objs = r#"{"type": "box", "name": "shell", "min": [-1, -1, -1e-7], "max": [1, 1, 1e-7], "material": "glass"}"#;
    let robust = scene(mats, objs, r#""offset": {"strategy": "robust"}"#);
    let (_, st, _) = render(
        &SceneIntegrator::new(&robust),
        &RenderOptions::diagnosed(),
        &|_| {},
    )
    .into_parts();
    assert_eq!((st.rays.self_hits, st.rays.leaks), (0, 0));
    assert!(st.rays.refracted > 0);
    let coarse = scene(
        mats,
        objs,
        r#""offset": {"strategy": "normal", "epsilon": 1e-4}"#,
    );
    let (_, st, _) = render(
        &SceneIntegrator::new(&coarse),
        &RenderOptions::diagnosed(),
        &|_| {},
    )
    .into_parts();
    assert!(st.rays.leaks > 0, "a 1e-4 offset must jump the 2e-7 shell");
    let tree = trace_pixel(&coarse, 4, 4).unwrap();
    let leak = tree.nodes.iter().find_map(|n| n.leak.as_ref()).unwrap();
    assert_eq!(leak.object_name, "shell");
    assert!(raytree::text::tree_text(&tree).contains("LEAK (offset skipped shell"));
}

#[test]
fn nested_dielectrics_record_glass_in_water() {
    let mut s = Scene::from_json(include_str!("../fixtures/nested.json")).unwrap();
    s.camera = s.camera.with_size(64, 36);
    let mut found = false;
    for x in 28..36 {
        let tree = trace_pixel(&s, x, 16).unwrap();
        assert!(tree_violations(&tree, s.background).is_empty());
        found |= tree
            .nodes
            .iter()
            .filter_map(|n| n.interface.as_ref())
            .any(|i| (i.n1 - 1.333).abs() < 1e-12 && (i.n2 - 1.5).abs() < 1e-12);
    }
    assert!(found, "no water -> glass interface recorded");
}

#[test]
fn long_tir_chain_ends_exactly_at_max_depth() {
    // Inside a glass block seen through its top at a steep angle, light bounces by total
    // internal reflection until max_depth cuts it.
    let mut s = Scene::from_json(include_str!("../fixtures/tir-block.json")).unwrap();
    s.camera = s.camera.with_size(48, 27);
    s.settings.whitted.min_weight = Some(0.0); // the exhaustive chain
    for max_depth in [3, 7, 16] {
        s.settings.max_depth = max_depth;
        let (mut tir, mut deepest) = (0, 0);
        for (x, y) in [(10, 14), (24, 14), (38, 14), (24, 20)] {
            let tree = trace_pixel(&s, x, y).unwrap();
            assert!(tree_violations(&tree, s.background).is_empty());
            assert!(tree.nodes.iter().all(|n| n.depth <= max_depth));
            tir += tree
                .nodes
                .iter()
                .filter(|n| n.interface.as_ref().is_some_and(|i| i.tir))
                .count();
            for n in tree.nodes.iter().filter(|n| n.end == EndReason::MaxDepth) {
                assert_eq!(n.depth, max_depth);
                assert!(n.truncated.max_element() > 0.0);
            }
            let d = tree
                .nodes
                .iter()
                .filter(|n| n.kind != RayKind::Shadow)
                .map(|n| n.depth);
            deepest = deepest.max(d.max().unwrap_or(0));
        }
        assert_eq!(deepest, max_depth, "the chain must reach max_depth exactly");
        assert!(tir > 0, "max_depth {max_depth}: no TIR seen");
    }
}

#[test]
fn no_nan_or_infinity_reaches_an_image() {
    // Two emitters of the largest finite radiance, one seen through the other: their sum
    // overflows to infinity.
    let s = scene(
        r#""hot": {"emission": [1.7e308, 1.7e308, 1.7e308], "transmissivity": [1, 1, 1]},
           "hotter": {"emission": [1.7e308, 1.7e308, 1.7e308]}"#,
        r#"{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "hot"},
           {"type": "sphere", "center": [0, 0, -4], "radius": 2, "material": "hotter"}"#,
        "",
    );
    let (img, stats, _) =
        render(&SceneIntegrator::new(&s), &RenderOptions::new(), &|_| {}).into_parts();
    assert!(img.pixels.iter().all(|p| p.is_finite()));
    assert!(stats.nonfinite_pixels > 0);
    let (x, y) = stats.first_nonfinite.unwrap();
    let tree = trace_pixel(&s, x, y).unwrap();
    assert!(!tree.radiance.is_finite());
}
