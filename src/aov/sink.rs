//! The AOV render's sink of the pixel loop ([`crate::render::pixel_loop`]): each sample's
//! contributions split by light path expression ([`AovRecorder`]) and the debug views'
//! statistics ([`McPixel`]), for the same samples, fixed or adaptive, as the render's.

use super::{AovRecorder, McPixel};
use crate::lpe::Lpe;
use crate::math::Rgb;
use crate::render::pixel_loop::{Sample, SampleSink};

/// The sink: the recorder that splits each sample by expression, and a spare luminance
/// buffer (a finished pixel's, so a render without a second pass allocates none per pixel).
pub(super) struct AovSink<'a>(pub AovRecorder<'a>, Vec<f64>);

impl<'a> AovSink<'a> {
    pub(super) fn new(lpes: &'a [Lpe]) -> Self {
        Self(AovRecorder::new(lpes), Vec::new())
    }
}

/// One pixel's sums while its samples come in.
#[derive(Clone, Debug, Default)]
pub(super) struct AovPixel {
    /// Sum per expression of the kept samples' contributions (empty until the first).
    aov: Vec<Rgb>,
    segments: u64,
    roulette: u32,
    dropped: u32,
    /// Each sample's luminance as it enters the pixel (black when dropped).
    lums: Vec<f64>,
}

impl<'a> SampleSink for AovSink<'a> {
    type Rec = AovRecorder<'a>;
    type Pixel = AovPixel;
    type Out = (Vec<Rgb>, McPixel);

    fn recorder(&mut self) -> &mut Self::Rec {
        &mut self.0
    }

    fn start_sample(&mut self) {
        self.0.start_sample();
    }

    fn sample(&mut self, px: &mut AovPixel, s: &Sample) {
        if px.lums.capacity() == 0 {
            px.lums = std::mem::take(&mut self.1);
        }
        let rec = &self.0;
        px.segments += u64::from(rec.segments);
        px.roulette += u32::from(rec.roulette);
        if s.kept {
            if px.aov.is_empty() {
                px.aov = vec![Rgb::ZERO; rec.sample.len()];
            }
            for (a, c) in px.aov.iter_mut().zip(&rec.sample) {
                *a += *c;
            }
            // (A non-finite Whitted sample makes a black pixel: it adds no spread.)
            let l = s.radiance;
            px.lums.push(if l.is_finite() {
                crate::bsdf::luminance(l)
            } else {
                0.0
            });
        } else {
            // Dropped as the render drops it: black, counted.
            px.dropped += 1;
            px.lums.push(0.0);
        }
    }

    fn finish(&mut self, px: AovPixel, taken: u32) -> (Vec<Rgb>, McPixel) {
        let n = f64::from(taken);
        let mut aov = px.aov;
        aov.resize(self.0.sample.len(), Rgb::ZERO);
        for a in &mut aov {
            *a /= n;
        }
        let mut mc = McPixel {
            samples: taken,
            dropped: px.dropped,
            roulette: px.roulette,
            path_length: px.segments as f64 / n,
            ..McPixel::default()
        };
        mc.set_spread(&px.lums);
        let mut spare = px.lums;
        spare.clear();
        self.1 = spare;
        (aov, mc)
    }
}
