//! Colours (ray kinds, the selection, errors and warnings) and number formatting shared by the
//! panels and the app.

use crate::math::{Rgb, linear_to_srgb8};
use crate::tree::RayKind;
use egui::Color32;

/// The colour of a ray kind, everywhere (tree, overlay, legend); the diagram's dark theme.
#[must_use]
pub fn kind_colour(kind: RayKind) -> Color32 {
    match kind {
        RayKind::Camera => Color32::from_rgb(235, 235, 235),
        RayKind::Reflected => Color32::from_rgb(255, 107, 107),
        RayKind::Refracted => Color32::from_rgb(77, 171, 247),
        RayKind::Shadow => Color32::from_rgb(255, 212, 59),
        RayKind::Diffuse => Color32::from_rgb(105, 219, 124),
        RayKind::Light => Color32::from_rgb(255, 146, 43),
        RayKind::Connection => Color32::from_rgb(204, 153, 255),
    }
}

/// Highlight for the selected node and pixel.
pub const SELECTED: Color32 = Color32::from_rgb(255, 70, 200);

/// The colour of error messages.
pub const ERROR: Color32 = Color32::from_rgb(255, 110, 110);
/// Colour of a warning (an export that clamped or left out non-finite values).
pub const WARNING: Color32 = Color32::from_rgb(255, 200, 80);

/// `[r, g, b]` with 4 decimals.
#[must_use]
pub fn rgb(c: Rgb) -> String {
    if c.x == c.y && c.y == c.z {
        return format!("{:.4}", c.x);
    }
    format!("[{:.4}, {:.4}, {:.4}]", c.x, c.y, c.z)
}

/// A linear colour as an sRGB swatch colour.
#[must_use]
pub fn swatch(c: Rgb) -> Color32 {
    let [r, g, b] = c.to_array().map(linear_to_srgb8);
    Color32::from_rgb(r, g, b)
}

/// Short number: 4 significant digits, scientific when tiny or huge.
#[must_use]
pub fn num(v: f64) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

/// A weight as `raytree trace` prints it: 4 decimals (a rounding residue such as 4.3e-30
/// reads 0.0000, as in `trace`).
#[must_use]
pub fn weight(v: f64) -> String {
    format!("{v:.4}")
}

/// An amount that may be small but matter (a contribution to the pixel): 4 decimals from 1e-3
/// on, 3 significant digits below, and `0` below 5e-10, which no 8-bit or 16-bit image can
/// show (products of Fresnel and BRDF factors leave residues like 4.3e-30 there).
#[must_use]
pub fn amount(v: f64) -> String {
    if v.abs() < 5e-10 {
        "0".into()
    } else if (1e-3..1e5).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.2e}")
    }
}

/// A vector `(x, y, z)`.
#[must_use]
pub fn vec3(v: glam::DVec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

/// A small filled circle in `colour` (the default fonts have no bullet glyph).
pub fn dot(ui: &mut egui::Ui, colour: Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
    ui.painter().circle_filled(rect.center(), 4.5, colour);
}

/// A small colour square.
pub fn square(ui: &mut egui::Ui, colour: Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, colour);
}
