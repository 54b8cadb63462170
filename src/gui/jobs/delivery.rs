//! What the render worker sends back: bands of the image and of the debug statistics, the
//! end of each pass, the growth line and progressive passes' reports. Its own file, below both
//! the [`worker`](super::worker) and the [`progressive`](super::progressive) passes it runs.

use crate::gui::model::progressive::Report;
use crate::gui::model::stats::PixelStats;
use crate::integrator::RayCounts;
use crate::math::Rgb;

/// What the worker sends back.
#[derive(Debug)]
pub enum Delivery {
    /// Image rows `y0 .. y0 + pixels.len() / width` of generation `generation`.
    Band {
        /// The job this band belongs to.
        generation: u64,
        /// First row.
        y0: u32,
        /// Linear radiance, row-major (non-finite values written black).
        pixels: Vec<Rgb>,
    },
    /// The image of generation `generation` is complete.
    Done {
        /// The finished job.
        generation: u64,
        /// Wall-clock seconds of the image pass.
        seconds: f64,
        /// Rays traced.
        rays: RayCounts,
    },
    /// Debug statistics of rows `y0 .. y0 + stats.len() / width`.
    Stats {
        /// The job these rows belong to.
        generation: u64,
        /// First row.
        y0: u32,
        /// One per pixel, row-major.
        stats: Vec<PixelStats>,
    },
    /// The statistics of generation `generation` are complete.
    StatsDone {
        /// The finished job.
        generation: u64,
        /// Wall-clock seconds of the statistics pass.
        seconds: f64,
    },
    /// How the scene's ray tree grows and what the automatic cut saves (issue 18), measured
    /// after the statistics.
    Growth {
        /// The job this belongs to.
        generation: u64,
        /// One line for the statistics.
        line: String,
    },
    /// A progressive pass is complete ([`super::progressive`]).
    Pass {
        /// The job this belongs to.
        generation: u64,
        /// The samples so far, the noise estimate and whether the run stopped.
        report: Report,
    },
}

impl Delivery {
    /// The generation this delivery belongs to.
    #[must_use]
    pub fn generation(&self) -> u64 {
        match self {
            Delivery::Band { generation, .. }
            | Delivery::Done { generation, .. }
            | Delivery::Stats { generation, .. }
            | Delivery::StatsDone { generation, .. }
            | Delivery::Growth { generation, .. }
            | Delivery::Pass { generation, .. } => *generation,
        }
    }
}
