//! Mitsuba front-end: one test per element family and per convention in
//! `/work/shared/notes/scene-format-conventions.md`.

use super::convert;
use crate::formats::{Converted, FormatError, Limits};
use crate::scene::desc::{LightDesc, ObjectDesc, TextureDesc};
use crate::scene::validate;
use glam::DVec3;
use std::collections::HashMap;

const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/></film></sensor>"#;

fn run_with(
    src: &str,
    fs: &HashMap<String, Vec<u8>>,
    defines: &[(String, String)],
) -> Result<Converted, FormatError> {
    let mut res = |p: &str| fs.get(p).cloned().ok_or_else(|| "no such file".to_string());
    convert(
        "s.xml",
        src.as_bytes(),
        defines,
        &mut res,
        Limits::default(),
    )
}

fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{SENSOR}\n{body}\n</scene>\n")
}

fn run(body: &str) -> Converted {
    run_with(&scene(body), &HashMap::new(), &[]).unwrap()
}

fn fail(body: &str) -> FormatError {
    run_with(&scene(body), &HashMap::new(), &[]).unwrap_err()
}

#[test]
fn sensor_is_right_handed_with_x_fov_by_default() {
    let c = run(
        r#"<shape type="sphere"><point name="center" x="1" y="0" z="0"/><float name="radius" value="0.2"/></shape>"#,
    );
    let s = validate(&c.desc, "", &mut |_| Err(String::new())).unwrap();
    let ObjectDesc::Sphere { center, .. } = c.desc.objects[0] else {
        panic!()
    };
    // Looking down -z with y up, world +x is image-right; no mirror needed.
    assert!((DVec3::from(center) - s.camera.position).dot(s.camera.right) > 0.5);
    assert!(!c.notes.iter().any(|n| n.message.contains("left-handed")));
    // fov_axis x (Mitsuba's default) on a 64x48 film.
    let want = 2.0 * (20f64.to_radians().tan() * 48.0 / 64.0).atan().to_degrees();
    assert!((c.desc.camera.fov_y - want).abs() < 1e-12);
    let smaller = run_with(
        &scene("").replace(
            r#"<float name="fov" value="40"/>"#,
            r#"<float name="fov" value="40"/><string name="fov_axis" value="smaller"/>"#,
        ),
        &HashMap::new(),
        &[],
    )
    .unwrap();
    assert!((smaller.desc.camera.fov_y - 40.0).abs() < 1e-12);
}

