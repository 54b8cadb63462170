//! glTF front-end: one test per feature, and hostile inputs (each an error naming its JSON
//! path, never a panic).

use super::convert;
use crate::formats::{Converted, FormatError, Limits};
use crate::scene::desc::{LightDesc, ObjectDesc, TextureDesc};
use crate::scene::validate;
use glam::DVec3;
use serde_json::{Value, json};
use std::collections::HashMap;

/// Little-endian bytes of `v`.
fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn u16s(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn b64(b: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in b.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(char::from(A[(n >> (18 - 6 * k)) as usize & 63]));
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// A data URI of `b`.
fn uri(b: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", b64(b))
}

/// The binary data of [`scene`]: a right triangle in the xy plane (positions, then normals,
/// then u16 indices padded to 4 bytes).
fn tri_bytes() -> Vec<u8> {
    let mut b = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    b.extend(f32s(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]));
    b.extend(u16s(&[0, 1, 2, 0]));
    b
}

/// A camera on +z looking at one triangle (node 1) whose buffer is `buffer`.
fn scene(buffer: Value) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"camera": 0, "translation": [0, 0, 5]},
            {"mesh": 0, "name": "tri"}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
            {"buffer": 0, "byteOffset": 72, "byteLength": 6}
        ],
        "buffers": [buffer]
    })
}

fn tri_scene() -> Value {
    scene(json!({"byteLength": 80, "uri": uri(&tri_bytes())}))
}

fn run_files(doc: &[u8], fs: &HashMap<String, Vec<u8>>) -> Result<Converted, FormatError> {
    let mut res = |p: &str| {
        fs.get(p)
            .cloned()
            .ok_or_else(|| format!("cannot read {p}: no such file"))
    };
    convert("dir/s.gltf", doc, &mut res, Limits::default())
}

fn run(v: &Value) -> Result<Converted, FormatError> {
    run_files(v.to_string().as_bytes(), &HashMap::new())
}

fn ok(v: &Value) -> Converted {
    let c = run(v).unwrap();
    validate(&c.desc, "", &mut |_| Err(String::new())).unwrap();
    c
}

fn fail(v: &Value) -> String {
    run(v).unwrap_err().to_string()
}

/// A GLB container of `json` and `bin`.
fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = json.to_string().into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

fn trimesh(c: &Converted, i: usize) -> (Vec<DVec3>, Vec<[u32; 3]>, Option<Vec<DVec3>>) {
    match &c.desc.objects[i] {
        ObjectDesc::Trimesh {
            positions,
            indices,
            normals,
            ..
        } => (
            positions.iter().map(|&p| DVec3::from(p)).collect(),
            indices.clone(),
            normals
                .as_ref()
                .map(|n| n.iter().map(|&p| DVec3::from(p)).collect()),
        ),
        o => panic!("{o:?}"),
    }
}

