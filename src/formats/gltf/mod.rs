//! glTF 2.0 scenes (`.gltf` JSON with external or data-URI buffers, `.glb` binary containers;
//! the subset in `docs/scenes.md`).
//!
//! The JSON is deserialised and its indices validated by the `gltf` crate (`gltf::json`, no
//! default features: it reads no file and decodes no image). Everything else is done here,
//! strictly: the GLB container, buffers (the GLB `BIN` chunk, `data:` URIs, and files read
//! through the caller's [`Resolver`]), accessors with every offset, stride and count checked
//! against the bytes there are (the crate's own accessor reader asserts and can panic on
//! hostile input), the node hierarchy (a tree, walked without recursion), and the mapping of
//! cameras, lights and materials onto raytree's (`material`).
//!
//! Locations: glTF has no useful line numbers, so every note and error names the JSON path of
//! what it concerns (`materials[2].pbrMetallicRoughness.baseColorTexture`), with line 0;
//! syntax errors in the JSON carry its line and column.
//!
//! Conventions (glTF 2.0 specification, section 3): right-handed, +Y up, metres; a camera looks
//! along its local -Z with +Y up and +X right; node matrices are column-major; a triangle's
//! front is counter-clockwise, and a node whose global transform has a negative determinant
//! flips it (section 3.7.2.1), which `build::Builder` does for every mesh.

mod data;
mod material;
mod scene;

use crate::formats::{Converted, FormatError, Limits, Resolver};

/// The extensions this front-end reads (a file that requires any other is refused).
pub const SUPPORTED_EXTENSIONS: [&str; 7] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_unlit",
    "KHR_mesh_quantization",
];

/// Whether `bytes` is a binary glTF container (starts with the magic `glTF`).
#[must_use]
pub fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(b"glTF")
}

/// An error at JSON path `path` of `file` (line 0: the path is the location).
pub(crate) fn err(file: &str, path: &str, message: impl std::fmt::Display) -> FormatError {
    FormatError {
        file: file.to_string(),
        line: 0,
        column: 0,
        message: if path.is_empty() {
            message.to_string()
        } else {
            format!("{path}: {message}")
        },
    }
}

