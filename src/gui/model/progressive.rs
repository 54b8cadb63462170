//! Progressive rendering's options and reports (issue 16): what the user set, where a run
//! stands after a pass, and the document's side of both. Plain data; the passes themselves are
//! [`crate::gui::jobs::progressive`].

/// The mode as the user set it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Progressive rendering on (off: the one render at the scene's spp).
    pub on: bool,
    /// Stop when the estimate
    /// ([`Accumulator::error`](crate::gui::jobs::progressive::Accumulator::error)) is at or
    /// below this (0.01 = 1%).
    pub target: f64,
    /// Stop at this many samples per pixel at most.
    pub cap: u32,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            on: false,
            // A preview's stop: the Cornell box reaches it at 512 spp (1% would need about
            // 6,600 there); type a smaller target for a final image.
            target: 0.05,
            cap: 1024,
        }
    }
}

/// Why a progressive run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The estimate fell to the target.
    Target,
    /// The samples reached the cap.
    Cap,
}

/// Where a progressive run stands after a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// Samples per pixel accumulated so far.
    pub spp: u32,
    /// The image's mean relative standard error (the documentation of
    /// [`crate::gui::jobs::progressive`]).
    pub error: f64,
    /// Wall-clock seconds since the run started.
    pub seconds: f64,
    /// Set on the last pass: why the run stopped.
    pub stop: Option<Stop>,
}

/// The document's side: the options and the last report of the current render.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// The options.
    pub options: Options,
    /// The last pass of the current render (`None` before the first or when off).
    pub report: Option<Report>,
}
