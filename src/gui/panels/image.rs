//! The image panel: zoom and pan, pixel grid, hover readout, selection, ray-path overlay and the
//! debug-view legend (in a strip below the image, never over it).

use crate::gui::model::document::{Command, Document};
use crate::gui::model::project::{clip_to_film, sample_segments};
use crate::gui::model::stats::{self, DebugView};
use crate::gui::style::{SELECTED, kind_colour, rgb};
use crate::math::linear_to_srgb8;
use egui::epaint::{Mesh, TessellationOptions, Tessellator};
use egui::{Color32, FontId, Pos2, Rect, Sense, Shape, Stroke, StrokeKind, Vec2, pos2, vec2};
use std::sync::Arc;

/// Zoom at which the pixel grid appears (screen points per pixel).
const GRID_ZOOM: f32 = 8.0;
/// Least height of the legend strip under the image when a debug view is on (points); it
/// grows when the panel is too narrow for the legend's lines.
const LEGEND_HEIGHT: f32 = 58.0;
/// The legend's margin from the strip's left and right edges (points).
const LEGEND_MARGIN: f32 = 12.0;
/// The legend's colour bar: at most this wide (points), narrower in a narrow panel.
const LEGEND_BAR: f32 = 240.0;

/// What the overlay mesh was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct OverlayKey {
    tree_version: u64,
    node: Option<crate::tree::NodeId>,
    rect: Rect,
    pixels_per_point: f32,
    /// Deepest depth drawn (step along a ray).
    depth: Option<u32>,
}

/// The ray overlay tessellated once per change (selection, node, zoom, pan): a frame adds one
/// mesh instead of re-tessellating every ray.
#[derive(Default)]
pub struct OverlayCache {
    key: Option<OverlayKey>,
    mesh: Arc<Mesh>,
    /// Rays drawn (segments inside the image).
    pub rays: usize,
}
/// Where the image was drawn this frame (for tests and hit-testing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImagePlacement {
    /// Screen rectangle of the whole image.
    pub rect: Rect,
    /// Points per image pixel.
    pub zoom: f32,
    /// The debug-view legend's strip, under the image (none without a debug view).
    pub legend: Option<Rect>,
}

impl ImagePlacement {
    /// Screen position of the centre of pixel (x, y).
    #[must_use]
    pub fn screen_of(&self, x: u32, y: u32) -> Pos2 {
        self.rect.min + vec2(x as f32 + 0.5, y as f32 + 0.5) * self.zoom
    }

    /// Film position (pixels) of a screen point.
    #[must_use]
    pub fn film_of(&self, p: Pos2) -> Vec2 {
        (p - self.rect.min) / self.zoom
    }
}

/// Show the image; push commands; return where it was drawn.
pub fn image_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    texture: Option<egui::TextureId>,
    overlay_cache: &mut OverlayCache,
    cmds: &mut Vec<Command>,
) -> ImagePlacement {
    let mut area = ui.available_rect_before_wrap();
    let legend_text =
        (doc.view.debug != DebugView::Off).then(|| legend_layout(ui, doc, area.width()));
    let legend_strip = legend_text.as_ref().map(|l| {
        let strip = Rect::from_min_max(pos2(area.min.x, area.max.y - l.height), area.max);
        area.max.y -= l.height;
        strip
    });
    let resp = ui.allocate_rect(area, Sense::click_and_drag());
    let (w, h) = (doc.image.width as f32, doc.image.height as f32);
    let fit = (area.width() / w).min(area.height() / h).max(1e-3);
    let zoom = doc.view.zoom.unwrap_or(fit);
    let centre = area.center() + Vec2::from(doc.view.pan);
    let place = ImagePlacement {
        rect: Rect::from_center_size(centre, vec2(w, h) * zoom),
        zoom,
        legend: legend_strip,
    };
    let painter = ui.painter_at(area);
    painter.rect_filled(area, 0.0, Color32::from_gray(24));
    if let Some(tex) = texture {
        let uv = Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
        painter.image(tex, place.rect, uv, Color32::WHITE);
    }
    if zoom >= GRID_ZOOM {
        grid(&painter, place, area, doc);
    }
    if doc.view.overlay {
        overlay(ui, &painter, place, area, doc, overlay_cache);
    }
    if let Some([x, y]) = doc.selection {
        let r = Rect::from_min_size(
            place.screen_of(x, y) - Vec2::splat(zoom * 0.5),
            Vec2::splat(zoom),
        );
        painter.rect_stroke(
            r.expand(2.0),
            0.0,
            Stroke::new(2.0, SELECTED),
            StrokeKind::Outside,
        );
    }
    interact(ui, &resp, place, fit, doc, cmds);
    if let Some(p) = resp.hover_pos() {
        hover_readout(ui, area, place.film_of(p), doc);
    }
    if let (Some(strip), Some(text)) = (legend_strip, legend_text) {
        legend(&ui.painter_at(strip), strip, text);
    }
    place
}

