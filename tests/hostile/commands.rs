//! The whole-command property of issue 13: for any scene the loader accepts, every command ends
//! with exit 0 or 2 within bounded memory, writes only finite numbers, and leaves no temp file.
//!
//! Scenes are the fixtures with extreme but accepted values stacked on them (huge and tiny radii,
//! lights of 1e30..1.7e308, epsilons up to 1e308, absorption, ior near 1 and huge, depth up to
//! 1024, a few samples, a far camera, a mesh scaled to 1e-150 or 1e150, ...), shrunk to 12x8,
//! kept only when `Scene::from_json` accepts them. Each is run through `render` (EXR and PNG),
//! `trace` (JSON and text), `diagram` (SVG) and `effects` under the harness's memory cap and a
//! timeout, and every number each writes (EXR pixels, JSON numbers, SVG attributes and text,
//! standard output and error) is checked to be finite.
//!
//! The per-sample ray budget is set to at most 4096 so that a case costs milliseconds: the
//! default budget's time is the business of `bounds.rs`, not of this property.

use super::harness::{MEM_MIB, Run, run_with, temp_files};
use proptest::prelude::*;
use proptest::test_runner::Config;
use serde_json::{Value, json};
use std::path::Path;
use std::time::Duration;

const FIXTURES: [(&str, &str); 9] = [
    ("absorption", include_str!("../../fixtures/absorption.json")),
    ("classic", include_str!("../../fixtures/classic.json")),
    ("diffuse", include_str!("../../fixtures/diffuse.json")),
    ("mirrors", include_str!("../../fixtures/mirrors.json")),
    ("nested", include_str!("../../fixtures/nested.json")),
    ("slab", include_str!("../../fixtures/slab.json")),
    ("tir-block", include_str!("../../fixtures/tir-block.json")),
    (
        "translucent-shadow",
        include_str!("../../fixtures/translucent-shadow.json"),
    ),
    (
        "water-grazing",
        include_str!("../../fixtures/water-grazing.json"),
    ),
];

/// A closed tetrahedron, for the mesh mutation.
const TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

const WIDTH: u32 = 12;
const HEIGHT: u32 = 8;

