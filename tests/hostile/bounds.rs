//! Hostile-input cases: bounds (issue 13): no panic in the BVH, bounded memory and time.

use super::harness::{run, temp_files};
use std::fmt::Write;
use std::path::Path;

#[test]
fn the_default_scene_renders_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(&["render", "--size", "8x6", "-o", "a.png"], dir.path());
    r.assert_clean();
    assert_eq!(r.code, Some(0));
    assert!(temp_files(dir.path()).is_empty());
}

/// `scene.json` placing `mesh.obj` of `n` copies of one triangle, in `dir`.
fn duplicated_mesh(dir: &Path, n: usize) {
    let mut obj = String::from("v -1 0 0\nv 1 0 0\nv 0 1.5 0\n");
    for _ in 0..n {
        obj.push_str("f 1 2 3\n");
    }
    std::fs::write(dir.join("mesh.obj"), obj).unwrap();
    let mut scene = String::new();
    write!(
        scene,
        r#"{{"camera": {{"position": [0, 0.7, 4], "look_at": [0, 0.7, 0], "up": [0, 1, 0],
             "fov_y": 40, "width": 32, "height": 18}},
           "materials": {{"m": {{"diffuse": [0.8, 0.8, 0.8]}}}},
           "objects": [{{"type": "mesh", "file": "mesh.obj", "material": "m"}}],
           "lights": [{{"type": "point", "position": [2, 4, 4], "intensity": [30, 30, 30]}}]}}"#
    )
    .unwrap();
    std::fs::write(dir.join("scene.json"), scene).unwrap();
}

#[test]
fn meshes_of_many_identical_triangles_render() {
    // 61 identical triangles panicked in the wide BVH build ("leaf of at most 15 groups").
    for n in [60, 61, 1000] {
        let dir = tempfile::tempdir().unwrap();
        duplicated_mesh(dir.path(), n);
        let r = run(&["render", "scene.json", "-o", "a.png"], dir.path());
        r.assert_clean();
        assert_eq!(r.code, Some(0), "{n} triangles: {r:#?}");
        let r = run(&["trace", "scene.json", "--pixel", "16,9"], dir.path());
        assert_eq!(r.code, Some(0), "{n} triangles: {r:#?}");
        assert!(r.stdout.contains("mesh"), "{n} triangles: {r:#?}");
    }
}
