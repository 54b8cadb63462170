//! A standard partition of the path tracer's complete paths into light transport classes, by
//! the first non-specular vertex (Heckbert's regular-expression notation of light paths, 1990,
//! in OSL's alphabet): every path string ending in `L` or `B` matches exactly one class.

use crate::lpe::Lpe;

/// One light transport class.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Class {
    /// Short name (an AOV name).
    pub name: &'static str,
    /// The expression.
    pub lpe: &'static str,
    /// Whether the Whitted integrator renders this transport too (its recursion follows
    /// specular chains and lights diffuse and glossy surfaces directly).
    pub whitted: bool,
    /// What it is, in words.
    pub what: &'static str,
}

/// The partition: `S*` before the first diffuse or glossy vertex, then nothing more
/// (`emission`, `background`), the light or background (`direct`, `environment`), a specular
/// chain to it (`caustics`), or another diffuse or glossy vertex (`indirect`).
pub const CLASSES: [Class; 6] = [
    Class {
        name: "emission",
        lpe: "CS*L",
        whitted: true,
        what: "emitters seen directly or through mirrors and glass",
    },
    Class {
        name: "background",
        lpe: "CS*B",
        whitted: true,
        what: "the background seen directly or through mirrors and glass",
    },
    Class {
        name: "direct",
        lpe: "CS*[DG]L",
        whitted: true,
        what: "direct light on diffuse and glossy surfaces",
    },
    Class {
        name: "environment",
        lpe: "CS*[DG]B",
        whitted: false,
        what: "the background lighting diffuse and glossy surfaces",
    },
    Class {
        name: "caustics",
        lpe: "CS*[DG]S+[LB]",
        whitted: false,
        what: "light through mirrors and glass onto diffuse and glossy surfaces",
    },
    Class {
        name: "indirect",
        lpe: "CS*[DG]S*[DG].*[LB]",
        whitted: false,
        what: "indirect diffuse and glossy light (interreflection, colour bleeding)",
    },
];

/// [`CLASSES`]' expressions, compiled.
///
/// # Panics
/// Never: the expressions are constants that parse (tested).
#[must_use]
pub fn standard_classes() -> Vec<Lpe> {
    CLASSES
        .iter()
        .map(|c| Lpe::parse(c.lpe).expect("the standard classes parse"))
        .collect()
}
