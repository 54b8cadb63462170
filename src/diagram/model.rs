//! The diagram model: plain data in canvas coordinates (pixels, origin top-left, y down), built
//! from a scene and a ray tree. No drawing library here: the SVG and PNG back-ends and the GUI
//! all paint the same primitives.

use super::plane::PlaneFrame;
use crate::tree::{NodeId, RayKind};
use glam::DVec2;

/// A point or vector in canvas coordinates (pixels, y down).
pub type Point = DVec2;

/// An axis-aligned rectangle in canvas coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Top-left corner.
    pub min: Point,
    /// Bottom-right corner.
    pub max: Point,
}

impl Rect {
    /// The rectangle from its corners.
    #[must_use]
    pub fn new(min: Point, max: Point) -> Self {
        Self { min, max }
    }

    /// Width and height.
    #[must_use]
    pub fn size(&self) -> Point {
        self.max - self.min
    }

    /// Whether the rectangles overlap (touching does not count).
    #[must_use]
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.min.x < o.max.x && o.min.x < self.max.x && self.min.y < o.max.y && o.min.y < self.max.y
    }

    /// Whether `o` lies entirely inside.
    #[must_use]
    pub fn contains_rect(&self, o: &Rect) -> bool {
        o.min.x >= self.min.x
            && o.min.y >= self.min.y
            && o.max.x <= self.max.x
            && o.max.y <= self.max.y
    }
}

/// How an object's slice is filled, by material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fill {
    /// Transmissive with an index of refraction: tinted, labelled with the index.
    Glass {
        /// Index of refraction.
        ior: f64,
        /// Transmittance over one world unit, `exp(-absorption)` (white when clear).
        tint: [f64; 3],
    },
    /// Transmissive absorbing medium without an index: tinted by its absorption.
    Absorbing {
        /// Transmittance over one world unit, `exp(-absorption)`.
        tint: [f64; 3],
    },
    /// Emissive (a lamp or area light): drawn in the light's colour with a glow.
    Emitter,
    /// Reflective: hatched.
    Mirror,
    /// Anything else: grey.
    Diffuse,
}

/// The exact cross-section of one object with the diagram plane.
#[derive(Clone, Debug, PartialEq)]
pub enum SliceShape {
    /// A sphere's slice.
    Circle {
        /// Centre.
        center: Point,
        /// Radius in pixels.
        radius: f64,
    },
    /// A box's slice (convex), or a plane's inside clipped to the view (convex).
    Polygon(Vec<Point>),
    /// A triangle's slice.
    Segment(Point, Point),
    /// A mesh's slice: one segment per triangle cut.
    Segments(Vec<(Point, Point)>),
}

/// One object cut by the diagram plane.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSlice {
    /// Object index in the scene.
    pub object: usize,
    /// Object name.
    pub name: String,
    /// Fill by material.
    pub fill: Fill,
    /// The cross-section.
    pub shape: SliceShape,
    /// For planes: the visible boundary line (the surface itself).
    pub edge: Option<(Point, Point)>,
}

/// How a ray segment ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayEnd {
    /// At a surface hit.
    Hit,
    /// Missed everything: clipped at the frame.
    Miss,
    /// A shadow ray reaching its light (possibly attenuated).
    Light,
    /// A shadow ray stopped by an opaque blocker (drawn with a cross).
    Blocked,
    /// The light is behind the surface: no ray was cast (drawn as a short stub).
    LightBehind,
}

/// One ray of the tree as a 2D segment. Every ray node drawn appears exactly once.
#[derive(Clone, Debug, PartialEq)]
pub struct RaySegment {
    /// The tree node.
    pub node: NodeId,
    /// Ray kind (colour).
    pub kind: RayKind,
    /// Recursion depth.
    pub depth: u32,
    /// Start (the spawn point; the eye for camera rays).
    pub from: Point,
    /// End (hit, light, blocker or frame).
    pub to: Point,
    /// How it ends.
    pub end: RayEnd,
    /// Throughput at the ray's origin, largest channel clamped to [0, 1] (width and opacity).
    pub throughput: f64,
    /// Signed distance from the diagram plane of the 3D start and end points, in world units.
    pub plane_distance: [f64; 2],
    /// Whether the 3D segment leaves the plane (drawn dotted and faded).
    pub off_plane: bool,
    /// Opacity factor from the distance to the plane, in (0, 1].
    pub fade: f64,
    /// Ends a total-internal-reflection parent bounce (its parent had TIR).
    pub tir: bool,
    /// The node chosen in [`super::DiagramOptions::highlight`].
    pub highlighted: bool,
}

/// An angle arc at a hit, in canvas coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct AngleArc {
    /// Centre (the hit point).
    pub center: Point,
    /// Radius in pixels.
    pub radius: f64,
    /// Start angle in radians (canvas, y down: atan2(y, x)).
    pub start: f64,
    /// Signed sweep in radians.
    pub sweep: f64,
    /// The true 3D angle in degrees (from the tree's cosines).
    pub degrees: f64,
}

impl AngleArc {
    /// The arc as a polyline with `n + 1` points.
    #[must_use]
    pub fn points(&self, n: usize) -> Vec<Point> {
        (0..=n)
            .map(|i| {
                let a = self.start + self.sweep * i as f64 / n as f64;
                self.center + self.radius * DVec2::new(a.cos(), a.sin())
            })
            .collect()
    }
}

/// Annotations at one surface hit.
#[derive(Clone, Debug, PartialEq)]
pub struct HitMark {
    /// The ray that hit.
    pub node: NodeId,
    /// Hit point.
    pub point: Point,
    /// Unit projected normal on the incident side (zero if the normal is perpendicular to the
    /// plane).
    pub normal: Point,
    /// Half-length of the drawn normal in pixels.
    pub normal_len: f64,
    /// Total internal reflection here.
    pub tir: bool,
    /// The recursion was cut here (max depth or min weight).
    pub truncated: bool,
    /// theta_i and theta_t arcs (only on labelled levels).
    pub arcs: Vec<AngleArc>,
    /// Whether this hit is off the plane.
    pub fade: f64,
}

