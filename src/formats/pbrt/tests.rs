//! pbrt-v4 front-end: one test per directive family and per convention in
//! `/work/shared/notes/scene-format-conventions.md`.

use super::convert;
use crate::formats::{Converted, FormatError, Limits};
use crate::scene::desc::{LightDesc, ObjectDesc, TextureDesc};
use crate::scene::validate;
use glam::DVec3;
use std::collections::HashMap;

const CAMERA: &str = "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
    Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 48\n";

fn files(extra: &[(&str, &[u8])]) -> HashMap<String, Vec<u8>> {
    extra
        .iter()
        .map(|(k, v)| ((*k).to_string(), v.to_vec()))
        .collect()
}

fn run_with(src: &str, fs: &HashMap<String, Vec<u8>>) -> Result<Converted, FormatError> {
    let mut res = |p: &str| fs.get(p).cloned().ok_or_else(|| "no such file".to_string());
    convert("s.pbrt", src.as_bytes(), &mut res, Limits::default())
}

fn run(world: &str) -> Converted {
    run_with(&format!("{CAMERA}WorldBegin\n{world}"), &HashMap::new()).unwrap()
}

fn fail(src: &str) -> FormatError {
    run_with(src, &HashMap::new()).unwrap_err()
}

fn sphere_center(c: &Converted, i: usize) -> DVec3 {
    match &c.desc.objects[i] {
        ObjectDesc::Sphere { center, .. } => DVec3::from(*center),
        o => panic!("{o:?}"),
    }
}

#[test]
fn transform_is_column_major_and_replaces_concat_multiplies() {
    let c = run(
        "Translate 1 0 0\nTransform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]\nShape \"sphere\"\n\
         AttributeBegin\nTranslate 1 0 0\nConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  1 0 0 1]\n\
         Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\nShape \"sphere\"\n",
    );
    assert_eq!(sphere_center(&c, 0), DVec3::new(5.0, 6.0, 7.0));
    // Translate(1) * Concat(scale 2, translate 1): the origin goes to 1 + 1.
    assert_eq!(sphere_center(&c, 1), DVec3::new(7.0, 6.0, 7.0));
    let ObjectDesc::Sphere { radius, .. } = c.desc.objects[1] else {
        panic!()
    };
    assert_eq!(radius, 1.0);
    // AttributeEnd restores the matrix.
    assert_eq!(sphere_center(&c, 2), DVec3::new(5.0, 6.0, 7.0));
}

/// pbrt's camera space is left-handed with +x image-right: `Scale -1 1 1` before `LookAt` makes
/// world +x image-right; without it, world +x is on the image's left, and raytree mirrors the
/// world to keep it there.
#[test]
fn camera_handedness_keeps_image_right_where_pbrt_has_it() {
    let side = |prefix: &str| {
        let src = format!(
            "{prefix}LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
             Translate 1 0 0\nShape \"sphere\" \"float radius\" 0.2\n"
        );
        let c = run_with(&src, &HashMap::new()).unwrap();
        let scene = validate(&c.desc, "", &mut |_| Err(String::new())).unwrap();
        let p = sphere_center(&c, 0);
        (p - scene.camera.position).dot(scene.camera.right)
    };
    assert!(side("Scale -1 1 1\n") > 0.5);
    assert!(side("") < -0.5);
    let c = run_with(
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n",
        &HashMap::new(),
    )
    .unwrap();
    assert!(c.notes.iter().any(|n| n.message.contains("left-handed")));
}

#[test]
fn fov_spans_the_shorter_image_axis() {
    let fov = |w: u32, h: u32| {
        let src = format!(
            "Camera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" {w} \"integer yresolution\" {h}\nWorldBegin\n"
        );
        run_with(&src, &HashMap::new()).unwrap().desc.camera.fov_y
    };
    assert_eq!(fov(200, 100), 30.0);
    let want = 2.0 * (15f64.to_radians().tan() * 2.0).atan().to_degrees();
    assert!((fov(100, 200) - want).abs() < 1e-12);
}

#[test]
fn settings_map_spp_depth_and_filters() {
    let c = run_with(&format!("Sampler \"zsobol\" \"integer pixelsamples\" 64\nIntegrator \"volpath\" \"integer maxdepth\" 1\nPixelFilter \"triangle\"\n{CAMERA}WorldBegin\n"), &HashMap::new()).unwrap();
    // pbrt's maxdepth 1 is direct light only: raytree's max_depth 0.
    assert_eq!(c.desc.settings.max_depth, 0);
    assert_eq!(c.desc.settings.spp, 64);
    assert_eq!(
        c.desc.settings.filter,
        crate::scene::FilterDesc::Tent { radius: 2.0 }
    );
    // Defaults: maxdepth 5, 16 spp, Gaussian.
    let d = run("");
    assert_eq!((d.desc.settings.max_depth, d.desc.settings.spp), (4, 16));
    assert!(matches!(
        d.desc.settings.filter,
        crate::scene::FilterDesc::Gaussian { .. }
    ));
}

