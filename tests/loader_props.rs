//! Property tests of the scene loader and the OBJ reader (issue 13): a scene the loader
//! accepts reads back the same after re-serialising; any damage to a fixture's text ends in
//! `Ok` or an error with a line and column, never a panic.

use proptest::prelude::*;
use raytree::Scene;
use raytree::scene::SceneDesc;
use serde_json::{Value, json};

const FIXTURES: [&str; 4] = [
    include_str!("../fixtures/classic.json"),
    include_str!("../fixtures/nested.json"),
    include_str!("../fixtures/tir-block.json"),
    include_str!("../fixtures/translucent-shadow.json"),
];

const OBJ: &str = "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1//1 2//1 3//1 4//1\nf -4 -3 -2\n";

/// Keys and names users write: plain, and with dots, brackets, quotes, escapes, newlines,
/// control characters and non-ASCII.
fn name() -> impl Strategy<Value = String> {
    prop_oneof![
        "[a-z][a-z0-9_-]{0,8}",
        "[a-z.\\[\\]\"\\\\ ]{0,8}",
        any::<String>().prop_map(|s| s.chars().take(12).collect()),
        Just("\u{1b}[31m\nerror: x".to_string()),
    ]
}

/// Any finite number, with the awkward ones often.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>().prop_filter("finite", |f| f.is_finite()),
        Just(0.0),
        Just(-0.0),
        Just(5e-324),
        Just(1e308),
        -10.0..10.0f64,
    ]
}

/// A fixture with its materials renamed (objects follow), a few numbers replaced, and some
/// objects and lights named.
fn scene_text() -> impl Strategy<Value = String> {
    (
        0..FIXTURES.len(),
        prop::collection::vec(name(), 4),
        prop::collection::vec((any::<prop::sample::Index>(), number()), 0..6),
        prop::collection::vec(name(), 0..3),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(f, names, numbers, labels, pretty, bom)| {
            let mut doc: Value = serde_json::from_str(FIXTURES[f]).unwrap();
            let old: Vec<String> = doc["materials"]
                .as_object()
                .unwrap()
                .keys()
                .cloned()
                .collect();
            let mut renamed = serde_json::Map::new();
            for (i, k) in old.iter().enumerate() {
                let new = names.get(i).cloned().unwrap_or_else(|| k.clone());
                renamed.insert(new, doc["materials"][k].clone());
            }
            // Names that collide collapse in the map; objects then point at whatever is left.
            let keys: Vec<String> = renamed.keys().cloned().collect();
            for o in doc["objects"].as_array_mut().unwrap() {
                let i = old
                    .iter()
                    .position(|k| o["material"] == json!(k))
                    .unwrap_or(0);
                o["material"] = json!(
                    names
                        .get(i)
                        .filter(|n| keys.contains(n))
                        .unwrap_or(&keys[0])
                );
            }
            doc["materials"] = Value::Object(renamed);
            let mut leaves = Vec::new();
            numbers_in(&doc, "", &mut leaves);
            for (at, x) in numbers {
                if !leaves.is_empty() {
                    *doc.pointer_mut(&leaves[at.index(leaves.len())]).unwrap() = json!(x);
                }
            }
            for (i, l) in labels.into_iter().enumerate() {
                if let Some(o) = doc["objects"].get_mut(i) {
                    o["name"] = json!(l);
                }
            }
            let text = if pretty {
                serde_json::to_string_pretty(&doc).unwrap()
            } else {
                serde_json::to_string(&doc).unwrap()
            };
            if bom { format!("\u{feff}{text}") } else { text }
        })
}

