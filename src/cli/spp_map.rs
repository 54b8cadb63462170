//! `raytree render --spp-map`: the samples each pixel took as a grey PNG.

use anyhow::Result;
use raytree::DiagnosticMap;

/// A grey PNG of `map.samples`: black for the fewest samples in the image, white for the most
/// (all mid-grey when every pixel took the same number).
pub fn png(map: &DiagnosticMap) -> Result<Vec<u8>> {
    let lo = map.samples.iter().copied().min().unwrap_or(0);
    let hi = map.samples.iter().copied().max().unwrap_or(0);
    let bytes: Vec<u8> = map
        .samples
        .iter()
        .flat_map(|&n| {
            let v = if hi > lo {
                (f64::from(n - lo) / f64::from(hi - lo) * 255.0).round() as u8
            } else {
                128
            };
            [v; 3]
        })
        .collect();
    super::output::encode_rgb8_png(&bytes, map.width, map.height)
}
