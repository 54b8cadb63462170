//! Scene front-ends for other renderers' formats: pbrt-v4 (`.pbrt`), Mitsuba 3 (`.xml`) and
//! glTF 2.0 (`.gltf`, `.glb`).
//!
//! Each front-end is a pure parser: it takes the scene's text and a caller-supplied
//! [`Resolver`] for the files the scene names (`Include`, `Import`, PLY and OBJ meshes), and
//! returns raytree's own [`SceneDesc`] (what `raytree convert` writes) plus a [`Note`] for every
//! construct it approximated, so nothing is dropped silently. Errors name the file, the line and
//! column, and the directive or XML element (glTF: the JSON path, with line 0). The mapping of each material onto raytree's model is
//! one small function in [`material_map`], so a richer material model can replace it piece by
//! piece. Supported subsets: `docs/scenes.md`.

pub mod build;
pub mod gltf;
pub mod material_map;
pub mod mitsuba;
pub mod pbrt;
pub mod ply;
pub mod spectrum;
pub mod xform;

use crate::scene::desc::SceneDesc;

/// Reads the files a scene refers to, by the name written in the scene (relative names are the
/// caller's to resolve, normally against the scene's directory). The library does no I/O.
pub trait Resolver {
    /// The bytes of `path`, or why they cannot be read.
    ///
    /// # Errors
    /// A message naming the failure (missing file, not a regular file, too large).
    fn read(&mut self, path: &str) -> Result<Vec<u8>, String>;

    /// Whether `path` is a directory, where the caller can tell (`None`: it cannot, as a
    /// resolver of files alone; a Mitsuba `<path>` is then taken unchecked).
    fn is_dir(&mut self, path: &str) -> Option<bool> {
        let _ = path;
        None
    }
}

impl<F: FnMut(&str) -> Result<Vec<u8>, String>> Resolver for F {
    fn read(&mut self, path: &str) -> Result<Vec<u8>, String> {
        self(path)
    }
}

/// An approximation made while converting: where, and what raytree does instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Note {
    /// The file as named in the scene (the top file by its caller-given name).
    pub file: String,
    /// 1-based line of the directive or element; 0 when the message starts with the location
    /// (glTF's JSON path).
    pub line: usize,
    /// What was approximated and how.
    pub message: String,
}

impl std::fmt::Display for Note {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}:{}: {}", self.file, self.line, self.message)
        }
    }
}

/// A construct that cannot be converted, or malformed input. Shown as
/// `file:line:column: message`, or `file: message` when the line is 0 (the whole file, or a
/// glTF JSON path at the start of the message).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct FormatError {
    /// The file as named in the scene.
    pub file: String,
    /// 1-based line (0 when the error concerns the whole file).
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong, naming the directive or XML path.
    pub message: String,
}

impl std::fmt::Display for FormatError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(
                f,
                "{}:{}:{}: {}",
                self.file, self.line, self.column, self.message
            )
        }
    }
}

/// A converted scene: raytree's description and the approximations made.
#[derive(Clone, Debug)]
pub struct Converted {
    /// The scene as raytree JSON would describe it (self-contained: meshes inline).
    pub desc: SceneDesc,
    /// Every approximation, in file order.
    pub notes: Vec<Note>,
}

/// Bounds on what a scene may make a front-end read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Deepest `Include`/`Import`/`<include>` nesting.
    pub include_depth: usize,
    /// Vertices (and, separately, triangles) in the whole scene.
    pub vertices: usize,
    /// Files read in all (includes and meshes).
    pub files: usize,
    /// Bytes of binary data (glTF buffers and images) read in all.
    pub bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            include_depth: 32,
            vertices: 50_000_000,
            files: 4096,
            bytes: 1 << 30,
        }
    }
}

/// The scene formats raytree reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// raytree's own JSON (`docs/scene-format.md`).
    Json,
    /// pbrt-v4 scene description.
    Pbrt,
    /// Mitsuba 3 XML (and the 0.x/2.x spellings Mitsuba upgrades).
    Mitsuba,
    /// glTF 2.0: JSON (`.gltf`) or the binary container (`.glb`).
    Gltf,
}

impl Format {
    /// Which front-end reads the file named `name` with contents `bytes`: by content where it
    /// is unambiguous (the GLB magic `glTF`; `{` opens JSON, which is glTF when the name ends
    /// in `.gltf` or its top-level object has an `"asset"` member, raytree's otherwise; `<`
    /// XML), otherwise by extension (`.pbrt`, `.xml`, `.gltf`, `.glb`), otherwise pbrt when the
    /// first word is a pbrt directive, otherwise JSON (whose parser then says what is wrong).
    #[must_use]
    pub fn detect(name: &str, bytes: &[u8]) -> Format {
        let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        let lower = name.to_ascii_lowercase();
        if self::gltf::is_glb(bytes) {
            return Format::Gltf;
        }
        let first = text.iter().find(|b| !b.is_ascii_whitespace());
        match first {
            Some(b'{') if lower.ends_with(".gltf") || has_asset(text) => return Format::Gltf,
            Some(b'{') => return Format::Json,
            Some(b'<') => return Format::Mitsuba,
            _ => {}
        }
        if lower.ends_with(".gltf") || lower.ends_with(".glb") {
            return Format::Gltf;
        }
        if lower.ends_with(".pbrt") {
            return Format::Pbrt;
        }
        if lower.ends_with(".xml") {
            return Format::Mitsuba;
        }
        if lower.ends_with(".json") {
            return Format::Json;
        }
        let head = String::from_utf8_lossy(&text[..text.len().min(4096)]);
        let word = head
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !l.starts_with('#'))
            .and_then(|l| l.split_whitespace().next())
            .unwrap_or("");
        if pbrt::is_directive(word) {
            Format::Pbrt
        } else {
            Format::Json
        }
    }
}