/// One extreme but (mostly) accepted change to a scene. Indices pick an object, light or
/// material modulo how many the scene has.
#[derive(Clone, Debug)]
enum Mutation {
    Radius(usize, f64),
    LightPower(usize, f64),
    Epsilon(&'static str, f64),
    Absorption(usize, f64),
    Ior(usize, f64),
    Weights(usize, f64, f64),
    Emission(usize, f64),
    Shininess(usize, f64),
    MaxDepth(u32),
    Spp(u32),
    Fresnel(&'static str),
    Shadows(&'static str),
    /// The camera moved away from what it looks at by this factor.
    CameraFar(f64),
    /// Camera and look-at shifted by this much on every axis (the scene stays near the origin).
    CameraShift(f64),
    Fov(f64),
    Background(f64),
    Ambient(f64),
    MinWeight(f64),
    Tolerance(f64),
    /// A plane normal or a directional light's direction this short.
    TinyDirection(usize, f64),
    /// The tetrahedron, scaled and translated.
    Mesh(f64, f64),
    /// A box from `min` (every axis) of side `size`.
    Box(f64, f64),
    Directional(f64),
}

fn huge() -> impl Strategy<Value = f64> {
    prop::sample::select(vec![1e30, 1e100, 1e200, 1e300, f64::MAX])
}

fn length() -> impl Strategy<Value = f64> {
    prop::sample::select(vec![
        5e-324,
        1e-300,
        1e-150,
        1e-12,
        1e-3,
        1.0,
        1e3,
        1e12,
        1e150,
        1e300,
        f64::MAX,
    ])
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let i = 0..8usize;
    prop_oneof![
        (i.clone(), length()).prop_map(|(i, v)| Mutation::Radius(i, v)),
        (i.clone(), huge()).prop_map(|(i, v)| Mutation::LightPower(i, v)),
        (
            prop::sample::select(vec!["normal", "ray", "scaled", "robust"]),
            prop::sample::select(vec![0.0, 5e-324, 1e-12, 1.0, 1e3, 1e30, 1e300, 1e308])
        )
            .prop_map(|(s, e)| Mutation::Epsilon(s, e)),
        (
            i.clone(),
            prop::sample::select(vec![0.0, 1e-300, 1.0, 1e3, 1e300, f64::MAX])
        )
            .prop_map(|(i, v)| Mutation::Absorption(i, v)),
        (
            i.clone(),
            prop::sample::select(vec![
                1e-300,
                1e-9,
                1.0 - 1e-15,
                1.0,
                1.0 + 1e-15,
                1.0 + 1e-9,
                1e9,
                1e300,
                f64::MAX
            ])
        )
            .prop_map(|(i, v)| Mutation::Ior(i, v)),
        (
            i.clone(),
            prop::sample::select(vec![0.0, 1.0, 2.0, 1e300]),
            prop::sample::select(vec![0.0, 1.0, 2.0, 1e300])
        )
            .prop_map(|(i, r, t)| Mutation::Weights(i, r, t)),
        (i.clone(), huge()).prop_map(|(i, v)| Mutation::Emission(i, v)),
        (
            i.clone(),
            prop::sample::select(vec![0.0, 1e-300, 1e300, f64::MAX])
        )
            .prop_map(|(i, v)| Mutation::Shininess(i, v)),
        prop::sample::select(vec![0u32, 1, 2, 64, 1024]).prop_map(Mutation::MaxDepth),
        (1u32..=4).prop_map(Mutation::Spp),
        prop::sample::select(vec!["exact", "schlick", "none"]).prop_map(Mutation::Fresnel),
        prop::sample::select(vec!["opaque", "translucent"]).prop_map(Mutation::Shadows),
        prop::sample::select(vec![1e-300, 1e-9, 1e6, 1e150, 1e300]).prop_map(Mutation::CameraFar),
        prop::sample::select(vec![1e8, 1e16, 1e100, 1e300, -1e300]).prop_map(Mutation::CameraShift),
        prop::sample::select(vec![1e-300, 1e-9, 1.0, 179.0, 180.0 - 1e-13]).prop_map(Mutation::Fov),
        huge().prop_map(Mutation::Background),
        huge().prop_map(Mutation::Ambient),
        prop::sample::select(vec![0.0, 1e-300, 0.5, 1e300]).prop_map(Mutation::MinWeight),
        prop::sample::select(vec![0.0, 1e-300, 1e300]).prop_map(Mutation::Tolerance),
        (
            i.clone(),
            prop::sample::select(vec![1e-320, 1e-200, 1e-100])
        )
            .prop_map(|(i, v)| Mutation::TinyDirection(i, v)),
        (
            prop::sample::select(vec![-1e150, 1e-150, 1e-3, 1.0, 1e150]),
            prop::sample::select(vec![0.0, 1.0, 1e12, 1e300])
        )
            .prop_map(|(s, t)| Mutation::Mesh(s, t)),
        (
            prop::sample::select(vec![-1e300, -1.0, 0.5, 1e300]),
            prop::sample::select(vec![1e-300, 1.0, 1e300])
        )
            .prop_map(|(m, s)| Mutation::Box(m, s)),
        huge().prop_map(Mutation::Directional),
    ]
}

fn grey(v: f64) -> Value {
    json!([v, v, v])
}

/// The `i`-th member (modulo the count) of the array or map at `key`.
fn pick<'a>(scene: &'a mut Value, key: &str, i: usize) -> Option<&'a mut Value> {
    match scene.get_mut(key)? {
        Value::Array(a) if !a.is_empty() => {
            let n = a.len();
            a.get_mut(i % n)
        }
        Value::Object(o) if !o.is_empty() => {
            let n = o.len();
            o.values_mut().nth(i % n)
        }
        _ => None,
    }
}

fn settings(scene: &mut Value) -> &mut serde_json::Map<String, Value> {
    let s = &mut scene["settings"];
    if !s.is_object() {
        *s = json!({});
    }
    s.as_object_mut().expect("an object")
}

fn first_material(scene: &Value) -> String {
    scene["materials"]
        .as_object()
        .and_then(|m| m.keys().next().cloned())
        .expect("fixtures have materials")
}

fn apply(scene: &mut Value, m: &Mutation) {
    match *m {
        Mutation::Radius(i, v) => {
            if let Some(o) = pick(scene, "objects", i).filter(|o| o.get("radius").is_some()) {
                o["radius"] = json!(v);
            }
        }
        Mutation::LightPower(i, v) => {
            if let Some(l) = pick(scene, "lights", i) {
                let key = if l.get("intensity").is_some() {
                    "intensity"
                } else {
                    "irradiance"
                };
                l[key] = grey(v);
            }
        }
        Mutation::Epsilon(s, e) => {
            settings(scene).insert("offset".into(), json!({"strategy": s, "epsilon": e}));
        }
        Mutation::Absorption(i, v) => {
            if let Some(mat) = pick(scene, "materials", i) {
                mat["absorption"] = grey(v);
            }
        }
        Mutation::Ior(i, v) => {
            if let Some(mat) = pick(scene, "materials", i) {
                mat["ior"] = json!(v);
            }
        }
        Mutation::Weights(i, r, t) => {
            if let Some(mat) = pick(scene, "materials", i) {
                mat["reflectivity"] = grey(r);
                mat["transmissivity"] = grey(t);
            }
        }
        Mutation::Emission(i, v) => {
            if let Some(mat) = pick(scene, "materials", i) {
                mat["emission"] = grey(v);
            }
        }
        Mutation::Shininess(i, v) => {
            if let Some(mat) = pick(scene, "materials", i) {
                mat["shininess"] = json!(v);
                mat["specular"] = grey(1.0);
            }
        }
        Mutation::MaxDepth(d) => {
            settings(scene).insert("max_depth".into(), json!(d));
        }
        Mutation::Spp(n) => {
            settings(scene).insert("spp".into(), json!(n));
        }
        Mutation::Fresnel(f) => {
            settings(scene).insert("fresnel".into(), json!(f));
        }
        Mutation::Shadows(s) => {
            settings(scene).insert("shadows".into(), json!(s));
        }
        Mutation::CameraFar(k) => {
            let cam = &mut scene["camera"];
            let (Some(p), Some(a)) = (vec3(&cam["position"]), vec3(&cam["look_at"])) else {
                return;
            };
            cam["position"] = json!([0, 1, 2].map(|j| a[j] + (p[j] - a[j]) * k));
        }
        Mutation::CameraShift(d) => {
            let cam = &mut scene["camera"];
            for key in ["position", "look_at"] {
                if let Some(p) = vec3(&cam[key]) {
                    cam[key] = json!(p.map(|c| c + d));
                }
            }
        }
        Mutation::Fov(f) => scene["camera"]["fov_y"] = json!(f),
        Mutation::Background(v) => scene["background"] = grey(v),
        Mutation::Ambient(v) => scene["ambient"] = grey(v),
        Mutation::MinWeight(w) => {
            settings(scene).insert("min_weight".into(), json!(w));
        }
        Mutation::Tolerance(t) => {
            settings(scene).insert("tolerance".into(), json!(t));
        }
        Mutation::TinyDirection(i, v) => {
            if let Some(o) = pick(scene, "objects", i).filter(|o| o.get("normal").is_some()) {
                o["normal"] = json!([0.0, v, v]);
            } else if let Some(l) =
                pick(scene, "lights", i).filter(|l| l.get("direction").is_some())
            {
                l["direction"] = json!([v, -v, 0.0]);
            }
        }
        Mutation::Mesh(s, t) => {
            let material = first_material(scene);
            if let Some(objects) = scene["objects"].as_array_mut() {
                objects.push(json!({"type": "mesh", "name": "tet", "file": "tet.obj",
                    "scale": s, "translate": [t, 0.0, -t], "material": material}));
            }
        }
        Mutation::Box(lo, size) => {
            let material = first_material(scene);
            if let Some(objects) = scene["objects"].as_array_mut() {
                objects.push(json!({"type": "box", "name": "crate", "min": [lo, lo, lo],
                    "max": [lo + size, lo + size, lo + size], "material": material}));
            }
        }
        Mutation::Directional(v) => {
            if let Some(lights) = scene["lights"].as_array_mut() {
                lights.push(json!({"type": "directional", "name": "sun",
                    "direction": [-1.0, -2.0, -0.5], "irradiance": grey(v)}));
            }
        }
    }
}

fn vec3(v: &Value) -> Option<[f64; 3]> {
    let a = v.as_array()?;
    Some([
        a.first()?.as_f64()?,
        a.get(1)?.as_f64()?,
        a.get(2)?.as_f64()?,
    ])
}

/// A fixture with the mutations applied, shrunk to the test's size, its ray budget bounded.
fn scene_text(fixture: usize, mutations: &[Mutation], max_rays: u64) -> String {
    let mut scene: Value = serde_json::from_str(FIXTURES[fixture].1).expect("fixture JSON");
    for m in mutations {
        apply(&mut scene, m);
    }
    scene["camera"]["width"] = json!(WIDTH);
    scene["camera"]["height"] = json!(HEIGHT);
    settings(&mut scene).insert("max_rays".into(), json!(max_rays));
    serde_json::to_string_pretty(&scene).expect("serialisable")
}

fn accepted(text: &str) -> bool {
    raytree::Scene::from_json_with(text, &mut |_| {
        raytree::mesh::parse_obj(TET).map_err(|e| e.to_string())
    })
    .is_ok()
}

/// Every token of `text` that a program would read as a non-finite number: Rust's and most
/// languages' spellings of NaN and infinity (`NaN`, `inf`, `-inf`, `infinity`), however cased.
fn nonfinite_tokens(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || "+-._".contains(c)))
        .filter(|t| t.parse::<f64>().is_ok_and(|v| !v.is_finite()))
        .map(str::to_string)
        .take(5)
        .collect()
}

