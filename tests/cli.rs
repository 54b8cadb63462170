//! The `raytree` binary: the main jobs and every kind of bad input (`effects`, `cost` and
//! `compare` are in `tests/cli_analysis.rs`).

mod common;
use common::{fails, fixture, raytree, stderr};

use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use std::path::PathBuf;

const GOOD: &str = r#"{
  "camera": {"position": [0,1,5], "look_at": [0,0,0], "fov_y": 40, "width": 8, "height": 6},
  "materials": {"m": {"diffuse": [0.5, 0.5, 0.5]}},
  "objects": [
    {"type": "plane", "point": [0,0,0], "normal": [0,1,0], "material": "m"},
    {"type": "sphere", "center": [0,0.5,0], "radius": 0.5, "material": "m"}
  ],
  "lights": [{"type": "point", "position": [2,4,3], "intensity": [10,10,10]}]
}"#;

#[test]
fn render_default_scene_to_png_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    let o = raytree(&["render", "-o", "a.png", "--size", "64x36"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("camera 2304") && out.contains("Mrays/s"),
        "{out}"
    );
    let img = image::open(dir.path().join("a.png")).unwrap();
    assert_eq!((img.width(), img.height()), (64, 36));
    let o = raytree(
        &["render", "-o", "a.exr", "--size", "16x9", "--spp", "4"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let exr = image::open(dir.path().join("a.exr")).unwrap().into_rgb32f();
    assert_eq!(exr.dimensions(), (16, 9));
    assert!(
        exr.pixels()
            .all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0))
    );
    // Only the two images, no temporary files left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn trace_prints_text_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let o = raytree(&["trace", "--pixel", "400,200"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("camera #0 -> glass ball"), "{text}");
    assert!(
        text.contains("n1 1.000 -> n2 1.500") && text.contains("R=0.04"),
        "{text}"
    );
    let o = raytree(
        &["trace", "--pixel", "400,200", "--json", "--max-depth", "2"],
        dir.path(),
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["schema"], "raytree.tree/2");
    assert_eq!(v["settings"]["max_depth"], 2);
    assert_eq!(v["nodes"][0]["kind"], "camera");
    assert!(
        v["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|n| n["depth"].as_u64().unwrap() <= 2)
    );
}

/// Every fixture renders from the command line with every override spelled out, and the EXR
/// holds exactly (as f32) what the library renders for the same scene and settings.
#[test]
fn fixtures_render_from_the_command_line() {
    use raytree::math::FresnelModel;
    use raytree::scene::{OffsetStrategy, ShadowMode};
    let dir = tempfile::tempdir().unwrap();
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut names: Vec<_> = std::fs::read_dir(&fixtures)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".json"))
        .collect();
    names.sort();
    assert!(names.len() >= 9, "{names:?}");
    for name in &names {
        let o = raytree(
            &[
                "render",
                &fixture(name),
                "-o",
                "t.exr",
                "--size",
                "32x18",
                "--fresnel",
                "schlick",
                "--offset",
                "ray",
                "--shadows",
                "opaque",
                "--max-depth",
                "5",
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let mut scene =
            raytree::Scene::from_json(&std::fs::read_to_string(fixtures.join(name)).unwrap())
                .unwrap();
        scene.camera = scene.camera.with_size(32, 18);
        scene.settings.whitted.fresnel = FresnelModel::Schlick;
        scene.settings.offset.strategy = OffsetStrategy::Ray;
        scene.settings.whitted.shadows = ShadowMode::Opaque;
        scene.settings.max_depth = 5;
        let (expect, _, _) = raytree::render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        let got = image::open(dir.path().join("t.exr")).unwrap().into_rgb32f();
        assert_eq!(got.dimensions(), (32, 18), "{name}");
        let mut lit = 0;
        for (p, e) in got.pixels().zip(&expect.pixels) {
            let e = e.to_array().map(|c| c as f32);
            assert_eq!(p.0, e, "{name}");
            lit += usize::from(e.iter().any(|c| *c > 0.0));
        }
        assert!(lit > 32 * 18 / 2, "{name}: mostly black ({lit} lit pixels)");
    }
}

#[test]
fn bad_scenes_name_file_path_and_position() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, String, &str)] = &[
        (
            "radius",
            GOOD.replace("\"radius\": 0.5", "\"radius\": -1"),
            "bad.json:6:55: objects[1].radius: must be positive",
        ),
        (
            "syntax",
            GOOD.replace("\"height\": 6}", "\"height\": 6"),
            "bad.json:3:",
        ),
        (
            "unknown field",
            GOOD.replace("\"fov_y\": 40", "\"fov_y\": 40, \"fov\": 3"),
            "camera.fov: unknown field",
        ),
        (
            "unknown material",
            GOOD.replace("\"material\": \"m\"}\n  ]", "\"material\": \"gold\"}\n  ]"),
            "objects[1].material: unknown material \"gold\"",
        ),
        (
            "fov",
            GOOD.replace("\"fov_y\": 40", "\"fov_y\": 0"),
            "camera.fov_y: must be in (0, 180)",
        ),
        (
            "zero normal",
            GOOD.replace("\"normal\": [0,1,0]", "\"normal\": [0,0,0]"),
            "objects[0].normal: must be a non-zero direction",
        ),
        (
            "huge",
            GOOD.replace("[10,10,10]", "[1e400,10,10]"),
            "bad.json:8:",
        ),
        (
            "missing field",
            GOOD.replace("\"fov_y\": 40, ", ""),
            "missing field `fov_y`",
        ),
        (
            "ior",
            GOOD.replace("\"diffuse\": [0.5, 0.5, 0.5]", "\"ior\": 0"),
            "materials.m.ior: must be positive",
        ),
    ];
    for (what, src, expect) in cases {
        std::fs::write(dir.path().join("bad.json"), src).unwrap();
        std::fs::write(dir.path().join("keep.png"), b"keep").unwrap();
        let err = fails(&raytree(
            &["render", "bad.json", "-o", "keep.png"],
            dir.path(),
        ));
        assert!(err.contains(expect), "{what}: {err}");
        assert_eq!(
            std::fs::read(dir.path().join("keep.png")).unwrap(),
            b"keep",
            "{what}: output truncated"
        );
        let err = fails(&raytree(
            &["trace", "bad.json", "--pixel", "0,0"],
            dir.path(),
        ));
        assert!(err.contains(expect), "{what}: {err}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "no stray files"
    );
}

