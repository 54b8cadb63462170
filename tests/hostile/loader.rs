//! Hostile-input cases: reading input (issue 13, items 3, 5, 7, 8). Each runs the binary under
//! the harness's memory cap and timeout, must be refused with exit 2 and one line naming the
//! file, the JSON path and line:column, and must leave no output and no temp file behind.

use super::harness::{run, run_with, temp_files};
use std::path::Path;
use std::time::Duration;

const CLASSIC: &str = include_str!("../../fixtures/classic.json");

/// A tetrahedron in front of the classic camera: dropping its first vertex changes the image.
const TETRA: &str = "v -1 0 0\nv 1 0 0\nv 0 2 0\nv 0 0.5 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

/// The classic scene with one more object, `object` (JSON text).
fn with_object(object: &str) -> String {
    CLASSIC.replacen(
        "\"objects\": [",
        &format!("\"objects\": [\n    {object},"),
        1,
    )
}

/// `render FILE -o out.png` in `dir` must be refused: exit 2, the first stderr line
/// `error: FILE:L:C: PATH: ...` (when `path` is given), one line only, no control characters,
/// no output file and no temp file.
fn refused_at(dir: &Path, file: &str, path: Option<&str>) -> String {
    let r = run(&["render", file, "--size", "8x6", "-o", "out.png"], dir);
    r.assert_refused();
    let err = r.stderr.trim_end().to_string();
    assert_eq!(err.lines().count(), 1, "one line: {err:?}");
    assert!(
        !err.chars().any(|c| c.is_control()),
        "raw control characters: {err:?}"
    );
    let rest = err
        .strip_prefix(&format!("error: {file}:"))
        .unwrap_or_else(|| panic!("no file: {err}"));
    let mut parts = rest.splitn(3, ':');
    let line = parts.next().unwrap_or("");
    let col = parts.next().unwrap_or("");
    assert!(
        line.parse::<usize>().is_ok() && col.parse::<usize>().is_ok(),
        "no line:column: {err}"
    );
    if let Some(p) = path {
        assert!(
            parts.next().unwrap_or("").starts_with(&format!(" {p}: ")),
            "path {p:?} expected: {err}"
        );
    }
    assert!(!dir.join("out.png").exists(), "output written");
    assert!(temp_files(dir).is_empty());
    err
}

fn write(dir: &Path, name: &str, text: impl AsRef<[u8]>) {
    std::fs::write(dir.join(name), text).unwrap();
}

/// Refused quickly without a position (not a file, too large): exit 2, the reason, no output.
fn refused_unread(dir: &Path, file: &str, reason: &str) {
    let r = run_with(
        &["render", file, "--size", "8x6", "-o", "out.png"],
        dir,
        512,
        Duration::from_secs(30),
    );
    r.assert_refused();
    assert!(r.stderr.contains(reason), "{reason:?}: {r:#?}");
    assert!(!dir.join("out.png").exists());
}

fn mkfifo(path: &Path) {
    let ok = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "mkfifo");
}

#[test]
fn special_files_are_refused_before_reading_as_scene_or_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mkfifo(&d.join("fifo.json"));
    mkfifo(&d.join("fifo.obj"));
    refused_unread(d, "/dev/zero", "not a regular file (a character device)");
    refused_unread(d, "fifo.json", "not a regular file (a FIFO)");
    refused_unread(d, ".", "not a regular file (a directory)");
    for (name, mesh) in [("zero.json", "/dev/zero"), ("fifo-mesh.json", "fifo.obj")] {
        let object =
            format!("{{\"type\": \"mesh\", \"file\": \"{mesh}\", \"material\": \"glass\"}}");
        write(d, name, with_object(&object));
        let err = refused_at(d, name, Some("objects[0].file"));
        assert!(err.contains("not a regular file"), "{err}");
    }
}

#[test]
fn files_over_the_limits_are_refused_without_reading_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Sparse: 64 MiB + 1 byte for the scene, 1 GiB + 1 for a mesh, no disk used.
    let big = std::fs::File::create(d.join("big.json")).unwrap();
    big.set_len((64 << 20) + 1).unwrap();
    refused_unread(d, "big.json", "larger than the limit of 64 MiB");
    let big = std::fs::File::create(d.join("big.obj")).unwrap();
    big.set_len((1 << 30) + 1).unwrap();
    let object = "{\"type\": \"mesh\", \"file\": \"big.obj\", \"material\": \"glass\"}";
    write(d, "m.json", with_object(object));
    let err = refused_at(d, "m.json", Some("objects[0].file"));
    assert!(err.contains("larger than the limit of 1024 MiB"), "{err}");
}

