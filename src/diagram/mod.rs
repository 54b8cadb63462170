//! Cross-section diagrams of a pixel's ray tree, as in the lecture's 2D figures.
//!
//! [`Diagram::build`] slices the scene with a plane and projects the recorded rays onto it,
//! giving a pure-data [`Diagram`] in canvas pixels. [`to_svg`] and [`to_png`] draw it; the GUI
//! can paint the same primitives ([`paint::display_list`]).

mod annotate;
mod build;
pub mod font;
mod inset;
mod layout;
mod marks;
pub mod model;
mod objects;
pub mod paint;
pub mod plane;
mod raster;
mod segments;
pub mod slice;
mod svg;

pub use model::{Diagram, Label, LabelRole, RayEnd, RaySegment};
pub use paint::{Style, Theme, display_list};
pub use plane::{PlaneFrame, PlaneSpec};
pub use raster::{to_pixmap, to_png};
pub use svg::{to_svg, to_svg_counting};

use crate::tree::{NodeId, RayKind};

/// What to draw and how big.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagramOptions {
    /// The slicing plane.
    pub plane: PlaneSpec,
    /// Canvas width in pixels.
    pub width: u32,
    /// Canvas height in pixels.
    pub height: u32,
    /// Draw rays up to this depth only (all when `None`).
    pub max_depth: Option<u32>,
    /// Ray kinds to draw.
    pub kinds: Vec<RayKind>,
    /// Which sample of the pixel (for spp > 1).
    pub sample: usize,
    /// Add zoomed insets at spawn points showing the offset epsilon.
    pub zoom_offsets: bool,
    /// A node to emphasise (the GUI's selection).
    pub highlight: Option<NodeId>,
    /// Angle, interface and attenuation labels on depths up to this one (deeper rays are drawn
    /// without text, so deep trees stay readable).
    pub label_depth: u32,
    /// Title line (e.g. the scene and pixel); empty for none.
    pub title: String,
}

impl Default for DiagramOptions {
    fn default() -> Self {
        Self {
            plane: PlaneSpec::Incidence,
            width: 1280,
            height: 720,
            max_depth: None,
            kinds: RayKind::ALL.to_vec(),
            sample: 0,
            zoom_offsets: false,
            highlight: None,
            label_depth: 2,
            title: String::new(),
        }
    }
}

/// Why a diagram cannot be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DiagramError {
    /// The requested sample does not exist.
    #[error("sample {sample} does not exist: the tree has {count} sample(s)")]
    NoSuchSample {
        /// Requested.
        sample: usize,
        /// Available.
        count: usize,
    },
    /// The canvas is too small or too large.
    #[error("size {0}x{1} is out of range (64..=16384 each)")]
    BadSize(u32, u32),
}