#[test]
fn bad_arguments_and_outputs_exit_2_without_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("good.json"), GOOD).unwrap();
    let d = dir.path();
    let err = fails(&raytree(&["trace", "good.json", "--pixel", "8,0"], d));
    assert!(err.contains("outside the 8x6 image"), "{err}");
    let err = fails(&raytree(&["trace", "good.json", "--pixel", "a,b"], d));
    assert!(err.contains("--pixel"), "{err}");
    let err = fails(&raytree(
        &["render", "good.json", "-o", "no/such/dir/x.png"],
        d,
    ));
    assert!(err.contains("cannot write no/such/dir/x.png"), "{err}");
    let err = fails(&raytree(&["render", "good.json", "-o", "x.jpg"], d));
    assert!(err.contains(".png or .exr"), "{err}");
    let err = fails(&raytree(
        &["render", "good.json", "-o", "x.png", "--fresnel", "fast"],
        d,
    ));
    assert!(err.contains("--fresnel"), "{err}");
    for eps in [["--epsilon=-1", ""], ["--epsilon", "-1"]] {
        let mut args = vec!["render", "good.json", "-o", "x.png"];
        args.extend(eps.iter().filter(|a| !a.is_empty()));
        let err = fails(&raytree(&args, d));
        assert!(
            err.contains("--epsilon: must be a finite number >= 0"),
            "{err}"
        );
    }
    let err = fails(&raytree(
        &["render", "good.json", "-o", "x.png", "--spp", "0"],
        d,
    ));
    assert!(err.contains("--spp"), "{err}");
    let err = fails(&raytree(
        &["render", "good.json", "-o", "x.png", "--size", "0x5"],
        d,
    ));
    assert!(err.contains("--size"), "{err}");
    let err = fails(&raytree(&["render", "missing.json", "-o", "x.png"], d));
    assert!(err.contains("cannot read scene missing.json"), "{err}");
    fails(&raytree(&["render", "--bogus"], d));
    assert_eq!(std::fs::read_dir(d).unwrap().count(), 1, "no output files");
}

