//! pbrt-v4 scene files (the subset in `docs/scenes.md`): a tokenizer, typed parameter lists,
//! and an interpreter of the directives that keeps pbrt's graphics state (current
//! transformation, attribute stack, named materials, coordinate systems, object instances).
//!
//! Conventions (pbrt-v4 book and `docs/fileformat.md` of pbrt-v4): `Transform` takes 16 numbers
//! in column-major order and replaces the current matrix, `ConcatTransform` multiplies it; before
//! `WorldBegin` the current matrix is camera-from-world; camera space is left-handed with +x
//! image-right, +y image-up, +z forward.

mod get;
pub mod lex;
pub mod params;
mod scene;
mod shapes;

use crate::formats::{Converted, FormatError, Limits, Resolver};

/// Every directive of pbrt-v4's format (recognised; not all are supported).
pub const DIRECTIVES: [&str; 38] = [
    "Accelerator",
    "ActiveTransform",
    "AreaLightSource",
    "Attribute",
    "AttributeBegin",
    "AttributeEnd",
    "Camera",
    "ColorSpace",
    "ConcatTransform",
    "CoordinateSystem",
    "CoordSysTransform",
    "Film",
    "Identity",
    "Import",
    "Include",
    "Integrator",
    "LightSource",
    "LookAt",
    "MakeNamedMaterial",
    "MakeNamedMedium",
    "Material",
    "MediumInterface",
    "NamedMaterial",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Option",
    "PixelFilter",
    "ReverseOrientation",
    "Rotate",
    "Sampler",
    "Scale",
    "Shape",
    "Texture",
    "Transform",
    "TransformBegin",
    "TransformEnd",
    "Translate",
];

/// Whether `w` is a pbrt directive name (`WorldBegin` too).
#[must_use]
pub fn is_directive(w: &str) -> bool {
    w == "WorldBegin" || w == "WorldEnd" || w == "TransformTimes" || DIRECTIVES.contains(&w)
}

/// Convert the pbrt-v4 scene `bytes` of `file`, reading included files and meshes through
/// `resolver` (names relative to the including file's directory).
///
/// # Errors
/// Malformed or unsupported input, with file, line and column.
pub fn convert(
    file: &str,
    bytes: &[u8],
    resolver: &mut dyn Resolver,
    limits: Limits,
) -> Result<Converted, FormatError> {
    let mut st = scene::State::new(resolver, limits);
    st.run_file(file, bytes, 0)?;
    st.finish(file)
}

#[cfg(test)]
mod tests;
