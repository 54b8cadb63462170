//! The inspector opens pbrt-v4, Mitsuba 3 and glTF scenes through its file hook (binary meshes
//! and `.glb` scenes by `Files::read_bytes`), and its status line says what the conversion
//! approximated.

mod common;
use raytree::gui::{Files, Session};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// The real files, read-only.
struct Disk;

impl Files for Disk {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        std::fs::read_to_string(path)
    }
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        std::fs::read(path)
    }
    fn modified(&self, _: &Path) -> Option<SystemTime> {
        Some(SystemTime::UNIX_EPOCH)
    }
    fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
        Err(std::io::Error::other("read-only"))
    }
}

fn open(name: &str) -> Session {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/formats")
        .join(name);
    Session::new(
        Some(path),
        Box::new(Disk),
        Box::new(|_| Ok(())),
        Arc::new(|| {}),
    )
}

#[test]
fn the_inspector_opens_pbrt_and_mitsuba_scenes() {
    let pbrt = open("cornell-box.pbrt");
    assert!(pbrt.doc.error.is_none(), "{:?}", pbrt.doc.error);
    assert_eq!(pbrt.doc.scene.objects.len(), 8);
    assert!(pbrt.doc.status.starts_with("loaded"), "{}", pbrt.doc.status);
    let xml = open("cornell-box.xml");
    assert!(xml.doc.error.is_none(), "{:?}", xml.doc.error);
    assert_eq!(xml.doc.scene.objects[0].name, "floor");
    assert!(
        xml.doc.status.contains("1 approximation(s)")
            && xml.doc.status.contains("cornell-box.xml:62:"),
        "{}",
        xml.doc.status
    );
}

#[test]
fn a_bad_pbrt_scene_shows_its_position() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.pbrt");
    std::fs::write(&p, "WorldBegin\nShape \"torus\"\n").unwrap();
    let s = Session::new(
        Some(p),
        Box::new(Disk),
        Box::new(|_| Ok(())),
        Arc::new(|| {}),
    );
    let e = s.doc.error.clone().unwrap_or_default();
    assert!(
        e.contains("bad.pbrt:2:1: Shape \"torus\": unknown shape"),
        "{e}"
    );
}

/// A binary glTF opens too: it is read as bytes (every other scene as text).
#[test]
fn the_inspector_opens_a_glb() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cb.glb");
    std::fs::write(&p, common::fixture_glb()).unwrap();
    let s = Session::new(
        Some(p),
        Box::new(Disk),
        Box::new(|_| Ok(())),
        Arc::new(|| {}),
    );
    assert!(s.doc.error.is_none(), "{:?}", s.doc.error);
    assert!(s.doc.status.starts_with("loaded"), "{}", s.doc.status);
    let gltf = open("cornell-box.gltf");
    assert_eq!(s.doc.scene.objects.len(), gltf.doc.scene.objects.len());
}
