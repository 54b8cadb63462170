//! Hostile-input cases: outputs (issue 13, parts 1, 2, 4, 6 and 9). What the CLI writes: never a
//! file it did not create, never through a FIFO or device, never an input; no panic on a closed
//! or full stdout/stderr; no non-finite number in any output; no temp file left, even after a
//! signal.

use super::harness::{Run, run, snapshot, temp_files};
use std::os::unix::fs::FileTypeExt;
use std::path::Path;
use std::process::{Command, Stdio};

pub const BIN: &str = env!("CARGO_BIN_EXE_raytree");

pub fn classic() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/classic.json"
    ))
    .unwrap()
}

/// The classic scene with the key light's intensity set to `v`.
pub fn hot(v: &str) -> String {
    classic().replace(
        "\"intensity\": [120.0, 120.0, 120.0]",
        &format!("\"intensity\": [{v}, {v}, {v}]"),
    )
}

/// A tetrahedron in OBJ, and a scene that places it.
pub fn mesh_scene(dir: &Path) {
    std::fs::write(
        dir.join("tet.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let s = classic().replace(
        "\"objects\": [",
        "\"objects\": [\n    {\"type\": \"mesh\", \"name\": \"tet\", \"file\": \"tet.obj\", \"material\": \"mirror\"},",
    );
    std::fs::write(dir.join("mesh.json"), s).unwrap();
}

/// Run a shell script in `dir` with `$RT` the binary, under the harness's memory cap.
pub fn sh(script: &str, dir: &Path) -> Run {
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {}; {script}",
            super::harness::MEM_MIB * 1024
        ))
        .env("RT", BIN)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    Run {
        code: out.status.code(),
        timed_out: false,
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// A refused run that changed nothing and left no temp file.
pub fn refused_unchanged(args: &[&str], dir: &Path, why: &str) {
    let before = snapshot(dir);
    let r = run(args, dir);
    r.assert_refused();
    assert!(r.stderr.contains(why), "expected {why:?}: {r:#?}");
    assert_eq!(snapshot(dir), before, "a refused run changed files");
    assert!(temp_files(dir).is_empty(), "{:?}", temp_files(dir));
}

const ACNE: [&str; 6] = ["--size", "8x6", "--epsilons", "1e-4", "--scales", "1"];

#[test]
fn acne_never_deletes_a_directory_that_holds_its_scene_as_report_json() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("d");
    std::fs::create_dir(&d).unwrap();
    std::fs::write(d.join("report.json"), classic()).unwrap();
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    let mut args = vec!["acne", "d/report.json", "-o", "d"];
    args.extend(ACNE);
    refused_unchanged(&args, dir.path(), "an input of this command");
}

#[test]
fn acne_and_cost_replace_only_their_own_files_in_an_existing_directory() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.json"), classic()).unwrap();
    for (cmd, dname) in [("acne", "a"), ("cost", "c")] {
        let d = dir.path().join(dname);
        std::fs::create_dir(&d).unwrap();
        std::fs::write(d.join("report.json"), "an old report").unwrap();
        std::fs::write(d.join("notes.txt"), "mine").unwrap();
        let mut args = vec![cmd, "scene.json", "-o", dname];
        if cmd == "acne" {
            args.extend(ACNE);
        } else {
            args.extend(["--quick", "--repeats", "1", "--size", "16x9"]);
        }
        let r = run(&args, dir.path());
        r.assert_clean();
        assert_eq!(r.code, Some(0), "{r:#?}");
        assert_eq!(
            std::fs::read_to_string(d.join("notes.txt")).unwrap(),
            "mine"
        );
        let names: Vec<String> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.len() > 3, "{names:?}");
        assert!(temp_files(dir.path()).is_empty());
    }
}