#[test]
fn materials_map_with_notes() {
    let c = run(
        "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.04\n\
        NamedMaterial \"gold\"\nShape \"sphere\"\n\
        Material \"dielectric\" \"float roughness\" 0.09 \"bool remaproughness\" false\nShape \"sphere\"\n\
        Material \"coateddiffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"sphere\"\n",
    );
    let gold = &c.desc.materials["gold"];
    // raytree's own gold (the exact conductor Fresnel); alpha = sqrt(0.04).
    let cond = gold.conductor.as_ref().unwrap();
    assert_eq!(cond.metal.as_deref(), Some("Au"));
    assert_eq!(gold.reflectivity, [0.0; 3]);
    assert!((gold.roughness - 0.2).abs() < 1e-15);
    let glass = c
        .desc
        .materials
        .values()
        .find(|m| m.ior == Some(1.5))
        .unwrap();
    // remaproughness false: alpha is the roughness.
    assert_eq!(glass.roughness, 0.09);
    assert!(c.notes.iter().any(|n| {
        n.line == 6
            && n.message
                .contains("spectrum \"metal-Au-eta\" taken as raytree's RGB projection")
    }));
    assert!(c.notes.iter().any(|n| n.message.contains("coateddiffuse")));
    let coated = c
        .desc
        .materials
        .values()
        .find(|m| m.coating.is_some())
        .unwrap();
    assert!(matches!(
        coated.diffuse,
        Some(TextureDesc::Solid([0.5, 0.5, 0.5]))
    ));
    assert!(!c.notes.iter().any(|n| n.message.contains("mirror")));
}

#[test]
fn a_materials_unused_parameters_are_named_once_and_its_name_once() {
    let c = run(
        "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5] \"float bogus\" 3\nShape \"sphere\"\n\
        MakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"float other\" 1\n\
        Material \"measured\" \"string filename\" \"x.bsdf\"\nShape \"sphere\"\n",
    );
    let notes: Vec<&str> = c.notes.iter().map(|n| n.message.as_str()).collect();
    let count = |s: &str| notes.iter().filter(|n| n.contains(s)).count();
    assert_eq!(count("ignored \"float bogus\""), 1, "{notes:?}");
    assert_eq!(count("ignored \"float other\""), 1, "{notes:?}");
    assert_eq!(count("ignored \"string filename\""), 1, "{notes:?}");
    assert!(
        notes.contains(&"Material \"measured\": not supported by raytree: grey diffuse 0.5 used"),
        "{notes:?}"
    );
}

#[test]
fn conductors_by_reflectance_and_anisotropic_roughness() {
    let c = run(
        "Material \"conductor\" \"rgb reflectance\" [0.5 0.5 0.5] \"float uroughness\" 0.04 \"float vroughness\" 0.16\n\
         Shape \"sphere\"\nMaterial \"conductor\"\nShape \"sphere\"\n",
    );
    let m = &c.desc.materials[c.desc.objects[0].material()];
    let k = m.conductor.as_ref().unwrap().k.unwrap();
    // pbrt-v4: eta 1, k = 2 sqrt(r) / sqrt(1 - r).
    assert!((k[0] - 2.0).abs() < 1e-12, "{k:?}");
    assert_eq!((m.roughness, m.roughness_v), (0.2, Some(0.4)));
    assert!(c.notes.iter().any(|n| n.message.contains("dpdu")));
    // The default conductor is raytree's copper, exactly.
    let cu = &c.desc.materials[c.desc.objects[1].material()];
    assert_eq!(cu.conductor.as_ref().unwrap().metal.as_deref(), Some("Cu"));
    let s = validate(&c.desc, "", &mut |_| Err(String::new())).unwrap();
    assert!(s.materials.iter().all(|m| m.conductor.is_some()));
}