#[test]
fn twenty_thousand_unknown_keys_are_reported_in_linear_time() {
    // The quadratic locator took 145 s for 20,000 keys; 200,000 keys (2.9 MB) would take
    // hours, and must finish well inside the harness's timeout.
    let dir = tempfile::tempdir().unwrap();
    let keys: Vec<String> = (0..200_000).map(|i| format!("\"k{i}\": {i}")).collect();
    let object = format!(
        "{{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": \"glass\", {}}}",
        keys.join(", ")
    );
    write(dir.path(), "keys.json", with_object(&object));
    let err = refused_at(dir.path(), "keys.json", Some("objects[0].k0"));
    assert!(err.contains("unknown field \"k0\""), "{err}");
    // A type error before them is still named, by elimination over the known members only.
    let object = object.replace("\"radius\": 1", "\"radius\": \"big\"");
    write(dir.path(), "typed.json", with_object(&object));
    let err = refused_at(dir.path(), "typed.json", Some("objects[0].radius"));
    assert!(err.contains("expected f64"), "{err}");
}

#[test]
fn a_byte_order_mark_is_accepted_in_obj_and_scene() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "plain.obj", TETRA);
    write(d, "bom.obj", format!("\u{feff}{TETRA}"));
    let render = |scene: &str, out: &str| {
        let r = run(&["render", scene, "--size", "32x18", "-o", out], d);
        r.assert_clean();
        assert_eq!(r.code, Some(0), "{r:#?}");
        std::fs::read(d.join(out)).unwrap()
    };
    for obj in ["plain", "bom"] {
        let object = format!(
            "{{\"type\": \"mesh\", \"file\": \"{obj}.obj\", \"material\": \"mirror\", \"translate\": [0, 0.2, 2]}}"
        );
        write(d, &format!("{obj}.json"), with_object(&object));
    }
    write(d, "classic.json", CLASSIC);
    let classic = render("classic.json", "classic.png");
    let plain = render("plain.json", "plain.png");
    assert_ne!(plain, classic, "the mesh is in view");
    assert_eq!(render("bom.json", "bom.png"), plain);
    write(d, "bomscene.json", format!("\u{feff}{CLASSIC}"));
    assert_eq!(render("bomscene.json", "bomscene.png"), classic);
}

#[test]
fn duplicate_keys_are_refused_at_the_second() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A material defined twice: the second is where the error is.
    let dup = CLASSIC.replacen(
        "\"glass\": {",
        "\"glass\": {\"ior\": -1},\n    \"glass\": {",
        1,
    );
    write(d, "mat.json", &dup);
    let err = refused_at(d, "mat.json", Some("materials.glass"));
    let second = dup
        .lines()
        .position(|l| l.contains("\"glass\": {\"ior\": -1}"))
        .unwrap()
        + 2;
    assert!(err.contains(&format!("mat.json:{second}:")), "{err}");
    assert!(err.contains("duplicate key \"glass\""), "{err}");
    let object = "{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"radius\": 2, \"material\": \"glass\"}";
    write(d, "radius.json", with_object(object));
    refused_at(d, "radius.json", Some("objects[0].radius"));
    write(
        d,
        "top.json",
        CLASSIC.replacen('{', "{\"background\": [0,0,0],", 1),
    );
    refused_at(d, "top.json", Some("background"));
}

#[test]
fn arrays_are_refused_where_objects_belong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let v: serde_json::Value = serde_json::from_str(CLASSIC).unwrap();
    let cases: [(&str, &str, serde_json::Value); 6] = [
        ("settings", "/settings", serde_json::json!([3, 7])),
        (
            "camera",
            "/camera",
            serde_json::json!([[0, 2, 7], [0, 0.9, 0], [0, 1, 0], 40, 64, 36]),
        ),
        (
            "materials.glass",
            "/materials/glass",
            serde_json::json!([null, [0, 0, 0], 0]),
        ),
        (
            "objects[0]",
            "/objects/0",
            serde_json::json!(["sphere", [0, 0, 0], 1, "glass"]),
        ),
        (
            "lights[0]",
            "/lights/0",
            serde_json::json!(["point", [0, 5, 0], [1, 1, 1]]),
        ),
        (
            "materials.checker.diffuse.checker",
            "/materials/checker/diffuse/checker",
            serde_json::json!([[1, 1, 1], [0, 0, 0], 1]),
        ),
    ];
    for (i, (path, pointer, value)) in cases.into_iter().enumerate() {
        let mut doc = v.clone();
        *doc.pointer_mut(pointer).unwrap() = value;
        let name = format!("arr{i}.json");
        write(d, &name, serde_json::to_string_pretty(&doc).unwrap());
        let err = refused_at(d, &name, Some(path));
        assert!(err.contains("got an array"), "{err}");
    }
    // An empty settings object is still fine.
    let mut doc = v.clone();
    doc["settings"] = serde_json::json!({});
    write(d, "empty.json", serde_json::to_string(&doc).unwrap());
    let r = run(&["effects", "empty.json"], d);
    assert_eq!(r.code, Some(0), "{r:#?}");
}