/// Whether the JSON `text` is an object with a top-level `"asset"` member (every glTF file has
/// one; raytree's scene JSON refuses unknown members, so never has). Invalid JSON is not.
fn has_asset(text: &[u8]) -> bool {
    #[derive(serde::Deserialize)]
    struct Probe {
        asset: Option<serde::de::IgnoredAny>,
    }
    serde_json::from_slice::<Probe>(text).is_ok_and(|p| p.asset.is_some())
}

/// Convert `bytes` of `file` (pbrt, Mitsuba or glTF, per [`Format::detect`]) with `defines`
/// (Mitsuba `-D name=value`; ignored by pbrt). JSON is not converted here: it is already
/// raytree's.
///
/// # Errors
/// Malformed or unsupported input, with its position.
pub fn convert(
    format: Format,
    file: &str,
    bytes: &[u8],
    defines: &[(String, String)],
    resolver: &mut dyn Resolver,
) -> Result<Converted, FormatError> {
    match format {
        Format::Pbrt => pbrt::convert(file, bytes, resolver, Limits::default()),
        Format::Mitsuba => mitsuba::convert(file, bytes, defines, resolver, Limits::default()),
        Format::Gltf => self::gltf::convert(file, bytes, resolver, Limits::default()),
        Format::Json => Err(FormatError {
            file: file.to_string(),
            line: 0,
            column: 0,
            message: "raytree JSON needs no conversion".into(),
        }),
    }
}

/// `bytes` as UTF-8 text (a byte-order mark dropped), or an error at the first bad byte.
pub(crate) fn text<'a>(file: &str, bytes: &'a [u8]) -> Result<&'a str, FormatError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let (line, column) = crate::formats::line_col(bytes, e.valid_up_to());
        FormatError {
            file: file.to_string(),
            line,
            column,
            message: "invalid UTF-8".into(),
        }
    })
}

/// 1-based line and column (in characters) of byte `offset` of `bytes`.
pub(crate) fn line_col(bytes: &[u8], offset: usize) -> (usize, usize) {
    let before = &bytes[..offset.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = String::from_utf8_lossy(&before[start..]).chars().count() + 1;
    (line, column)
}

/// Join `name` to the directory of `base` (both as written in scenes, `/`-separated); an
/// absolute `name` stays as it is.
#[must_use]
pub fn relative_to(base: &str, name: &str) -> String {
    if name.starts_with('/') {
        return name.to_string();
    }
    match base.rfind('/') {
        Some(i) => format!("{}/{name}", &base[..i]),
        None => name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_by_content_then_extension() {
        assert_eq!(Format::detect("a.pbrt", b"  {\"camera\": 1}"), Format::Json);
        assert_eq!(Format::detect("a.json", b"<scene/>"), Format::Mitsuba);
        assert_eq!(Format::detect("a.pbrt", b"# c\nLookAt 0 0 0"), Format::Pbrt);
        assert_eq!(
            Format::detect("scene", b"# c\n\nWorldBegin\n"),
            Format::Pbrt
        );
        assert_eq!(Format::detect("scene.txt", b"hello"), Format::Json);
        assert_eq!(Format::detect("a.xml", b""), Format::Mitsuba);
        assert_eq!(Format::detect("a.gltf", b"{}"), Format::Gltf);
        assert_eq!(
            Format::detect("scene.json", b" {\"asset\": {\"version\": \"2.0\"}}"),
            Format::Gltf
        );
        assert_eq!(Format::detect("x.bin", b"glTF\x02\0\0\0"), Format::Gltf);
        assert_eq!(Format::detect("a.glb", b""), Format::Gltf);
        assert_eq!(Format::detect("a.json", b"{\"camera\": {}}"), Format::Json);
    }

    #[test]
    fn relative_names_and_positions() {
        assert_eq!(relative_to("dir/a.pbrt", "m.ply"), "dir/m.ply");
        assert_eq!(relative_to("a.pbrt", "m.ply"), "m.ply");
        assert_eq!(relative_to("dir/a.pbrt", "/abs/m.ply"), "/abs/m.ply");
        assert_eq!(line_col(b"ab\ncd", 4), (2, 2));
        let e = text("f", b"ok\n\xff").unwrap_err();
        assert_eq!((e.line, e.column), (2, 1));
    }
}
