//! The page's files: the built-in fixtures and the user's uploads, in memory, behind the
//! inspector's [`Files`] hook; an export "writes" by handing the bytes to the browser as a
//! download (the same bytes the desktop inspector writes to disk).

use raytree::gui::Files;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::SystemTime;

/// Where a write goes: the file's name (no directory) and its bytes.
pub type Sink = fn(&str, &[u8]) -> std::io::Result<()>;

/// The files the page knows, shared between the hook and the app (which adds uploads): text
/// (scenes, OBJ meshes, pbrt includes) and bytes (PLY meshes, glTF buffers).
#[derive(Clone)]
pub struct MemFiles {
    files: Arc<Mutex<HashMap<PathBuf, Vec<u8>>>>,
    sink: Sink,
}

impl MemFiles {
    /// The built-in fixtures; writes go to `sink`.
    #[must_use]
    pub fn new(sink: Sink) -> Self {
        let files = crate::fixtures::FIXTURES
            .iter()
            .map(|(name, json)| {
                (
                    PathBuf::from(crate::fixtures::path_of(name)),
                    json.as_bytes().to_vec(),
                )
            })
            .collect();
        Self {
            files: Arc::new(Mutex::new(files)),
            sink,
        }
    }

    /// Add (or replace) `path`.
    pub fn insert(&self, path: PathBuf, bytes: Vec<u8>) {
        self.files
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(path, bytes);
    }

    /// The bytes of `path`. A browser hands over files without their folders, so an upload's
    /// companion named with folders (a pbrt scene's `geometry/mesh.ply`, opened as
    /// `uploads/geometry/mesh.ply`) is found by its name among the uploads.
    fn get(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        let files = self.files.lock().unwrap_or_else(PoisonError::into_inner);
        let flat = || {
            let name = path.file_name()?;
            path.starts_with(UPLOADS)
                .then(|| Path::new(UPLOADS).join(name))
        };
        files
            .get(path)
            .or_else(|| flat().and_then(|p| files.get(&p)))
            .cloned()
            .ok_or_else(|| {
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "not among the built-in scenes or the files opened in this page \
                     (open it together with the scene)",
                )
            })
    }
}

/// The folder the page files uploads under.
pub const UPLOADS: &str = "uploads";

impl Files for MemFiles {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        String::from_utf8(self.get(path)?).map_err(|e| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "not UTF-8 text (byte {} is not; a binary file?)",
                    e.utf8_error().valid_up_to()
                ),
            )
        })
    }

    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.get(path)
    }

    /// Files in memory do not change behind the page's back.
    fn modified(&self, _path: &Path) -> Option<SystemTime> {
        None
    }

    fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        (self.sink)(&name, bytes)
    }
}

/// Pixels the page renders at most: the image (24 bytes a pixel) and the debug statistics
/// live in wasm32's 4 GiB of memory, on one thread. Larger cameras are refused with a message.
pub const MAX_PIXELS: u64 = 1 << 22;

/// The deepest recursion the page traces: the browser runs wasm on its JavaScript stack (about
/// 1 MB in Chromium, whatever wasm's own `-zstack-size`), which a recorded recursion of two
/// facing mirrors overflowed at max_depth 1024 and held at 512 (`web/test.mjs`).
pub const MAX_DEPTH: u32 = 512;

