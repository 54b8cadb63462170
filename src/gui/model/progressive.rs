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
    /// Which pixels carry the estimate (`None` before two samples or on a non-finite one).
    pub composition: Option<Composition>,
}

/// The share of the pixels [`composition`] calls the top (1%, at least one pixel).
pub const TOP_FRACTION: f64 = 0.01;
/// The top pixels' share of the squared error from which they dominate the estimate: 30 times
/// their share of the pixels. The caustic fixture at 80x60 and 64 spp puts 51% there.
pub const DOMINATED_SHARE: f64 = 0.3;

/// How the noise estimate is made up: the estimate is the RMS of the pixels' relative errors,
/// so its square is the mean of theirs; this says how much of that the noisiest pixels carry
/// and where they are (issue 32: the estimate plateaued on the caustic with nothing on screen
/// saying why).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composition {
    /// Pixels in the estimate.
    pub pixels: usize,
    /// The noisiest [`TOP_FRACTION`] of them (at least one).
    pub top: usize,
    /// Their share of the summed squared relative error (0..=1; 0 when nothing is noisy).
    pub top_share: f64,
    /// The estimate over the other pixels alone (RMS of their relative errors).
    pub rest_error: f64,
    /// The bounding box of the top pixels, `[x0, y0, x1, y1]` inclusive.
    pub bounds: [u32; 4],
    /// The noisiest pixel.
    pub worst: [u32; 2],
}

/// The composition of an estimate from each pixel's squared relative error (`terms`,
/// row-major, `width` pixels a row). `None` for no pixels, a zero width, or a term that is not
/// a finite non-negative number (a pixel with fewer than two samples).
#[must_use]
pub fn composition(terms: &[f64], width: u32) -> Option<Composition> {
    if terms.is_empty() || width == 0 || terms.iter().any(|t| !t.is_finite() || *t < 0.0) {
        return None;
    }
    let mut order: Vec<usize> = (0..terms.len()).collect();
    order.sort_by(|a, b| terms[*b].total_cmp(&terms[*a]));
    let top = ((terms.len() as f64 * TOP_FRACTION).ceil() as usize).clamp(1, terms.len());
    let total: f64 = terms.iter().sum();
    let top_sum: f64 = order[..top].iter().map(|i| terms[*i]).sum();
    let rest = terms.len() - top;
    let rest_error = if rest == 0 {
        0.0
    } else {
        ((total - top_sum).max(0.0) / rest as f64).sqrt()
    };
    let at = |i: usize| [(i % width as usize) as u32, (i / width as usize) as u32];
    let mut bounds = [u32::MAX, u32::MAX, 0, 0];
    for &i in &order[..top] {
        let [x, y] = at(i);
        bounds = [
            bounds[0].min(x),
            bounds[1].min(y),
            bounds[2].max(x),
            bounds[3].max(y),
        ];
    }
    Some(Composition {
        pixels: terms.len(),
        top,
        top_share: if total > 0.0 { top_sum / total } else { 0.0 },
        rest_error,
        bounds,
        worst: at(order[0]),
    })
}

impl Composition {
    /// Whether a few pixels dominate the estimate ([`DOMINATED_SHARE`]).
    #[must_use]
    pub fn dominated(&self) -> bool {
        self.top_share >= DOMINATED_SHARE
    }

    /// The composition in words; when a few pixels dominate, why the estimate plateaus and
    /// what would help.
    #[must_use]
    pub fn sentence(&self) -> String {
        let [x0, y0, x1, y1] = self.bounds;
        let [wx, wy] = self.worst;
        let pixels = if self.top == 1 { "pixel" } else { "pixels" };
        let what = format!(
            "the noisiest {} {pixels} (top {}%, within x {x0}..{x1}, y {y0}..{y1}; worst {wx},{wy}) carry {:.0}% of the squared error; the other pixels alone are at {:.2}%",
            self.top,
            TOP_FRACTION * 100.0,
            self.top_share * 100.0,
            self.rest_error * 100.0
        );
        if self.dominated() {
            format!(
                "A few rare-event pixels dominate: {what}. Their light comes from rare samples (a caustic through glass, fireflies), whose variance shows only as they are found, so the estimate falls slower than 1/sqrt(n) and plateaus: expected here, not a bug. More samples help slowly; a method that reaches the light another way (light tracing or photons for caustics), a larger or less hidden lamp, or judging the image by the other pixels' figure does."
            )
        } else {
            format!("The noise is spread over the image: {what}.")
        }
    }
}

/// The document's side: the options and the last report of the current render.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// The options.
    pub options: Options,
    /// The last pass of the current render (`None` before the first or when off).
    pub report: Option<Report>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_noise_is_not_dominated() {
        // 200 equal pixels: the top 2 carry 1% of the error.
        let c = composition(&[0.04; 200], 20).unwrap();
        assert_eq!((c.pixels, c.top), (200, 2));
        assert!((c.top_share - 0.01).abs() < 1e-12, "{c:?}");
        assert!((c.rest_error - 0.2).abs() < 1e-12);
        assert!(!c.dominated());
        assert!(
            c.sentence().starts_with("The noise is spread"),
            "{}",
            c.sentence()
        );
    }

    #[test]
    fn a_few_rare_event_pixels_dominate_and_are_located() {
        // 1000 pixels 0.01^2, two of them (at 5,3 and 7,4 in a 10-wide image) 1.0^2.
        let mut t = vec![1e-4; 1000];
        t[35] = 1.0;
        t[47] = 0.81;
        let c = composition(&t, 10).unwrap();
        assert_eq!(c.top, 10);
        assert_eq!(c.worst, [5, 3]);
        assert_eq!((c.bounds[0], c.bounds[1]), (0, 0));
        let want = (1.81 + 8.0 * 1e-4) / (1.81 + 998.0 * 1e-4);
        assert!((c.top_share - want).abs() < 1e-12, "{c:?}");
        assert!((c.rest_error - 0.01).abs() < 1e-12);
        assert!(c.dominated());
        let s = c.sentence();
        assert!(s.starts_with("A few rare-event pixels dominate"), "{s}");
        assert!(s.contains("worst 5,3") && s.contains("plateaus"), "{s}");
    }

    #[test]
    fn the_top_pixels_bounds_are_where_they_are() {
        // 100 pixels: the top one is at 3,2 in a 10-wide image.
        let mut t = vec![0.0; 100];
        t[23] = 4.0;
        let c = composition(&t, 10).unwrap();
        assert_eq!((c.top, c.bounds, c.worst), (1, [3, 2, 3, 2], [3, 2]));
        assert_eq!((c.top_share, c.rest_error), (1.0, 0.0));
        assert!(c.sentence().contains("1 pixel (top 1%"));
    }

    #[test]
    fn bad_input_gives_none_never_a_panic() {
        assert_eq!(composition(&[], 4), None);
        assert_eq!(composition(&[1.0], 0), None);
        assert_eq!(composition(&[1.0, f64::INFINITY], 2), None);
        assert_eq!(composition(&[1.0, f64::NAN], 2), None);
        assert_eq!(composition(&[-1.0], 1), None);
        // All black and noiseless: nothing to carry.
        let c = composition(&[0.0; 10], 5).unwrap();
        assert_eq!(
            (c.top_share, c.rest_error, c.dominated()),
            (0.0, 0.0, false)
        );
    }
}
