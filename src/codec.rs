//! In-memory image encoding (PNG, EXR): bytes only, the caller decides where they go.

use crate::render::Image;
use image::{ExtendedColorType, ImageEncoder, ImageError};

/// PNG bytes of 8-bit RGB data, `width * height * 3` bytes, top row first.
pub fn png_rgb8(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, ImageError> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes).write_image(
        rgb,
        width,
        height,
        ExtendedColorType::Rgb8,
    )?;
    Ok(bytes)
}

/// The image as an 8-bit sRGB PNG (clamped).
pub fn png(image: &Image) -> Result<Vec<u8>, ImageError> {
    png_rgb8(&image.to_srgb8(), image.width, image.height)
}

/// The image as a linear 32-bit float OpenEXR; values beyond `f32`'s range are clamped to
/// `±f32::MAX` and NaN is written as 0 (see [`exr_clamped`] for how many pixels that touched).
pub fn exr(image: &Image) -> Result<Vec<u8>, ImageError> {
    exr_clamped(image).map(|(bytes, _)| bytes)
}

/// A channel value as a finite `f32`: finite `f64`s beyond `f32`'s range (a light of 1e42)
/// clamp to `±f32::MAX`, infinities too, NaN becomes 0. Also says whether it changed.
#[must_use]
pub fn finite_f32(v: f64) -> (f32, bool) {
    let max = f64::from(f32::MAX);
    if v.is_nan() {
        (0.0, true)
    } else {
        (v.clamp(-max, max) as f32, v.abs() > max)
    }
}

/// [`exr`], and the number of pixels with a channel that had to be clamped: no infinity or NaN
/// ever reaches the file.
pub fn exr_clamped(image: &Image) -> Result<(Vec<u8>, usize), ImageError> {
    let mut clamped = 0;
    let mut raw: Vec<u8> = Vec::with_capacity(image.pixels.len() * 12);
    for p in &image.pixels {
        let mut any = false;
        for c in p.to_array() {
            let (f, changed) = finite_f32(c);
            any |= changed;
            raw.extend_from_slice(&f.to_le_bytes());
        }
        clamped += usize::from(any);
    }
    let mut bytes = std::io::Cursor::new(Vec::new());
    image::codecs::openexr::OpenExrEncoder::new(&mut bytes).write_image(
        &raw,
        image.width,
        image.height,
        ExtendedColorType::Rgb32F,
    )?;
    Ok((bytes.into_inner(), clamped))
}

#[cfg(test)]
mod tests {
    use super::finite_f32;

    #[test]
    fn f32_overflow_clamps_and_is_reported() {
        assert_eq!(finite_f32(1.5), (1.5, false));
        assert_eq!(finite_f32(0.1), (0.1f64 as f32, false)); // rounding is not clamping
        assert_eq!(finite_f32(1e42), (f32::MAX, true));
        assert_eq!(finite_f32(-1e300), (-f32::MAX, true));
        assert_eq!(finite_f32(f64::INFINITY), (f32::MAX, true));
        assert_eq!(finite_f32(f64::NAN), (0.0, true));
        assert_eq!(finite_f32(f64::from(f32::MAX)), (f32::MAX, false));
    }
}
