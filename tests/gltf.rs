//! glTF 2.0 scenes through the binary: `convert` of the Cornell box fixture writes the golden
//! JSON, which renders the same image; the same scene as a GLB (built here) renders the same
//! too; approximations are printed with their JSON paths; bad scenes exit 2 naming the path and
//! write nothing. Plus a fuzz of the front-end (numbers in the JSON, bytes of a GLB): Ok or
//! Err, never a panic.

mod common;
use common::{decode_base64, fails, fixture, fixture_glb, raytree, stderr};
use proptest::prelude::*;
use serde_json::Value;
use std::path::Path;

fn render_exr(scene: &str, dir: &Path, out: &str) -> Vec<u8> {
    let o = raytree(
        &["render", scene, "-o", out, "--size", "48x48", "--spp", "4"],
        dir,
    );
    assert!(o.status.success(), "{scene}: {}", stderr(&o));
    std::fs::read(dir.join(out)).unwrap()
}

#[test]
fn convert_writes_the_golden_json_which_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let src = fixture("formats/cornell-box.gltf");
    let o = raytree(&["convert", &src, "-o", "out.json"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let got = std::fs::read_to_string(dir.path().join("out.json")).unwrap();
    let want = std::fs::read_to_string(fixture("formats/cornell-box.gltf.json")).unwrap();
    assert!(
        got == want,
        "convert differs from formats/cornell-box.gltf.json"
    );
    let a = render_exr("out.json", dir.path(), "a.exr");
    let b = render_exr(&src, dir.path(), "b.exr");
    assert!(a == b, "the converted JSON renders differently");
    // The GLB form of the same scene renders the same image.
    std::fs::write(dir.path().join("cb.glb"), fixture_glb()).unwrap();
    let c = render_exr("cb.glb", dir.path(), "c.exr");
    assert!(a == c, "the GLB renders differently");
}

#[test]
fn approximations_are_printed_with_their_json_paths_and_listed_by_effects() {
    let dir = tempfile::tempdir().unwrap();
    let src = fixture("formats/cornell-box.gltf");
    let o = raytree(&["effects", &src], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("cornell-box.gltf: materials[4]: metallic 1: glTF's Schlick Fresnel of F0"),
        "{err}"
    );
    assert!(err.contains("cornell-box.gltf: extensions.KHR_lights_punctual: photometric units"));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("approximated:") && out.contains("materials[4]"),
        "{out}"
    );
}

/// Each bad scene: exit 2, the JSON path in the message, no output file.
#[test]
fn bad_scenes_fail_with_their_json_path_and_write_nothing() {
    let text = std::fs::read_to_string(fixture("formats/cornell-box.gltf")).unwrap();
    let good: Value = serde_json::from_str(&text).unwrap();
    let edit = |f: &dyn Fn(&mut Value)| {
        let mut v = good.clone();
        f(&mut v);
        v.to_string().into_bytes()
    };
    let whole = fixture_glb();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "bad.gltf",
            edit(&|v| v["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99.into()),
            "bad.gltf: meshes[0].primitives[0].attributes: accessors[99] does not exist",
        ),
        (
            "bad.gltf",
            edit(&|v| v["buffers"][0]["uri"] = "missing.bin".into()),
            "bad.gltf: buffers[0].uri: cannot read missing.bin",
        ),
        (
            "bad.gltf",
            edit(&|v| v["buffers"][0]["byteLength"] = 99999.into()),
            "bad.gltf: buffers[0]: byteLength is 99999 but its data URI holds",
        ),
        (
            "bad.gltf",
            edit(&|v| v["meshes"][6]["primitives"][0]["mode"] = 0.into()),
            "bad.gltf: meshes[6].primitives[0].mode: POINTS",
        ),
        (
            "bad.glb",
            whole[..whole.len() - 100].to_vec(),
            "bad.glb: GLB container: the header says",
        ),
        ("bad.gltf", b"{\"asset\": ".to_vec(), "bad.gltf:1:"),
    ];
    for (name, bytes, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(name), bytes).unwrap();
        for args in [
            vec!["render", name, "-o", "out.png"],
            vec!["convert", name, "-o", "out.json"],
        ] {
            let err = fails(&raytree(&args, dir.path()));
            assert!(err.contains(want), "{args:?}: {err}");
            assert!(!dir.path().join("out.png").exists() && !dir.path().join("out.json").exists());
        }
    }
}

/// Every number in `v`, by its place, to be replaced.
fn numbers(v: &Value, out: &mut Vec<Vec<PathStep>>, at: &mut Vec<PathStep>) {
    match v {
        Value::Number(_) => out.push(at.clone()),
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(PathStep::Index(i));
                numbers(x, out, at);
                at.pop();
            }
        }
        Value::Object(m) => {
            for (k, x) in m {
                at.push(PathStep::Key(k.clone()));
                numbers(x, out, at);
                at.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum PathStep {
    Key(String),
    Index(usize),
}

fn at_mut<'a>(v: &'a mut Value, path: &[PathStep]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match s {
        PathStep::Key(k) => &mut v[k.as_str()],
        PathStep::Index(i) => &mut v[*i],
    })
}

