//! The tree schema: `raytree.tree/2` trees round-trip, `raytree.tree/1` trees still read.

use super::{RayTree, TREE_SCHEMA, TREE_SCHEMAS_READ};
use crate::scene::IntegratorKind;
use crate::{Scene, trace_pixel};

#[test]
fn path_trees_round_trip_and_version_1_trees_still_read() {
    let mut scene = Scene::default_scene();
    scene.settings.integrator = IntegratorKind::Path;
    scene.settings.spp = 2;
    let tree = trace_pixel(&scene, 400, 200).unwrap();
    assert_eq!(tree.schema, TREE_SCHEMA);
    let json = serde_json::to_string(&tree).unwrap();
    assert!(json.contains("\"lpe\":\"C"), "{json}");
    let back: RayTree = serde_json::from_str(&json).unwrap();
    assert_eq!(back, tree);
    // A version-1 tree (Whitted, written before the path fields existed) reads as it is.
    scene.settings.integrator = IntegratorKind::Whitted;
    let mut v = serde_json::to_value(trace_pixel(&scene, 400, 200).unwrap()).unwrap();
    v["schema"] = "raytree.tree/1".into();
    for n in v["nodes"].as_array_mut().unwrap() {
        assert!(n.get("path").is_none());
    }
    v["settings"].as_object_mut().unwrap().remove("rr_depth");
    let old: RayTree = serde_json::from_value(v).unwrap();
    assert!(TREE_SCHEMAS_READ.contains(&old.schema.as_str()));
    assert!(old.nodes.iter().all(|n| n.path.is_none()));
}

/// A directional light's shadow rays have an infinite distance: JSON writes it as `null` (no
/// other non-finite number is left to refuse) and reads it back as infinity, the same tree.
#[test]
fn infinite_light_distances_round_trip_as_null() {
    let scene = Scene::from_json(include_str!("../../fixtures/tir-block.json")).unwrap();
    let tree = trace_pixel(&scene, 320, 230).unwrap();
    let infinite = tree
        .nodes
        .iter()
        .filter_map(|n| n.shadow.as_ref())
        .filter(|s| s.distance == f64::INFINITY)
        .count();
    assert!(infinite > 0);
    assert_eq!(crate::finite::first_nonfinite(&tree), None);
    let text = serde_json::to_string(&tree).unwrap();
    assert_eq!(text.matches("\"distance\":null").count(), infinite);
    let back: RayTree = serde_json::from_str(&text).unwrap();
    assert_eq!(back, tree);
    // A NaN distance is still refused (written as null it would read back as infinity).
    let mut bad = tree.clone();
    let n = bad.nodes.iter_mut().find(|n| n.shadow.is_some()).unwrap();
    n.shadow.as_mut().unwrap().distance = f64::NAN;
    assert!(crate::finite::first_nonfinite(&bad).is_some());
}
