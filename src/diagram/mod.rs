//! Cross-section diagrams of a pixel's ray tree, as in the lecture's 2D figures.
//!
//! [`Diagram::build`] slices the scene with a plane and projects the recorded rays onto it,
//! giving a pure-data [`Diagram`] in canvas pixels. [`to_svg`] and [`to_png`] draw it; the GUI
//! can paint the same primitives ([`paint::display_list`]).

pub mod all_samples;
mod annotate;
mod build;
pub mod font;
mod framing;
mod inset;
mod layout;
mod legend;
mod marks;
pub mod model;
mod objects;
pub mod paint;
pub mod plane;
pub mod plane_pick;
mod raster;
mod segments;
pub mod share;
pub mod slice;
mod svg;

pub use layout::{label_box, percent};
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
    /// Leave out rays carrying less than this share of the sample's value
    /// ([`share::keep`]; 0 keeps every ray). The legend says how many and how much.
    pub min_share: f64,
    /// Magnification on the automatic framing (1 = as framed).
    pub zoom: f64,
    /// Shift of the view's centre from the automatic framing, in plane units (right, up).
    pub pan: [f64; 2],
    /// Also draw every other sample of the pixel, under `sample`, faded by its value
    /// ([`all_samples`]).
    pub all_samples: bool,
}

/// The default contribution threshold: 1 % of the sample's value.
pub const MIN_SHARE: f64 = 0.01;

impl Default for DiagramOptions {
    fn default() -> Self {
        Self {
            plane: PlaneSpec::Auto,
            width: 1280,
            height: 720,
            max_depth: None,
            kinds: RayKind::ALL.to_vec(),
            sample: 0,
            zoom_offsets: false,
            highlight: None,
            label_depth: 2,
            title: String::new(),
            min_share: MIN_SHARE,
            zoom: 1.0,
            pan: [0.0, 0.0],
            all_samples: false,
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
    /// The plane follows a ray the tree does not have.
    #[error("ray #{node} does not exist: the tree has {count} rays (#0 to #{last})", last = count.saturating_sub(1))]
    NoSuchNode {
        /// Requested node id.
        node: u32,
        /// Nodes in the tree.
        count: usize,
    },
    /// The canvas is too small or too large.
    #[error("size {0}x{1} is out of range (64..=16384 each)")]
    BadSize(u32, u32),
}
