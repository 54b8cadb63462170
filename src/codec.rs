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

/// The image as a linear 32-bit float OpenEXR.
pub fn exr(image: &Image) -> Result<Vec<u8>, ImageError> {
    let raw: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| p.as_vec3().to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    let mut bytes = std::io::Cursor::new(Vec::new());
    image::codecs::openexr::OpenExrEncoder::new(&mut bytes).write_image(
        &raw,
        image.width,
        image.height,
        ExtendedColorType::Rgb32F,
    )?;
    Ok(bytes.into_inner())
}