/// A light's marker.
#[derive(Clone, Debug, PartialEq)]
pub struct LightMark {
    /// Light index (`scene.lights.len() + object` for an emissive object, as in
    /// [`crate::tree::ShadowInfo::light`]).
    pub light: usize,
    /// An emissive object (area light) rather than a point or directional light: marked where
    /// the rays meet it.
    pub area: bool,
    /// Position (for directional lights, where its rays enter the frame).
    pub point: Point,
    /// For directional lights: unit canvas direction of travel.
    pub directional: Option<Point>,
    /// For a spot light whose cone the plane cuts: the unit canvas directions of the cone's two
    /// edges in the plane (drawn dashed from the light, as the lecture sketches a spot).
    pub cone: Option<[Point; 2]>,
    /// Distance from the plane in world units.
    pub plane_distance: f64,
    /// Opacity factor from the distance.
    pub fade: f64,
}

/// The camera as in the lecture's "A = aperture, P = pixel centre" figure.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraMark {
    /// The eye (aperture A).
    pub eye: Point,
    /// The image plane's slice (at distance 1 along the view direction), if cut.
    pub image_plane: Option<(Point, Point)>,
    /// The pixel centre P.
    pub pixel: Point,
    /// The pixel's footprint on the image-plane slice, if cut.
    pub pixel_span: Option<(Point, Point)>,
}

/// What a label is about (for styling and for the GUI).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LabelRole {
    /// Title line.
    Title,
    /// Object name or index of refraction.
    Object,
    /// Angle value.
    Angle,
    /// n1/n2, R/T, TIR at an interface.
    Interface,
    /// Beer factor on a segment, or a shadow transmittance.
    Attenuation,
    /// Light name.
    Light,
    /// Camera, aperture, pixel.
    Camera,
    /// Text inside a zoom inset.
    Inset,
    /// Legend text.
    Legend,
}

/// Horizontal text anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// `pos` is the left end of the baseline.
    Start,
    /// `pos` is the middle of the baseline.
    Middle,
    /// `pos` is the right end of the baseline.
    End,
}

/// A text label at its final (collision-free) position.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// Baseline anchor point.
    pub pos: Point,
    /// Text (UTF-8; Greek letters allowed).
    pub text: String,
    /// Font size in pixels (em).
    pub size: f64,
    /// Horizontal anchor.
    pub anchor: Anchor,
    /// What it labels.
    pub role: LabelRole,
    /// The ray node it belongs to, if any.
    pub node: Option<NodeId>,
    /// The kind colour to use, if any.
    pub kind: Option<RayKind>,
}

/// A zoomed inset at a spawn point (`--zoom-offsets`).
#[derive(Clone, Debug, PartialEq)]
pub struct Inset {
    /// Where the inset sits on the canvas.
    pub rect: Rect,
    /// The spawn point in the main view (for the leader line).
    pub anchor: Point,
    /// The surface line through the hit point, clipped to the inset.
    pub surface: (Point, Point),
    /// A point inside the surface (to shade the solid side).
    pub inside: Point,
    /// The hit point P.
    pub hit: Point,
    /// The offset origins of the rays spawned here, with their kinds and end points in the inset.
    pub rays: Vec<(RayKind, Point, Point)>,
    /// World units per inset pixel.
    pub world_per_px: f64,
}

/// A line in the legend.
#[derive(Clone, Debug, PartialEq)]
pub enum LegendKey {
    /// A ray kind swatch.
    Ray(RayKind),
    /// Off-plane rays (dotted, faded).
    OffPlane,
    /// The blocked-shadow cross.
    Blocked,
    /// Surface normal (dashed).
    Normal,
    /// Text only.
    Note,
}

/// One legend entry: swatch at `pos`, text to its right.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// Swatch kind.
    pub key: LegendKey,
    /// Left end of the swatch, on the text's middle line.
    pub pos: Point,
    /// Text label (already in [`Diagram::labels`]).
    pub text: String,
}

/// The whole figure, in canvas coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagram {
    /// Canvas width in pixels.
    pub width: f64,
    /// Canvas height in pixels.
    pub height: f64,
    /// The diagram plane and the world-to-canvas mapping.
    pub frame: PlaneFrame,
    /// Where rays and slices are drawn (misses are clipped to it).
    pub view: Rect,
    /// How the plane was chosen, in words.
    pub plane_text: String,
    /// Object slices.
    pub objects: Vec<ObjectSlice>,
    /// Ray segments, depth-first.
    pub rays: Vec<RaySegment>,
    /// Hit annotations.
    pub hits: Vec<HitMark>,
    /// Lights.
    pub lights: Vec<LightMark>,
    /// The camera (when its rays are drawn).
    pub camera: Option<CameraMark>,
    /// Zoom insets.
    pub insets: Vec<Inset>,
    /// The legend box.
    pub legend_rect: Rect,
    /// Legend swatches.
    pub legend: Vec<LegendEntry>,
    /// All text.
    pub labels: Vec<Label>,
    /// Number of segments that leave the plane.
    pub off_plane_rays: usize,
    /// Rays of the sample left out by the contribution threshold.
    pub dropped_rays: usize,
    /// The part of the sample's value those rays carry (a fraction, luminance).
    pub dropped_share: f64,
    /// Other samples left out whole by [`super::all_samples::MAX_OTHER_RAYS`] (all-samples
    /// figures only).
    pub other_samples_left_out: usize,
}
