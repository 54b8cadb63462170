//! A Wavefront OBJ reader for what a ray tracer needs: `v`, `vn` and `f` (triangles and
//! polygons, fan-triangulated; `v`, `v/vt`, `v//vn`, `v/vt/vn`; negative indices count back).
//! Every other statement (`vt`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, ...) is ignored.
//!
//! Parses text, not files (the library does no I/O); every error carries its 1-based line.
//! We do not use `tobj` here: its `LoadError` is a bare enum without a position, and it checks
//! face indices only after the whole file is read, so it cannot say which line is wrong.

use super::{Face, MeshData};
use glam::DVec3;
use std::fmt;

/// An OBJ file that cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct ObjError {
    /// 1-based line, 0 for the file as a whole.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ObjError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(f, "line {}: ", self.line)?;
        }
        f.write_str(&self.message)
    }
}

/// Parse OBJ text into positions, normals and triangles.
/// A leading UTF-8 byte-order mark is skipped (it would otherwise hide the first statement).
pub fn parse_obj(src: &str) -> Result<MeshData, ObjError> {
    let src = crate::input::strip_bom(src);
    let mut data = MeshData::default();
    let mut corners: Vec<(u32, Option<u32>)> = Vec::new();
    for (i, raw) in src.lines().enumerate() {
        let line = i + 1;
        let fail = |message: String| ObjError { line, message };
        let text = raw.split('#').next().unwrap_or("");
        let mut words = text.split_whitespace();
        match words.next() {
            Some("v") => data.positions.push(vector(&mut words, "v").map_err(fail)?),
            Some("vn") => data.normals.push(vector(&mut words, "vn").map_err(fail)?),
            Some("f") => {
                corners.clear();
                for w in words {
                    corners.push(corner(w, &data).map_err(fail)?);
                }
                if corners.len() < 3 {
                    return Err(fail(format!(
                        "a face needs at least 3 vertices, got {}",
                        corners.len()
                    )));
                }
                let all_normals = corners.iter().all(|c| c.1.is_some());
                for k in 1..corners.len() - 1 {
                    let tri = [corners[0], corners[k], corners[k + 1]];
                    data.faces.push(Face {
                        vertices: tri.map(|c| c.0),
                        normals: all_normals.then(|| tri.map(|c| c.1.unwrap_or(0))),
                    });
                }
            }
            _ => {}
        }
    }
    if data.faces.is_empty() {
        return Err(ObjError {
            line: 0,
            message: "no faces (`f` lines) in the file".into(),
        });
    }
    Ok(data)
}

fn vector<'a>(words: &mut impl Iterator<Item = &'a str>, what: &str) -> Result<DVec3, String> {
    let mut v = [0.0; 3];
    for (k, c) in v.iter_mut().enumerate() {
        let Some(w) = words.next() else {
            return Err(format!("`{what}` needs 3 numbers, got {k}"));
        };
        *c = number(w)?;
    }
    Ok(DVec3::from(v))
}

fn number(w: &str) -> Result<f64, String> {
    match w.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{w:?} is not a finite number")),
    }
}

/// One face corner `v[/vt][/vn]`: 0-based position index and optional normal index.
fn corner(w: &str, data: &MeshData) -> Result<(u32, Option<u32>), String> {
    let mut parts = w.split('/');
    let v = index(
        parts.next().unwrap_or(""),
        data.positions.len(),
        "vertex",
        w,
    )?;
    let _texcoord = parts.next();
    let n = match parts.next() {
        Some(s) if !s.is_empty() => Some(index(s, data.normals.len(), "normal", w)?),
        _ => None,
    };
    if parts.next().is_some() {
        return Err(format!("face corner {w:?} has more than 3 parts"));
    }
    Ok((v, n))
}

/// Resolve a 1-based (or negative, relative) OBJ index against `count` items defined so far.
fn index(s: &str, count: usize, what: &str, corner: &str) -> Result<u32, String> {
    let Ok(i) = s.parse::<i64>() else {
        return Err(format!(
            "face corner {corner:?}: {s:?} is not a {what} index"
        ));
    };
    let resolved = if i > 0 {
        i - 1
    } else if i < 0 {
        count as i64 + i
    } else {
        return Err(format!(
            "face corner {corner:?}: {what} index 0 (OBJ counts from 1)"
        ));
    };
    if resolved < 0 || resolved >= count as i64 {
        return Err(format!(
            "face corner {corner:?}: {what} index {i} is out of range (only {count} defined above this line)"
        ));
    }
    u32::try_from(resolved).map_err(|_| format!("{what} index {i} is too large"))
}

