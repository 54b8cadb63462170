//! Tests of `validate`.

use super::*;

const BASE: &str = r#"{
  "camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
  "materials": {"m": {"diffuse": [0.5, 0.5, 0.5]}},
  "objects": [
    {"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}
  ]
}"#;

fn err(src: &str) -> SceneError {
    Scene::from_json(src).unwrap_err()
}

#[test]
fn base_scene_loads() {
    let s = Scene::from_json(BASE).unwrap();
    assert_eq!(s.objects[0].name, "sphere#0");
    assert_eq!(s.settings.max_depth, 16);
    assert!((s.camera.right - DVec3::X).length() < 1e-12);
}

#[test]
fn bad_radius_names_path_and_position() {
    let e = err(&BASE.replace("\"radius\": 1", "\"radius\": -1"));
    assert_eq!(e.path, "objects[0].radius");
    assert_eq!((e.line, e.column), (Some(5), Some(53)));
    assert!(e.message.contains("positive"), "{e}");
}

#[test]
fn unknown_material_and_field() {
    let e = err(&BASE.replace("\"material\": \"m\"", "\"material\": \"glass\""));
    assert_eq!(e.path, "objects[0].material");
    assert!(e.message.contains("glass"));
    let e = err(&BASE.replace("\"fov_y\": 40", "\"fov_y\": 40, \"zoom\": 2"));
    assert_eq!(e.path, "camera.zoom");
    assert!(e.message.contains("unknown field"), "{e}");
    assert!(e.line.is_some());
}

#[test]
fn fov_and_syntax() {
    assert_eq!(err(&BASE.replace("40", "180")).path, "camera.fov_y");
    let e = err(&BASE.replace("\"width\": 4,", "\"width\": 4"));
    assert_eq!(e.line, Some(2));
    let e = err(&format!("{BASE} x"));
    assert_eq!(e.line, Some(7));
}

#[test]
fn type_errors_inside_objects_and_lights_name_the_member() {
    // serde stops its path at an internally tagged element; the member is found again.
    let e = err(&BASE.replace("\"radius\": 1", "\"radius\": \"big\""));
    assert_eq!(e.path, "objects[0].radius", "{e}");
    assert_eq!((e.line, e.column), (Some(5), Some(53)));
    assert!(e.message.contains("expected f64"), "{e}");
    let e = err(&BASE.replace("\"center\": [0,0,0]", "\"center\": [0,0]"));
    assert_eq!(e.path, "objects[0].center", "{e}");
    let lights = BASE.replace(
            "\n  ]\n}",
            "\n  ],\n  \"lights\": [{\"type\": \"point\", \"position\": [1,2,3], \"intensity\": [1,1]}]\n}",
        );
    let e = err(&lights);
    assert_eq!(e.path, "lights[0].intensity", "{e}");
    assert_eq!(e.line, Some(7));
    let e = err(&BASE.replace("\"sphere\"", "\"cone\""));
    assert_eq!(
        (e.path.as_str(), e.line),
        ("objects[0].type", Some(5)),
        "{e}"
    );
    // A missing member is still named as such.
    let e = err(&BASE.replace("\"radius\": 1, ", ""));
    assert_eq!(e.path, "objects[0].radius", "{e}");
    assert!(e.message.contains("missing field"), "{e}");
}

#[test]
fn empty_documents_and_syntax_errors_get_columns_from_1_and_no_unknown_segment() {
    let e = err("");
    assert_eq!((e.line, e.column), (Some(1), Some(1)), "{e}");
    let e = err(r#"{"camera": {"position": [0,0,5],, }}"#);
    assert_eq!(e.path, "camera", "{e}");
    assert!(!e.to_string().contains('?'), "{e}");
}

#[test]
fn huge_numbers_are_rejected() {
    let e = err(&BASE.replace("\"radius\": 1", "\"radius\": 1e999"));
    assert!(e.line.is_some(), "{e}");
}