#[test]
fn an_output_that_is_an_input_is_refused_by_identity_not_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    std::fs::write(p.join("scene.png"), classic()).unwrap();
    std::os::unix::fs::symlink("scene.png", p.join("alias.png")).unwrap();
    std::fs::hard_link(p.join("scene.png"), p.join("hard.png")).unwrap();
    mesh_scene(p);
    std::fs::hard_link(p.join("tet.obj"), p.join("tet.png")).unwrap();
    let why = "an input of this command";
    let size = ["--size", "8x6"];
    for out in ["scene.png", "./scene.png", "alias.png", "hard.png"] {
        let mut args = vec!["render", "scene.png", "-o", out];
        args.extend(size);
        refused_unchanged(&args, p, why);
    }
    let mut args = vec!["render", "mesh.json", "-o", "tet.png"];
    args.extend(size);
    refused_unchanged(&args, p, why);
    refused_unchanged(
        &["diagram", "mesh.json", "--pixel", "1,1", "-o", "tet.png"],
        p,
        why,
    );
    run(&["render", "--size", "8x6", "-o", "a.png"], p).assert_clean();
    refused_unchanged(&["compare", "a.png", "a.png", "-o", "a.png"], p, why);
}

#[test]
fn a_symlinked_output_is_followed_and_the_link_kept() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    std::fs::write(p.join("real.png"), "old").unwrap();
    std::os::unix::fs::symlink("real.png", p.join("link.png")).unwrap();
    let r = run(&["render", "--size", "8x6", "-o", "link.png"], p);
    r.assert_clean();
    assert_eq!(r.code, Some(0));
    assert!(
        p.join("link.png")
            .symlink_metadata()
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(
        std::fs::read(p.join("real.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
    // A dangling link is refused rather than guessed at.
    std::os::unix::fs::symlink("missing/x.png", p.join("dangling.png")).unwrap();
    refused_unchanged(
        &["render", "--size", "8x6", "-o", "dangling.png"],
        p,
        "symlink to a missing file",
    );
}

#[test]
fn fifos_and_devices_are_refused_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    assert!(
        Command::new("mkfifo")
            .arg(p.join("f.png"))
            .status()
            .unwrap()
            .success()
    );
    std::os::unix::fs::symlink("/dev/null", p.join("null.png")).unwrap();
    std::os::unix::fs::symlink("/dev/null", p.join("nulldir")).unwrap();
    for args in [
        &["render", "--size", "8x6", "-o", "f.png"][..],
        &["render", "--size", "8x6", "-o", "null.png"],
        &["diagram", "--pixel", "1,1", "-o", "null.png"],
        &["compare", "x.png", "y.png", "-o", "f.png"],
        &["cost", "--quick", "--size", "8x6", "-o", "nulldir"],
    ] {
        let r = run(args, p);
        r.assert_refused();
        assert!(
            p.join("f.png")
                .symlink_metadata()
                .unwrap()
                .file_type()
                .is_fifo()
                && p.join("null.png")
                    .symlink_metadata()
                    .unwrap()
                    .file_type()
                    .is_symlink(),
            "{args:?} replaced a special file"
        );
        assert!(temp_files(p).is_empty());
    }
}

#[test]
fn output_names_of_251_to_255_bytes_work() {
    let dir = tempfile::tempdir().unwrap();
    for n in 251..=255 {
        let name = format!("{}.png", "a".repeat(n - 4));
        let r = run(&["render", "--size", "4x3", "-o", &name], dir.path());
        r.assert_clean();
        assert_eq!(r.code, Some(0), "{n}: {r:#?}");
        assert!(dir.path().join(&name).is_file());
    }
    assert!(temp_files(dir.path()).is_empty());
}

#[test]
fn compare_refuses_a_map_name_it_would_not_write_as_such() {
    let dir = tempfile::tempdir().unwrap();
    run(&["render", "--size", "8x6", "-o", "a.png"], dir.path()).assert_clean();
    for name in ["map.jpg", "map", "map.exr"] {
        refused_unchanged(
            &["compare", "a.png", "a.png", "-o", name],
            dir.path(),
            "must end in .png",
        );
    }
}

#[test]
fn cost_with_an_infinite_error_ends_and_writes_no_non_finite_number() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("hot.json"), hot("1e200")).unwrap();
    let r = run(
        &[
            "cost",
            "hot.json",
            "--quick",
            "--repeats",
            "1",
            "--size",
            "32x18",
            "-o",
            "c",
        ],
        dir.path(),
    );
    r.assert_clean();
    assert_eq!(r.code, Some(0), "{r:#?}");
    let md = std::fs::read_to_string(dir.path().join("c/cost.md")).unwrap();
    assert!(md.contains("not finite"), "{md}");
    for f in ["cost.md", "cost.csv", "cost.json"] {
        let s = std::fs::read_to_string(dir.path().join("c").join(f))
            .unwrap()
            .to_ascii_lowercase();
        assert!(!s.contains("inf") && !s.contains("nan"), "{f}: {s}");
    }
    assert!(temp_files(dir.path()).is_empty());
}