/// The world-space front normal of triangle `t` of a mesh.
fn front(p: &[DVec3], t: [u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    (b - a).cross(c - a).normalize()
}

fn has_note(c: &Converted, what: &str) -> bool {
    c.notes.iter().any(|n| n.to_string().contains(what))
}

#[test]
fn a_triangle_from_a_data_uri_with_its_camera() {
    let c = ok(&tri_scene());
    let cam = &c.desc.camera;
    assert_eq!(cam.position, [0.0, 0.0, 5.0]);
    assert_eq!(cam.look_at, [0.0, 0.0, 4.0]);
    assert!(
        (cam.fov_y - 0.5f64.to_degrees()).abs() < 1e-12,
        "{}",
        cam.fov_y
    );
    assert_eq!((cam.width, cam.height), (640, 320));
    let (p, t, n) = trimesh(&c, 0);
    assert_eq!(p[1], DVec3::X);
    assert_eq!(t, vec![[0, 1, 2]]);
    assert!(n.is_none());
    assert_eq!(c.desc.objects[0].name(), Some("tri"));
    // The diffuse base of the matte material under a 0.04 coat.
    let m = &c.desc.materials[c.desc.objects[0].material()];
    let Some(TextureDesc::Solid(d)) = m.diffuse else {
        panic!()
    };
    assert!((d[0] - 0.48).abs() < 1e-12);
    assert_eq!(c.desc.settings.spp, super::scene::SPP);
    // Every note names the file and a JSON path.
    assert!(
        c.notes
            .iter()
            .all(|n| n.line == 0 && n.to_string().starts_with("dir/s.gltf: materials")),
        "{:?}",
        c.notes
    );
}

#[test]
fn a_glb_reads_its_bin_chunk_and_equals_the_json_form() {
    let json = scene(json!({"byteLength": 80}));
    let bytes = glb(&json, &tri_bytes());
    let a = run_files(&bytes, &HashMap::new()).unwrap();
    let b = ok(&tri_scene());
    assert_eq!(
        serde_json::to_value(&a.desc).unwrap(),
        serde_json::to_value(&b.desc).unwrap()
    );
    assert_eq!(
        crate::formats::Format::detect("x.glb", &bytes),
        crate::formats::Format::Gltf
    );
}

#[test]
fn external_buffers_are_read_through_the_resolver_relative_to_the_file() {
    let json = scene(json!({"byteLength": 80, "uri": "my%20data.bin"}));
    let fs: HashMap<String, Vec<u8>> = [("dir/my data.bin".to_string(), tri_bytes())].into();
    let c = run_files(json.to_string().as_bytes(), &fs).unwrap();
    assert_eq!(trimesh(&c, 0).0[2], DVec3::Y);
    let e = run_files(json.to_string().as_bytes(), &HashMap::new())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("buffers[0].uri") && e.contains("cannot read dir/my data.bin"),
        "{e}"
    );
    // Other schemes are not fetched.
    let json = scene(json!({"byteLength": 80, "uri": "https://example.com/a.bin"}));
    assert!(fail(&json).contains("only relative file names"));
}

#[test]
fn node_hierarchies_compose_matrix_and_trs_parent_first() {
    let mut v = tri_scene();
    // Node 1 (translate x by 10) holds node 2 (rotate +90 about z, as a matrix) with the mesh.
    v["nodes"] = json!([
        {"camera": 0, "translation": [0, 0, 5]},
        {"translation": [10, 0, 0], "children": [2]},
        {"mesh": 0, "matrix": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}
    ]);
    let c = ok(&v);
    let (p, _, _) = trimesh(&c, 0);
    // x -> y under the rotation, then +10 in x.
    assert!(p[1].abs_diff_eq(DVec3::new(10.0, 1.0, 0.0), 1e-12), "{p:?}");
    assert!(p[2].abs_diff_eq(DVec3::new(9.0, 0.0, 0.0), 1e-12), "{p:?}");
    // The same rotation as a quaternion [0, 0, sin 45, cos 45].
    let h = std::f64::consts::FRAC_1_SQRT_2;
    v["nodes"][2] = json!({"mesh": 0, "rotation": [0, 0, h, h]});
    let (q, _, _) = trimesh(&ok(&v), 0);
    assert!(q[1].abs_diff_eq(p[1], 1e-6));
}

#[test]
fn a_negative_determinant_keeps_the_front_side() {
    // The triangle faces +z (counter-clockwise seen from +z). Mirrored in x its front must
    // still face +z: the winding is swapped back.
    let mut v = tri_scene();
    v["nodes"][1]["scale"] = json!([-1, 1, 1]);
    let c = ok(&v);
    let (p, t, _) = trimesh(&c, 0);
    assert_eq!(p[1], DVec3::new(-1.0, 0.0, 0.0));
    assert!(front(&p, t[0]).abs_diff_eq(DVec3::Z, 1e-12), "{t:?}");
    // Mirrored in z the front faces -z.
    v["nodes"][1]["scale"] = json!([1, 1, -1]);
    let (p, t, _) = trimesh(&ok(&v), 0);
    assert!(front(&p, t[0]).abs_diff_eq(-DVec3::Z, 1e-12));
}

