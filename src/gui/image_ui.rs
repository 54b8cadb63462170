//! The image panel: zoom and pan, pixel grid, hover readout, selection, ray-path overlay and the
//! debug-view legend.

use super::document::{Command, Document};
use super::project::path_segments;
use super::stats::{self, DebugView};
use super::style::{SELECTED, kind_colour, rgb};
use crate::math::linear_to_srgb8;
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, StrokeKind, Vec2, pos2, vec2};

/// Zoom at which the pixel grid appears (screen points per pixel).
const GRID_ZOOM: f32 = 8.0;

/// Where the image was drawn this frame (for tests and hit-testing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImagePlacement {
    /// Screen rectangle of the whole image.
    pub rect: Rect,
    /// Points per image pixel.
    pub zoom: f32,
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
    cmds: &mut Vec<Command>,
) -> ImagePlacement {
    let area = ui.available_rect_before_wrap();
    let resp = ui.allocate_rect(area, Sense::click_and_drag());
    let (w, h) = (doc.image.width as f32, doc.image.height as f32);
    let fit = (area.width() / w).min(area.height() / h).max(1e-3);
    let zoom = doc.view.zoom.unwrap_or(fit);
    let centre = area.center() + Vec2::from(doc.view.pan);
    let place = ImagePlacement {
        rect: Rect::from_center_size(centre, vec2(w, h) * zoom),
        zoom,
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
        overlay(&painter, place, doc);
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
        hover_readout(&painter, area, place.film_of(p), doc);
    }
    if doc.view.debug != DebugView::Off {
        legend(&painter, area, doc);
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

fn overlay(painter: &egui::Painter, place: ImagePlacement, doc: &Document) {
    let Some(tree) = &doc.tree else { return };
    let to_screen = |p: [f64; 2]| place.rect.min + vec2(p[0] as f32, p[1] as f32) * place.zoom;
    for seg in path_segments(&doc.scene.camera, tree) {
        let selected = doc.node == Some(seg.node);
        // Shadow rays are many and long: draw them faint so the bounce path stays readable.
        let (width, colour) = match (selected, seg.kind) {
            (true, _) => (3.5, SELECTED),
            (false, crate::tree::RayKind::Shadow) => {
                (1.0, kind_colour(seg.kind).gamma_multiply(0.45))
            }
            (false, k) => (1.5, kind_colour(k)),
        };
        let [a, b] = seg.film.map(to_screen);
        painter.line_segment(
            [a, b],
            Stroke::new(width + 1.5, Color32::from_black_alpha(140)),
        );
        painter.line_segment([a, b], Stroke::new(width, colour));
        painter.circle_filled(a, width, colour);
    }
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

fn hover_readout(painter: &egui::Painter, area: Rect, film: Vec2, doc: &Document) {
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
        "pixel {x}, {y}\nlinear {}\nsRGB {} {} {}\ndepth {}  rays {}  TIR {}  self-hits {}  leaks {}  cut {:.3}\nBVH nodes + primitive tests {}",
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
    let pos = area.left_top() + vec2(8.0, 8.0);
    let galley = painter.layout_no_wrap(text, FontId::monospace(12.0), Color32::WHITE);
    let bg = Rect::from_min_size(pos, galley.size()).expand(5.0);
    painter.rect_filled(bg, 4.0, Color32::from_black_alpha(190));
    painter.galley(pos, galley, Color32::WHITE);
}

fn legend(painter: &egui::Painter, area: Rect, doc: &Document) {
    let view = doc.view.debug;
    let (_, max) = stats::range(view, &doc.stats);
    let bar = Rect::from_min_size(area.left_bottom() + vec2(12.0, -40.0), vec2(240.0, 14.0));
    painter.rect_filled(bar.expand(24.0), 4.0, Color32::from_black_alpha(190));
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
    let font = FontId::proportional(12.0);
    painter.text(
        bar.left_top() - vec2(0.0, 4.0),
        Align2::LEFT_BOTTOM,
        view.label(),
        font.clone(),
        Color32::WHITE,
    );
    painter.text(
        bar.left_bottom() + vec2(0.0, 3.0),
        Align2::LEFT_TOP,
        "0 (black)",
        font.clone(),
        Color32::WHITE,
    );
    painter.text(
        bar.right_bottom() + vec2(0.0, 3.0),
        Align2::RIGHT_TOP,
        if view.clips() {
            format!("{max:.0} and above (99th percentile)")
        } else {
            format!("{max:.3}")
        },
        font,
        Color32::WHITE,
    );
}
