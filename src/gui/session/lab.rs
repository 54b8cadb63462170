//! The session's side of the acne lab: start a job on the current scene, fold its deliveries
//! into the document, wait for it (tests).

use super::Session;
use crate::gui::jobs::acne_lab::{LabDelivery, LabWorker};
use std::sync::Arc;

impl Session {
    /// Start the acne lab on the current scene with its parameters.
    pub(super) fn start_lab(&mut self) {
        if let Err(e) = self.doc.lab.params.check() {
            self.doc.error = Some(format!("acne lab: {e}"));
            return;
        }
        if self.lab.is_none() {
            self.lab = LabWorker::new(Arc::clone(&self.repaint));
        }
        let Some(lab) = &self.lab else {
            self.doc.error = Some("acne lab: cannot start its thread".into());
            return;
        };
        let l = &mut self.doc.lab;
        l.started = true;
        l.generation = lab.start(Arc::clone(&self.doc.scene), l.params);
        l.current = None;
        l.sweep.clear();
        l.done = false;
    }

    /// Block until the acne lab's job is complete (tests; returns at once if never started).
    pub fn wait_lab(&mut self) {
        while self.doc.lab.started && !self.doc.lab.done {
            match self.lab.as_ref().and_then(LabWorker::recv) {
                Some(d) => {
                    self.deliver_lab(d);
                }
                None => return,
            }
        }
    }

    pub(super) fn deliver_lab(&mut self, d: LabDelivery) -> bool {
        let lab = &mut self.doc.lab;
        if d.generation() != lab.generation {
            return false;
        }
        match d {
            LabDelivery::Current(_, c) => lab.current = Some(c),
            LabDelivery::Sweep(_, c) => lab.sweep.push(c),
            LabDelivery::Done(_) => lab.done = true,
        }
        true
    }
}