/// Convert the glTF scene `bytes` of `file` (JSON or GLB), reading external buffers and images
/// through `resolver` (names relative to `file`).
///
/// # Errors
/// Malformed or unsupported input, naming the JSON path.
pub fn convert(
    file: &str,
    bytes: &[u8],
    resolver: &mut dyn Resolver,
    limits: Limits,
) -> Result<Converted, FormatError> {
    let (json, bin) = if is_glb(bytes) {
        split_glb(file, bytes)?
    } else {
        (bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes), None)
    };
    let mut root = ::gltf::json::Root::from_slice(json).map_err(|e| FormatError {
        file: file.to_string(),
        line: e.line(),
        column: e.column(),
        message: format!("not glTF JSON: {}", strip_position(&e.to_string())),
    })?;
    check_version(file, &root)?;
    // Required extensions are checked here, with a message naming them; the crate's own check
    // knows only the extensions it was built with.
    for (i, name) in root.extensions_required.iter().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&name.as_str()) {
            return Err(err(
                file,
                &format!("extensionsRequired[{i}]"),
                format!(
                    "the scene requires {name}, which raytree does not read (it reads {})",
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    root.extensions_required.clear();
    // The crate's validation indexes `accessors` by the POSITION attribute before it checks
    // the index: check every attribute's index first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (j, p) in mesh.primitives.iter().enumerate() {
            for a in p.attributes.values() {
                if a.value() >= root.accessors.len() {
                    return Err(err(
                        file,
                        &format!("meshes[{m}].primitives[{j}].attributes"),
                        format!(
                            "accessors[{}] does not exist (the file has {})",
                            a.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    let doc = ::gltf::Document::from_json(root).map_err(|e| match e {
        ::gltf::Error::Validation(list) => {
            let (path, why) = &list[0];
            let more = if list.len() > 1 {
                format!(" (and {} more)", list.len() - 1)
            } else {
                String::new()
            };
            err(file, &path.to_string(), format!("{why}{more}"))
        }
        other => err(file, "", other),
    })?;
    let data = data::Data::new(file, doc.as_json(), bin, resolver, limits);
    scene::State::new(data, limits).run()
}

/// `asset.version` must be 2.x (and `minVersion`, when given, at most 2.0).
fn check_version(file: &str, root: &::gltf::json::Root) -> Result<(), FormatError> {
    let major = |v: &str| v.split('.').next().and_then(|m| m.parse::<u32>().ok());
    if major(&root.asset.version) != Some(2) {
        return Err(err(
            file,
            "asset.version",
            format!(
                "glTF version {:?}: raytree reads glTF 2.x",
                root.asset.version
            ),
        ));
    }
    if let Some(min) = &root.asset.min_version
        && min != "2.0"
    {
        return Err(err(
            file,
            "asset.minVersion",
            format!("the file needs glTF {min:?}: raytree reads glTF 2.0"),
        ));
    }
    Ok(())
}

/// serde_json's message without its trailing " at line L column C" (the error has them).
fn strip_position(s: &str) -> &str {
    s.find(" at line ").map_or(s, |i| &s[..i])
}

/// The JSON chunk and the optional BIN chunk of a GLB container (glTF 2.0 section 4.4):
/// a 12-byte header (`glTF`, version 2, total length), then chunks of a 4-byte length, a
/// 4-byte type and the data, each padded to 4 bytes; the first is `JSON`, an optional `BIN\0`
/// follows, unknown chunk types are skipped.
fn split_glb<'a>(file: &str, b: &'a [u8]) -> Result<(&'a [u8], Option<&'a [u8]>), FormatError> {
    let u32_at = |o: usize| -> Option<u32> {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    };
    let bad = |m: String| err(file, "", format!("GLB container: {m}"));
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err(bad(format!(
            "{} bytes, shorter than its 12-byte header",
            b.len()
        )));
    };
    if version != 2 {
        return Err(bad(format!("version {version}: raytree reads version 2")));
    }
    let length = length as usize;
    if length > b.len() {
        return Err(bad(format!(
            "the header says {length} bytes, the file has {} (truncated?)",
            b.len()
        )));
    }
    // Bytes after the header's length are not part of the container.
    let b = &b[..length];
    let mut at = 12usize;
    let (mut json, mut bin) = (None, None);
    let mut k = 0;
    while at < b.len() {
        let (Some(len), Some(ty)) = (u32_at(at), b.get(at + 4..at + 8)) else {
            return Err(bad(format!("chunk {k} header at byte {at} is cut off")));
        };
        let len = len as usize;
        let start = at + 8;
        let Some(end) = start.checked_add(len).filter(|&e| e <= b.len()) else {
            return Err(bad(format!(
                "chunk {k} ({}) says {len} bytes, only {} follow (truncated?)",
                String::from_utf8_lossy(ty).escape_debug(),
                b.len() - start
            )));
        };
        let chunk = &b[start..end];
        match (k, ty) {
            (0, b"JSON") => json = Some(chunk),
            (0, _) => return Err(bad("the first chunk is not JSON".into())),
            (1, b"BIN\0") => bin = Some(chunk),
            (_, b"JSON" | b"BIN\0") => {
                return Err(bad(format!(
                    "chunk {k}: a second {} chunk",
                    String::from_utf8_lossy(ty).trim_end_matches('\0')
                )));
            }
            _ => {}
        }
        k += 1;
        // Chunks start on 4-byte boundaries.
        at = end.div_ceil(4) * 4;
    }
    let json = json.ok_or_else(|| bad("no JSON chunk".into()))?;
    // The JSON chunk is padded with spaces; a trailing NUL padding is tolerated as well.
    let json = json.strip_suffix(b"\0").unwrap_or(json);
    Ok((json, bin))
}

/// The bytes of a `data:` URI (`data:[<mediatype>][;base64],<data>`, RFC 2397); `None` if
/// `uri` is not one.
///
/// # Errors
/// A data URI that is not base64 or has bad base64.
pub(crate) fn data_uri(uri: &str) -> Option<Result<Vec<u8>, String>> {
    let rest = uri.strip_prefix("data:")?;
    let Some((head, payload)) = rest.split_once(',') else {
        return Some(Err("a data URI without ','".into()));
    };
    if !head.ends_with(";base64") {
        return Some(Err(
            "a data URI that is not base64 (glTF buffers are base64)".into(),
        ));
    }
    Some(base64(payload))
}

/// Standard base64 (RFC 4648, `+/`, `=` padding optional), whitespace refused.
fn base64(s: &str) -> Result<Vec<u8>, String> {
    let s = s.trim_end_matches('=');
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    for (i, c) in s.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => {
                return Err(format!(
                    "bad base64 character {:?} at offset {i}",
                    char::from(c)
                ));
            }
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("truncated base64 (a lone final character)".into());
    }
    Ok(out)
}

/// A relative URI reference decoded to the file name it names (`%20` -> space); `None` for
/// a URI with a scheme other than `file:` or with a bad escape.
pub(crate) fn uri_path(uri: &str) -> Option<String> {
    let uri = uri.strip_prefix("file://").unwrap_or(uri);
    if let Some(colon) = uri.find(':') {
        let scheme = &uri[..colon];
        if !scheme.is_empty()
            && !scheme.contains('/')
            && scheme.len() > 1
            && scheme
                .bytes()
                .all(|c| c.is_ascii_alphanumeric() || c == b'+')
        {
            return None;
        }
    }
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests;