fn grid(painter: &egui::Painter, place: ImagePlacement, area: Rect, doc: &Document) {
    let stroke = Stroke::new(1.0, Color32::from_black_alpha(110));
    let vis = place.rect.intersect(area);
    let x0 = ((vis.min.x - place.rect.min.x) / place.zoom)
        .floor()
        .max(0.0) as u32;
    let x1 = (((vis.max.x - place.rect.min.x) / place.zoom).ceil() as u32).min(doc.image.width);
    let y0 = ((vis.min.y - place.rect.min.y) / place.zoom)
        .floor()
        .max(0.0) as u32;
    let y1 = (((vis.max.y - place.rect.min.y) / place.zoom).ceil() as u32).min(doc.image.height);
    for x in x0..=x1 {
        let sx = place.rect.min.x + x as f32 * place.zoom;
        painter.vline(sx, vis.y_range(), stroke);
    }
    for y in y0..=y1 {
        let sy = place.rect.min.y + y as f32 * place.zoom;
        painter.hline(vis.x_range(), sy, stroke);
    }
}

/// The selected sample's rays (the sample holding the selected node), projected and clipped to
/// the image; a shadow ray stopped by an opaque blocker ends there with a cross.
fn overlay(
    ui: &egui::Ui,
    painter: &egui::Painter,
    place: ImagePlacement,
    area: Rect,
    doc: &Document,
    cache: &mut OverlayCache,
) {
    let Some(tree) = &doc.tree else { return };
    let key = OverlayKey {
        tree_version: doc.tree_version,
        node: doc.node,
        rect: place.rect,
        pixels_per_point: ui.ctx().pixels_per_point(),
        depth: doc.step.depth,
    };
    if cache.key != Some(key) {
        cache.key = Some(key);
        let shapes = overlay_shapes(place, doc, tree);
        cache.rays = shapes.1;
        let mut tess = Tessellator::new(
            key.pixels_per_point,
            TessellationOptions::default(),
            [1, 1],
            Vec::new(),
        );
        let mut mesh = Mesh::default();
        for shape in shapes.0 {
            tess.tessellate_shape(shape, &mut mesh);
        }
        cache.mesh = Arc::new(mesh);
    }
    let clipped = painter.with_clip_rect(place.rect.intersect(area));
    clipped.add(Shape::Mesh(Arc::clone(&cache.mesh)));
    super::step::paint_on_image(&clipped, doc, |p| {
        place.rect.min + vec2(p[0] as f32, p[1] as f32) * place.zoom
    });
}

