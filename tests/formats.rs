//! pbrt-v4 and Mitsuba 3 scenes through the binary: the Cornell box in both formats renders the
//! JSON fixture's image bit for bit, `convert` writes the golden JSON, approximations are
//! printed, and bad scenes exit 2 with file:line and write nothing. Plus a fuzz of both
//! front-ends on mutated fixtures (Ok or Err, never a panic).

mod common;
use common::{fails, fixture, raytree, stderr};
use proptest::prelude::*;
use std::collections::HashMap;
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
fn the_cornell_box_renders_the_same_from_pbrt_mitsuba_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let json = render_exr(&fixture("cornell-box.json"), dir.path(), "j.exr");
    let pbrt = render_exr(&fixture("formats/cornell-box.pbrt"), dir.path(), "p.exr");
    let xml = render_exr(&fixture("formats/cornell-box.xml"), dir.path(), "x.exr");
    assert!(json == pbrt, "the pbrt Cornell box renders differently");
    assert!(json == xml, "the Mitsuba Cornell box renders differently");
}

#[test]
fn convert_writes_the_golden_json_which_renders_the_same() {
    let dir = tempfile::tempdir().unwrap();
    for (src, golden) in [
        ("formats/cornell-box.pbrt", "formats/cornell-box.pbrt.json"),
        ("formats/cornell-box.xml", "formats/cornell-box.xml.json"),
    ] {
        let o = raytree(&["convert", &fixture(src), "-o", "out.json"], dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let got = std::fs::read_to_string(dir.path().join("out.json")).unwrap();
        let want = std::fs::read_to_string(fixture(golden)).unwrap();
        assert!(got == want, "{src}: convert differs from {golden}");
        let a = render_exr("out.json", dir.path(), "a.exr");
        let b = render_exr(&fixture(src), dir.path(), "b.exr");
        assert!(a == b, "{src}: the converted JSON renders differently");
    }
}

#[test]
fn approximations_are_printed_and_listed_by_effects() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.pbrt"),
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 8\n\
         WorldBegin\nMaterial \"coateddiffuse\"\nShape \"sphere\"\n",
    )
    .unwrap();
    let o = raytree(&["effects", "s.pbrt"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("note: s.pbrt:5: Material \"coateddiffuse\""),
        "{err}"
    );
    assert!(
        err.contains("note: s.pbrt:2: the camera is left-handed"),
        "{err}"
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("approximated:") && out.contains("s.pbrt:5:"),
        "{out}"
    );
}

#[test]
fn mitsuba_defines_come_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let xml = std::fs::read_to_string(fixture("formats/cornell-box.xml")).unwrap();
    let xml = xml.replace("<default name=\"spp\" value=\"64\"/>", "");
    std::fs::write(dir.path().join("s.xml"), &xml).unwrap();
    std::fs::copy(
        fixture("formats/box-tall.obj"),
        dir.path().join("box-tall.obj"),
    )
    .unwrap();
    std::fs::copy(
        fixture("formats/box-short.obj"),
        dir.path().join("box-short.obj"),
    )
    .unwrap();
    let err = fails(&raytree(&["convert", "s.xml", "-o", "o.json"], dir.path()));
    assert!(
        err.contains("s.xml:") && err.contains("$spp") && err.contains("-D spp"),
        "{err}"
    );
    assert!(!dir.path().join("o.json").exists());
    let o = raytree(
        &["convert", "s.xml", "-o", "o.json", "-D", "spp=3"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("o.json")).unwrap()).unwrap();
    assert_eq!(v["settings"]["spp"], 3);
    // The output may not replace a file the scene read.
    let err = fails(&raytree(
        &["convert", "s.xml", "-o", "box-tall.obj", "-D", "spp=3"],
        dir.path(),
    ));
    assert!(err.contains("an input of this command"), "{err}");
    assert!(
        std::fs::read_to_string(dir.path().join("box-tall.obj"))
            .unwrap()
            .starts_with("# The")
    );
}