/// A negative number in exponent form reaches validation (clap's own negative-number test
/// takes `-1e-4` for a flag), so the message names the rule, not a parsing accident.
#[test]
fn negative_exponent_values_reach_validation() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value, expect) in [
        (
            "--epsilon",
            "-1e-4",
            "--epsilon: must be a finite number >= 0",
        ),
        ("--min-weight", "-1e-3", "--min-weight"),
        ("--aperture", "-2e-1", "--aperture"),
    ] {
        let o = raytree(&["render", flag, value, "-o", "x.png"], dir.path());
        let err = fails(&o);
        assert!(
            err.contains(expect) && !err.contains("unexpected argument"),
            "{flag} {value}: {err}"
        );
        assert!(!dir.path().join("x.png").exists());
    }
}

/// Flags the path integrator does not read, given for a path-traced scene, get a note on
/// stderr naming them (the render still runs); without them, or under Whitted, no note; and
/// `--rr-depth`, which the Whitted integrator does not read, gets one under Whitted.
#[test]
fn flags_the_path_integrator_ignores_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let caustic = fixture("caustic.json");
    let base = ["render", caustic.as_str(), "--size", "8x6", "--spp", "1"];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let o = raytree(&args, d);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o)
    };
    let err = run(&["--fresnel", "schlick", "--min-weight", "0", "-o", "a.png"]);
    assert!(
        err.contains("note: the path integrator ignores --fresnel, --min-weight:"),
        "{err}"
    );
    assert!(!run(&["-o", "b.png"]).contains("ignores"));
    let err = run(&[
        "--integrator",
        "whitted",
        "--fresnel",
        "schlick",
        "-o",
        "c.png",
    ]);
    assert!(!err.contains("ignores"), "{err}");
    let err = run(&["--integrator", "whitted", "--rr-depth", "3", "-o", "d.png"]);
    assert!(
        err.contains("note: the Whitted integrator ignores --rr-depth"),
        "{err}"
    );
}

/// `raytree effects` names the settings keys a scene writes in the old spelling and prints its
/// settings in the new one, which reads back to the same render; the new spelling gets no
/// such line, and a key of another integrator inside `settings.integrator` is refused with
/// the file and position, exit 2.
#[test]
fn effects_names_the_old_spelling_and_the_new_one_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let old = GOOD.replace(
        "\n}",
        r#", "settings": {"integrator": "path", "rr_depth": 3, "light_samples": 2, "spp": 2}}"#,
    );
    std::fs::write(d.join("old.json"), &old).unwrap();
    let o = raytree(&["effects", "old.json"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let line = out
        .lines()
        .find(|l| l.starts_with("settings written in the old spelling"))
        .unwrap_or_else(|| panic!("{out}"));
    let want = r#"integrator, light_samples, rr_depth; in the new spelling: "integrator": {"type":"path","rr_depth":3}, "other_integrators": [{"type":"whitted","light_samples":2}]"#;
    assert!(line.ends_with(want), "{line}");
    let new = GOOD.replace(
        "\n}",
        r#", "settings": {"integrator": {"type":"path","rr_depth":3}, "other_integrators": [{"type":"whitted","light_samples":2}], "spp": 2}}"#,
    );
    std::fs::write(d.join("new.json"), &new).unwrap();
    let o = raytree(&["effects", "new.json"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("old spelling"));
    for (scene, out) in [("old.json", "old.exr"), ("new.json", "new.exr")] {
        let o = raytree(&["render", scene, "-o", out], d);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(
        std::fs::read(d.join("old.exr")).unwrap(),
        std::fs::read(d.join("new.exr")).unwrap()
    );
    let bad = GOOD.replace(
        "\n}",
        ",\n\"settings\": {\"integrator\": {\"type\": \"path\", \"fresnel\": \"schlick\"}}}",
    );
    std::fs::write(d.join("bad.json"), &bad).unwrap();
    let o = raytree(&["render", "bad.json", "-o", "bad.png"], d);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("bad.json:9:")
            && err.contains(
                "settings.integrator.fresnel: unknown field \"fresnel\", expected `rr_depth`"
            ),
        "{err}"
    );
    assert!(!d.join("bad.png").exists());
}
