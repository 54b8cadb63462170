//! The diagram panel's options as the document keeps them ([`DiagramView`]: plane, filters,
//! zoom and pan, export highlight). Plain data; what they mean for the document's selection is
//! in [`super::diagram`], the controls that edit them in the diagram panel.

use crate::diagram::{DiagramOptions, MIN_SHARE};
use crate::tree::RayKind;

/// Which plane the panel slices with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlaneChoice {
    /// [`PlaneSpec::Auto`](crate::diagram::PlaneSpec::Auto).
    Auto,
    /// [`PlaneSpec::Incidence`](crate::diagram::PlaneSpec::Incidence).
    Incidence,
    /// [`PlaneSpec::Camera`](crate::diagram::PlaneSpec::Camera).
    Camera,
    /// The plane through the selected ray and its parent
    /// ([`PlaneSpec::Ray`](crate::diagram::PlaneSpec::Ray)); follows the selection.
    SelectedRay,
    /// `x`, `y` or `z` = the selected ray's hit coordinate (fixed when chosen).
    Axis {
        /// 0, 1 or 2.
        axis: usize,
        /// The coordinate.
        value: f64,
    },
}

/// The diagram panel's options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagramView {
    /// The slicing plane.
    pub plane: PlaneChoice,
    /// Insets magnifying the spawn points (offset epsilon).
    pub zoom_offsets: bool,
    /// Draw rays up to this depth only (`None`: all).
    pub draw_depth: Option<u32>,
    /// Kinds drawn, in [`RayKind::ALL`] order.
    pub kinds: [bool; RayKind::COUNT],
    /// Labels on depths up to this one.
    pub label_depth: u32,
    /// The contribution threshold (a share of the pixel, 0 = every ray).
    pub min_share: f64,
    /// The sample drawn; `None` follows the selected node's sample.
    pub sample: Option<usize>,
    /// Draw every other sample too, faded by its value ([`crate::diagram::all_samples`]).
    pub all_samples: bool,
    /// Magnification on the automatic framing.
    pub zoom: f64,
    /// Shift from the automatic framing in plane units.
    pub pan: [f64; 2],
    /// Whether exports highlight the selected ray (off: slides without the magenta ray).
    pub export_highlight: bool,
}

impl Default for DiagramView {
    fn default() -> Self {
        let d = DiagramOptions::default();
        Self {
            plane: PlaneChoice::Auto,
            zoom_offsets: false,
            draw_depth: None,
            kinds: [true; RayKind::COUNT],
            label_depth: d.label_depth,
            min_share: MIN_SHARE,
            sample: None,
            all_samples: false,
            zoom: 1.0,
            pan: [0.0, 0.0],
            export_highlight: false,
        }
    }
}