#[test]
fn depth_counts_segments_and_filters_default_to_gaussian() {
    let c = run(r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>"#);
    // Mitsuba's max_depth 2 is direct light: raytree's 0.
    assert_eq!(c.desc.settings.max_depth, 0);
    assert!(
        matches!(c.desc.settings.filter, crate::scene::FilterDesc::Gaussian { sigma, radius: Some(r) } if sigma == 0.5 && r == 2.0)
    );
    let c = run(r#"<integrator type="path"><integer name="max_depth" value="8"/></integrator>"#);
    assert_eq!(c.desc.settings.max_depth, 6);
}

#[test]
fn shapes_transforms_and_emitters() {
    let c = run(r#"
      <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="17, 12, 4"/></emitter>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></shape>
      <shape type="cube"><transform name="to_world"><scale x="0.5" y="1" z="2"/><translate x="3"/></transform></shape>
      <emitter type="point"><point name="position" value="0, 4, 0"/><rgb name="intensity" value="2"/></emitter>
      <emitter type="directional"><vector name="direction" value="0, -1, 0"/><rgb name="irradiance" value="1"/></emitter>
      <emitter type="constant"><rgb name="radiance" value="0.25"/></emitter>"#);
    let ObjectDesc::Quad {
        corner,
        edge_u,
        edge_v,
        material,
        ..
    } = &c.desc.objects[0]
    else {
        panic!("{:?}", c.desc.objects[0])
    };
    // Rotating +z by +90 degrees about x gives -y: the lamp faces down.
    let n = DVec3::from(*edge_u).cross(DVec3::from(*edge_v));
    assert!(n.y < 0.0 && n.x.abs() < 1e-12, "{n}");
    assert!(
        (DVec3::from(*corner) - DVec3::new(-0.5, 2.0, -0.5)).length() < 1e-12,
        "{corner:?}"
    );
    assert_eq!(c.desc.materials[material].emission, [17.0, 12.0, 4.0]);
    assert!(
        matches!(
            c.desc.objects[1],
            ObjectDesc::Box {
                min: [2.5, -1.0, -2.0],
                max: [3.5, 1.0, 2.0],
                ..
            }
        ),
        "{:?}",
        c.desc.objects[1]
    );
    assert!(matches!(
        c.desc.lights[0],
        LightDesc::Point {
            position: [0.0, 4.0, 0.0],
            intensity: [2.0, 2.0, 2.0],
            ..
        }
    ));
    assert!(matches!(
        c.desc.lights[1],
        LightDesc::Directional {
            direction: [0.0, -1.0, 0.0],
            ..
        }
    ));
    assert_eq!(c.desc.background, [0.25; 3]);
}

#[test]
fn bsdfs_map_with_notes_and_one_sidedness() {
    let c = run(r#"
      <bsdf type="twosided" id="white"><bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf></bsdf>
      <bsdf type="roughconductor" id="gold"><string name="material" value="Au"/></bsdf>
      <bsdf type="roughdielectric" id="glass"><string name="int_ior" value="bk7"/><float name="alpha" value="0.2"/><string name="distribution" value="ggx"/></bsdf>
      <bsdf type="plastic" id="red"><rgb name="diffuse_reflectance" value="0.5, 0, 0"/></bsdf>
      <shape type="sphere"><ref id="white"/></shape>
      <shape type="sphere"><ref id="gold"/></shape>
      <shape type="sphere"><ref id="glass"/></shape>
      <shape type="sphere"><ref id="red"/></shape>
      <shape type="sphere"><bsdf type="diffuse"/></shape>"#);
    let m = |i: usize| &c.desc.materials[c.desc.objects[i].material()];
    assert!(matches!(
        m(0).diffuse,
        Some(TextureDesc::Solid([0.7, 0.7, 0.7]))
    ));
    // Rough BSDFs default to Beckmann alpha 0.1: raytree's Beckmann, exactly.
    assert_eq!(m(1).roughness, 0.1);
    assert_eq!(m(1).distribution, crate::bsdf::Distribution::Beckmann);
    assert_eq!(
        m(1).conductor.as_ref().unwrap().metal.as_deref(),
        Some("Au")
    );
    assert_eq!(m(2).distribution, crate::bsdf::Distribution::Ggx);
    assert!(!c.notes.iter().any(|n| n.message.contains("Beckmann")));
    assert!((m(2).ior.unwrap() - 1.5046 / 1.000_277).abs() < 1e-12);
    assert_eq!(m(2).roughness, 0.2);
    // Plastic: raytree's coating over the base, polypropylene by default, untinted.
    let coat = m(3).coating.as_ref().unwrap();
    assert!((coat.ior - 1.49 / 1.000_277).abs() < 1e-12);
    assert_eq!((m(3).reflectivity, coat.scale), ([0.0; 3], None));
    assert!(matches!(
        m(3).diffuse,
        Some(TextureDesc::Solid([0.5, 0.0, 0.0]))
    ));
    // Mitsuba's BSDFs are one-sided unless wrapped in twosided: noted, except for twosided.
    let one_sided: Vec<usize> = c
        .notes
        .iter()
        .filter(|n| n.message.contains("only the front"))
        .map(|n| n.line)
        .collect();
    assert_eq!(one_sided.len(), 3, "{:?}", c.notes);
}

#[test]
fn forward_refs_defaults_defines_and_includes() {
    let fs: HashMap<String, Vec<u8>> = [("parts/inc.xml".to_string(), br#"<scene version="3.0.0"><shape type="sphere"><float name="radius" value="$r"/><ref id="later"/></shape></scene>"#.to_vec())].into();
    let src = scene(
        r#"<default name="r" value="2"/><include filename="parts/inc.xml"/><bsdf type="diffuse" id="later"/>"#,
    );
    let c = run_with(&src, &fs, &[]).unwrap();
    assert!(matches!(
        c.desc.objects[0],
        ObjectDesc::Sphere { radius: 2.0, .. }
    ));
    let c = run_with(&src, &fs, &[("r".into(), "3".into())]).unwrap();
    assert!(matches!(
        c.desc.objects[0],
        ObjectDesc::Sphere { radius: 3.0, .. }
    ));
}

#[test]
fn old_spellings_are_upgraded() {
    let src = r#"<scene version="0.6.0"><sensor type="perspective"><float name="fov" value="30"/><string name="fovAxis" value="y"/>
      <transform name="toWorld"><lookAt origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
      <shape type="sphere"><bsdf type="dielectric"><float name="intIOR" value="1.33"/><float name="extIOR" value="1"/></bsdf></shape></scene>"#;
    let c = run_with(src, &HashMap::new(), &[]).unwrap();
    assert_eq!(c.desc.camera.fov_y, 30.0);
    assert_eq!(c.desc.camera.position, [0.0, 0.0, 5.0]);
    assert_eq!(
        c.desc.materials[c.desc.objects[0].material()].ior,
        Some(1.33)
    );
}

#[test]
fn ply_meshes_are_smoothed_unless_face_normals() {
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let fs: HashMap<String, Vec<u8>> = [("m.ply".to_string(), ply.to_vec())].into();
    let smooth = run_with(
        &scene(r#"<shape type="ply"><string name="filename" value="m.ply"/></shape>"#),
        &fs,
        &[],
    )
    .unwrap();
    assert!(matches!(
        &smooth.desc.objects[0],
        ObjectDesc::Trimesh {
            normals: Some(_),
            ..
        }
    ));
    let flat = run_with(&scene(r#"<shape type="ply"><string name="filename" value="m.ply"/><boolean name="face_normals" value="true"/></shape>"#), &fs, &[]).unwrap();
    assert!(matches!(
        &flat.desc.objects[0],
        ObjectDesc::Trimesh { normals: None, .. }
    ));
}

#[test]
fn errors_have_positions_and_name_the_element() {
    let e = fail(r#"<shape type="sphere"><ref id="nowhere"/></shape>"#);
    assert!(e.message.contains("undefined id") && e.line == 5, "{e}");
    let e = fail(r#"<bsdf type="diffuse" id="a"/><bsdf type="diffuse" id="a"/>"#);
    assert!(e.message.contains("duplicate id"), "{e}");
    let e = fail(r#"<shape type="sphere"><float name="radius" value="$nope"/></shape>"#);
    assert!(
        e.message.contains("$nope") && e.message.contains("-D nope"),
        "{e}"
    );
    let e =
        fail(r#"<shape type="serialized"><string name="filename" value="x.serialized"/></shape>"#);
    assert!(e.message.contains("serialized"), "{e}");
    let e = fail(r#"<shape type="sphere"><integer name="radius" value="1.5"/></shape>"#);
    assert!(
        e.message.contains("not a number") || e.message.contains("radius"),
        "{e}"
    );
    let e = fail(r#"<shape type="obj"><string name="filename" value="missing.obj"/></shape>"#);
    assert!(e.message.contains("missing.obj"), "{e}");
    let e = run_with(
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>",
        &HashMap::new(),
        &[],
    )
    .unwrap_err();
    assert!(e.message.contains("malformed XML") && e.line == 3, "{e}");
    let fs: HashMap<String, Vec<u8>> = [(
        "a.xml".to_string(),
        br#"<scene version="3.0.0"><include filename="s.xml"/></scene>"#.to_vec(),
    )]
    .into();
    let e = run_with(&scene(r#"<include filename="a.xml"/>"#), &fs, &[]).unwrap_err();
    assert!(e.message.contains("include cycle"), "{e}");
    assert!(fail(r#"<shape type="sphere"><transform name="to_world"><scale value="0"/></transform></shape>"#).message.contains("zero"));
    assert!(fail("<frobnicate/>").message.contains("unknown element"));
    let e = fail(r#"<alias id="nope" as="x"/>"#);
    assert!(e.message.contains("aliases undefined id \"nope\""), "{e}");
}

#[test]
fn paths_extend_the_file_search_and_aliases_rename() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n".to_vec();
    let fs: HashMap<String, Vec<u8>> = [
        ("meshes/m.obj".to_string(), obj.clone()),
        (
            "lib/inc.xml".to_string(),
            br#"<scene version="3.0.0"><bsdf type="diffuse" id="grey"/></scene>"#.to_vec(),
        ),
    ]
    .into();
    let body = r#"<path value="meshes"/><path value="lib"/><include filename="inc.xml"/>
      <alias id="grey" as="stone"/>
      <shape type="obj"><string name="filename" value="m.obj"/><ref id="stone"/></shape>"#;
    let c = run_with(&scene(body), &fs, &[]).unwrap();
    assert_eq!(c.desc.objects.len(), 1);
    assert!(
        c.desc.materials.keys().any(|k| k == "grey"),
        "{:?}",
        c.desc.materials.keys()
    );
    // Without the <path>, the mesh is not found, and the message says where it looked.
    let e = run_with(
        &scene(r#"<path value="lib"/><shape type="obj"><string name="filename" value="m.obj"/></shape>"#),
        &fs,
        &[],
    )
    .unwrap_err();
    assert!(
        e.message.contains("\"m.obj\"") && e.message.contains("lib/m.obj"),
        "{e}"
    );
    let e =
        fail(r#"<bsdf type="diffuse" id="a"/><bsdf type="diffuse" id="b"/><alias id="a" as="b"/>"#);
    assert!(e.message.contains("already an id"), "{e}");
}

/// `spot`: Mitsuba 3's cone (`cutoff_angle`, `beam_width` default 3/4 of it) and its linear
/// falloff, at to_world's origin along its +z; a beam wider than the cutoff is refused.
#[test]
fn spot_emitters_keep_their_cone() {
    let c = run(
        "<emitter type=\"spot\"><rgb name=\"intensity\" value=\"3\"/>\
         <float name=\"cutoff_angle\" value=\"40\"/>\
         <transform name=\"to_world\"><lookat origin=\"0, 4, 0\" target=\"0, 0, 0\" up=\"0, 0, 1\"/></transform>\
         </emitter>",
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
    assert!((DVec3::from(position) - DVec3::new(0.0, 4.0, 0.0)).length() < 1e-12);
    assert!(
        (DVec3::from(direction) - DVec3::NEG_Y).length() < 1e-12,
        "{direction:?}"
    );
    assert_eq!(intensity, [3.0; 3]);
    assert_eq!((cone_angle, falloff_angle), (40.0, Some(30.0)));
    assert_eq!(profile, crate::lights::SpotProfile::Linear);
    let e = fail(
        "<emitter type=\"spot\"><float name=\"cutoff_angle\" value=\"10\"/>\
         <float name=\"beam_width\" value=\"12\"/></emitter>",
    );
    assert!(
        e.to_string()
            .contains("beam_width 12 is not in [0, cutoff_angle]"),
        "{e}"
    );
}

/// mitsuba-data's Cornell box as shipped: a mesh named in an included file (in a subfolder) is
/// found in the top file's directory, as Mitsuba's resolver finds it; a named top-level area
/// emitter lights the shape that refers to it; clip planes other than Mitsuba's defaults are
/// noted.
#[test]
fn included_files_resolve_from_the_scene_directory_and_area_emitters_by_ref() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec();
    let fs: HashMap<String, Vec<u8>> = [
        ("meshes/lamp.obj".to_string(), obj.clone()),
        (
            "fragments/shapes.xml".to_string(),
            br#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="meshes/lamp.obj"/><ref id="light"/></shape></scene>"#
                .to_vec(),
        ),
    ]
    .into();
    let body = r#"<emitter type="area" id="light"><rgb name="radiance" value="5, 4, 3"/></emitter>
      <include filename="fragments/shapes.xml"/>"#;
    let c = run_with(&scene(body), &fs, &[]).unwrap();
    assert_eq!(c.desc.objects.len(), 1);
    let m = &c.desc.materials[c.desc.objects[0].material()];
    assert_eq!(m.emission, [5.0, 4.0, 3.0]);
    // The mesh beside the included file is still found there.
    let mut fs2 = fs.clone();
    let moved = fs2.remove("meshes/lamp.obj").unwrap();
    fs2.insert("fragments/meshes/lamp.obj".into(), moved);
    assert_eq!(
        run_with(&scene(body), &fs2, &[])
            .unwrap()
            .desc
            .objects
            .len(),
        1
    );
    // Nowhere: the message names every place looked in.
    fs2.remove("fragments/meshes/lamp.obj");
    let e = run_with(&scene(body), &fs2, &[]).unwrap_err();
    assert!(
        e.message.contains("fragments/meshes/lamp.obj") && e.message.contains("scene's directory"),
        "{e}"
    );
    // An unnamed top-level area emitter belongs to no shape.
    let e = fail(r#"<emitter type="area"><rgb name="radiance" value="1"/></emitter>"#);
    assert!(e.message.contains("inside a <shape>"), "{e}");
    // Clip planes: Mitsuba's defaults silently, others noted.
    let sensor = |extra: &str| {
        format!(
            "<scene version=\"3.0.0\"><sensor type=\"perspective\">{extra}<film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film></sensor></scene>"
        )
    };
    let quiet = run_with(
        &sensor(r#"<float name="near_clip" value="0.01"/>"#),
        &fs,
        &[],
    )
    .unwrap();
    assert!(!quiet.notes.iter().any(|n| n.message.contains("clip")));
    let noted = run_with(&sensor(r#"<float name="far_clip" value="5"/>"#), &fs, &[]).unwrap();
    assert!(
        noted.notes.iter().any(|n| n.message.contains("far_clip 5")),
        "{:?}",
        noted.notes
    );
}