/// The first number in a JSON value that is missing: `null` inside an array (vectors and
/// colours are arrays of numbers; serde_json writes NaN and infinities as `null`).
fn null_in_array(v: &Value, path: &str, in_array: bool) -> Option<String> {
    match v {
        Value::Null if in_array => Some(path.to_string()),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| null_in_array(x, &format!("{path}[{i}]"), true)),
        Value::Object(o) => o
            .iter()
            .find_map(|(k, x)| null_in_array(x, &format!("{path}.{k}"), false)),
        _ => None,
    }
}

/// Why the SVG is not all finite, if it is not: every attribute value and text node split into
/// tokens, none of which may read as a non-finite number, and every coordinate must parse.
fn svg_problem(svg: &str) -> Option<String> {
    let doc = match roxmltree::Document::parse(svg) {
        Ok(d) => d,
        Err(e) => return Some(format!("not XML: {e}")),
    };
    for n in doc.descendants() {
        if let Some(t) = n.text() {
            let bad = nonfinite_tokens(t);
            if !bad.is_empty() {
                return Some(format!("text {t:?}: {bad:?}"));
            }
        }
        for a in n.attributes() {
            let bad = nonfinite_tokens(a.value());
            if !bad.is_empty() {
                return Some(format!("{}={:?}", a.name(), a.value()));
            }
            let numeric = ["x", "y", "cx", "cy", "r", "width", "height", "font-size"];
            if numeric.contains(&a.name()) && !a.value().parse::<f64>().is_ok_and(f64::is_finite) {
                return Some(format!(
                    "{}={:?} is not a finite number",
                    a.name(),
                    a.value()
                ));
            }
            if a.name() == "points" {
                for c in a.value().split([' ', ',']).filter(|c| !c.is_empty()) {
                    if !c.parse::<f64>().is_ok_and(f64::is_finite) {
                        return Some(format!("points has {c:?}"));
                    }
                }
            }
        }
    }
    None
}

