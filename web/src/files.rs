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

/// The files the page knows, shared between the hook and the app (which adds uploads).
#[derive(Clone)]
pub struct MemFiles {
    files: Arc<Mutex<HashMap<PathBuf, String>>>,
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
                    (*json).into(),
                )
            })
            .collect();
        Self {
            files: Arc::new(Mutex::new(files)),
            sink,
        }
    }

    /// Add (or replace) `path`.
    pub fn insert(&self, path: PathBuf, text: String) {
        self.files
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(path, text);
    }
}

impl Files for MemFiles {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        let files = self.files.lock().unwrap_or_else(PoisonError::into_inner);
        files.get(path).cloned().ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "not among the built-in scenes or the files opened in this page \
                 (open it together with the scene)",
            )
        })
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

/// An uploaded file as text, or why not: too large for a scene (as the desktop refuses) or not
/// UTF-8 (an image, an archive, ... opened by mistake). `limit` is in bytes.
pub fn upload_text(name: &str, bytes: Vec<u8>, limit: u64) -> Result<String, String> {
    if bytes.len() as u64 > limit {
        return Err(too_large(name, bytes.len() as u64, limit));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "cannot open {name}: not UTF-8 text (byte {} is not; a binary file?): a scene is \
             JSON and a mesh OBJ text",
            e.utf8_error().valid_up_to()
        )
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

/// Bytes an uploaded file may have: a mesh's limit for `.obj`, a scene's otherwise.
#[must_use]
pub fn limit_for(name: &str) -> u64 {
    if name.to_ascii_lowercase().ends_with(".obj") {
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
        files.insert("uploads/a.json".into(), "{}".into());
        assert_eq!(files.read(Path::new("uploads/a.json")).unwrap(), "{}");

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

        let e = upload_text("big.json", vec![b' '; 2048], 1024).unwrap_err();
        assert!(e.contains("larger than the limit"), "{e}");
        let e = upload_text("a.png", vec![0x89, b'P', b'N', b'G', 0xff], 1024).unwrap_err();
        assert!(e.contains("not UTF-8 text (byte 0 is not"), "{e}");
        assert_eq!(upload_text("a.json", b"{}".to_vec(), 1024).unwrap(), "{}");
        assert_eq!(limit_for("S.JSON"), raytree::input::MAX_SCENE_BYTES);
    }
}