/// The overlay's shapes (selected ray last, on top) and the number of rays drawn.
fn overlay_shapes(
    place: ImagePlacement,
    doc: &Document,
    tree: &crate::tree::RayTree,
) -> (Vec<Shape>, usize) {
    let to_screen = |p: [f64; 2]| place.rect.min + vec2(p[0] as f32, p[1] as f32) * place.zoom;
    let (w, h) = (f64::from(doc.image.width), f64::from(doc.image.height));
    let mut shapes = Vec::new();
    let mut top = Vec::new();
    let mut rays = 0;
    let shown = |seg: &crate::gui::model::project::PathSegment| {
        doc.step
            .depth
            .is_none_or(|d| tree.node(seg.node).depth <= d)
    };
    for seg in sample_segments(&doc.scene.camera, tree, doc.node)
        .into_iter()
        .filter(shown)
    {
        let Some(film) = clip_to_film(seg.film, w, h) else {
            continue;
        };
        rays += 1;
        let selected = doc.node == Some(seg.node);
        // Shadow rays are many and long: draw them faint so the bounce path stays readable.
        let (width, colour) = match (selected, seg.kind) {
            (true, _) => (3.5, SELECTED),
            (false, crate::tree::RayKind::Shadow) => {
                (1.0, kind_colour(seg.kind).gamma_multiply(0.45))
            }
            (false, k) => (1.5, kind_colour(k)),
        };
        let out = if selected { &mut top } else { &mut shapes };
        let [a, b] = film.map(to_screen);
        // Faint shadow rays need no dark outline, and they start at their surface's hit point,
        // which the bounce ray ending there already marks: half the shapes of a deep tree.
        let shadow = seg.kind == crate::tree::RayKind::Shadow && !selected;
        if !shadow {
            out.push(Shape::line_segment(
                [a, b],
                Stroke::new(width + 1.5, Color32::from_black_alpha(140)),
            ));
        }
        out.push(Shape::line_segment([a, b], Stroke::new(width, colour)));
        if film[0] == seg.film[0] && !shadow {
            out.push(Shape::circle_filled(a, width, colour));
        }
        if seg.blocked && film[1] == seg.film[1] {
            // The blocker: a cross where the shadow ray stops.
            let mark = Stroke::new(2.0, kind_colour(seg.kind));
            let r = 4.0;
            out.push(Shape::line_segment(
                [b + vec2(-r, -r), b + vec2(r, r)],
                mark,
            ));
            out.push(Shape::line_segment(
                [b + vec2(-r, r), b + vec2(r, -r)],
                mark,
            ));
        }
    }
    shapes.extend(top);
    (shapes, rays)
}

fn interact(
    ui: &egui::Ui,
    resp: &egui::Response,
    place: ImagePlacement,
    fit: f32,
    doc: &Document,
    cmds: &mut Vec<Command>,
) {
    let mut view = doc.view;
    if resp.clicked()
        && let Some(p) = resp.interact_pointer_pos()
    {
        let f = place.film_of(p);
        if f.x >= 0.0 && f.y >= 0.0 && f.x < doc.image.width as f32 && f.y < doc.image.height as f32
        {
            cmds.push(Command::SelectPixel([f.x as u32, f.y as u32]));
        }
    }
    if resp.dragged() {
        let d = resp.drag_delta();
        view.pan = [view.pan[0] + d.x, view.pan[1] + d.y];
    }
    if resp.double_clicked() {
        view.zoom = None;
        view.pan = [0.0, 0.0];
    }
    if let Some(hover) = resp.hover_pos() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        let pinch = ui.input(egui::InputState::zoom_delta);
        let factor = (scroll / 200.0).exp() * pinch;
        if (factor - 1.0).abs() > 1e-4 {
            let new_zoom = (place.zoom * factor).clamp(fit.min(1.0) * 0.5, 64.0);
            // Keep the film point under the cursor fixed.
            let film = place.film_of(hover);
            let area_centre = resp.rect.center();
            let new_min = hover - film * new_zoom;
            let size = vec2(doc.image.width as f32, doc.image.height as f32) * new_zoom;
            let new_centre = new_min + size * 0.5;
            view.pan = (new_centre - area_centre).into();
            view.zoom = Some(new_zoom);
        }
    }
    if view != doc.view {
        cmds.push(Command::SetView(view));
    }
}

