//! PLY meshes (Turk 1994; the format pbrt-v4's `plymesh` and Mitsuba's `ply` read): ASCII and
//! binary (little- and big-endian), vertex positions, optional normals, faces as index lists
//! (polygons fan-triangulated). Other properties and elements are skipped. Every count in the
//! header is checked against the bytes that follow before anything is allocated, so a header
//! that lies about its size is an error, not a huge allocation.

use glam::DVec3;

/// A mesh as read from a PLY file (object space).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex normals, when the file has `nx ny nz`.
    pub normals: Option<Vec<DVec3>>,
    /// Triangles (0-based vertex indices, in range).
    pub triangles: Vec<[u32; 3]>,
    /// Whether the file had texture coordinates (not used by raytree).
    pub has_uv: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(Scalar, String),
    List(Scalar, Scalar, String),
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Parse a PLY file; `max_vertices` bounds the vertex and face counts.
///
/// # Errors
/// A message naming the header line or the element that is malformed or short.
pub fn parse(bytes: &[u8], max_vertices: usize) -> Result<PlyMesh, String> {
    let (encoding, elements, body) = header(bytes)?;
    for e in &elements {
        if e.count > max_vertices {
            return Err(format!(
                "element {} has {} entries, more than the limit of {max_vertices}",
                e.name, e.count
            ));
        }
    }
    let mut reader = match encoding {
        Encoding::Ascii => Reader::Ascii(
            std::str::from_utf8(body)
                .map_err(|_| "the ASCII body is not UTF-8".to_string())?
                .split_ascii_whitespace(),
        ),
        Encoding::Little | Encoding::Big => Reader::Binary {
            bytes: body,
            at: 0,
            big: encoding == Encoding::Big,
        },
    };
    let mut mesh = PlyMesh::default();
    for e in &elements {
        // Each entry needs at least this many bytes (or tokens): check before allocating.
        let min: usize = e
            .props
            .iter()
            .map(|p| match p {
                Property::Scalar(s, _) => s.size(),
                Property::List(c, _, _) => c.size(),
            })
            .sum();
        let need = match reader {
            Reader::Ascii(_) => e.count.saturating_mul(e.props.len()),
            Reader::Binary { .. } => e.count.saturating_mul(min),
        };
        if need > body.len() {
            return Err(format!(
                "the header promises {} {} entries, more than the file's {} bytes of data hold",
                e.count,
                e.name,
                body.len()
            ));
        }
        match e.name.as_str() {
            "vertex" => vertices(e, &mut reader, &mut mesh)?,
            "face" => faces(e, &mut reader, &mut mesh, max_vertices)?,
            _ => skip(e, &mut reader)?,
        }
    }
    let n = mesh.positions.len();
    if let Some(bad) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= n) {
        return Err(format!("face index {bad} out of range ({n} vertices)"));
    }
    Ok(mesh)
}

fn header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, &[u8]), String> {
    let end = find(bytes, b"end_header").ok_or("no end_header line in the first 64 KiB")?;
    let mut body_at = end + b"end_header".len();
    if bytes.get(body_at) == Some(&b'\r') {
        body_at += 1;
    }
    if bytes.get(body_at) == Some(&b'\n') {
        body_at += 1;
    }
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not ASCII")?;
    let mut lines = text.lines().enumerate();
    if lines.next().map(|(_, l)| l.trim()) != Some("ply") {
        return Err("not a PLY file (the first line is not \"ply\")".into());
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (i, line) in lines {
        let at = |m: String| format!("header line {}: {m}", i + 1);
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _] => {
                encoding = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    _ => return Err(at(format!("unknown format {f:?}"))),
                });
            }
            ["element", name, count] => elements.push(Element {
                name: (*name).to_string(),
                count: count
                    .parse()
                    .map_err(|_| at(format!("bad element count {count:?}")))?,
                props: Vec::new(),
            }),
            ["property", "list", c, t, name] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| at("property before element".into()))?;
                let (Some(c), Some(t)) = (Scalar::parse(c), Scalar::parse(t)) else {
                    return Err(at(format!("unknown list types {c:?} {t:?}")));
                };
                e.props.push(Property::List(c, t, (*name).to_string()));
            }
            ["property", t, name] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| at("property before element".into()))?;
                let t = Scalar::parse(t).ok_or_else(|| at(format!("unknown type {t:?}")))?;
                e.props.push(Property::Scalar(t, (*name).to_string()));
            }
            _ => return Err(at(format!("cannot read {:?}", line.trim()))),
        }
    }
    let encoding = encoding.ok_or("the header has no format line")?;
    Ok((encoding, elements, &bytes[body_at.min(bytes.len())..]))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    let hay = &hay[..hay.len().min(64 << 10)];
    hay.windows(needle.len()).position(|w| w == needle)
}