#[test]
fn area_lights_emit_and_two_sided_is_noted() {
    let c = run(
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3] \"float scale\" 2 \"bool twosided\" true\n\
        Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\nAttributeEnd\nShape \"sphere\"\n",
    );
    let ObjectDesc::Quad {
        material,
        edge_u,
        edge_v,
        ..
    } = &c.desc.objects[0]
    else {
        panic!("{:?}", c.desc.objects[0])
    };
    assert_eq!(c.desc.materials[material].emission, [2.0, 4.0, 6.0]);
    assert_eq!((*edge_u, *edge_v), ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
    assert!(
        c.notes
            .iter()
            .any(|n| n.message.contains("two-sided") && n.line == 7)
    );
    // The sphere after AttributeEnd does not emit.
    assert_eq!(
        c.desc.materials[c.desc.objects[1].material()].emission,
        [0.0; 3]
    );
}

#[test]
fn reverse_orientation_and_mirrors_keep_the_outward_side() {
    let c = run(
        "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n\
        ReverseOrientation\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n\
        ReverseOrientation\nScale 1 1 -1\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n",
    );
    let n = |i: usize| match &c.desc.objects[i] {
        ObjectDesc::Quad { edge_u, edge_v, .. } => DVec3::from(*edge_u).cross(DVec3::from(*edge_v)),
        o => panic!("{o:?}"),
    };
    assert!(n(0).z > 0.0);
    assert!(n(1).z < 0.0);
    // A mirror in z maps the object-space +z normal to world -z.
    assert!(n(2).z < 0.0);
}

/// pbrt turns a triangle's geometric normal to face its shading normal N.
#[test]
fn shading_normals_decide_the_front_of_a_mesh() {
    let c = run(
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2] \"normal N\" [0 0 -1  0 0 -1  0 0 -1]\n",
    );
    let scene = validate(&c.desc, "", &mut |_| Err(String::new())).unwrap();
    let crate::geometry::Shape::Mesh(m) = &scene.objects[0].shape else {
        panic!()
    };
    assert!(m.geometric_normal(0).z < 0.0);
}

#[test]
fn sheared_spheres_are_baked_and_boxes_and_quads_recognised() {
    let c = run(
        "AttributeBegin\nScale 1 2 1\nShape \"sphere\"\nAttributeEnd\n\
        Shape \"trianglemesh\" \"point3 P\" [0 0 0  2 0 0  2 0 3  0 0 3] \"integer indices\" [0 1 3  1 2 3]\n",
    );
    assert!(
        matches!(&c.desc.objects[0], ObjectDesc::Trimesh { indices, normals: Some(_), .. } if indices.len() == 1280)
    );
    assert!(c.notes.iter().any(|n| n.message.contains("baked")));
    let ObjectDesc::Quad {
        corner,
        edge_u,
        edge_v,
        ..
    } = &c.desc.objects[1]
    else {
        panic!("{:?}", c.desc.objects[1])
    };
    assert_eq!(
        (*corner, *edge_u, *edge_v),
        ([0.0; 3], [2.0, 0.0, 0.0], [0.0, 0.0, 3.0])
    );
    // A 12-triangle axis-aligned box mesh becomes a box.
    let (p, t) =
        crate::formats::build::box_triangles(DVec3::new(-1.0, 0.0, 2.0), DVec3::new(1.0, 3.0, 4.0));
    let pts: Vec<String> = p
        .iter()
        .map(|v| format!("{} {} {}", v.x, v.y, v.z))
        .collect();
    let idx: Vec<String> = t.iter().flatten().map(u32::to_string).collect();
    let c = run(&format!(
        "Shape \"trianglemesh\" \"point3 P\" [{}] \"integer indices\" [{}]\n",
        pts.join(" "),
        idx.join(" ")
    ));
    assert!(
        matches!(
            c.desc.objects[0],
            ObjectDesc::Box {
                min: [-1.0, 0.0, 2.0],
                max: [1.0, 3.0, 4.0],
                ..
            }
        ),
        "{:?}",
        c.desc.objects[0]
    );
}

#[test]
fn lights_and_instances() {
    let c = run(
        "LightSource \"point\" \"rgb I\" [1 1 1] \"point3 from\" [0 2 0]\n\
        LightSource \"distant\" \"blackbody L\" 6500 \"point3 from\" [0 1 0] \"point3 to\" [0 0 0]\n\
        LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n\
        ObjectBegin \"ball\"\nShape \"sphere\" \"float radius\" 0.5\nObjectEnd\n\
        Translate 3 0 0\nObjectInstance \"ball\"\nTranslate 3 0 0\nObjectInstance \"ball\"\n\
        CoordinateSystem \"here\"\nIdentity\nCoordSysTransform \"here\"\nShape \"sphere\"\n",
    );
    assert!(matches!(
        c.desc.lights[0],
        LightDesc::Point {
            position: [0.0, 2.0, 0.0],
            ..
        }
    ));
    let LightDesc::Directional {
        direction,
        irradiance,
        ..
    } = c.desc.lights[1]
    else {
        panic!()
    };
    assert_eq!(direction, [0.0, -1.0, 0.0]);
    assert!(
        irradiance.iter().all(|&x| (x - 1.0).abs() < 0.2),
        "{irradiance:?}"
    );
    assert_eq!(c.desc.background, [0.1, 0.2, 0.3]);
    assert_eq!(sphere_center(&c, 0), DVec3::new(3.0, 0.0, 0.0));
    assert_eq!(sphere_center(&c, 1), DVec3::new(6.0, 0.0, 0.0));
    assert_eq!(sphere_center(&c, 2), DVec3::new(6.0, 0.0, 0.0));
}

