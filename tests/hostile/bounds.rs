//! Hostile-input cases: bounds (issue 13).

use super::harness::{run, temp_files};

#[test]
fn the_default_scene_renders_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(&["render", "--size", "8x6", "-o", "a.png"], dir.path());
    r.assert_clean();
    assert_eq!(r.code, Some(0));
    assert!(temp_files(dir.path()).is_empty());
}