const NASTY: [f64; 10] = [
    0.0,
    -1.0,
    1.0,
    3.0,
    255.0,
    65536.0,
    4294967295.0,
    1e300,
    -1e-300,
    0.5,
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_numbers_convert_or_fail_but_never_panic(
        edits in proptest::collection::vec((any::<usize>(), 0usize..10), 1..5),
    ) {
        let text = std::fs::read_to_string(fixture("formats/cornell-box.gltf")).unwrap();
        let mut v: Value = serde_json::from_str(&text).unwrap();
        let mut places = Vec::new();
        numbers(&v, &mut places, &mut Vec::new());
        for (i, k) in edits {
            let p = &places[i % places.len()];
            *at_mut(&mut v, p) = serde_json::json!(NASTY[k]);
        }
        let bytes = v.to_string().into_bytes();
        let mut res = |_: &str| Err::<Vec<u8>, String>("no files".into());
        if let Ok(c) = raytree::formats::convert(raytree::formats::Format::Gltf, "s.gltf", &bytes, &[], &mut res) {
            let _ = raytree::scene::validate(&c.desc, "", &mut |_| Err(String::new()));
        }
    }

    #[test]
    fn mutated_glb_bytes_convert_or_fail_but_never_panic(
        edits in proptest::collection::vec((any::<usize>(), any::<u8>()), 1..6),
    ) {
        let mut b = fixture_glb();
        // Mostly the binary part and the headers, where lengths and data live.
        for (at, byte) in edits {
            let n = b.len();
            let i = if at % 3 == 0 { at % 28 } else { n - 1 - at % (n / 2) };
            b[i] = byte;
        }
        let mut res = |_: &str| Err::<Vec<u8>, String>("no files".into());
        if let Ok(c) = raytree::formats::convert(raytree::formats::Format::Gltf, "s.glb", &b, &[], &mut res) {
            let _ = raytree::scene::validate(&c.desc, "", &mut |_| Err(String::new()));
        }
    }
}

/// The inspector opens a glTF scene through its file hook, and its status line names the first
/// approximation by its JSON path.
#[cfg(feature = "gui")]
#[test]
fn the_inspector_opens_a_gltf_scene() {
    use raytree::gui::{Files, Session};
    use std::path::PathBuf;
    struct Disk;
    impl Files for Disk {
        fn read(&self, path: &Path) -> std::io::Result<String> {
            std::fs::read_to_string(path)
        }
        fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
            std::fs::read(path)
        }
        fn modified(&self, _: &Path) -> Option<std::time::SystemTime> {
            Some(std::time::SystemTime::UNIX_EPOCH)
        }
        fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
            Err(std::io::Error::other("read-only"))
        }
    }
    let path = PathBuf::from(fixture("formats/cornell-box.gltf"));
    let s = Session::new(
        Some(path),
        Box::new(Disk),
        Box::new(|_| Ok(())),
        std::sync::Arc::new(|| {}),
    );
    assert!(s.doc.error.is_none(), "{:?}", s.doc.error);
    assert_eq!(s.doc.scene.objects[0].name, "floor");
    assert!(
        s.doc.status.contains("approximation(s)")
            && s.doc
                .status
                .contains("cornell-box.gltf: extensions.KHR_lights_punctual"),
        "{}",
        s.doc.status
    );
}

/// External buffers and images are read relative to the scene, count as inputs (an output may
/// not overwrite them), and a texture's mean is noted.
#[test]
fn external_buffers_and_images_are_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("formats/cornell-box.gltf")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    let uri = v["buffers"][0]["uri"].as_str().unwrap().to_string();
    std::fs::create_dir(dir.path().join("data")).unwrap();
    std::fs::write(
        dir.path().join("data/cb.bin"),
        decode_base64(uri.split_once(',').unwrap().1),
    )
    .unwrap();
    v["buffers"][0]["uri"] = "data/cb.bin".into();
    let mut png = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut png),
        &[255, 0, 0, 255, 0, 0, 255, 255],
        2,
        1,
        image::ExtendedColorType::Rgba8,
    )
    .unwrap();
    std::fs::write(dir.path().join("data/red blue.png"), png).unwrap();
    v["images"] = serde_json::json!([{"uri": "data/red%20blue.png"}]);
    v["textures"] = serde_json::json!([{"source": 0}]);
    v["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = serde_json::json!({"index": 0});
    std::fs::write(dir.path().join("s.gltf"), v.to_string()).unwrap();
    let o = raytree(&["convert", "s.gltf", "-o", "out.json"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "s.gltf: materials[0].pbrMetallicRoughness.baseColorTexture: textures[0] (images[0], PNG 2x1) read as its mean colour [0.5000, 0.0000, 0.5000]"
        ),
        "{}",
        stderr(&o)
    );
    let bin = std::fs::read(dir.path().join("data/cb.bin")).unwrap();
    let err = fails(&raytree(
        &["convert", "s.gltf", "-o", "data/cb.bin"],
        dir.path(),
    ));
    assert!(err.contains("cb.bin"), "{err}");
    assert_eq!(std::fs::read(dir.path().join("data/cb.bin")).unwrap(), bin);
}
