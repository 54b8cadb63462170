//! Colours: [`Rgba`], the light and dark [`Theme`]s and the [`Style`] they give.

use crate::tree::RayKind;

/// An sRGB colour with straight alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgba(pub u8, pub u8, pub u8, pub u8);

impl Rgba {
    /// The same colour with alpha multiplied by `f` (clamped to [0, 1]).
    #[must_use]
    pub fn fade(self, f: f64) -> Self {
        Self(
            self.0,
            self.1,
            self.2,
            (f64::from(self.3) * f.clamp(0.0, 1.0)).round() as u8,
        )
    }
}

/// Colour theme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Theme {
    /// Dark on white (slides, print).
    #[default]
    Light,
    /// Light on near-black.
    Dark,
}

/// Colours and the theme they come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Canvas background.
    pub background: Rgba,
    /// Text and outlines.
    pub ink: Rgba,
    /// Normals and secondary lines.
    pub muted: Rgba,
    /// Ray colours in [`RayKind::ALL`] order.
    pub rays: [Rgba; RayKind::COUNT],
    /// Diffuse fill.
    pub diffuse: Rgba,
    /// Glass fill (before the absorption tint).
    pub glass: Rgba,
    /// Mirror fill.
    pub mirror: Rgba,
    /// Highlighted node underlay.
    pub highlight: Rgba,
}

impl Style {
    /// The colours of `theme`.
    #[must_use]
    pub fn new(theme: Theme) -> Self {
        match theme {
            Theme::Light => Self {
                background: Rgba(255, 255, 255, 255),
                ink: Rgba(26, 26, 26, 255),
                muted: Rgba(110, 110, 110, 255),
                rays: [
                    Rgba(40, 40, 40, 255),
                    Rgba(214, 39, 40, 255),
                    Rgba(20, 110, 200, 255),
                    Rgba(225, 150, 0, 255),
                    Rgba(30, 150, 60, 255),
                    Rgba(230, 110, 0, 255),
                    Rgba(140, 80, 200, 255),
                ],
                diffuse: Rgba(215, 215, 215, 255),
                glass: Rgba(150, 205, 235, 110),
                mirror: Rgba(225, 228, 232, 255),
                highlight: Rgba(255, 0, 200, 110),
            },
            Theme::Dark => Self {
                background: Rgba(21, 23, 28, 255),
                ink: Rgba(232, 232, 232, 255),
                muted: Rgba(150, 150, 150, 255),
                rays: [
                    Rgba(235, 235, 235, 255),
                    Rgba(255, 107, 107, 255),
                    Rgba(77, 171, 247, 255),
                    Rgba(255, 212, 59, 255),
                    Rgba(105, 219, 124, 255),
                    Rgba(255, 146, 43, 255),
                    Rgba(204, 153, 255, 255),
                ],
                diffuse: Rgba(62, 65, 72, 255),
                glass: Rgba(80, 160, 220, 90),
                mirror: Rgba(80, 84, 92, 255),
                highlight: Rgba(255, 60, 220, 120),
            },
        }
    }

    /// The colour of rays of `kind`.
    #[must_use]
    pub fn ray(&self, kind: RayKind) -> Rgba {
        self.rays[RayKind::ALL.iter().position(|k| *k == kind).unwrap_or(0)]
    }
}

impl Default for Style {
    fn default() -> Self {
        Self::new(Theme::Light)
    }
}

pub(super) fn mix(a: Rgba, b: Rgba) -> Rgba {
    let m = |x: u8, y: u8| ((u16::from(x) + u16::from(y)) / 2) as u8;
    Rgba(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2), 255)
}