/// The page's check on every scene it opens (the inspector's `Adjust` hook): its size and
/// depth.
pub fn check_size(scene: &mut raytree::Scene) -> Result<(), String> {
    let depth = scene.settings.max_depth;
    if depth > MAX_DEPTH {
        return Err(depth_error(depth));
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = u64::from(w) * u64::from(h);
    if n > MAX_PIXELS {
        return Err(format!(
            "camera.width x camera.height: {w}x{h} is {n} pixels; the web page renders at most \
             {MAX_PIXELS} (about 2048x2048: it has one thread and wasm32's 4 GiB of memory). \
             Lower them, or use the desktop inspector (raytree view)"
        ));
    }
    Ok(())
}

/// The message for a recursion deeper than [`MAX_DEPTH`].
#[must_use]
pub fn depth_error(depth: u32) -> String {
    format!(
        "settings.max_depth: {depth} is deeper than the web page traces ({MAX_DEPTH}: the \
         browser's stack); lower it, or use the desktop inspector (raytree view)"
    )
}

/// Extensions of files the page opens as binary: PLY meshes (pbrt, Mitsuba), a glTF's
/// buffers and binary glTF. Every other upload must be UTF-8 text.
const BINARY: [&str; 3] = ["ply", "bin", "glb"];

/// Extensions of scenes, in the order the page prefers one when several are opened together:
/// raytree JSON, glTF, Mitsuba 3, pbrt-v4.
const SCENES: [&str; 5] = ["json", "gltf", "glb", "xml", "pbrt"];

/// The lower-case extension of `name`.
fn extension(name: &str) -> String {
    name.rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default()
}

/// An uploaded file's bytes, or why not: too large (as the desktop refuses), or not UTF-8
/// where the file must be text (an image, an archive, ... opened by mistake). `limit` is in
/// bytes.
pub fn upload(name: &str, bytes: Vec<u8>, limit: u64) -> Result<Vec<u8>, String> {
    if bytes.len() as u64 > limit {
        return Err(too_large(name, bytes.len() as u64, limit));
    }
    if BINARY.contains(&extension(name).as_str()) {
        return Ok(bytes);
    }
    match std::str::from_utf8(&bytes) {
        Ok(_) => Ok(bytes),
        Err(e) => Err(format!(
            "cannot open {name}: not UTF-8 text (byte {} is not; a binary file?): a scene is \
             JSON, pbrt, Mitsuba XML or glTF, a mesh OBJ text or PLY",
            e.valid_up_to()
        )),
    }
}

/// Which of the uploaded files (names and bytes) to open as the scene: by [`SCENES`]' order
/// of extensions, and among pbrt files the first that no other one includes (`Include` or
/// `Import` of its name); else the first file that is not a mesh or buffer (its format is
/// then told from its content). `None` when all are meshes or buffers.
#[must_use]
pub fn scene_among(files: &[(String, Vec<u8>)]) -> Option<usize> {
    let included = |name: &str| {
        files.iter().any(|(other, bytes)| {
            other != name
                && extension(other) == "pbrt"
                && String::from_utf8_lossy(bytes).lines().any(|l| {
                    let l = l.trim_start();
                    (l.starts_with("Include") || l.starts_with("Import"))
                        && (l.contains(&format!("\"{name}\"")) || l.contains(&format!("/{name}\"")))
                })
        })
    };
    SCENES
        .iter()
        .find_map(|ext| {
            files.iter().position(|(name, _)| {
                extension(name) == *ext && !(*ext == "pbrt" && included(name))
            })
        })
        .or_else(|| {
            files
                .iter()
                .position(|(name, _)| !["obj", "ply", "bin"].contains(&extension(name).as_str()))
        })
}

/// The message for a file over `limit` bytes.
#[must_use]
pub fn too_large(name: &str, size: u64, limit: u64) -> String {
    format!(
        "cannot open {name}: {} MiB is larger than the limit of {} MiB",
        size >> 20,
        limit >> 20
    )
}

/// Bytes an uploaded file may have: a mesh's limit for meshes and buffers (`.obj`, `.ply`,
/// `.bin`), a scene's otherwise.
#[must_use]
pub fn limit_for(name: &str) -> u64 {
    if ["obj", "ply", "bin"].contains(&extension(name).as_str()) {
        // In memory, in the page: a quarter of the desktop's limit.
        raytree::input::MAX_OBJ_BYTES / 4
    } else {
        raytree::input::MAX_SCENE_BYTES
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixtures_read_exports_go_to_the_sink_and_hostile_input_is_refused() {
        fn sink(name: &str, bytes: &[u8]) -> std::io::Result<()> {
            assert_eq!((name, bytes), ("classic-tree-1-2.json", &b"{}"[..]));
            Ok(())
        }
        let files = MemFiles::new(sink);
        let classic = files.read(Path::new("fixtures/classic.json")).unwrap();
        assert_eq!(classic, crate::fixtures::get("classic").unwrap());
        let e = files.read(Path::new("uploads/x.obj")).unwrap_err();
        assert!(e.to_string().contains("open it together with the scene"));
        files
            .write(Path::new("fixtures/classic-tree-1-2.json"), b"{}")
            .unwrap();
        files.insert("uploads/a.json".into(), b"{}".to_vec());
        assert_eq!(files.read(Path::new("uploads/a.json")).unwrap(), "{}");
        // A companion named with folders is found by its name among the uploads.
        files.insert("uploads/m.ply".into(), vec![0xff, 0]);
        assert_eq!(
            files
                .read_bytes(Path::new("uploads/geometry/m.ply"))
                .unwrap(),
            [0xff, 0]
        );
        assert!(
            files
                .read(Path::new("uploads/m.ply"))
                .unwrap_err()
                .to_string()
                .contains("not UTF-8")
        );
        assert!(
            files
                .read_bytes(Path::new("fixtures/geometry/m.ply"))
                .is_err()
        );

        let mut scene = raytree::Scene::default_scene();
        assert!(check_size(&mut scene).is_ok());
        scene.camera = scene.camera.with_size(65536, 65536);
        let e = check_size(&mut scene).unwrap_err();
        assert!(e.contains("65536x65536 is 4294967296 pixels"), "{e}");
        let mut scene = raytree::Scene::default_scene();
        scene.settings.max_depth = MAX_DEPTH;
        assert!(check_size(&mut scene).is_ok());
        scene.settings.max_depth = MAX_DEPTH + 1;
        assert!(
            check_size(&mut scene)
                .unwrap_err()
                .contains("deeper than the web page")
        );

        let e = upload("big.json", vec![b' '; 2048], 1024).unwrap_err();
        assert!(e.contains("larger than the limit"), "{e}");
        let e = upload("a.png", vec![0x89, b'P', b'N', b'G', 0xff], 1024).unwrap_err();
        assert!(e.contains("not UTF-8 text (byte 0 is not"), "{e}");
        assert_eq!(upload("a.json", b"{}".to_vec(), 1024).unwrap(), b"{}");
        assert_eq!(upload("m.PLY", vec![0xff], 1024).unwrap(), [0xff]);
        assert!(upload("m.ply", vec![0; 2048], 1024).is_err());
        assert_eq!(limit_for("S.JSON"), raytree::input::MAX_SCENE_BYTES);
        assert_eq!(limit_for("m.ply"), raytree::input::MAX_OBJ_BYTES / 4);
    }

    #[test]
    fn the_scene_among_uploads_is_the_json_else_the_format_that_is_not_a_companion() {
        let f = |names: &[(&str, &str)]| -> Vec<(String, Vec<u8>)> {
            names
                .iter()
                .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec()))
                .collect()
        };
        assert_eq!(scene_among(&f(&[("m.obj", ""), ("s.json", "{}")])), Some(1));
        assert_eq!(scene_among(&f(&[("m.obj", ""), ("n.ply", "")])), None);
        assert_eq!(
            scene_among(&f(&[("m.obj", ""), ("scene.txt", "{}")])),
            Some(1)
        );
        let pbrt = f(&[
            ("box.pbrt", "Shape \"trianglemesh\""),
            ("cornell.pbrt", "WorldBegin\nInclude \"box.pbrt\"\n"),
            ("m.ply", ""),
        ]);
        assert_eq!(scene_among(&pbrt), Some(1));
        let nested = f(&[("b.pbrt", ""), ("a.pbrt", "Import \"parts/b.pbrt\"")]);
        assert_eq!(scene_among(&nested), Some(1));
        // Only an Include or Import makes a companion, not another directive naming the file.
        let named = f(&[("b.pbrt", ""), ("a.pbrt", "Texture \"t\" \"x/b.pbrt\"")]);
        assert_eq!(scene_among(&named), Some(0));
        assert_eq!(
            scene_among(&f(&[("m.obj", ""), ("c.xml", "<scene/>"), ("x.pbrt", "")])),
            Some(1)
        );
    }
}