fn exr_problem(path: &Path) -> Option<String> {
    let img = match image::open(path) {
        Ok(i) => i.into_rgb32f(),
        Err(e) => return Some(format!("unreadable EXR: {e}")),
    };
    let bad = img
        .pixels()
        .flat_map(|p| p.0)
        .filter(|v| !v.is_finite())
        .count();
    (bad > 0).then(|| format!("{bad} non-finite channels"))
}

fn tree_json_problem(stdout: &str) -> Option<String> {
    let v: Value = match serde_json::from_str(stdout) {
        Ok(v) => v,
        Err(e) => return Some(format!("not JSON (a NaN or inf token?): {e}")),
    };
    if let Some(p) = null_in_array(&v, "", false) {
        return Some(format!("null where a number belongs at {p}"));
    }
    // Every number that is not optional in the schema is typed: a null there fails here.
    serde_json::from_value::<raytree::RayTree>(v)
        .err()
        .map(|e| format!("not a tree: {e}"))
}

/// A check of a successful run's output (its streams, its output file).
type Check = dyn Fn(&Run, Option<&Path>) -> Option<String>;

/// What one command did wrong, if anything: its exit, a panic, a timeout, a temp file, an
/// output left by a refused run, a non-finite number in its streams or its output file.
fn command_problem(
    dir: &Path,
    args: &[&str],
    output: Option<&str>,
    check: &Check,
) -> Option<String> {
    let r = run_with(args, dir, MEM_MIB, Duration::from_secs(30));
    let out = output.map(|o| dir.join(o));
    let problem = if r.timed_out {
        Some("timed out".to_string())
    } else if !matches!(r.code, Some(0 | 2)) {
        Some(format!("exit {:?}", r.code))
    } else if r.stderr.contains("panicked") {
        Some("panicked".into())
    } else if !temp_files(dir).is_empty() {
        Some(format!("temp files left: {:?}", temp_files(dir)))
    } else if r.code == Some(2) && !r.stderr.contains("error:") {
        Some("exit 2 without an error message".into())
    } else if r.code == Some(2) && out.as_ref().is_some_and(|o| o.exists()) {
        Some("a refused run left its output".into())
    } else if r.code == Some(0) && out.as_ref().is_some_and(|o| !o.exists()) {
        Some("exit 0 but no output file".into())
    } else if let Some(t) = Some(nonfinite_tokens(&r.stdout)).filter(|t| !t.is_empty()) {
        Some(format!("stdout holds {t:?}"))
    } else if let Some(t) = Some(nonfinite_tokens(&r.stderr)).filter(|t| !t.is_empty()) {
        Some(format!("stderr holds {t:?}"))
    } else if r.code == Some(0) {
        check(&r, out.as_deref())
    } else {
        None
    };
    if let Some(o) = &out {
        let _ = std::fs::remove_file(o);
    }
    problem.map(|p| {
        format!(
            "raytree {}: {p}\nexit {:?}\nstdout {}\nstderr {}",
            args.join(" "),
            r.code,
            cut(&r.stdout),
            cut(&r.stderr)
        )
    })
}

