//! Mitsuba 3 XML scenes (the subset in `docs/scenes.md`), and the version 0.x/2.x spellings
//! Mitsuba's own upgrade accepts (`toWorld`, `intIOR`, `<lookAt>`: camelCase names become
//! snake_case when `<scene version>` is below 3).
//!
//! The XML is read into an owned tree first: `<include>` files are spliced in, `$name` is
//! replaced from `<default>` and the caller's `-D name=value`, and every `id` is indexed, so a
//! `<ref>` may point forward. Conventions: Mitsuba 3 documentation ("Scene XML file format",
//! plugin reference); matrices are written row-major; transforms apply in the order written.

mod objects;
mod props;
mod tree;

use crate::formats::{Converted, FormatError, Limits, Resolver};

pub use tree::El;

/// Convert the Mitsuba scene `bytes` of `file`, reading includes and meshes through `resolver`.
///
/// # Errors
/// Malformed or unsupported input, with file, line:column and the element.
pub fn convert(
    file: &str,
    bytes: &[u8],
    defines: &[(String, String)],
    resolver: &mut dyn Resolver,
    limits: Limits,
) -> Result<Converted, FormatError> {
    let mut reader = tree::Reader::new(resolver, limits, defines);
    let root = reader.read_root(file, bytes)?;
    let mut st = objects::State::new(reader, limits);
    st.scene(&root)?;
    st.finish(file)
}

#[cfg(test)]
mod tests;
