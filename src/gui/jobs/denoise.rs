//! The inspector's "denoised image" toggle (issue 16): once a render has finished, the scene is
//! gathered again with the denoiser's guide buffers (`crate::denoise::gather`, which gives the
//! render's own pixels bit for bit) and filtered (`crate::denoise::denoise`, the a-trous filter
//! of docs/denoise.md) on a thread of its own; the image panel shows the result while the
//! toggle is on. The selected pixel's tree, the overlay, the diagram and the exports stay the
//! raw samples: the denoiser never changes what a pixel's tree explains.

use crate::denoise::{DenoiseParams, denoise, gather};
use crate::gui::model::document::Document;
use crate::integrator::SceneIntegrator;
use crate::render::Image;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, channel};
use web_time::Instant;

/// Which finished render an image belongs to: its generation and the seconds it took (a
/// re-render of the same generation, as a progressive pass, gets a new key).
type Key = (u64, u64);

/// The denoised image of the last finished render, and the job computing the next one.
#[derive(Default)]
pub struct DenoiseView {
    pending: Option<(Key, Receiver<(Image, f64)>)>,
    done: Option<(Key, Image, f64)>,
}

/// What the toggle shows.
#[derive(Clone, Debug, PartialEq)]
pub enum DenoiseState {
    /// The render has not finished yet.
    Waiting,
    /// The filter is running.
    Running,
    /// Shown; it took this many seconds (guide buffers and filter).
    Ready(f64),
    /// Not available for this scene, with the reason.
    Unavailable(&'static str),
}

fn key(doc: &Document) -> Option<Key> {
    let seconds = doc.progress.seconds?;
    doc.rendered()
        .then_some((doc.progress.generation, seconds.to_bits()))
}

impl DenoiseView {
    /// The denoised image of `doc`'s finished render, if computed; otherwise starts (or keeps
    /// waiting for) its computation, calling `repaint` when it is done.
    pub fn image(
        &mut self,
        doc: &Document,
        repaint: impl Fn() + Send + 'static,
    ) -> (Option<&Image>, DenoiseState) {
        if doc.progressive.options.on {
            // The guide pass renders the scene's spp, not the progressive accumulation shown.
            return (
                None,
                DenoiseState::Unavailable("not with progressive rendering"),
            );
        }
        if doc.scene.settings.integrator.splats() {
            // As `raytree render --denoise` refuses: the guide pass is a camera pass, and these
            // pixels also hold the light paths' splats (a light-traced image is nearly all
            // splats: the filter would show a black image).
            return (
                None,
                DenoiseState::Unavailable(
                    "not under light tracing or BDPT (their pixels also hold light-path splats, which the guide pass leaves out)",
                ),
            );
        }
        let Some(key) = key(doc) else {
            return (None, DenoiseState::Waiting);
        };
        if let Some((k, rx)) = &self.pending
            && *k == key
            && let Ok((image, secs)) = rx.try_recv()
        {
            self.done = Some((key, image, secs));
            self.pending = None;
        }
        if let Some((k, image, secs)) = &self.done
            && *k == key
        {
            return (Some(image), DenoiseState::Ready(*secs));
        }
        if self.pending.as_ref().is_none_or(|(k, _)| *k != key) {
            let scene = Arc::clone(&doc.scene);
            let (tx, rx) = channel();
            let spawned = super::background::spawn(
                "raytree-denoise",
                Some(crate::integrator::THREAD_STACK_BYTES),
                move || {
                    let start = Instant::now();
                    let (raw, _, features) = gather(&SceneIntegrator::new(&scene), &|_| {});
                    let image = denoise(&raw, &features, &DenoiseParams::default());
                    // A newer render dropped the receiver: nothing to deliver.
                    if tx.send((image, start.elapsed().as_secs_f64())).is_ok() {
                        repaint();
                    }
                },
            );
            if spawned.is_err() {
                return (
                    None,
                    DenoiseState::Unavailable("no thread for the denoiser"),
                );
            }
            self.pending = Some((key, rx));
        }
        (None, DenoiseState::Running)
    }
}
