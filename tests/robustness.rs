//! Bad input and non-finite output: the scene loader under fuzzing (proptest over mutated
//! JSON, bounded case count), and the CLI's acne sweep and NaN guard.

mod common;
use common::raytree;

use proptest::prelude::*;
use raytree::Scene;
use serde_json::Value;

const CLASSIC: &str = include_str!("../fixtures/classic.json");

/// Every JSON pointer below the root of `v`.
fn pointers(v: &Value, at: &str, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let p = format!("{at}/{k}");
                out.push(p.clone());
                pointers(x, &p, out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let p = format!("{at}/{i}");
                out.push(p.clone());
                pointers(x, &p, out);
            }
        }
        _ => {}
    }
}

fn replacement() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        Just(Value::Bool(true)),
        Just(serde_json::json!(-1)),
        Just(serde_json::json!(0)),
        Just(serde_json::json!(1e308)),
        Just(serde_json::json!(-1e308)),
        Just(serde_json::json!(5e-324)),
        Just(serde_json::json!(4_294_967_296u64)),
        Just(serde_json::json!("x")),
        Just(serde_json::json!([])),
        Just(serde_json::json!({})),
        Just(serde_json::json!([1, 2])),
        Just(serde_json::json!([0, 0, 0])),
        Just(serde_json::json!([1, 2, 3, 4])),
        Just(serde_json::json!({"type": "sphere"})),
        any::<f64>()
            .prop_filter("JSON numbers are finite", |f| f.is_finite())
            .prop_map(|f| serde_json::json!(f)),
        "[a-z_]{1,8}".prop_map(Value::String),
    ]
}

#[derive(Clone, Debug)]
enum Mutation {
    Replace(usize, Value),
    Remove(usize),
    AddKey(usize, String),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), replacement()).prop_map(|(i, v)| Mutation::Replace(i, v)),
        any::<usize>().prop_map(Mutation::Remove),
        (any::<usize>(), "[a-z]{1,6}").prop_map(|(i, k)| Mutation::AddKey(i, k)),
    ]
}

fn apply(doc: &mut Value, m: &Mutation) {
    let mut ps = Vec::new();
    pointers(doc, "", &mut ps);
    let pick = |i: usize| ps[i % ps.len()].clone();
    match m {
        Mutation::Replace(i, v) => {
            if let Some(x) = doc.pointer_mut(&pick(*i)) {
                *x = v.clone();
            }
        }
        Mutation::Remove(i) => {
            let p = pick(*i);
            let (parent, key) = p.rsplit_once('/').expect("below the root");
            match doc.pointer_mut(parent) {
                Some(Value::Object(m)) => {
                    m.remove(key);
                }
                Some(Value::Array(a)) => {
                    let k: usize = key.parse().expect("index");
                    a.remove(k);
                }
                _ => {}
            }
        }
        Mutation::AddKey(i, k) => {
            let p = pick(*i);
            let parent = p.rsplit_once('/').map_or("", |x| x.0);
            if let Some(Value::Object(m)) = doc.pointer_mut(parent) {
                m.insert(format!("zz_{k}"), Value::Null);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, failure_persistence: None, ..ProptestConfig::default() })]

    /// Structured mutations of a valid scene: never a panic; every rejection names a JSON path.
    #[test]
    fn mutated_scenes_never_panic_and_name_a_path(ms in prop::collection::vec(mutation(), 1..4)) {
        let mut doc: Value = serde_json::from_str(CLASSIC).unwrap();
        for m in &ms {
            apply(&mut doc, m);
        }
        let src = serde_json::to_string_pretty(&doc).unwrap();
        if let Err(e) = Scene::from_json(&src) {
            prop_assert!(!e.path.is_empty(), "rejection without a path: {e}\n{src}");
            prop_assert!(e.line.is_some() && e.column.is_some(), "no position: {e}");
        }
    }

    /// Byte-level damage (truncation, a flipped character): never a panic; a truncated
    /// document is always rejected, and every rejection has a line and column.
    #[test]
    fn damaged_text_never_panics(cut in 0usize..2000, at in 0usize..2000, ch in any::<char>()) {
        let src: String = CLASSIC.chars().take(cut.max(1)).collect();
        let result = Scene::from_json(&src);
        if src.len() < CLASSIC.trim_end().len() {
            // A strict prefix lacks at least the closing brace.
            prop_assert!(result.is_err(), "a truncated scene was accepted:\n{src}");
        }
        if let Err(e) = result {
            prop_assert!(e.line.is_some() && e.column.is_some(), "no position: {e}");
        }
        let i = at % CLASSIC.len();
        if CLASSIC.is_char_boundary(i) && CLASSIC.is_char_boundary(i + 1) {
            let flipped = format!("{}{ch}{}", &CLASSIC[..i], &CLASSIC[i + 1..]);
            if let Err(e) = Scene::from_json(&flipped) {
                prop_assert!(e.line.is_some() && e.column.is_some(), "no position: {e}");
            }
        }
    }
}