#[test]
fn awkward_names_keep_their_position_and_never_reach_the_terminal_raw() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let names = [
        ("a.b", r#"materials["a.b"].ior"#),
        ("x[0]", r#"materials["x[0]"].ior"#),
        ("q\"\\", r#"materials["q\"\\"].ior"#),
        ("line\nerror: fake", r#"materials["line\nerror: fake"].ior"#),
        ("\u{1b}[31mred", r#"materials["\u001b[31mred"].ior"#),
    ];
    for (i, (name, path)) in names.into_iter().enumerate() {
        let mut doc: serde_json::Value = serde_json::from_str(CLASSIC).unwrap();
        doc["materials"][name] = serde_json::json!({"ior": -1});
        let file = format!("name{i}.json");
        write(d, &file, serde_json::to_string_pretty(&doc).unwrap());
        refused_at(d, &file, Some(path));
        // The same name as an unknown material of an object: quoted and escaped.
        doc["materials"][name] = serde_json::json!({});
        doc["objects"][0]["material"] = serde_json::json!(format!("{name}!"));
        write(d, &file, serde_json::to_string_pretty(&doc).unwrap());
        let err = refused_at(d, &file, Some("objects[0].material"));
        assert!(err.contains("unknown material"), "{err}");
    }
    // An unknown key with a newline and an escape in it.
    let bad = CLASSIC.replacen("\"fov_y\"", "\"zz\\n\\u001b[2J\": 1, \"fov_y\"", 1);
    write(d, "key.json", bad);
    refused_at(d, "key.json", Some(r#"camera["zz\n\u001b[2J"]"#));
}

#[test]
fn non_utf8_input_is_placed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut bytes = CLASSIC.as_bytes().to_vec();
    let at = CLASSIC.find("\"fov_y\"").unwrap() + 1;
    bytes[at] = 0xff;
    write(d, "latin.json", &bytes);
    let line = CLASSIC[..at].matches('\n').count() + 1;
    let col = at - CLASSIC[..at].rfind('\n').unwrap();
    let err = refused_at(d, "latin.json", None);
    assert!(
        err.starts_with(&format!("error: latin.json:{line}:{col}: not valid UTF-8")),
        "{err}"
    );
    // In a mesh: the file, the line and the column.
    write(d, "latin.obj", b"v 0 0 0\nv 1 0 0\nv 0 1\xe9 0\nf 1 2 3\n");
    let object = "{\"type\": \"mesh\", \"file\": \"latin.obj\", \"material\": \"glass\"}";
    write(d, "m.json", with_object(object));
    let err = refused_at(d, "m.json", Some("objects[0].file"));
    assert!(err.contains("3:6: not valid UTF-8"), "{err}");
}

#[test]
fn an_unknown_material_among_100k_lists_a_few_closest_first() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(CLASSIC).unwrap();
    let mats: serde_json::Map<String, serde_json::Value> = (0..100_000)
        .map(|i| (format!("material{i}"), serde_json::json!({})))
        .collect();
    doc["materials"] = serde_json::Value::Object(mats);
    doc["objects"][0]["material"] = serde_json::json!("material7x");
    write(
        dir.path(),
        "many.json",
        serde_json::to_string(&doc).unwrap(),
    );
    let err = refused_at(dir.path(), "many.json", Some("objects[0].material"));
    assert!(err.len() < 300, "{} bytes: {err}", err.len());
    assert!(err.contains("(defined: \"material7\", "), "{err}");
    assert!(err.ends_with("and 99997 more)"), "{err}");
}