#[test]
fn includes_plymeshes_and_textures() {
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let fs = files(&[
        (
            "sub/inc.pbrt",
            b"Shape \"plymesh\" \"string filename\" \"m.ply\"\n",
        ),
        ("sub/m.ply", ply),
    ]);
    let c = run_with(&format!("{CAMERA}WorldBegin\nTexture \"t\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0]\n\
        Material \"diffuse\" \"texture reflectance\" \"t\"\nInclude \"sub/inc.pbrt\"\n"), &fs).unwrap();
    // pbrt renders PLY meshes without normals faceted.
    assert!(matches!(
        &c.desc.objects[0],
        ObjectDesc::Trimesh { normals: None, .. }
    ));
    let Some(TextureDesc::Solid(d)) = &c.desc.materials[c.desc.objects[0].material()].diffuse
    else {
        panic!()
    };
    assert_eq!(*d, [0.5; 3]);
    assert!(c.notes.iter().any(|n| n.message.contains("checkerboard")));
}

#[test]
fn errors_name_file_line_and_column() {
    let e = fail("WorldBegin\n  Shap \"sphere\"\n");
    assert_eq!((e.line, e.column), (2, 3));
    assert!(e.message.contains("unknown directive"), "{e}");
    let e = fail("WorldBegin\nShape \"sphere\" \"integer radius\" 1\n");
    assert!(
        e.message.contains("must be of type float") && e.line == 2 && e.column == 16,
        "{e}"
    );
    let e = fail("WorldBegin\nInclude \"missing.pbrt\"\n");
    assert!(e.message.contains("missing.pbrt") && e.line == 2, "{e}");
    let fs = files(&[("a.pbrt", b"Include \"s.pbrt\"\n")]);
    let e = run_with("WorldBegin\nInclude \"a.pbrt\"\n", &fs).unwrap_err();
    assert!(
        e.message.contains("include cycle") && e.file == "a.pbrt",
        "{e}"
    );
    let e = fail("WorldBegin\nShape \"sphere\" \"float radius\" -1\n");
    assert!(e.message.contains("radius"), "{e}");
    let e = fail(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 5]\n",
    );
    assert!(e.message.contains("out of range"), "{e}");
    let e = fail("Translate 1 2\n");
    assert!(e.message.contains("expected 3 numbers"), "{e}");
    assert!(fail("AttributeEnd\n").message.contains("without"));
    assert!(
        fail("LookAt 0 0 0 0 0 1 0 1 0\n")
            .message
            .contains("WorldBegin")
    );
    let e = fail("WorldBegin\nShape \"sphere\" \"float radius\" [1 2]\n");
    assert!(e.message.contains("one number"), "{e}");
}

#[test]
fn unknown_parameters_and_unsupported_features_are_noted() {
    let c = run(
        "Shape \"sphere\" \"float radius\" 1 \"float zmax\" 0.5 \"float frobnicate\" 3\nShape \"cylinder\"\n",
    );
    assert!(c.notes.iter().any(|n| n.message.contains("frobnicate")));
    assert!(c.notes.iter().any(|n| n.message.contains("partial sphere")));
    assert!(c.notes.iter().any(|n| n.message.contains("cylinder")));
}

#[test]
fn only_the_start_time_transform_is_used() {
    let c = run(
        "ActiveTransform EndTime\nTranslate 5 0 0\nActiveTransform All\nTranslate 1 0 0\nShape \"sphere\"\n",
    );
    assert_eq!(sphere_center(&c, 0), DVec3::new(1.0, 0.0, 0.0));
    assert!(
        c.notes
            .iter()
            .any(|n| n.message.contains("ActiveTransform EndTime"))
    );
}

