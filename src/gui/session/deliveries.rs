//! The session's side of the render worker: fold its deliveries (image bands, statistics, the
//! tree-growth line, progressive passes) into the document, and wait for them (tests,
//! benchmarks, exports).

use super::Session;
use crate::gui::jobs::acne_lab::LabWorker;
use crate::gui::jobs::delivery::Delivery;
use crate::gui::model::document::Document;
use crate::gui::model::stats::DebugView;

impl Session {
    /// Fold every waiting delivery into the image. Returns whether anything changed.
    pub fn pump(&mut self) -> bool {
        // On wasm32 the render runs here, a slice per frame; natively its thread does.
        self.worker.tick();
        let mut changed = false;
        while let Some(d) = self.worker.try_recv() {
            changed |= self.deliver(d);
        }
        while let Some(d) = self.lab.as_ref().and_then(LabWorker::try_recv) {
            changed |= self.deliver_lab(d);
        }
        changed
    }

    /// Block until the current render's image is complete (its debug statistics may still be
    /// on the way).
    pub fn wait_image(&mut self) {
        self.wait_until(|d| d.rendered() && d.progress.seconds.is_some());
    }

    /// Block until the current render, its statistics and the tree-growth line (the last
    /// delivery of a job, which adds a line to the settings panel) have arrived (for tests,
    /// benchmarks and exports: a click right after this meets the final layout).
    pub fn wait_render(&mut self) {
        self.wait_until(|d| {
            d.rendered()
                && d.progress.seconds.is_some()
                && d.progress.stats_seconds.is_some()
                && d.progress.growth_current
        });
    }

    /// Fold in deliveries, blocking, until `done` holds (or the worker is gone).
    fn wait_until(&mut self, done: impl Fn(&Document) -> bool) {
        while !done(&self.doc) {
            match self.worker.recv() {
                Some(d) => {
                    self.deliver(d);
                }
                None => return,
            }
        }
    }

    fn deliver(&mut self, d: Delivery) -> bool {
        if d.generation() != self.doc.progress.generation {
            return false;
        }
        match d {
            Delivery::Band { y0, pixels, .. } => {
                let at = (y0 * self.doc.image.width) as usize;
                self.doc.image.pixels[at..at + pixels.len()].copy_from_slice(&pixels);
                self.doc.progress.rows = y0 + (pixels.len() as u32) / self.doc.image.width.max(1);
                self.doc.progress.seconds = None;
                self.doc.image_version += 1;
            }
            Delivery::Done { seconds, rays, .. } => {
                self.doc.progress.rows = self.doc.image.height;
                self.doc.progress.seconds = Some(seconds);
                self.doc.progress.rays = rays.total();
            }
            Delivery::Stats { y0, stats, .. } => {
                let at = (y0 * self.doc.image.width) as usize;
                self.doc.stats[at..at + stats.len()].copy_from_slice(&stats);
                self.doc.progress.stats_rows =
                    y0 + (stats.len() as u32) / self.doc.image.width.max(1);
                // A debug view shows the statistics: its texture must be rebuilt.
                if self.doc.view.debug != DebugView::Off {
                    self.doc.image_version += 1;
                }
            }
            Delivery::StatsDone { seconds, .. } => {
                self.doc.progress.stats_rows = self.doc.image.height;
                self.doc.progress.stats_seconds = Some(seconds);
            }
            Delivery::Growth { line, .. } => {
                self.doc.progress.growth = Some(line);
                self.doc.progress.growth_current = true;
            }
            Delivery::Pass { report, .. } => self.doc.progressive.report = Some(report),
        }
        true
    }
}