/// The hovered pixel's values in a box at the top left of the image area (an egui area, so the
/// box is laid out around its text).
fn hover_readout(ui: &egui::Ui, area: Rect, film: Vec2, doc: &Document) {
    if film.x < 0.0
        || film.y < 0.0
        || film.x >= doc.image.width as f32
        || film.y >= doc.image.height as f32
    {
        return;
    }
    let (x, y) = (film.x as u32, film.y as u32);
    let c = doc.image.get(x, y);
    let s = c.to_array().map(linear_to_srgb8);
    let st = doc.stats_at(x, y);
    let text = format!(
        "pixel {x}, {y}\nlinear {}\nsRGB {} {} {}\ndepth {}  rays {}  TIR {}\nself-hits {}  leaks {}  cut {:.3}\nboxes + primitive tests {}",
        rgb(c),
        s[0],
        s[1],
        s[2],
        st.depth,
        st.rays,
        st.tir,
        st.self_hits,
        st.leaks,
        st.cut,
        st.traversal
    );
    egui::Area::new(ui.make_persistent_id("hover-readout"))
        .order(egui::Order::Foreground)
        .fixed_pos(area.left_top() + vec2(8.0, 8.0))
        .interactable(false)
        .show(ui.ctx(), |ui| {
            egui::Frame::new()
                .fill(Color32::from_black_alpha(200))
                .corner_radius(4.0)
                .inner_margin(6.0)
                .show(ui, |ui| {
                    ui.add(
                        egui::Label::new(
                            egui::RichText::new(text)
                                .font(FontId::monospace(12.0))
                                .color(Color32::WHITE),
                        )
                        .extend(),
                    );
                });
        });
}

/// The legend's text laid out for a strip `width` points wide, and the strip's height: every
/// line wraps inside the strip (issue 32: the noise legend was cut at the panel's edge).
struct LegendText {
    title: Arc<egui::Galley>,
    low: Arc<egui::Galley>,
    high: Arc<egui::Galley>,
    bar: f32,
    /// The high end's text goes under the low end's (they do not fit side by side).
    stacked: bool,
    height: f32,
}

fn legend_layout(ui: &egui::Ui, doc: &Document, width: f32) -> LegendText {
    let view = doc.view.debug;
    let (_, max) = stats::range(view, &doc.stats);
    let font = FontId::proportional(12.0);
    let wrap = (width - 2.0 * LEGEND_MARGIN).max(40.0);
    // A pixel of one sample has no spread to estimate: its 0 is not a measured zero.
    let label = if view == DebugView::Noise && doc.stats.iter().any(|s| s.samples < 2) {
        format!("{}; black: one sample, not estimable", view.label())
    } else {
        view.label().to_string()
    };
    let high = if view.clips() && max >= 10.0 {
        format!("{max:.0} and above (99th percentile)")
    } else if view.clips() {
        format!("{max:.3} and above (99th percentile)")
    } else {
        format!("{max:.3}")
    };
    let layout = |t: String| ui.painter().layout(t, font.clone(), Color32::WHITE, wrap);
    let (title, low, high) = (layout(label), layout("0 (black)".into()), layout(high));
    let bar = LEGEND_BAR.min(wrap);
    let stacked = low.size().x + 8.0 + high.size().x > bar;
    let below = if stacked {
        low.size().y + high.size().y
    } else {
        low.size().y.max(high.size().y)
    };
    let height = (title.size().y + 4.0 + 14.0 + 3.0 + below + 10.0).max(LEGEND_HEIGHT);
    LegendText {
        title,
        low,
        high,
        bar,
        stacked,
        height,
    }
}

fn legend(painter: &egui::Painter, area: Rect, text: LegendText) {
    let top = area.left_top() + vec2(LEGEND_MARGIN, 4.0);
    let bar = Rect::from_min_size(
        top + vec2(0.0, text.title.size().y + 4.0),
        vec2(text.bar, 14.0),
    );
    let steps = 48;
    for i in 0..steps {
        let t = (i as f32 + 0.5) / steps as f32;
        let [r, g, b] = stats::ramp(t);
        let x0 = bar.min.x + bar.width() * i as f32 / steps as f32;
        let cell = Rect::from_min_max(
            pos2(x0, bar.min.y),
            pos2(x0 + bar.width() / steps as f32 + 0.5, bar.max.y),
        );
        painter.rect_filled(cell, 0.0, Color32::from_rgb(r, g, b));
    }
    let low_at = bar.left_bottom() + vec2(0.0, 3.0);
    let high_at = if text.stacked {
        low_at + vec2(0.0, text.low.size().y)
    } else {
        bar.right_bottom() + vec2(-text.high.size().x, 3.0)
    };
    painter.galley(top, text.title, Color32::WHITE);
    painter.galley(low_at, text.low, Color32::WHITE);
    painter.galley(high_at, text.high, Color32::WHITE);
}
