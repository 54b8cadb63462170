//! A small raster canvas for report figures: tiny-skia for rectangles and PNG encoding,
//! ab_glyph for text (with the Hack font egui already ships, so no system font is needed).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use anyhow::{Context, Result};
use tiny_skia::{Color, Paint, Pixmap, PremultipliedColorU8, Rect, Transform};

/// An opaque RGB canvas.
pub struct Canvas {
    pixmap: Pixmap,
    font: FontRef<'static>,
}

/// An sRGB colour.
pub type Rgb8 = [u8; 3];

impl Canvas {
    /// A `width x height` canvas filled with `bg`.
    pub fn new(width: u32, height: u32, bg: Rgb8) -> Result<Self> {
        let mut pixmap = Pixmap::new(width, height).context("figure too large")?;
        pixmap.fill(Color::from_rgba8(bg[0], bg[1], bg[2], 255));
        let font = FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR)
            .context("the built-in font")?;
        Ok(Self { pixmap, font })
    }

    /// Fill an axis-aligned rectangle.
    pub fn rect(&mut self, x: f32, y: f32, w: f32, h: f32, c: Rgb8) {
        if let Some(r) = Rect::from_xywh(x, y, w, h) {
            let mut paint = Paint::default();
            paint.set_color_rgba8(c[0], c[1], c[2], 255);
            self.pixmap
                .fill_rect(r, &paint, Transform::identity(), None);
        }
    }

    /// Set one pixel.
    pub fn pixel(&mut self, x: u32, y: u32, c: Rgb8) {
        let w = self.pixmap.width();
        if x < w && y < self.pixmap.height() {
            self.pixmap.pixels_mut()[(y * w + x) as usize] =
                PremultipliedColorU8::from_rgba(c[0], c[1], c[2], 255).expect("opaque");
        }
    }

    /// Width of `text` at `size` pixels.
    pub fn text_width(&self, text: &str, size: f32) -> f32 {
        let f = self.font.as_scaled(PxScale::from(size));
        text.chars().map(|ch| f.h_advance(f.glyph_id(ch))).sum()
    }

    /// Draw `text` with its baseline-left at `(x, y)`.
    pub fn text(&mut self, x: f32, y: f32, size: f32, text: &str, c: Rgb8) {
        let text = &*raytree::text::guard_nonfinite(text);
        let scaled = self.font.as_scaled(PxScale::from(size));
        let mut caret = x;
        let (w, h) = (self.pixmap.width(), self.pixmap.height());
        for ch in text.chars() {
            let glyph = scaled
                .glyph_id(ch)
                .with_scale_and_position(size, point(caret, y));
            caret += scaled.h_advance(glyph.id);
            let Some(outline) = self.font.outline_glyph(glyph) else {
                continue;
            };
            let b = outline.px_bounds();
            let pixels = self.pixmap.pixels_mut();
            outline.draw(|gx, gy, cov| {
                let (px, py) = (
                    b.min.x as i64 + i64::from(gx),
                    b.min.y as i64 + i64::from(gy),
                );
                if px < 0 || py < 0 || px >= i64::from(w) || py >= i64::from(h) {
                    return;
                }
                let i = (py * i64::from(w) + px) as usize;
                let bg = pixels[i];
                let a = cov.clamp(0.0, 1.0);
                let mix =
                    |b: u8, f: u8| (f32::from(b) * (1.0 - a) + f32::from(f) * a).round() as u8;
                pixels[i] = PremultipliedColorU8::from_rgba(
                    mix(bg.red(), c[0]),
                    mix(bg.green(), c[1]),
                    mix(bg.blue(), c[2]),
                    255,
                )
                .expect("opaque");
            });
        }
    }

    /// Encode as PNG.
    pub fn png(&self) -> Result<Vec<u8>> {
        self.pixmap.encode_png().context("encoding PNG")
    }
}
