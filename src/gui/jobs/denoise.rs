//! The inspector's "denoised image" toggle (issue 16): once a render has finished, the scene is
//! gathered again with the denoiser's guide buffers (`crate::denoise::gather`, which gives the
//! render's own pixels bit for bit) and filtered (`crate::denoise::denoise`, the a-trous filter
//! of docs/denoise.md) on a thread of its own; the image panel shows the result while the
//! toggle is on. The selected pixel's tree, the overlay, the diagram and the exports stay the
//! raw samples: the denoiser never changes what a pixel's tree explains.

use super::background::{Inbox, Work, deliver};
use crate::Scene;
use crate::denoise::{DenoiseParams, DenoiseSteps, Features, GatherSteps, denoise, gather};
use crate::gui::model::document::Document;
use crate::integrator::SceneIntegrator;
use crate::render::Image;
use std::sync::Arc;
use web_time::Instant;

/// Which finished render an image belongs to: its generation and the seconds it took (a
/// re-render of the same generation, as a progressive pass, gets a new key).
type Key = (u64, u64);

/// The denoised image of the last finished render, and the job computing the next one.
#[derive(Default)]
pub struct DenoiseView {
    pending: Option<(Key, Inbox<(Image, f64)>)>,
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
            && let Some((image, secs)) = rx.try_recv()
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
            let work = Denoising {
                scene: Arc::clone(&doc.scene),
                start: None,
                phase: None,
            };
            let spawned = deliver(
                "raytree-denoise",
                Some(crate::integrator::THREAD_STACK_BYTES),
                work,
                repaint,
            );
            let Ok(rx) = spawned else {
                return (
                    None,
                    DenoiseState::Unavailable("no thread for the denoiser"),
                );
            };
            self.pending = Some((key, rx));
        }
        (None, DenoiseState::Running)
    }
}

/// The denoiser as a background job: the guide pass ([`gather`]) and the filter, whole
/// natively; on wasm32 a pixel at a time ([`GatherSteps`], then [`DenoiseSteps`]: the same
/// pixels, features and filtered image). Its outcome: the image and the seconds taken.
struct Denoising {
    scene: Arc<Scene>,
    start: Option<Instant>,
    phase: Option<Phase>,
}

/// Where a stepped [`Denoising`] stands.
enum Phase {
    Gather(Box<GatherSteps>),
    Filter(Box<(Image, Features, DenoiseSteps)>),
}

impl Work for Denoising {
    type Out = (Image, f64);

    fn whole(self) -> Self::Out {
        let start = Instant::now();
        let (raw, _, features) = gather(&SceneIntegrator::new(&self.scene), &|_| {});
        let image = denoise(&raw, &features, &DenoiseParams::default());
        (image, start.elapsed().as_secs_f64())
    }

    fn piece(&mut self, more_time: &dyn Fn() -> bool) -> Option<Self::Out> {
        let start = *self.start.get_or_insert_with(Instant::now);
        let tracer = SceneIntegrator::new(&self.scene);
        let params = DenoiseParams::default();
        match self.phase.take() {
            None => self.phase = Some(Phase::Gather(Box::new(GatherSteps::new(&tracer)))),
            Some(Phase::Gather(mut steps)) => {
                if steps.step(&tracer, more_time) {
                    self.phase = Some(Phase::Gather(steps));
                } else {
                    let (raw, _, features) = steps.finish(&tracer);
                    let filter = DenoiseSteps::new(&raw, &features);
                    self.phase = Some(Phase::Filter(Box::new((raw, features, filter))));
                }
            }
            Some(Phase::Filter(mut f)) => {
                let (_, features, filter) = &mut *f;
                if !filter.step(features, &params, more_time) {
                    let (raw, features, filter) = *f;
                    let image = filter.finish(&raw, &features);
                    return Some((image, start.elapsed().as_secs_f64()));
                }
                self.phase = Some(Phase::Filter(f));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stepped_denoiser_filters_the_same_image() {
        let mut scene = Scene::default_scene();
        scene.camera = scene.camera.with_size(24, 16);
        scene.settings.integrator = crate::scene::IntegratorKind::Path;
        scene.settings.spp = 2;
        let job = || Denoising {
            scene: Arc::new(scene.clone()),
            start: None,
            phase: None,
        };
        let (whole, _) = job().whole();
        let mut stepped = job();
        let mut n = 1;
        let (image, secs) = loop {
            match stepped.piece(&|| false) {
                Some(out) => break out,
                None => n += 1,
            }
        };
        // The start, a pixel of the guide pass a piece (the last also starts the filter), then
        // a pixel of each of the filter's passes a piece.
        let passes = DenoiseParams::default().iterations as usize;
        assert_eq!(n, 1 + 24 * 16 * (1 + passes), "a pixel a piece");
        assert_eq!(image, whole);
        assert!(secs.is_finite() && secs >= 0.0);
    }
}
