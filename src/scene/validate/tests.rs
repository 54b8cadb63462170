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

fn with_material(m: &str) -> String {
    BASE.replace(r#"{"diffuse": [0.5, 0.5, 0.5]}"#, m)
}

#[test]
fn conductors_and_microfacets_load() {
    let s = Scene::from_json(&with_material(
        r#"{"conductor": {"metal": "Au"}, "roughness": 0.2, "roughness_v": 0.05, "distribution": "beckmann", "tangent": [0, 2, 0]}"#,
    ))
    .unwrap();
    let m = &s.materials[0];
    assert_eq!(m.conductor, crate::bsdf::ComplexIor::metal("Au"));
    assert_eq!(m.reflectivity, DVec3::ONE);
    assert_eq!((m.roughness, m.roughness_v), (0.2, 0.05));
    assert_eq!(m.distribution, crate::bsdf::Distribution::Beckmann);
    assert_eq!(m.tangent, DVec3::Y);
    assert!(m.is_anisotropic() && m.is_rough());
    let s = Scene::from_json(&with_material(
        r#"{"conductor": {"eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1], "scale": [0.5, 0.5, 0.5]}}"#,
    ))
    .unwrap();
    let m = &s.materials[0];
    assert_eq!(m.reflectivity, DVec3::splat(0.5));
    assert_eq!(m.conductor.unwrap().k, DVec3::new(3.9, 2.4, 2.1));
    // Without the new fields: isotropic GGX, no conductor, the default frame.
    let m = &Scene::from_json(BASE).unwrap().materials[0];
    assert!(m.conductor.is_none() && !m.is_anisotropic());
    assert_eq!(m.distribution, crate::bsdf::Distribution::Ggx);
}

#[test]
fn bad_conductors_and_microfacets_are_named() {
    let cases = [
        (
            r#"{"conductor": {"metal": "Pt"}}"#,
            "materials.m.conductor.metal",
            "unknown metal",
        ),
        (
            r#"{"conductor": {"eta": [1, 1, 1]}}"#,
            "materials.m.conductor",
            "both",
        ),
        (
            r#"{"conductor": {"metal": "Cu", "eta": [1, 1, 1], "k": [1, 1, 1]}}"#,
            "materials.m.conductor",
            "either",
        ),
        (
            r#"{"conductor": {"eta": [0, 1, 1], "k": [1, 1, 1]}}"#,
            "materials.m.conductor.eta",
            "positive",
        ),
        (
            r#"{"conductor": {"eta": [1, 1, 1], "k": [-1, 1, 1]}}"#,
            "materials.m.conductor.k",
            "negative",
        ),
        (
            r#"{"conductor": {"metal": "Cu"}, "reflectivity": [1, 1, 1]}"#,
            "materials.m.reflectivity",
            "conductor.scale",
        ),
        (
            r#"{"roughness": 0.2, "roughness_v": 1.5}"#,
            "materials.m.roughness_v",
            "[0, 1]",
        ),
        (r#"{"tangent": [0, 0, 0]}"#, "materials.m.tangent", "zero"),
        (
            r#"{"distribution": "phong"}"#,
            "materials.m.distribution",
            "unknown variant",
        ),
        (
            r#"{"conductor": {"metal": "Cu", "tint": [1, 1, 1]}}"#,
            "materials.m.conductor.tint",
            "unknown field",
        ),
    ];
    for (m, path, words) in cases {
        let e = err(&with_material(m));
        assert_eq!(e.path, path, "{m}: {e}");
        assert!(e.message.contains(words), "{m}: {e}");
        assert!(e.line.is_some(), "{m}: {e}");
    }
}

#[test]
fn coatings_load_and_their_clashes_are_named() {
    let s = Scene::from_json(&with_material(
        r#"{"diffuse": [0.5, 0.1, 0.1], "coating": {"ior": 1.5, "scale": [0.5, 0.5, 0.5]}, "roughness": 0.2}"#,
    ))
    .unwrap();
    let m = &s.materials[0];
    let c = m.coating.expect("a coating");
    assert_eq!(c.eta, 1.5);
    assert!(c.rough.is_some() && m.is_rough());
    // The tint is the coating's reflectivity; the coating's own reflectance is its Fresnel.
    assert_eq!(m.reflectivity, DVec3::splat(0.5));
    let s = Scene::from_json(&with_material(
        r#"{"diffuse": [0.5, 0.5, 0.5], "coating": {"ior": 1.49}}"#,
    ))
    .unwrap();
    let c = s.materials[0].coating.unwrap();
    assert!(c.rough.is_none() && !c.nonlinear);
    let s = Scene::from_json(&with_material(
        r#"{"diffuse": [0.5, 0.5, 0.5], "coating": {"ior": 1.49, "nonlinear": true}}"#,
    ))
    .unwrap();
    assert!(s.materials[0].coating.unwrap().nonlinear);
    assert_eq!(s.materials[0].reflectivity, DVec3::ONE);
    let cases = [
        (
            r#"{"coating": {"ior": 0}}"#,
            "materials.m.coating.ior",
            "positive",
        ),
        (
            r#"{"coating": {"ior": 1.5}, "reflectivity": [1, 1, 1]}"#,
            "materials.m.reflectivity",
            "coating.scale",
        ),
        (
            r#"{"coating": {"ior": 1.5}, "transmissivity": [1, 1, 1]}"#,
            "materials.m.transmissivity",
            "opaque",
        ),
        (
            r#"{"coating": {"ior": 1.5}, "conductor": {"metal": "Cu"}}"#,
            "materials.m.conductor",
            "either",
        ),
        (
            r#"{"coating": {"ior": 1.5}, "roughness": 0.2, "roughness_v": 0.3}"#,
            "materials.m.roughness_v",
            "isotropic",
        ),
        (
            r#"{"coating": {"ior": 1.5, "scale": [-1, 1, 1]}}"#,
            "materials.m.coating.scale",
            "negative",
        ),
        (
            r#"{"coating": {"ior": 1.5, "eta": 1}}"#,
            "materials.m.coating.eta",
            "unknown field",
        ),
    ];
    for (m, path, words) in cases {
        let e = err(&with_material(m));
        assert_eq!(e.path, path, "{m}: {e}");
        assert!(e.message.contains(words), "{m}: {e}");
        assert!(e.line.is_some(), "{m}: {e}");
    }
}

#[test]
fn thin_sheets_load_and_their_clashes_are_named() {
    let s = Scene::from_json(&with_material(
        r#"{"transmissivity": [1, 1, 1], "thin": {"ior": 1.5}}"#,
    ))
    .unwrap();
    let m = &s.materials[0];
    assert_eq!((m.thin, m.ior), (Some(1.5), None));
    let b = crate::bsdf::Bsdf::from_material(
        m,
        DVec3::ZERO,
        crate::bsdf::Frame::from_normal(DVec3::Z),
        0.0,
        1.0,
    );
    assert!(matches!(
        b.lobes().next(),
        Some((crate::bsdf::Lobe::ThinDielectric { eta, .. }, _)) if *eta == 1.5
    ));
    let cases = [
        (
            r#"{"thin": {"ior": 1.5}}"#,
            "materials.m.transmissivity",
            "transmits",
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "ior": 1.5, "thin": {"ior": 1.5}}"#,
            "materials.m.ior",
            "thin.ior",
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "absorption": [1, 1, 1], "thin": {"ior": 1.5}}"#,
            "materials.m.absorption",
            "volume",
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "roughness": 0.1, "thin": {"ior": 1.5}}"#,
            "materials.m.roughness",
            "smooth",
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "thin": {"ior": -1}}"#,
            "materials.m.thin.ior",
            "positive",
        ),
        (
            r#"{"transmissivity": [1, 1, 1], "thin": {"eta": 1.5}}"#,
            "materials.m.thin.eta",
            "unknown field",
        ),
    ];
    for (m, path, words) in cases {
        let e = err(&with_material(m));
        assert_eq!(e.path, path, "{m}: {e}");
        assert!(e.message.contains(words), "{m}: {e}");
        assert!(e.line.is_some(), "{m}: {e}");
    }
}