/// `LightSource "spot"`: pbrt-v4's cone (`coneangle`, falloff from `coneangle - conedelta`,
/// defaults 30 and 5) and smoothstep profile, along `to - from`; a delta that puts the falloff
/// outside the cone is refused.
#[test]
fn spot_lights_keep_their_cone() {
    let c = run(
        "LightSource \"spot\" \"rgb I\" [2 2 2] \"point3 from\" [0 3 0] \"point3 to\" [0 0 1] \
         \"float coneangle\" 40 \"float conedelta\" 10\n\
         LightSource \"spot\" \"point3 from\" [0 1 0]\n",
    );
    let LightDesc::Spot {
        position,
        direction: Some(direction),
        intensity,
        cone_angle,
        falloff_angle,
        profile,
        ..
    } = c.desc.lights[0]
    else {
        panic!("{:?}", c.desc.lights[0])
    };
    assert_eq!((position, intensity), ([0.0, 3.0, 0.0], [2.0; 3]));
    let d = DVec3::from(direction).normalize();
    assert!(
        (d - DVec3::new(0.0, -3.0, 1.0).normalize()).length() < 1e-12,
        "{d}"
    );
    assert_eq!((cone_angle, falloff_angle), (40.0, Some(30.0)));
    assert_eq!(profile, crate::lights::SpotProfile::Smoothstep);
    assert!(matches!(
        c.desc.lights[1],
        LightDesc::Spot {
            cone_angle: 30.0,
            falloff_angle: Some(25.0),
            ..
        }
    ));
    assert!(
        c.notes.iter().all(|n| !n.message.contains("spot")),
        "{:?}",
        c.notes
    );
    let e = fail(&format!(
        "{CAMERA}WorldBegin\nLightSource \"spot\" \"float coneangle\" 30 \"float conedelta\" 70\n"
    ));
    assert!(
        e.to_string()
            .contains("\"conedelta\" 70 is not in [0, 2 coneangle]"),
        "{e}"
    );
    let e = fail(&format!(
        "{CAMERA}WorldBegin\nLightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 0]\n"
    ));
    assert!(e.to_string().contains("from and to coincide"), "{e}");
}

/// pbrt-v4's photometric targets: `power` on point and spot lights (the intensity is
/// scale * power / k_e, k_e = 4 pi for a point and pbrt's ramp-halved cone solid angle for a
/// spot), `illuminance` on distant (k_e = 1) and infinite lights (k_e = pi); the RGB is not
/// normalised (pbrt-v4 normalises the illuminant only). Nothing is noted as ignored.
#[test]
fn power_and_illuminance_set_the_intensity_as_pbrt_does() {
    use std::f64::consts::PI;
    let c = run(
        "LightSource \"point\" \"rgb I\" [1 0.5 2] \"float power\" 100 \"float scale\" 2\n\
         LightSource \"spot\" \"rgb I\" [1 1 1] \"float power\" 10 \"float coneangle\" 40 \
         \"float conedelta\" 10\n\
         LightSource \"distant\" \"rgb L\" [1 1 1] \"float illuminance\" 3\n\
         LightSource \"infinite\" \"rgb L\" [0.5 0.5 0.5] \"float illuminance\" 2\n\
         LightSource \"point\" \"rgb I\" [3 3 3]\n",
    );
    let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12 * b[i]);
    let LightDesc::Point { intensity, .. } = c.desc.lights[0] else {
        panic!("{:?}", c.desc.lights[0])
    };
    let k = 2.0 * 100.0 / (4.0 * PI);
    assert!(close(intensity, [k, 0.5 * k, 2.0 * k]), "{intensity:?}");
    let LightDesc::Spot { intensity, .. } = c.desc.lights[1] else {
        panic!("{:?}", c.desc.lights[1])
    };
    let (end, start) = (40f64.to_radians().cos(), 30f64.to_radians().cos());
    let k_e = 2.0 * PI * ((1.0 - start) + (start - end) / 2.0);
    assert!(close(intensity, [10.0 / k_e; 3]), "{intensity:?}");
    let LightDesc::Directional { irradiance, .. } = c.desc.lights[2] else {
        panic!("{:?}", c.desc.lights[2])
    };
    assert!(close(irradiance, [3.0; 3]), "{irradiance:?}");
    assert!(close(c.desc.background, [1.0 / PI; 3]));
    let LightDesc::Point { intensity, .. } = c.desc.lights[3] else {
        panic!("{:?}", c.desc.lights[3])
    };
    assert_eq!(intensity, [3.0; 3], "no target: I times scale");
    assert!(
        c.notes.iter().all(|n| !n.message.contains("ignored")),
        "{:?}",
        c.notes
    );
    assert!(
        c.notes.iter().any(|n| n
            .message
            .contains("illuminance\" 3 is taken on a surface facing the light")),
        "{:?}",
        c.notes
    );
}
