//! The scenes of the whole-command property (`commands.rs`): the fixtures with extreme but
//! accepted values stacked on them, shrunk, their ray budget bounded.

use proptest::prelude::*;
use serde_json::{Value, json};

pub const FIXTURES: [(&str, &str); 9] = [
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
pub const TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

pub const WIDTH: u32 = 12;
pub const HEIGHT: u32 = 8;

/// One extreme but (mostly) accepted change to a scene. Indices pick an object, light or
/// material modulo how many the scene has.
#[derive(Clone, Debug)]
pub enum Mutation {
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

pub fn huge() -> impl Strategy<Value = f64> {
    prop::sample::select(vec![1e30, 1e100, 1e200, 1e300, f64::MAX])
}

pub fn length() -> impl Strategy<Value = f64> {
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

pub fn mutation() -> impl Strategy<Value = Mutation> {
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

pub fn grey(v: f64) -> Value {
    json!([v, v, v])
}

/// The `i`-th member (modulo the count) of the array or map at `key`.
pub fn pick<'a>(scene: &'a mut Value, key: &str, i: usize) -> Option<&'a mut Value> {
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

pub fn settings(scene: &mut Value) -> &mut serde_json::Map<String, Value> {
    let s = &mut scene["settings"];
    if !s.is_object() {
        *s = json!({});
    }
    s.as_object_mut().expect("an object")
}

pub fn first_material(scene: &Value) -> String {
    scene["materials"]
        .as_object()
        .and_then(|m| m.keys().next().cloned())
        .expect("fixtures have materials")
}

pub fn apply(scene: &mut Value, m: &Mutation) {
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

pub fn vec3(v: &Value) -> Option<[f64; 3]> {
    let a = v.as_array()?;
    Some([
        a.first()?.as_f64()?,
        a.get(1)?.as_f64()?,
        a.get(2)?.as_f64()?,
    ])
}

/// A fixture with the mutations applied, shrunk to the test's size, its ray budget bounded.
pub fn scene_text(fixture: usize, mutations: &[Mutation], max_rays: u64) -> String {
    let mut scene: Value = serde_json::from_str(FIXTURES[fixture].1).expect("fixture JSON");
    for m in mutations {
        apply(&mut scene, m);
    }
    scene["camera"]["width"] = json!(WIDTH);
    scene["camera"]["height"] = json!(HEIGHT);
    settings(&mut scene).insert("max_rays".into(), json!(max_rays));
    serde_json::to_string_pretty(&scene).expect("serialisable")
}

pub fn accepted(text: &str) -> bool {
    raytree::Scene::from_json_with(text, &mut |_| {
        raytree::mesh::parse_obj(TET).map_err(|e| e.to_string())
    })
    .is_ok()
}