/// [`parse_obj`] for a scene's mesh `file` (the name as the scene writes it), given what
/// reading it from `resolved` (the name joined to the scene's directory) returned. Messages
/// name the file as written, with the line for bad contents, and say where it was looked for
/// when that differs. The library does no I/O: the CLI and the inspector read, this formats.
///
/// # Errors
/// The message for a failed read or bad contents.
pub fn parse_obj_read(
    file: &str,
    resolved: &std::path::Path,
    read: std::io::Result<String>,
) -> Result<MeshData, String> {
    let text = read.map_err(|e| {
        if resolved == std::path::Path::new(file) {
            format!("cannot read {file}: {e}")
        } else {
            format!(
                "cannot read {file} (looked for {}): {e}",
                resolved.display()
            )
        }
    })?;
    parse_obj(&text).map_err(|e| match e.line {
        0 => format!("{file}: {}", e.message),
        line => format!("{file}:{line}: {}", e.message),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_with_normals_and_negative_indices() {
        let src = "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
                   f -4//1 -3//1 -2//1 -1//1\no x\nf 1/1 2/1 3/1\n";
        let d = parse_obj(src).unwrap();
        assert_eq!(d.positions.len(), 4);
        assert_eq!(d.faces.len(), 3);
        assert_eq!(d.faces[0].vertices, [0, 1, 2]);
        assert_eq!(d.faces[1].vertices, [0, 2, 3]);
        assert_eq!(d.faces[0].normals, Some([0, 0, 0]));
        assert_eq!(d.faces[2].normals, None);
    }

    #[test]
    fn a_byte_order_mark_keeps_the_first_vertex() {
        let plain = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 2 3 4\n";
        let with_bom = format!("\u{feff}{plain}");
        assert_eq!(parse_obj(&with_bom).unwrap(), parse_obj(plain).unwrap());
        assert_eq!(parse_obj(&with_bom).unwrap().positions.len(), 4);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n").unwrap_err();
        assert_eq!(e.line, 5);
        assert!(
            e.message
                .contains("vertex index 4 is out of range (only 3 defined above this line)"),
            "{e}"
        );
        assert!(e.to_string().starts_with("line 5: "), "{e}");
        let e = parse_obj("v 0 0 zero\n").unwrap_err();
        assert_eq!(e.line, 1);
        assert!(e.message.contains("\"zero\""), "{e}");
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n").unwrap_err();
        assert_eq!((e.line, e.message.contains("at least 3")), (4, true));
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\n").unwrap_err();
        assert!(e.message.contains("normal index 2"), "{e}");
        assert_eq!(parse_obj("v 0 0 0\nf 0 1 1\n").unwrap_err().line, 2);
        assert_eq!(parse_obj("v 1 2 3\n").unwrap_err().line, 0);
        assert_eq!(parse_obj("v 1 2 nan\n").unwrap_err().line, 1);
    }

    #[test]
    fn scene_mesh_errors_name_the_file_as_written() {
        use std::io::{Error, ErrorKind};
        use std::path::Path;
        let missing = || Err(Error::new(ErrorKind::NotFound, "not found"));
        let e = parse_obj_read("m.obj", Path::new("/scenes/m.obj"), missing()).unwrap_err();
        assert_eq!(e, "cannot read m.obj (looked for /scenes/m.obj): not found");
        let e = parse_obj_read("m.obj", Path::new("m.obj"), missing()).unwrap_err();
        assert_eq!(e, "cannot read m.obj: not found");
        let bad = Ok("v 0 0 0\nv 1 x 0\n".to_string());
        let e = parse_obj_read("sub/m.obj", Path::new("/s/sub/m.obj"), bad).unwrap_err();
        assert!(e.starts_with("sub/m.obj:2: "), "{e}");
        let empty = Ok("v 1 2 3\n".to_string());
        let e = parse_obj_read("e.obj", Path::new("/s/e.obj"), empty).unwrap_err();
        assert!(e.starts_with("e.obj: ") && !e.contains("/s/"), "{e}");
        let good = Ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_string());
        assert_eq!(
            parse_obj_read("t.obj", Path::new("t.obj"), good)
                .unwrap()
                .faces
                .len(),
            1
        );
    }
}