#[test]
fn normals_are_carried_by_the_inverse_transpose() {
    let mut v = tri_scene();
    v["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(1);
    v["nodes"][1]["scale"] = json!([1, 1, -2]);
    let (_, _, n) = trimesh(&ok(&v), 0);
    let n = n.unwrap();
    assert!(n[0].normalize().abs_diff_eq(-DVec3::Z, 1e-12), "{n:?}");
    // A zero normal: flat shading, noted.
    let mut b = tri_bytes();
    b[36..48].copy_from_slice(&f32s(&[0.0, 0.0, 0.0]));
    let mut v = scene(json!({"byteLength": 80, "uri": uri(&b)}));
    v["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(1);
    let c = ok(&v);
    assert!(trimesh(&c, 0).2.is_none());
    assert!(has_note(&c, "attributes.NORMAL: normal 0 is zero"));
}

#[test]
fn strips_and_fans_are_triangulated_and_points_refused() {
    // Four points of a unit square; strip 0 1 2 3 and fan 0 1 2 3.
    let mut b = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.5, 1.0, 0.0]);
    b.extend([0u8; 36 + 8 - 12]);
    let mut v = scene(json!({"byteLength": 80, "uri": uri(&b)}));
    v["accessors"][0]["count"] = json!(4);
    v["accessors"][0]["max"] = json!([1.5, 1, 0]);
    v["bufferViews"][0]["byteLength"] = json!(48);
    let prim = &mut v["meshes"][0]["primitives"][0];
    prim.as_object_mut().unwrap().remove("indices");
    prim["mode"] = json!(5);
    let (p, t, _) = trimesh(&ok(&v), 0);
    assert_eq!(t, vec![[0, 1, 2], [2, 1, 3]]);
    assert!(t.iter().all(|&t| front(&p, t).abs_diff_eq(DVec3::Z, 1e-12)));
    v["meshes"][0]["primitives"][0]["mode"] = json!(6);
    let (_, t, _) = trimesh(&ok(&v), 0);
    assert_eq!(t, vec![[0, 1, 2], [0, 2, 3]]);
    v["meshes"][0]["primitives"][0]["mode"] = json!(1);
    let e = fail(&v);
    assert!(e.contains("meshes[0].primitives[0].mode: LINES"), "{e}");
}

#[test]
fn without_a_camera_a_default_frames_the_geometry() {
    let mut v = tri_scene();
    v["scenes"][0]["nodes"] = json!([1]);
    let c = ok(&v);
    let cam = &c.desc.camera;
    assert_eq!(cam.fov_y, 45.0);
    assert!(cam.position[2] > 0.5 && (cam.position[0] - 0.5).abs() < 1e-12);
    assert!(has_note(&c, "scenes[0]: no camera"));
    v["cameras"][0] = json!({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}});
    v["scenes"][0]["nodes"] = json!([0, 1]);
    assert!(fail(&v).contains("cameras[0]: an orthographic camera"));
    let mut v = tri_scene();
    v["cameras"][0]["perspective"]
        .as_object_mut()
        .unwrap()
        .remove("aspectRatio");
    let c = ok(&v);
    assert_eq!((c.desc.camera.width, c.desc.camera.height), (640, 480));
    assert!(has_note(&c, "cameras[0].perspective: no aspectRatio"));
    // A camera rotated to look down -y.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    v["nodes"][0] = json!({"camera": 0, "translation": [0, 5, 0], "rotation": [-h, 0, 0, h]});
    let cam = ok(&v).desc.camera;
    assert!((cam.look_at[1] - 4.0).abs() < 1e-9, "{cam:?}");
}