fn cut(s: &str) -> String {
    if s.len() > 2000 {
        format!(
            "{}... ({} bytes)",
            &s[..s.floor_char_boundary(2000)],
            s.len()
        )
    } else {
        s.to_string()
    }
}

/// Run every command on `scene.json` in `dir`; the first problem found, if any.
fn commands_problem(dir: &Path, pixel: (u32, u32)) -> Option<String> {
    let size = format!("{WIDTH}x{HEIGHT}");
    let px = format!("{},{}", pixel.0, pixel.1);
    let none = |_: &Run, _: Option<&Path>| None;
    let exr = |_: &Run, o: Option<&Path>| o.and_then(exr_problem);
    let png = |_: &Run, o: Option<&Path>| {
        o.and_then(|o| image::open(o).err().map(|e| format!("unreadable PNG: {e}")))
    };
    let json = |r: &Run, _: Option<&Path>| tree_json_problem(&r.stdout);
    let svg = |_: &Run, o: Option<&Path>| {
        o.and_then(|o| svg_problem(&std::fs::read_to_string(o).unwrap_or_default()))
    };
    let s = size.as_str();
    let p = px.as_str();
    let runs: [(Vec<&str>, Option<&str>, &Check); 6] = [
        (
            vec!["render", "scene.json", "--size", s, "-o", "x.exr"],
            Some("x.exr"),
            &exr,
        ),
        (
            vec!["render", "scene.json", "--size", s, "-o", "x.png"],
            Some("x.png"),
            &png,
        ),
        (
            vec!["trace", "scene.json", "--size", s, "--pixel", p, "--json"],
            None,
            &json,
        ),
        (
            vec!["trace", "scene.json", "--size", s, "--pixel", p],
            None,
            &none,
        ),
        (
            vec!["diagram", "scene.json", "--pixel", p, "-o", "x.svg"],
            Some("x.svg"),
            &svg,
        ),
        (vec!["effects", "scene.json"], None, &none),
    ];
    runs.iter()
        .find_map(|(args, out, check)| command_problem(dir, args, *out, *check))
}