/// JSON pointers of every number in `v`.
fn numbers_in(v: &Value, at: &str, out: &mut Vec<String>) {
    match v {
        Value::Number(_) => out.push(at.to_string()),
        Value::Object(m) => {
            for (k, x) in m {
                let k = k.replace('~', "~0").replace('/', "~1");
                numbers_in(x, &format!("{at}/{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                numbers_in(x, &format!("{at}/{i}"), out);
            }
        }
        _ => {}
    }
}

/// Damage to text: cut a span, duplicate one, insert a JSON-ish token or any character,
/// replace a byte (kept UTF-8 by working on chars).
#[derive(Clone, Debug)]
enum Damage {
    Cut(prop::sample::Index, usize),
    Repeat(prop::sample::Index, usize),
    Insert(prop::sample::Index, String),
    Replace(prop::sample::Index, char),
    /// Replace the i-th number in the text with a bad value.
    Number(prop::sample::Index, &'static str),
}

const BAD_VALUES: [&str; 10] = [
    "-1",
    "0",
    "1e999",
    "-1e308",
    "\"x\"",
    "[]",
    "{}",
    "null",
    "[1, 2]",
    "4294967296",
];

fn damage() -> impl Strategy<Value = Damage> {
    let token = prop_oneof![
        Just("{".to_string()),
        Just("}".to_string()),
        Just("[".to_string()),
        Just("]".to_string()),
        Just(",".to_string()),
        Just(":".to_string()),
        Just("\"".to_string()),
        Just("\\".to_string()),
        Just("\u{feff}".to_string()),
        Just("1e999".to_string()),
        Just("-0".to_string()),
        Just("null".to_string()),
        Just("\"type\": \"mesh\"".to_string()),
        Just("\"radius\": 1,".to_string()),
        name().prop_map(|n| serde_json::to_string(&n).unwrap()),
    ];
    prop_oneof![
        (any::<prop::sample::Index>(), 1..40usize).prop_map(|(i, n)| Damage::Cut(i, n)),
        (any::<prop::sample::Index>(), 1..80usize).prop_map(|(i, n)| Damage::Repeat(i, n)),
        (any::<prop::sample::Index>(), token).prop_map(|(i, t)| Damage::Insert(i, t)),
        (any::<prop::sample::Index>(), any::<char>()).prop_map(|(i, c)| Damage::Replace(i, c)),
        (
            any::<prop::sample::Index>(),
            prop::sample::select(&BAD_VALUES[..])
        )
            .prop_map(|(i, v)| Damage::Number(i, v)),
    ]
}

fn apply(text: &str, d: &Damage) -> String {
    let chars: Vec<char> = text.chars().collect();
    let n = chars.len().max(1);
    let s = |a: usize, b: usize| {
        chars[a.min(chars.len())..b.min(chars.len())]
            .iter()
            .collect::<String>()
    };
    match d {
        Damage::Cut(i, len) => {
            let a = i.index(n);
            s(0, a) + &s(a + len, chars.len())
        }
        Damage::Repeat(i, len) => {
            let a = i.index(n);
            s(0, a + len) + &s(a, chars.len())
        }
        Damage::Insert(i, t) => {
            let a = i.index(n);
            s(0, a) + t + &s(a, chars.len())
        }
        Damage::Replace(i, c) => {
            let a = i.index(n);
            s(0, a) + &c.to_string() + &s(a + 1, chars.len())
        }
        Damage::Number(i, v) => {
            // Numbers: a digit or '-' after ':', '[' or ',' (and spaces), to the next delimiter.
            let mut spans = Vec::new();
            let mut k = 0;
            while k < chars.len() {
                let prev = chars[..k].iter().rev().find(|c| !c.is_whitespace());
                if (chars[k].is_ascii_digit() || chars[k] == '-')
                    && matches!(prev, Some(':' | '[' | ','))
                {
                    let end = (k..chars.len())
                        .find(|&e| matches!(chars[e], ',' | ']' | '}') || chars[e].is_whitespace())
                        .unwrap_or(chars.len());
                    spans.push((k, end));
                    k = end;
                } else {
                    k += 1;
                }
            }
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = spans[i.index(spans.len())];
            s(0, a) + v + &s(b, chars.len())
        }
    }
}

/// Meshes come from memory: the quad, or `mesh` when the scene names `damaged.obj`.
fn load(text: &str, mesh: &str) -> Result<Scene, raytree::scene::SceneError> {
    Scene::from_json_with(text, &mut |file| {
        let src = if file == "damaged.obj" { mesh } else { OBJ };
        raytree::mesh::parse_obj(src).map_err(|e| e.to_string())
    })
}

/// In well-formed JSON, an error's path leads to the value itself (not just somewhere near),
/// unless the value is absent from the text: a missing field, or a default such as
/// `camera.up` (its name is then nowhere in the text).
fn path_is_found(text: &str, e: &raytree::scene::SceneError) -> bool {
    let json = raytree::input::strip_bom(text);
    if serde_json::from_str::<Value>(json).is_err() || e.message.starts_with("missing field") {
        return true;
    }
    let last = e.path.rsplit(['.', ']']).next().unwrap_or("");
    let plain = !last.is_empty() && last.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    !plain
        || !json.contains(&format!("\"{last}\""))
        || raytree::scene::locate(json, &e.path).is_some()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    /// What the loader accepts reads back the same after serde writes it again.
    #[test]
    fn accepted_scenes_round_trip(text in scene_text()) {
        if let Ok(scene) = Scene::from_json(&text) {
            let desc: SceneDesc = serde_json::from_str(raytree::input::strip_bom(&text)).unwrap();
            let again = serde_json::to_string(&desc).unwrap();
            let reloaded = Scene::from_json(&again);
            prop_assert_eq!(reloaded.as_ref(), Ok(&scene), "{}", again);
        }
    }

    /// Damaged scene text and OBJ text: `Ok`, or an error with a line and a column.
    #[test]
    fn damaged_input_is_accepted_or_placed(
        text in scene_text(),
        ds in prop::collection::vec(damage(), 1..4),
        obj in prop::collection::vec(damage(), 0..3),
    ) {
        let mut t = text.replace("\"objects\": [", "\"objects\": [{\"type\": \"mesh\", \"file\": \"damaged.obj\", \"material\": \"M\"},");
        let mut mesh = OBJ.to_string();
        for d in &ds {
            t = apply(&t, d);
        }
        for d in &obj {
            mesh = apply(&mesh, d);
        }
        if let Err(e) = load(&t, &mesh) {
            prop_assert!(e.line.is_some() && e.column.is_some(), "no position: {e}\n{t}");
            prop_assert!(!e.to_string().chars().any(char::is_control), "{e:?}");
            prop_assert!(path_is_found(&t, &e), "path not found: {e}\n{t}");
        }
        if let Err(e) = raytree::mesh::parse_obj(&mesh) {
            prop_assert!(e.line > 0 || e.message.contains("no faces"), "{e}");
        }
    }
}
