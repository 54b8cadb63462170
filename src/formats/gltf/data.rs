//! Buffers, buffer views, accessors and image bytes, read strictly: every offset, stride,
//! length and count is checked (in 64-bit arithmetic that cannot overflow) against the bytes
//! that are there before anything is read or allocated, so a file that lies about its sizes is
//! an error naming the accessor, view or buffer, never a panic or an out-of-bounds read.

use super::{data_uri, err, uri_path};
use crate::formats::{FormatError, Limits, Resolver, relative_to};
use ::gltf::json::Root;
use ::gltf::json::accessor::{ComponentType, Type};
use ::gltf::json::validation::Checked;

/// What an accessor element is read into: `DIMS` components, each set from its decoded value.
pub trait Elem: Copy + Default {
    /// Components per element.
    const DIMS: usize;
    /// Set component `c` to `v`.
    fn set(&mut self, c: usize, v: f64);
    /// Whether every component is finite.
    fn finite(&self) -> bool;
}

impl Elem for glam::DVec3 {
    const DIMS: usize = 3;
    fn set(&mut self, c: usize, v: f64) {
        self[c] = v;
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

/// An unsigned index (the accessor's type is checked to be an unsigned integer, so every
/// value is a whole number below 2^32).
impl Elem for u32 {
    const DIMS: usize = 1;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    fn set(&mut self, _: usize, v: f64) {
        *self = v as u32;
    }
    fn finite(&self) -> bool {
        true
    }
}

/// A loaded buffer: the GLB `BIN` chunk in place, or bytes read or decoded.
enum Buf<'a> {
    Bin(&'a [u8]),
    Owned(Vec<u8>),
}

impl Buf<'_> {
    fn bytes(&self) -> &[u8] {
        match self {
            Buf::Bin(b) => b,
            Buf::Owned(v) => v,
        }
    }
}

/// What an accessor's elements are, checked against their use: shared by its dense part and
/// its sparse substitutions.
struct Layout {
    /// `accessors[i]`, for messages.
    path: String,
    /// The type of each number.
    ct: ComponentType,
    /// Numbers per element.
    dims: usize,
    /// Integers mapped to [0, 1] or [-1, 1].
    normalized: bool,
    /// Elements.
    count: usize,
}

/// The file's binary data, loaded on first use.
pub struct Data<'a, 'r> {
    /// The scene file as named by the caller.
    pub file: String,
    /// The validated glTF JSON.
    pub root: &'a Root,
    bin: Option<&'a [u8]>,
    resolver: &'r mut dyn Resolver,
    limits: Limits,
    buffers: Vec<Option<Buf<'a>>>,
    files: usize,
    bytes: u64,
}

/// An accessor's element type, in words.
fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

/// One component of type `ct` from the start of `b` (little-endian), normalised to [0, 1] or
/// [-1, 1] when `normalized` (glTF 2.0 section 3.11).
fn component(ct: ComponentType, b: &[u8], normalized: bool) -> f64 {
    match ct {
        ComponentType::I8 => {
            let v = f64::from(b[0].cast_signed());
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        ComponentType::U8 => {
            let v = f64::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        ComponentType::I16 => {
            let v = f64::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        ComponentType::U16 => {
            let v = f64::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        ComponentType::U32 => {
            let v = f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            if normalized {
                v / f64::from(u32::MAX)
            } else {
                v
            }
        }
        ComponentType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
    }
}

impl<'a, 'r> Data<'a, 'r> {
    /// The data of `root` (from `file`), with the GLB `BIN` chunk if any.
    pub fn new(
        file: &str,
        root: &'a Root,
        bin: Option<&'a [u8]>,
        resolver: &'r mut dyn Resolver,
        limits: Limits,
    ) -> Self {
        Self {
            file: file.to_string(),
            root,
            bin,
            resolver,
            limits,
            buffers: (0..root.buffers.len()).map(|_| None).collect(),
            files: 0,
            bytes: 0,
        }
    }

    /// An error at `path`.
    pub fn err(&self, path: &str, message: impl std::fmt::Display) -> FormatError {
        err(&self.file, path, message)
    }

    /// Count `n` more bytes of binary data against the limit.
    fn count_bytes(&mut self, n: u64, path: &str) -> Result<(), FormatError> {
        self.bytes = self.bytes.saturating_add(n);
        if self.bytes > self.limits.bytes {
            return Err(self.err(
                path,
                format!(
                    "the scene's buffers and images exceed {} MiB (the limit)",
                    self.limits.bytes >> 20
                ),
            ));
        }
        Ok(())
    }

    /// The file `uri` (relative to the scene) through the resolver; `path` is the JSON path
    /// of the `uri`.
    fn read_uri(&mut self, uri: &str, path: &str) -> Result<Vec<u8>, FormatError> {
        if let Some(d) = data_uri(uri) {
            return d.map_err(|e| self.err(path, e));
        }
        let Some(name) = uri_path(uri) else {
            return Err(self.err(
                path,
                format!(
                    "URI {:?}: only relative file names and data: URIs are read",
                    truncate(uri)
                ),
            ));
        };
        self.files += 1;
        if self.files > self.limits.files {
            return Err(self.err(
                path,
                format!("more than {} files read (the limit)", self.limits.files),
            ));
        }
        let full = relative_to(&self.file, &name);
        self.resolver.read(&full).map_err(|e| self.err(path, e))
    }

    /// The bytes of buffer `i` (at least its `byteLength`).
    ///
    /// # Errors
    /// A missing or unreadable source, or fewer bytes than `byteLength`.
    pub fn buffer(&mut self, i: usize) -> Result<&[u8], FormatError> {
        let path = format!("buffers[{i}]");
        let Some(b) = self.root.buffers.get(i) else {
            return Err(self.err(&path, "no such buffer"));
        };
        if self.buffers[i].is_none() {
            let want = b.byte_length.0;
            let (buf, source) = match &b.uri {
                None if i == 0 && self.bin.is_some() => {
                    (Buf::Bin(self.bin.unwrap_or_default()), "the GLB BIN chunk")
                }
                None if i == 0 => {
                    return Err(self.err(
                        &path,
                        "no uri, and the file has no GLB BIN chunk for it to refer to",
                    ));
                }
                None => {
                    return Err(self.err(
                        &path,
                        "no uri (only buffers[0] may refer to the GLB BIN chunk)",
                    ));
                }
                Some(uri) => {
                    let src = if uri.starts_with("data:") {
                        "its data URI"
                    } else {
                        "its file"
                    };
                    let v = self.read_uri(uri, &format!("{path}.uri"))?;
                    (Buf::Owned(v), src)
                }
            };
            let have = buf.bytes().len() as u64;
            if have < want {
                return Err(self.err(
                    &path,
                    format!("byteLength is {want} but {source} holds {have} bytes"),
                ));
            }
            self.count_bytes(want, &path)?;
            self.buffers[i] = Some(buf);
        }
        Ok(self.buffers[i].as_ref().map_or(&[][..], Buf::bytes))
    }

    /// The bytes of buffer view `v` and its stride (if given).
    ///
    /// # Errors
    /// A view that does not lie within its buffer.
    pub fn view(&mut self, v: usize) -> Result<(&[u8], Option<usize>), FormatError> {
        let path = format!("bufferViews[{v}]");
        let Some(view) = self.root.buffer_views.get(v) else {
            return Err(self.err(&path, "no such buffer view"));
        };
        let off = view.byte_offset.map_or(0, |o| o.0);
        let len = view.byte_length.0;
        let b = view.buffer.value();
        let blen = self.root.buffers.get(b).map_or(0, |x| x.byte_length.0);
        let end = off.checked_add(len).filter(|&e| e <= blen).ok_or_else(|| {
            self.err(
                &path,
                format!(
                    "bytes {off}..{} lie outside buffers[{b}] ({blen} bytes)",
                    u128::from(off) + u128::from(len)
                ),
            )
        })?;
        let stride = view.byte_stride.map(|s| s.0);
        let data = self.buffer(b)?;
        // `buffer` holds at least `blen >= end` bytes.
        let (off, end) = (off as usize, end as usize);
        Ok((&data[off..end], stride))
    }

    /// Accessor `index` as elements of `T::DIMS` numbers (`what` names its use in messages),
    /// decoded straight into `T` (no intermediate copy): floats as they are (every value must
    /// be finite), integers converted (normalised when the accessor says so), zeros where there
    /// is no buffer view, sparse substitutions applied. `unsigned_ints` requires an unsigned
    /// integer type (indices).
    ///
    /// # Errors
    /// A wrong type, a count above the vertex limit, offsets or strides outside the data,
    /// bad sparse indices, non-finite values.
    pub fn accessor<T: Elem>(
        &mut self,
        index: usize,
        what: &str,
        unsigned_ints: bool,
    ) -> Result<Vec<T>, FormatError> {
        let path = format!("accessors[{index}]");
        let root = self.root;
        let Some(a) = root.accessors.get(index) else {
            return Err(self.err(&path, "no such accessor"));
        };
        let layout = self.layout(a, path, T::DIMS, what, unsigned_ints)?;
        let mut out = vec![T::default(); layout.count];
        if let Some(v) = a.buffer_view {
            let off = a.byte_offset.map_or(0, |o| o.0);
            self.dense(v.value(), off, &layout, &mut out)?;
        }
        if let Some(s) = &a.sparse {
            self.sparse(s, &layout, &mut out)?;
        }
        if let Some(i) = out.iter().position(|x| !x.finite()) {
            return Err(self.err(
                &layout.path,
                format!("{what}: element {i} is not a finite number"),
            ));
        }
        Ok(out)
    }

    /// The layout of accessor `a` at `path`, checked: its type has `dims` numbers, its
    /// components are unsigned integers if `unsigned_ints`, its count is within the vertex
    /// limit (`what` names its use in messages).
    fn layout(
        &self,
        a: &::gltf::json::Accessor,
        path: String,
        dims: usize,
        what: &str,
        unsigned_ints: bool,
    ) -> Result<Layout, FormatError> {
        let Checked::Valid(ty) = a.type_ else {
            return Err(self.err(&format!("{path}.type"), "invalid type"));
        };
        if ty.multiplicity() != dims {
            let want = match dims {
                1 => "SCALAR",
                2 => "VEC2",
                3 => "VEC3",
                _ => "VEC4",
            };
            return Err(self.err(
                &path,
                format!("{what}: type {} where {want} is expected", type_name(ty)),
            ));
        }
        let Checked::Valid(gct) = a.component_type else {
            return Err(self.err(&format!("{path}.componentType"), "invalid component type"));
        };
        let ct = gct.0;
        if unsigned_ints
            && !matches!(
                ct,
                ComponentType::U8 | ComponentType::U16 | ComponentType::U32
            )
        {
            return Err(self.err(
                &format!("{path}.componentType"),
                format!("{what} must be unsigned bytes, shorts or ints, got {ct:?}"),
            ));
        }
        let count = a.count.0;
        if count > self.limits.vertices as u64 {
            return Err(self.err(
                &format!("{path}.count"),
                format!(
                    "{count} elements, more than the limit of {}",
                    self.limits.vertices
                ),
            ));
        }
        Ok(Layout {
            path,
            ct,
            dims,
            normalized: a.normalized && ct != ComponentType::F32,
            count: count as usize,
        })
    }

    /// Decode the elements of `layout` at byte `off` of buffer view `view` into `out`.
    fn dense<T: Elem>(
        &mut self,
        view: usize,
        off: u64,
        layout: &Layout,
        out: &mut [T],
    ) -> Result<(), FormatError> {
        let Layout {
            ref path,
            ct,
            dims,
            normalized,
            count,
        } = *layout;
        let csize = ct.size();
        let elem = csize * dims;
        let file = self.file.clone();
        let (bytes, stride) = self.view(view)?;
        let stride = stride.unwrap_or(elem);
        if stride < elem {
            return Err(err(
                &file,
                &format!("bufferViews[{view}].byteStride"),
                format!("{stride} is less than the {elem}-byte elements of {path}"),
            ));
        }
        if count > 0 {
            let need = u128::from(off) + (stride as u128) * (count as u128 - 1) + elem as u128;
            if need > bytes.len() as u128 {
                return Err(err(
                    &file,
                    path,
                    format!(
                        "{count} elements of {elem} bytes (stride {stride}, offset {off}) \
                         need {need} bytes of bufferViews[{view}], which has {}",
                        bytes.len()
                    ),
                ));
            }
        }
        let off = off as usize;
        for (k, e) in out.iter_mut().enumerate() {
            let base = off + k * stride;
            for c in 0..dims {
                let at = base + c * csize;
                e.set(c, component(ct, &bytes[at..at + csize], normalized));
            }
        }
        Ok(())
    }

    /// Apply the sparse substitutions `s` of the accessor of `layout` to `out`.
    fn sparse<T: Elem>(
        &mut self,
        s: &::gltf::json::accessor::sparse::Sparse,
        layout: &Layout,
        out: &mut [T],
    ) -> Result<(), FormatError> {
        let Layout {
            ref path,
            ct,
            dims,
            normalized,
            count,
        } = *layout;
        let n = s.count.0;
        if n > count as u64 {
            return Err(self.err(
                &format!("{path}.sparse.count"),
                format!("{n} substitutions in an accessor of {count} elements"),
            ));
        }
        let n = n as usize;
        let Checked::Valid(ict) = s.indices.component_type else {
            return Err(self.err(
                &format!("{path}.sparse.indices.componentType"),
                "invalid component type",
            ));
        };
        let ict = ict.0;
        let isize = ict.size();
        let indices = self.packed(
            s.indices.buffer_view.value(),
            s.indices.byte_offset.0,
            n * isize,
            &format!("{path}.sparse.indices"),
        )?;
        let elem = ct.size() * dims;
        let values = self.packed(
            s.values.buffer_view.value(),
            s.values.byte_offset.0,
            n * elem,
            &format!("{path}.sparse.values"),
        )?;
        let mut previous = None;
        for k in 0..n {
            let i = component(ict, &indices[k * isize..], false) as u64;
            if i >= count as u64 || previous.is_some_and(|p| i <= p) {
                return Err(self.err(
                    &format!("{path}.sparse.indices"),
                    format!(
                        "index {k} is {i}: sparse indices must increase strictly and be below \
                         the count {count}"
                    ),
                ));
            }
            previous = Some(i);
            for c in 0..dims {
                let at = k * elem + c * ct.size();
                out[i as usize].set(c, component(ct, &values[at..], normalized));
            }
        }
        Ok(())
    }

    /// `len` tightly packed bytes at `off` in buffer view `view` (sparse indices and values).
    fn packed(
        &mut self,
        view: usize,
        off: u64,
        len: usize,
        path: &str,
    ) -> Result<Vec<u8>, FormatError> {
        let file = self.file.clone();
        let (bytes, _) = self.view(view)?;
        if u128::from(off) + len as u128 > bytes.len() as u128 {
            return Err(err(
                &file,
                path,
                format!(
                    "{len} bytes at offset {off} of bufferViews[{view}], which has {}",
                    bytes.len()
                ),
            ));
        }
        Ok(bytes[off as usize..off as usize + len].to_vec())
    }

    /// The encoded bytes of image `i` (from its buffer view, data URI or file).
    ///
    /// # Errors
    /// Neither a buffer view nor a URI, or an unreadable source.
    pub fn image(&mut self, i: usize) -> Result<Vec<u8>, FormatError> {
        let path = format!("images[{i}]");
        let root = self.root;
        let Some(img) = root.images.get(i) else {
            return Err(self.err(&path, "no such image"));
        };
        let bytes = if let Some(v) = img.buffer_view {
            self.view(v.value())?.0.to_vec()
        } else if let Some(uri) = &img.uri {
            let b = self.read_uri(uri, &format!("{path}.uri"))?;
            self.count_bytes(b.len() as u64, &path)?;
            b
        } else {
            return Err(self.err(&path, "neither a bufferView nor a uri"));
        };
        Ok(bytes)
    }
}

/// At most 80 characters of `s` (for messages quoting a URI).
fn truncate(s: &str) -> String {
    if s.chars().count() > 80 {
        format!("{}...", s.chars().take(77).collect::<String>())
    } else {
        s.to_string()
    }
}