fn case() -> impl Strategy<Value = (usize, Vec<Mutation>, u64, (u32, u32))> {
    (
        0..FIXTURES.len(),
        prop::collection::vec(mutation(), 1..=5),
        prop::sample::select(vec![1u64, 16, 256, 4096]),
        (0..WIDTH, 0..HEIGHT),
    )
}

proptest! {
    #![proptest_config(Config {
        cases: 128,
        max_shrink_iters: 200,
        ..Config::default()
    })]

    #[test]
    fn every_command_on_an_accepted_scene_ends_cleanly_with_finite_output(
        (fixture, mutations, max_rays, pixel) in case()
    ) {
        let text = scene_text(fixture, &mutations, max_rays);
        prop_assume!(accepted(&text));
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("scene.json"), &text).unwrap();
        std::fs::write(dir.path().join("tet.obj"), TET).unwrap();
        if let Some(p) = commands_problem(dir.path(), pixel) {
            return Err(TestCaseError::fail(format!(
                "{}\nfixture {} with {mutations:?}, max_rays {max_rays}\n{text}",
                p, FIXTURES[fixture].0
            )));
        }
    }
}

/// The checks above catch what they are for: each is fed a known-bad output.
#[test]
fn the_checks_reject_non_finite_output() {
    assert_eq!(
        nonfinite_tokens("L [NaN, 0.5, inf]  t=-inf x=1e999"),
        ["NaN", "inf", "-inf", "1e999"]
    );
    assert!(nonfinite_tokens("infinite information, not finite: nan-free 1e308").is_empty());
    assert!(tree_json_problem("{\"radiance\": [NaN, 0, 0]}").is_some());
    assert!(
        tree_json_problem("{\"radiance\": [null, 0, 0]}")
            .unwrap()
            .contains("radiance[0]")
    );
    assert!(svg_problem("<svg><circle cx=\"1\" cy=\"NaN\" r=\"2\"/></svg>").is_some());
    assert!(svg_problem("<svg><circle cx=\"1\" cy=\"2\" r=\"inf\"/></svg>").is_some());
    assert!(svg_problem("<svg><polyline points=\"1,2 NaN,3\"/></svg>").is_some());
    assert!(svg_problem("<svg><text x=\"1\" y=\"2\">R=NaN</text></svg>").is_some());
    assert_eq!(
        svg_problem("<svg><circle cx=\"1\" cy=\"2\" r=\"3\"/></svg>"),
        None
    );
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::Rgb32FImage::from_pixel(2, 2, image::Rgb([0.5, 0.5, 0.5]));
    img.put_pixel(1, 1, image::Rgb([f32::INFINITY, 0.0, 0.0]));
    let p = dir.path().join("inf.exr");
    img.save(&p).unwrap();
    assert!(exr_problem(&p).is_some());
    // And the real outputs of the built-in scene pass them.
    let tree = raytree::trace_pixel(&raytree::Scene::default_scene(), 400, 200).unwrap();
    assert_eq!(
        tree_json_problem(&serde_json::to_string(&tree).unwrap()),
        None
    );
}
