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

/// The runaway cases of issue 13 at values the docs accept: each ends with 0 or 2 under the
/// harness's memory cap and timeout.
#[test]
fn deep_recursion_ends_quickly_with_the_default_cut() {
    let dir = tempfile::tempdir().unwrap();
    // Allocated 14 GB before the cut.
    let r = run(
        &[
            "trace",
            "--pixel",
            "329,189",
            "--max-depth",
            "1024",
            "--roulette-below",
            "0.01",
        ],
        dir.path(),
    );
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    assert!(r.stdout.contains("roulette: the"), "{r:#?}");
    // The cut alone (the default: no roulette below a weight) ends it too.
    let r = run(
        &[
            "trace",
            "--pixel",
            "329,189",
            "--max-depth",
            "1024",
            "--roulette-below",
            "0",
        ],
        dir.path(),
    );
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    assert!(r.stdout.contains("cut by min_weight"), "{r:#?}");
    assert!(!r.stdout.contains("roulette: the"), "{r:#?}");
    // Did not finish in a minute at depth 1024.
    let args = [
        "render",
        "--size",
        "32x18",
        "--max-depth",
        "1024",
        "-o",
        "a.png",
    ];
    let r = run(&args, dir.path());
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    assert!(!r.stderr.contains("ray budget"), "{r:#?}");
}

#[test]
fn the_exhaustive_tree_is_cut_by_the_ray_budget_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--size",
        "32x18",
        "--max-depth",
        "1024",
        "--min-weight",
        "0",
        "-o",
        "a.png",
    ];
    let r = run(&args, dir.path());
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    assert!(r.stderr.contains("reached the ray budget"), "{r:#?}");
    let args = [
        "trace",
        "--pixel",
        "329,189",
        "--max-depth",
        "1024",
        "--min-weight",
        "0",
        "--max-rays",
        "2000",
    ];
    let r = run(&args, dir.path());
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    assert!(r.stdout.contains("ray budget"), "{r:#?}");
    assert!(
        r.stderr
            .contains("1 of 1 samples reached the ray budget of 2000"),
        "{r:#?}"
    );
}

#[test]
fn what_cannot_fit_the_memory_budget_is_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    // Aborted at 4 GB.
    let r = run(
        &["trace", "--pixel", "400,200", "--spp", "65536", "--json"],
        dir.path(),
    );
    r.assert_clean();
    if r.code == Some(2) {
        assert!(r.stderr.contains("memory budget"), "{r:#?}");
        assert!(r.stdout.is_empty(), "{r:#?}");
    }
    // Refused whatever the cap: 65536 samples of at least 2 rays in 64 MiB.
    let args = [
        "trace",
        "--pixel",
        "400,200",
        "--spp",
        "65536",
        "--json",
        "--max-memory",
        "64",
    ];
    let r = run(&args, dir.path());
    r.assert_refused();
    assert!(
        r.stderr.contains("lower --spp or raise --max-memory"),
        "{r:#?}"
    );
    assert!(r.stdout.is_empty());
    // Grew at 150 MB/s and aborted.
    let r = run(
        &["render", "--size", "65536x65536", "-o", "a.png"],
        dir.path(),
    );
    r.assert_refused();
    assert!(
        r.stderr.contains("65536x65536 image needs about 320.0 GiB"),
        "{r:#?}"
    );
    let args = [
        "render",
        "--size",
        "2000x2000",
        "--max-memory",
        "100",
        "-o",
        "a.png",
    ];
    let r = run(&args, dir.path());
    r.assert_refused();
    assert!(r.stderr.contains("memory budget of 100 MiB"), "{r:#?}");
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
    assert!(temp_files(dir.path()).is_empty());
}

#[test]
fn new_settings_reject_bad_values_with_their_names() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expect) in [
        (
            &["--tolerance", "-1"][..],
            "--tolerance: must be a finite number >= 0",
        ),
        (
            &["--tolerance", "inf"][..],
            "--tolerance: must be a finite number >= 0",
        ),
        (&["--max-rays", "0"][..], "--max-rays: must be in 1..="),
        (
            &["--min-weight", "NaN"][..],
            "--min-weight: must be a finite number >= 0",
        ),
    ] {
        let mut all = vec!["render", "--size", "8x6", "-o", "a.png"];
        all.extend_from_slice(args);
        let r = run(&all, dir.path());
        r.assert_refused();
        assert!(r.stderr.contains(expect), "{args:?}: {r:#?}");
    }
    std::fs::write(
        dir.path().join("s.json"),
        r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
  "materials": {"m": {"diffuse": [0.5, 0.5, 0.5]}},
  "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}],
  "settings": {"max_rays": 0}}"#,
    )
    .unwrap();
    let r = run(&["render", "s.json", "-o", "a.png"], dir.path());
    r.assert_refused();
    assert!(
        r.stderr.contains("s.json:4:") && r.stderr.contains("settings.max_rays"),
        "{r:#?}"
    );
    assert!(!dir.path().join("a.png").exists());
}

/// `diagram --all-samples` was quadratic in spp (issue 27, item 9: 4096 spp took 11 s, 16384
/// did not finish in 60 s): linear now, and a figure draws a bounded number of rays, so 16384
/// samples end within the harness's timeout with a bounded file.
#[test]
fn all_samples_diagrams_of_many_samples_end_quickly() {
    let dir = tempfile::tempdir().unwrap();
    let caustic = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/caustic.json");
    let r = run(
        &[
            "diagram",
            caustic,
            "--pixel",
            "98,112",
            "--all-samples",
            "--spp",
            "16384",
            "-o",
            "d.svg",
        ],
        dir.path(),
    );
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    let svg = std::fs::read_to_string(dir.path().join("d.svg")).unwrap();
    let drawn = svg.matches("<polyline").count();
    assert!(
        drawn <= 2 * raytree::diagram::all_samples::MAX_OTHER_RAYS + 1000,
        "{drawn} polylines"
    );
    assert!(svg.contains("dimmest other samples"));
}