#[test]
fn punctual_lights_in_their_units_with_spot_cones_and_range_noted() {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mut v = tri_scene();
    v["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 0.5, 0.25], "intensity": 4, "range": 10},
        {"type": "spot", "intensity": 2, "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.5}},
        {"type": "directional", "intensity": 3}
    ]}});
    v["nodes"] = json!([
        {"camera": 0, "translation": [0, 0, 5]},
        {"mesh": 0},
        {"translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"rotation": [-h, 0, 0, h], "extensions": {"KHR_lights_punctual": {"light": 2}}}
    ]);
    v["scenes"][0]["nodes"] = json!([0, 1, 2, 3, 4]);
    let c = ok(&v);
    let LightDesc::Point {
        position,
        intensity,
        ..
    } = &c.desc.lights[0]
    else {
        panic!()
    };
    assert_eq!((*position, *intensity), ([1.0, 2.0, 3.0], [4.0, 2.0, 1.0]));
    let LightDesc::Spot {
        direction: Some(direction),
        intensity: [2.0, 2.0, 2.0],
        cone_angle,
        falloff_angle: Some(falloff),
        profile: crate::lights::SpotProfile::Gltf,
        ..
    } = c.desc.lights[1]
    else {
        panic!("{:?}", c.desc.lights[1])
    };
    // A spot light points along its node's -z; the cone is outerConeAngle, the full beam
    // innerConeAngle.
    assert_eq!(direction, [0.0, 0.0, -1.0]);
    assert!((cone_angle - 0.5f64.to_degrees()).abs() < 1e-12);
    assert!((falloff - 0.1f64.to_degrees()).abs() < 1e-6, "{falloff}");
    let LightDesc::Directional {
        direction,
        irradiance,
        ..
    } = &c.desc.lights[2]
    else {
        panic!()
    };
    // -z rotated -90 degrees about x points down.
    assert!(
        DVec3::from(*direction).abs_diff_eq(-DVec3::Y, 1e-6),
        "{direction:?}"
    );
    assert_eq!(*irradiance, [3.0; 3]);
    assert!(has_note(&c, "lights[0].range: range 10 ignored"));
    assert!(!c.notes.iter().any(|n| n.message.contains("spot")));
    assert!(has_note(&c, "photometric units"));
    v["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["innerConeAngle"] = json!(0.6);
    assert!(fail(&v).contains("lights[1].spot.innerConeAngle: 0.6 is not in [0, outerConeAngle)"));
    v["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"] = json!({"outerConeAngle": 2});
    assert!(fail(&v).contains("lights[1].spot.outerConeAngle: 2 is not in (0, pi/2]"));
    v["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"] =
        json!({"innerConeAngle": 0.1, "outerConeAngle": 0.5});
    v["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = json!(-1);
    assert!(fail(&v).contains("lights[0].intensity: -1 is not a finite number >= 0"));
}

/// A data URI of a PNG of `w x h` RGBA pixels.
fn png(px: &[u8], w: u32, h: u32) -> String {
    let mut out = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut out),
        px,
        w,
        h,
        image::ExtendedColorType::Rgba8,
    )
    .unwrap();
    format!("data:image/png;base64,{}", b64(&out))
}