#[test]
fn an_exr_beyond_f32_is_clamped_and_said_so() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("hot.json"), hot("1e42")).unwrap();
    let r = run(
        &["render", "hot.json", "--size", "32x18", "-o", "hot.exr"],
        dir.path(),
    );
    r.assert_clean();
    assert_eq!(r.code, Some(0));
    assert!(r.stderr.contains("were clamped"), "{r:#?}");
    let img = image::open(dir.path().join("hot.exr"))
        .unwrap()
        .into_rgb32f();
    assert!(img.pixels().flat_map(|p| p.0).all(f32::is_finite));
    assert!(img.pixels().flat_map(|p| p.0).any(|v| v == f32::MAX));
}

/// No `null` inside a JSON array (vectors are arrays of numbers; serde_json writes NaN as null).
fn no_null_in_arrays(v: &serde_json::Value, in_array: bool) -> bool {
    match v {
        serde_json::Value::Null => !in_array,
        serde_json::Value::Array(a) => a.iter().all(|x| no_null_in_arrays(x, true)),
        serde_json::Value::Object(o) => o.values().all(|x| no_null_in_arrays(x, false)),
        _ => true,
    }
}

#[test]
fn trace_json_never_writes_nan_as_null() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(
        &[
            "trace",
            "--pixel",
            "400,200",
            "--epsilon",
            "1e308",
            "--offset",
            "scaled",
            "--json",
        ],
        dir.path(),
    );
    r.assert_clean();
    if r.code == Some(0) {
        let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
        assert!(no_null_in_arrays(&v, false), "{}", r.stdout);
    } else {
        assert!(r.stderr.contains("error:") && r.stdout.is_empty(), "{r:#?}");
    }
}

#[test]
fn a_diagram_of_a_huge_sphere_writes_only_finite_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let s = classic().replace("\"radius\": 1.0,", "\"radius\": 1e300,");
    std::fs::write(dir.path().join("big.json"), s).unwrap();
    for px in ["320,180", "400,200"] {
        let r = run(
            &["diagram", "big.json", "--pixel", px, "-o", "big.svg"],
            dir.path(),
        );
        r.assert_clean();
        if r.code != Some(0) {
            continue; // refused up front is fine too
        }
        let svg = std::fs::read_to_string(dir.path().join("big.svg")).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        for n in doc.descendants().filter(|n| n.is_element()) {
            for a in n.attributes() {
                if ["x", "y", "cx", "cy", "r", "font-size", "stroke-width"].contains(&a.name()) {
                    let v: f64 = a.value().parse().unwrap();
                    assert!(v.is_finite(), "{}={}", a.name(), a.value());
                }
                if a.name() == "points" {
                    for c in a.value().split([' ', ',']) {
                        assert!(c.parse::<f64>().unwrap().is_finite(), "points {c}");
                    }
                }
            }
        }
    }
}

#[test]
fn compare_refuses_images_with_infinities() {
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::Rgb32FImage::from_pixel(4, 3, image::Rgb([0.5, 0.5, 0.5]));
    img.put_pixel(2, 1, image::Rgb([f32::INFINITY, 0.0, 0.0]));
    img.save(dir.path().join("inf.exr")).unwrap();
    let ok = image::Rgb32FImage::from_pixel(4, 3, image::Rgb([0.5, 0.5, 0.5]));
    ok.save(dir.path().join("ok.exr")).unwrap();
    refused_unchanged(
        &["compare", "inf.exr", "ok.exr", "-o", "map.png"],
        dir.path(),
        "not finite",
    );
}