/// Each bad scene: exit 2, the file and line in the message, no output file.
#[test]
fn bad_scenes_fail_with_their_position_and_write_nothing() {
    let cases: [(&str, &str, &str); 7] = [
        (
            "bad.pbrt",
            "WorldBegin\n  Sphere \"x\"\n",
            "bad.pbrt:2:3: unknown directive \"Sphere\"",
        ),
        (
            "bad.pbrt",
            "WorldBegin\nShape \"sphere\" \"string radius\" \"big\"\n",
            "bad.pbrt:2:16:",
        ),
        (
            "bad.pbrt",
            "WorldBegin\nInclude \"nope.pbrt\"\n",
            "bad.pbrt:2:1: Include \"nope.pbrt\"",
        ),
        (
            "bad.pbrt",
            "WorldBegin\nShape \"plymesh\" \"string filename\" \"m.ply\"\n",
            "m.ply",
        ),
        (
            "bad.xml",
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n<shape type=\"sphere\"><ref id=\"x\"/></shape></scene>",
            "bad.xml:3:22: <ref id=\"x\">: refers to undefined id",
        ),
        (
            "bad.xml",
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n</scene>",
            "bad.xml:3:",
        ),
        (
            "bad.xml",
            "<scene version=\"3.0.0\">\n<path value=\"nowhere\"/>\n</scene>",
            "bad.xml:2:1: <path>: \"nowhere\" is not a directory",
        ),
    ];
    for (name, text, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(name), text).unwrap();
        std::fs::write(
            dir.path().join("m.ply"),
            "ply\nformat ascii 1.0\nelement vertex 99999\nproperty float x\nend_header\n1\n",
        )
        .unwrap();
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

/// The fixtures and the files they include, by the names the front-ends ask for.
fn fixture_files() -> HashMap<String, Vec<u8>> {
    let mut m = HashMap::new();
    for f in [
        "cornell-box.pbrt",
        "box-tall.pbrt",
        "cornell-box.xml",
        "box-tall.obj",
        "box-short.obj",
    ] {
        m.insert(
            f.to_string(),
            std::fs::read(fixture(&format!("formats/{f}"))).unwrap(),
        );
    }
    m
}

fn mutate(src: &[u8], edits: &[(usize, u8, u8)]) -> Vec<u8> {
    let mut v = src.to_vec();
    for &(at, kind, byte) in edits {
        if v.is_empty() {
            break;
        }
        let i = at % v.len();
        match kind % 4 {
            0 => v[i] = byte,
            1 => {
                v.remove(i);
            }
            2 => v.insert(i, byte),
            _ => {
                // Splice in a token that stresses numbers and structure.
                let t: &[u8] = [
                    &b" nan "[..],
                    b" 1e308 ",
                    b" -1 ",
                    b"[",
                    b"]",
                    b"\"",
                    b"<",
                    b"/>",
                    b" 0 ",
                    b"$x",
                ][byte as usize % 10];
                v.splice(i..i, t.iter().copied());
            }
        }
    }
    v
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_convert_or_fail_but_never_panic(
        edits in proptest::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..6),
        which in 0usize..2,
    ) {
        let files = fixture_files();
        let (name, format) = [("cornell-box.pbrt", raytree::formats::Format::Pbrt), ("cornell-box.xml", raytree::formats::Format::Mitsuba)][which];
        let src = mutate(&files[name], &edits);
        let mut res = |p: &str| files.get(p).cloned().ok_or_else(|| "no such file".to_string());
        if let Ok(c) = raytree::formats::convert(format, name, &src, &[], &mut res) {
            // What converts either validates or is refused with a message; never a panic.
            let _ = raytree::scene::validate(&c.desc, "", &mut |_| Err(String::new()));
            prop_assert!(c.notes.iter().all(|n| n.line > 0));
        }
    }

    #[test]
    fn mutated_ply_files_parse_or_fail_but_never_panic(
        edits in proptest::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..6),
        binary in any::<bool>(),
    ) {
        let ascii = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
            property float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 1\n\
            property list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n".to_vec();
        let src = if binary {
            let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n\
                property double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
            for v in [0.0f64, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
                b.extend_from_slice(&v.to_le_bytes());
            }
            b.push(3);
            for i in 0u32..3 {
                b.extend_from_slice(&i.to_le_bytes());
            }
            b
        } else {
            ascii
        };
        let m = mutate(&src, &edits);
        if let Ok(mesh) = raytree::formats::ply::parse(&m, 1 << 20) {
            let n = mesh.positions.len();
            prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        }
    }
}