#[test]
fn textures_are_read_as_their_mean_and_named_in_a_note() {
    let mut v = tri_scene();
    // A 2x1 texture: sRGB white and black, mean linear 0.5; metallic-roughness: G 255 and 0
    // (mean roughness 0.5), B 0 (not metallic).
    v["images"] = json!([
        {"uri": png(&[255, 255, 255, 255, 0, 0, 0, 255], 2, 1)},
        {"uri": png(&[0, 255, 0, 255, 0, 0, 0, 255], 2, 1)},
        {"uri": "data:image/jpeg;base64,/9j/4AAQ"}
    ]);
    v["textures"] = json!([{"source": 0}, {"source": 1}, {"source": 2}]);
    v["materials"][0] = json!({
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}},
        "normalTexture": {"index": 2},
        "emissiveTexture": {"index": 2},
        "emissiveFactor": [1, 1, 1],
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1}}
    });
    let c = ok(&v);
    let m = &c.desc.materials[c.desc.objects[0].material()];
    // metallicFactor defaults to 1, times the texture's mean 0: a dielectric.
    assert!(m.conductor.is_none());
    let Some(TextureDesc::Solid(d)) = m.diffuse else {
        panic!("{m:?}")
    };
    assert!((d[0] - 0.5 * 0.96).abs() < 1e-12, "{d:?}");
    // roughnessFactor 1 times the mean 0.5: alpha 0.25.
    assert!((m.roughness - 0.25).abs() < 1e-12);
    // The JPEG emissive texture is not decoded: its factor alone.
    assert_eq!(m.emission, [1.0; 3]);
    for what in [
        "materials[0].pbrMetallicRoughness.baseColorTexture: textures[0] (images[0], PNG 2x1) read as its mean colour [0.5000, 0.5000, 0.5000]",
        "materials[0].pbrMetallicRoughness.metallicRoughnessTexture: textures[1]",
        "materials[0].emissiveTexture: textures[2] (images[2]): JPEG images are not decoded: emissiveFactor alone",
        "materials[0].normalTexture: textures[2] ignored",
        "materials[0].extensions.KHR_materials_clearcoat: not read",
    ] {
        assert!(has_note(&c, what), "{what}: {:#?}", c.notes);
    }
    // A broken PNG is an error naming the image.
    v["images"][0]["uri"] = json!("data:image/png;base64,iVBORw0KGgoAAAA=");
    assert!(fail(&v).contains("images[0]: cannot decode the PNG image"));
}

#[test]
fn transmission_ior_volume_emission_and_unlit_materials() {
    let mut v = tri_scene();
    v["materials"] = json!([
        {"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                        "KHR_materials_ior": {"ior": 1.33},
                        "KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": 2, "attenuationColor": [0.5, 1, 1]}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}, "emissiveFactor": [1, 0.5, 0.25],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1]}, "extensions": {"KHR_materials_unlit": {}}}
    ]);
    let mat = |v: &Value| {
        let c = ok(v);
        c.desc.materials[c.desc.objects[0].material()].clone()
    };
    let glass = mat(&v);
    assert_eq!(glass.ior, Some(1.33));
    assert_eq!(glass.transmissivity, [1.0; 3]);
    assert!((glass.absorption[0] - 2f64.ln() / 2.0).abs() < 1e-12);
    v["meshes"][0]["primitives"][0]["material"] = json!(1);
    assert_eq!(mat(&v).emission, [8.0, 4.0, 2.0]);
    v["meshes"][0]["primitives"][0]["material"] = json!(2);
    assert_eq!(mat(&v).emission, [0.2, 0.4, 0.6]);
    // No material: glTF's default (metallic 1, roughness 1, white).
    v["meshes"][0]["primitives"][0]
        .as_object_mut()
        .unwrap()
        .remove("material");
    let d = mat(&v);
    assert!(d.conductor.is_some() && d.roughness == 1.0);
    v["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = json!(0.5);
    v["meshes"][0]["primitives"][0]["material"] = json!(0);
    assert!(fail(&v).contains("KHR_materials_ior.ior: 0.5 is not a finite number >= 1"));
}

#[test]
fn extensions_required_and_used_are_refused_or_noted() {
    let mut v = tri_scene();
    v["extensionsUsed"] = json!(["KHR_draco_mesh_compression", "EXT_foo"]);
    let c = ok(&v);
    assert!(has_note(
        &c,
        "extensionsUsed[0]: KHR_draco_mesh_compression is not read"
    ));
    v["extensionsRequired"] = json!(["KHR_materials_ior", "KHR_draco_mesh_compression"]);
    let e = fail(&v);
    assert!(
        e.contains("extensionsRequired[1]: the scene requires KHR_draco_mesh_compression"),
        "{e}"
    );
    v["asset"]["version"] = json!("1.0");
    assert!(fail(&v).contains("asset.version"));
}