enum Reader<'a> {
    Ascii(std::str::SplitAsciiWhitespace<'a>),
    Binary {
        bytes: &'a [u8],
        at: usize,
        big: bool,
    },
}

impl Reader<'_> {
    /// One value of entry `i` of element `what` (messages are formatted only on failure).
    fn read(&mut self, t: Scalar, what: (&str, usize)) -> Result<f64, String> {
        let (name, i) = what;
        match self {
            Reader::Ascii(words) => {
                let w = words
                    .next()
                    .ok_or_else(|| format!("the data ends inside {name} {i}"))?;
                w.parse::<f64>()
                    .map_err(|_| format!("{name} {i}: {w:?} is not a number"))
            }
            Reader::Binary { bytes, at, big } => {
                let n = t.size();
                let b = bytes
                    .get(*at..*at + n)
                    .ok_or_else(|| format!("the data ends inside {name} {i} (byte {at})"))?;
                *at += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(b);
                if *big {
                    a[..n].reverse();
                }
                Ok(match t {
                    Scalar::I8 => f64::from(a[0] as i8),
                    Scalar::U8 => f64::from(a[0]),
                    Scalar::I16 => f64::from(i16::from_le_bytes([a[0], a[1]])),
                    Scalar::U16 => f64::from(u16::from_le_bytes([a[0], a[1]])),
                    Scalar::I32 => f64::from(i32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::U32 => f64::from(u32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::F32 => f64::from(f32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::F64 => f64::from_le_bytes(a),
                })
            }
        }
    }
}

fn vertices(e: &Element, r: &mut Reader, mesh: &mut PlyMesh) -> Result<(), String> {
    let index = |n: &str| {
        e.props
            .iter()
            .position(|p| matches!(p, Property::Scalar(_, m) if m == n))
    };
    let (Some(x), Some(y), Some(z)) = (index("x"), index("y"), index("z")) else {
        return Err("the vertex element lacks x, y or z".into());
    };
    let normal = match (index("nx"), index("ny"), index("nz")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        _ => None,
    };
    mesh.has_uv = ["u", "s", "texture_u"].iter().any(|n| index(n).is_some());
    mesh.positions.reserve(e.count);
    let mut normals = Vec::with_capacity(if normal.is_some() { e.count } else { 0 });
    let mut values = vec![0.0; e.props.len()];
    for i in 0..e.count {
        for (k, p) in e.props.iter().enumerate() {
            values[k] = match p {
                Property::Scalar(t, _) => r.read(*t, ("vertex", i))?,
                Property::List(c, t, _) => {
                    let n = r.read(*c, ("vertex", i))?;
                    for _ in 0..list_len(n, ("vertex", i))? {
                        r.read(*t, ("vertex", i))?;
                    }
                    0.0
                }
            };
        }
        let p = DVec3::new(values[x], values[y], values[z]);
        if !p.is_finite() {
            return Err(format!("vertex {i} is not finite"));
        }
        mesh.positions.push(p);
        if let Some([a, b, c]) = normal {
            normals.push(DVec3::new(values[a], values[b], values[c]));
        }
    }
    if normal.is_some() {
        mesh.normals = Some(normals);
    }
    Ok(())
}

fn list_len(n: f64, (name, i): (&str, usize)) -> Result<usize, String> {
    if n.fract() != 0.0 || !(0.0..=1024.0).contains(&n) {
        return Err(format!(
            "{name} {i}: list length {n} is not a whole number in 0..=1024"
        ));
    }
    Ok(n as usize)
}

fn faces(e: &Element, r: &mut Reader, mesh: &mut PlyMesh, max: usize) -> Result<(), String> {
    let is_index = |n: &str| n == "vertex_indices" || n == "vertex_index";
    if !e
        .props
        .iter()
        .any(|p| matches!(p, Property::List(_, _, n) if is_index(n)))
    {
        return Err("the face element has no vertex_indices list".into());
    }
    mesh.triangles.reserve(e.count);
    let mut poly: Vec<u32> = Vec::new();
    for i in 0..e.count {
        let what = ("face", i);
        for p in &e.props {
            match p {
                Property::Scalar(t, _) => {
                    r.read(*t, what)?;
                }
                Property::List(c, t, name) => {
                    let n = list_len(r.read(*c, what)?, what)?;
                    poly.clear();
                    for _ in 0..n {
                        let v = r.read(*t, what)?;
                        if is_index(name) {
                            if v < 0.0 || v.fract() != 0.0 || v > f64::from(u32::MAX) {
                                return Err(format!("face {i}: bad vertex index {v}"));
                            }
                            poly.push(v as u32);
                        }
                    }
                    if is_index(name) {
                        if n < 3 {
                            return Err(format!("face {i} has {n} vertices, fewer than 3"));
                        }
                        for k in 1..poly.len() - 1 {
                            mesh.triangles.push([poly[0], poly[k], poly[k + 1]]);
                        }
                        if mesh.triangles.len() > max {
                            return Err(format!("more than {max} triangles"));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

fn skip(e: &Element, r: &mut Reader) -> Result<(), String> {
    for i in 0..e.count {
        let what = (e.name.as_str(), i);
        for p in &e.props {
            match p {
                Property::Scalar(t, _) => {
                    r.read(*t, what)?;
                }
                Property::List(c, t, _) => {
                    for _ in 0..list_len(r.read(*c, what)?, what)? {
                        r.read(*t, what)?;
                    }
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment quad\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\nproperty float nx\n\
        property float ny\nproperty float nz\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n\
        0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n";

    /// The same quad, binary little-endian, without normals, with a skipped `material` element.
    fn binary() -> Vec<u8> {
        let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\n\
            property float x\nproperty float y\nproperty float z\nelement face 1\n\
            property list uchar uint vertex_indices\nelement material 1\nproperty uchar r\n\
            end_header\n"
            .to_vec();
        for p in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.push(4);
        for i in 0u32..4 {
            b.extend_from_slice(&i.to_le_bytes());
        }
        b.push(7);
        b
    }

    #[test]
    fn ascii_and_binary_read_the_same_quad() {
        let a = parse(ASCII.as_bytes(), 100).unwrap();
        assert_eq!(a.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(a.normals.as_ref().unwrap()[2], DVec3::Z);
        let b = parse(&binary(), 100).unwrap();
        assert_eq!(b.positions, a.positions);
        assert_eq!(b.triangles, a.triangles);
        assert!(b.normals.is_none());
    }

    #[test]
    fn lying_headers_and_bad_indices_are_errors() {
        let lie = ASCII.replace("element vertex 4", "element vertex 4000000000");
        let e = parse(lie.as_bytes(), usize::MAX).unwrap_err();
        assert!(e.contains("more than the file"), "{e}");
        let e = parse(lie.as_bytes(), 1000).unwrap_err();
        assert!(e.contains("limit"), "{e}");
        let mut short = binary();
        short.truncate(short.len() - 6);
        let e = parse(&short, 100).unwrap_err();
        assert!(e.contains("ends inside face 0"), "{e}");
        let bad = ASCII.replace("4 0 1 2 3", "3 0 1 9");
        assert!(
            parse(bad.as_bytes(), 100)
                .unwrap_err()
                .contains("out of range")
        );
        assert!(parse(b"plx\n", 100).is_err());
        let e = parse(ASCII.replace("float nz", "flot nz").as_bytes(), 100).unwrap_err();
        assert!(e.starts_with("header line 10"), "{e}");
    }
}