#[test]
fn acne_writes_a_complete_report_directory() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "acne",
        "--strategies",
        "normal,robust",
        "--epsilons",
        "1e-9,1e-1",
        "--scales",
        "1e-3,1e6",
        "--size",
        "12x9",
        "-o",
        "rep",
    ];
    let o = raytree(&args, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rep = dir.path().join("rep");
    for f in [
        "report.md",
        "report.json",
        "plot.png",
        "heatmap-normal.png",
        "heatmap-robust.png",
    ] {
        assert!(rep.join(f).is_file(), "missing {f}");
    }
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(rep.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["cells"].as_array().unwrap().len(), 8);
    let md = std::fs::read_to_string(rep.join("report.md")).unwrap();
    assert!(md.contains("| normal | 1e-9 |") && md.contains("`robust`: clean at every scale"));
    // Re-running replaces an earlier report; no staging directory is left behind.
    assert!(raytree(&args, dir.path()).status.success());
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["rep".to_string()]);
}

#[test]
fn acne_rejects_bad_lists_and_keeps_foreign_files() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, v) in [
        ("--strategies", "normal,fancy"),
        ("--epsilons", "1e-3,x"),
        ("--scales", "0"),
        ("--size", "0x3"),
    ] {
        let o = raytree(&["acne", flag, v, "-o", "r"], dir.path());
        assert_eq!(o.status.code(), Some(2), "{flag} {v}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(flag), "{flag}");
    }
    std::fs::create_dir(dir.path().join("mine")).unwrap();
    std::fs::write(dir.path().join("mine/notes.txt"), "keep").unwrap();
    // A foreign directory is written into, never emptied: only acne's own files appear.
    let o = raytree(
        &["acne", "--size", "4x3", "--scales", "1", "-o", "mine"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("mine/notes.txt")).unwrap(),
        "keep"
    );
    assert!(dir.path().join("mine/report.json").is_file());
}

#[test]
fn render_reports_the_first_nonfinite_pixel_and_its_tree() {
    let dir = tempfile::tempdir().unwrap();
    let scene = r#"{"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30, "width": 9, "height": 9},
        "materials": {"hot": {"emission": [1.7e308, 1.7e308, 1.7e308], "transmissivity": [1, 1, 1]},
                      "hotter": {"emission": [1.7e308, 1.7e308, 1.7e308]}},
        "objects": [{"type": "sphere", "name": "front", "center": [0, 0, 0], "radius": 1, "material": "hot"},
                    {"type": "sphere", "center": [0, 0, -4], "radius": 2, "material": "hotter"}]}"#;
    std::fs::write(dir.path().join("hot.json"), scene).unwrap();
    let o = raytree(
        &["render", "hot.json", "-o", "hot.png", "--diagnose"],
        dir.path(),
    );
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("not finite") && err.contains("raytree trace --pixel"),
        "{err}"
    );
    assert!(err.contains("camera #0 -> front"), "tree missing: {err}");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("diagnostics: 0 self-hit rays"), "{out}");
    let img = image::open(dir.path().join("hot.png")).unwrap();
    assert_eq!(img.width(), 9);
}
