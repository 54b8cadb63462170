//! Scenes in other renderers' formats (pbrt-v4, Mitsuba 3, glTF 2.0): read through the library's
//! front-ends ([`raytree::formats`]) with a resolver that reads the files they name relative to
//! the scene, bounded like every other read.

use super::read::read_limited;
use anyhow::{Result, anyhow};
use raytree::formats::{Format, Note};
use raytree::input::{MAX_OBJ_BYTES, MAX_SCENE_BYTES, escape_controls};
use raytree::scene::desc::SceneDesc;
use std::path::{Path, PathBuf};

/// A scene converted from another format.
pub struct Foreign {
    /// raytree's description of it.
    pub desc: SceneDesc,
    /// The approximations the conversion made.
    pub notes: Vec<Note>,
}

/// Parse `NAME=VALUE` flags (`-D`).
///
/// # Errors
/// A flag without `=` or with an empty name.
pub fn defines(flags: &[String]) -> Result<Vec<(String, String)>> {
    flags
        .iter()
        .map(|d| match d.split_once('=') {
            Some((k, v)) if !k.is_empty() => Ok((k.to_string(), v.to_string())),
            _ => Err(anyhow!("-D: expected NAME=VALUE, got {d:?}")),
        })
        .collect()
}

/// Convert the scene at `path` (contents `bytes`, already read) in `format`; every file it reads
/// is appended to `inputs`. Errors are `file:line:column: message`.
pub fn convert(
    path: &Path,
    bytes: &[u8],
    format: Format,
    defines: &[(String, String)],
    inputs: &mut Vec<PathBuf>,
) -> Result<Foreign> {
    let name = path.to_string_lossy().into_owned();
    let mut resolver = Disk { inputs };
    let c = raytree::formats::convert(format, &name, bytes, defines, &mut resolver)
        .map_err(|e| anyhow!("{}", escape_controls(&e.to_string())))?;
    Ok(Foreign {
        desc: c.desc,
        notes: c.notes,
    })
}

/// Validate a converted description (meshes are inline, so nothing more is read).
///
/// # Errors
/// The validation error at its JSON path, naming the file it was converted from.
pub fn validate(label: &str, desc: &SceneDesc) -> Result<raytree::Scene> {
    raytree::scene::validate(desc, "", &mut |_| {
        Err("a converted scene has no mesh files".to_string())
    })
    .map_err(|e| anyhow!("{label}: the converted scene is invalid: {e}"))
}

/// Whether `format` needs conversion.
#[must_use]
pub fn is_foreign(format: Format) -> bool {
    format != Format::Json
}

/// The notes as printed on stderr and by `raytree effects`: `note: file:line: message`.
#[must_use]
pub fn note_lines(notes: &[Note]) -> Vec<String> {
    notes
        .iter()
        .map(|n| format!("note: {}", escape_controls(&n.to_string())))
        .collect()
}

/// The scene's files on disk, each appended to `inputs` as it is read; directories (a Mitsuba
/// `<path>`) are checked.
struct Disk<'a> {
    inputs: &'a mut Vec<PathBuf>,
}

impl raytree::formats::Resolver for Disk<'_> {
    fn read(&mut self, file: &str) -> Result<Vec<u8>, String> {
        let p = PathBuf::from(file);
        let lower = file.to_ascii_lowercase();
        let limit = if [".ply", ".obj", ".bin", ".glb"]
            .iter()
            .any(|e| lower.ends_with(e))
        {
            MAX_OBJ_BYTES
        } else {
            MAX_SCENE_BYTES
        };
        self.inputs.push(p.clone());
        read_limited(&p, limit).map_err(|e| format!("cannot read {}: {e}", p.display()))
    }

    fn is_dir(&mut self, path: &str) -> Option<bool> {
        Some(Path::new(path).is_dir())
    }
}