#[test]
fn quantized_and_sparse_accessors() {
    // Positions as normalised u8 (KHR_mesh_quantization), 4-byte aligned: 255 is 1.
    let mut b = vec![0u8, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0];
    b.extend(u16s(&[0, 1, 2, 0]));
    // Sparse: replace element 2 with (0, 0, 1) as floats, index u16 2.
    b.extend(u16s(&[2, 0]));
    b.extend(f32s(&[0.0, 0.5, 0.0]));
    let mut v = scene(json!({"byteLength": b.len(), "uri": uri(&b)}));
    v["accessors"] = json!([
        {"bufferView": 0, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC3", "byteOffset": 0, "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC3"},
        {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0],
         "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 3}}}
    ]);
    v["bufferViews"] = json!([
        {"buffer": 0, "byteOffset": 0, "byteLength": 12, "byteStride": 4},
        {"buffer": 0, "byteOffset": 12, "byteLength": 6},
        {"buffer": 0, "byteOffset": 20, "byteLength": 2},
        {"buffer": 0, "byteOffset": 24, "byteLength": 12}
    ]);
    let (p, _, _) = trimesh(&ok(&v), 0);
    assert_eq!(p[1], DVec3::X);
    // Positions all zero except the sparse one: every triangle has zero area, noted.
    v["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(3);
    let c = run(&v).unwrap();
    assert!(has_note(&c, "no triangle with area: left out"));
    // A sparse index at or above the count.
    let mut b2 = b.clone();
    b2[20..22].copy_from_slice(&u16s(&[3]));
    v["buffers"][0]["uri"] = json!(uri(&b2));
    let e = fail(&v);
    assert!(
        e.contains("accessors[3].sparse.indices: index 0 is 3: sparse indices must increase"),
        "{e}"
    );
}

#[test]
fn hostile_containers_are_errors() {
    let json = scene(json!({"byteLength": 80}));
    let good = glb(&json, &tri_bytes());
    let err = |b: &[u8]| run_files(b, &HashMap::new()).unwrap_err().to_string();
    // Truncated anywhere: an error, never a panic.
    for cut in [0, 3, 4, 11, 12, 15, 19, 40, good.len() - 1] {
        let e = err(&good[..cut]);
        assert!(e.starts_with("dir/s.gltf:"), "{cut}: {e}");
    }
    assert!(err(&good[..good.len() - 1]).contains("truncated"));
    // The header's length below the data: the BIN chunk is cut off.
    let mut b = good.clone();
    b[8..12].copy_from_slice(&((good.len() - 8) as u32).to_le_bytes());
    assert!(err(&b).contains("chunk 1"));
    // A chunk length that lies.
    let mut b = good.clone();
    b[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(err(&b).contains("chunk 0 (JSON) says 4294967295 bytes"));
    let mut b = good.clone();
    b[4] = 1;
    assert!(err(&b).contains("version 1"));
    // A GLB whose buffer has no BIN chunk.
    let mut j = json.to_string().into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = b"glTF".to_vec();
    b.extend(2u32.to_le_bytes());
    b.extend(((20 + j.len()) as u32).to_le_bytes());
    b.extend((j.len() as u32).to_le_bytes());
    b.extend(b"JSON");
    b.extend(j);
    assert!(err(&b).contains("buffers[0]: no uri, and the file has no GLB BIN chunk"));
}

#[test]
fn hostile_documents_are_errors_naming_their_json_path() {
    let base = tri_scene();
    type Edit = Box<dyn Fn(&mut Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(9)),
            "meshes[0].primitives[0].attributes: accessors[9] does not exist",
        ),
        (
            Box::new(|v| v["meshes"][0]["primitives"][0]["indices"] = json!(7)),
            "meshes[0].primitives[0].indices: Index out of bounds",
        ),
        (
            Box::new(|v| v["bufferViews"][0]["byteLength"] = json!(3000)),
            "bufferViews[0]: bytes 0..3000 lie outside buffers[0] (80 bytes)",
        ),
        (
            Box::new(|v| {
                v["buffers"][0]["byteLength"] = json!(4000);
                v["bufferViews"][0]["byteLength"] = json!(3000);
            }),
            "buffers[0]: byteLength is 4000 but its data URI holds 80 bytes",
        ),
        (
            Box::new(|v| v["bufferViews"][0]["byteOffset"] = json!(70)),
            "bufferViews[0]: bytes 70..106 lie outside buffers[0] (80 bytes)",
        ),
        (
            Box::new(|v| v["accessors"][0]["count"] = json!(4)),
            "accessors[0]: 4 elements of 12 bytes (stride 12, offset 0) need 48 bytes of bufferViews[0], which has 36",
        ),
        (
            Box::new(|v| v["accessors"][0]["count"] = json!(4_000_000_000u64)),
            "accessors[0].count: 4000000000 elements, more than the limit",
        ),
        (
            Box::new(|v| v["accessors"][0]["byteOffset"] = json!(u64::MAX)),
            "accessors[0]",
        ),
        (
            Box::new(|v| v["bufferViews"][0]["byteStride"] = json!(4)),
            "bufferViews[0].byteStride",
        ),
        (
            Box::new(|v| v["accessors"][0]["type"] = json!("VEC2")),
            "accessors[0]: POSITION: type VEC2 where VEC3 is expected",
        ),
        (
            Box::new(|v| v["accessors"][2]["componentType"] = json!(5126)),
            "accessors[2].componentType: indices must be unsigned",
        ),
        (
            Box::new(|v| {
                v["nodes"][1]["matrix"] = json!([1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
            }),
            "not glTF JSON: number out of range",
        ),
        (
            Box::new(|v| {
                v["nodes"][1]["matrix"] = json!([1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
            }),
            "nodes[1]: matrix: the last row",
        ),
        (
            Box::new(|v| v["nodes"][1]["rotation"] = json!([0, 0, 0, 0])),
            "nodes[1]: rotation: a zero quaternion",
        ),
        (
            Box::new(|v| v["nodes"][1]["children"] = json!([1])),
            "nodes[1]: reached twice",
        ),
        (
            Box::new(|v| v["scenes"][0]["nodes"] = json!([0, 1, 1])),
            "nodes[1]: reached twice",
        ),
        (
            Box::new(|v| {
                v["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@")
            }),
            "buffers[0].uri: bad base64",
        ),
        (
            Box::new(|v| v["cameras"][0]["perspective"]["yfov"] = json!(4)),
            "cameras[0].perspective.yfov",
        ),
        (
            Box::new(|v| v["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = json!(2)),
            "materials[0].pbrMetallicRoughness.metallicFactor: 2 is not in [0, 1]",
        ),
        (
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("scene");
                v["scenes"] = json!([]);
            }),
            "scenes: the file has no scene",
        ),
        (
            Box::new(|v| v["meshes"][0]["primitives"][0]["mode"] = json!(0)),
            "meshes[0].primitives[0].mode: POINTS",
        ),
    ];
    for (edit, want) in cases {
        let mut v = base.clone();
        edit(&mut v);
        let e = fail(&v);
        assert!(
            e.starts_with("dir/s.gltf:") && e.contains(want),
            "want {want:?}, got {e}"
        );
    }
    // An index value out of range, NaN in a position.
    let mut b = tri_bytes();
    b[72..74].copy_from_slice(&9u16.to_le_bytes());
    let e = fail(&scene(json!({"byteLength": 80, "uri": uri(&b)})));
    assert!(
        e.contains("accessors[2]: index 0 is 9, out of range for the 3 vertices"),
        "{e}"
    );
    let mut b = tri_bytes();
    b[0..4].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = fail(&scene(json!({"byteLength": 80, "uri": uri(&b)})));
    assert!(
        e.contains("accessors[0]: POSITION: element 0 is not a finite number"),
        "{e}"
    );
    // JSON syntax errors keep their line and column.
    let e = run_files(b"{\n \"asset\": ", &HashMap::new()).unwrap_err();
    assert_eq!(e.line, 2);
    assert!(e.to_string().starts_with("dir/s.gltf:2:"), "{e}");
}

#[test]
fn limits_bound_files_and_bytes() {
    let json = scene(json!({"byteLength": 80, "uri": "a.bin"}));
    let fs: HashMap<String, Vec<u8>> = [("dir/a.bin".to_string(), tri_bytes())].into();
    let mut res = |p: &str| fs.get(p).cloned().ok_or_else(|| "no".to_string());
    let small = Limits {
        bytes: 40,
        ..Limits::default()
    };
    let e = convert("dir/s.gltf", json.to_string().as_bytes(), &mut res, small).unwrap_err();
    assert!(e.to_string().contains("exceed"), "{e}");
    let few = Limits {
        vertices: 2,
        ..Limits::default()
    };
    let e = convert("dir/s.gltf", json.to_string().as_bytes(), &mut res, few).unwrap_err();
    assert!(
        e.to_string().contains("accessors[0].count: 3 elements"),
        "{e}"
    );
}

#[test]
fn base64_and_uris_decode() {
    assert_eq!(
        super::data_uri("data:;base64,aGk=").unwrap().unwrap(),
        b"hi"
    );
    assert_eq!(super::data_uri("data:;base64,aGk").unwrap().unwrap(), b"hi");
    assert!(super::data_uri("data:text/plain,hi").unwrap().is_err());
    assert!(super::data_uri("data:;base64,a").unwrap().is_err());
    assert!(super::data_uri("a.bin").is_none());
    assert_eq!(super::uri_path("a%20b.bin").as_deref(), Some("a b.bin"));
    assert_eq!(super::uri_path("sub/a.bin").as_deref(), Some("sub/a.bin"));
    assert_eq!(super::uri_path("http://x/a.bin"), None);
    assert_eq!(super::uri_path("a%2"), None);
    let s = b64(&[1, 2, 3, 4, 5]);
    assert_eq!(super::base64(&s).unwrap(), vec![1, 2, 3, 4, 5]);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 512, failure_persistence: None, ..proptest::prelude::ProptestConfig::default() })]

    /// Any byte of a small GLB (headers, JSON, binary) replaced: Ok or Err, never a panic
    /// (run in a debug build too, where integer overflow would panic).
    #[test]
    fn mutated_glb_bytes_never_panic(
        edits in proptest::collection::vec((proptest::prelude::any::<usize>(), proptest::prelude::any::<u8>()), 1..5),
    ) {
        let mut v = scene(json!({"byteLength": 80}));
        v["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(1);
        let mut b = glb(&v, &tri_bytes());
        for (at, byte) in edits {
            let n = b.len();
            // Half the edits in the headers and the binary chunk, where the sizes are.
            let i = if at % 2 == 0 { at % 20 } else { n - 1 - at % 100 };
            b[i] = byte;
        }
        let _ = run_files(&b, &HashMap::new());
    }

    /// Numbers of the JSON replaced by awkward values: Ok or Err, never a panic.
    #[test]
    fn mutated_numbers_never_panic(
        edits in proptest::collection::vec((0usize..64, 0usize..9), 1..4),
    ) {
        const NASTY: [i64; 9] = [0, 1, 2, 3, 4, 255, 65535, 4_294_967_295, 9_007_199_254_740_991];
        let v = tri_scene();
        let mut text = v.to_string();
        // The byte ranges of every integer in the JSON text, edited in place.
        let spans: Vec<(usize, usize)> = {
            let b = text.as_bytes();
            let mut out = Vec::new();
            let mut i = 0;
            while i < b.len() {
                if b[i].is_ascii_digit() && i > 0 && matches!(b[i - 1], b':' | b',' | b'[' | b' ') {
                    let s = i;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                    out.push((s, i));
                } else {
                    i += 1;
                }
            }
            out
        };
        let mut chosen: Vec<(usize, usize, i64)> = edits
            .iter()
            .map(|&(k, n)| {
                let (s, e) = spans[k % spans.len()];
                (s, e, NASTY[n])
            })
            .collect();
        chosen.sort_by_key(|c| std::cmp::Reverse(c.0));
        chosen.dedup_by_key(|c| c.0);
        for (s, e, n) in chosen {
            text.replace_range(s..e, &n.to_string());
        }
        let _ = run_files(text.as_bytes(), &HashMap::new());
    }
}
