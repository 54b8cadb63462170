//! The diagram panel: the selected pixel's cross-section (from [`crate::diagram`]), the
//! selected node highlighted, with its controls (`controls.rs`: plane, depth, kinds,
//! labels, threshold, sample, insets, export highlight), zoom and pan. The figure is drawn by
//! the PNG export's rasteriser (dark theme) into a texture, on a thread of its own, once per
//! change: a frame paints one image instead of tessellating hundreds of rays and labels, and a
//! click does not wait for the rasteriser (the previous figure stays, marked, until it is done).

pub(super) mod controls;

use crate::diagram::model::Anchor;
use crate::diagram::paint::{Prim, Rgba};
use crate::diagram::{Diagram, Style, Theme, display_list, to_pixmap};
use crate::gui::model::diagram::diagram_options;
use crate::gui::model::diagram_view::DiagramView;
use crate::gui::model::document::{Command, Document};
use crate::tree::NodeId;
use egui::{
    Align2, Color32, ColorImage, FontId, Pos2, Shape, Stroke, TextureHandle, TextureOptions, pos2,
};
use std::sync::mpsc::{Receiver, channel};

/// What a cached display list was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    tree_version: u64,
    node: Option<NodeId>,
    view: DiagramView,
    size: [u32; 2],
    /// Deepest depth drawn (step along a ray).
    depth: Option<u32>,
}

/// A figure to rasterise: the key it is for, the diagram, and whom to wake when it is done.
type Job = (Key, Diagram, egui::Context);

/// The rasteriser ([`crate::gui::jobs::background::Lane`]): always draws the newest job
/// waiting, sends back its pixels.
struct Rasteriser {
    jobs: crate::gui::jobs::background::Lane<Job>,
    done: Receiver<(Key, ColorImage)>,
}

impl Rasteriser {
    fn start() -> Option<Self> {
        let (tx, done) = channel();
        // Only the newest figure matters (arrow keys held down queue many).
        let jobs =
            crate::gui::jobs::background::Lane::new("raytree-diagram", None, move |job: Job| {
                let (key, d, ctx) = job;
                let pm = to_pixmap(&d, &Style::new(Theme::Dark));
                let img = ColorImage::from_rgba_premultiplied(
                    [pm.width() as usize, pm.height() as usize],
                    pm.data(),
                );
                if tx.send((key, img)).is_ok() {
                    ctx.request_repaint();
                }
            })
            .ok()?;
        Some(Self { jobs, done })
    }
}

/// The last diagram built, reused while nothing it depends on changes.
pub struct DiagramCache {
    key: Option<Key>,
    /// The display list of the figure for `key` (built at once; cheap).
    prims: Result<Vec<Prim>, String>,
    /// The figure on screen and the key it was drawn for.
    texture: Option<(TextureHandle, Key)>,
    /// Whether the figure for `key` is still being drawn.
    pending: bool,
    /// The world-to-canvas mapping of the figure for `key` (the step point; zoom about the
    /// cursor, pan by dragging).
    frame: Option<crate::diagram::PlaneFrame>,
    rasteriser: Option<Rasteriser>,
    /// Rays drawn and left out in the figure for `key` (for tests and the status line).
    counts: (usize, usize),
}

impl Default for DiagramCache {
    fn default() -> Self {
        Self {
            key: None,
            prims: Ok(Vec::new()),
            texture: None,
            pending: false,
            frame: None,
            rasteriser: None,
            counts: (0, 0),
        }
    }
}

impl DiagramCache {
    /// The display list of the figure shown and its size (for tests: it must equal a fresh
    /// build).
    #[must_use]
    pub fn display_list(&self) -> Option<([u32; 2], &[Prim])> {
        Some((self.key?.size, self.prims.as_deref().ok()?))
    }

    /// Rays drawn and rays left out by the threshold in the figure shown.
    #[must_use]
    pub fn ray_counts(&self) -> (usize, usize) {
        self.counts
    }

    /// Build the figure for `key`: the display list now, the pixels on the rasteriser's thread.
    fn rebuild(&mut self, ctx: &egui::Context, doc: &Document, key: Key) {
        self.key = Some(key);
        self.pending = false;
        self.frame = None;
        let built = doc
            .tree
            .as_ref()
            .ok_or_else(|| "select a pixel".to_string())
            .and_then(|tree| {
                Diagram::build(&doc.scene, tree, &diagram_options(doc, key.size))
                    .map_err(|e| e.to_string())
            });
        let d = match built {
            Ok(d) => d,
            Err(e) => {
                self.prims = Err(e);
                return;
            }
        };
        self.prims = Ok(display_list(&d, &Style::new(Theme::Dark)));
        self.frame = Some(d.frame);
        self.counts = (d.rays.len(), d.dropped_rays);
        if self.rasteriser.is_none() {
            self.rasteriser = Rasteriser::start();
        }
        if let Some(r) = &self.rasteriser {
            self.pending = r.jobs.send((key, d, ctx.clone()));
        }
    }

    /// Take finished figures into the texture (only the current key's is shown).
    fn receive(&mut self, ctx: &egui::Context) {
        let Some(r) = &self.rasteriser else { return };
        while let Ok((key, img)) = r.done.try_recv() {
            if Some(key) != self.key {
                continue;
            }
            self.pending = false;
            match &mut self.texture {
                Some((t, k)) => {
                    t.set(img, TextureOptions::LINEAR);
                    *k = key;
                }
                None => {
                    let t = ctx.load_texture("raytree-diagram", img, TextureOptions::LINEAR);
                    self.texture = Some((t, key));
                }
            }
        }
    }
}

/// The panel: controls, then the figure (scroll zooms about the cursor, drag pans,
/// double-click goes back to the automatic framing).
pub fn diagram_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    cache: &mut DiagramCache,
    cmds: &mut Vec<Command>,
) {
    let mut v = doc.view;
    controls::controls_ui(ui, doc, &mut v.diagram);
    if v != doc.view {
        cmds.push(Command::SetView(v));
    }
    if doc.tree.is_none() {
        ui.label("Select a pixel to see its diagram.");
        // Fill the panel: egui keeps a bottom panel's height from its content, so a panel
        // holding one line would stay one line tall once a diagram arrives.
        ui.allocate_space(ui.available_size());
        return;
    }
    let area = ui.available_rect_before_wrap();
    let size = [
        area.width().max(64.0) as u32,
        area.height().max(64.0) as u32,
    ];
    let key = Key {
        tree_version: doc.tree_version,
        node: doc.node,
        view: doc.view.diagram,
        size,
        depth: doc.step.depth,
    };
    if cache.key != Some(key) {
        cache.rebuild(ui.ctx(), doc, key);
    }
    cache.receive(ui.ctx());
    let response = ui.allocate_rect(area, egui::Sense::click_and_drag());
    if let Some(frame) = cache.frame
        && let Some(d) = controls::navigate(ui, &response, area, &frame, doc.view.diagram)
    {
        let mut v = doc.view;
        v.diagram = d;
        cmds.push(Command::SetView(v));
    }
    let painter = ui.painter_at(area);
    if let Err(e) = &cache.prims {
        painter.text(
            area.center(),
            Align2::CENTER_CENTER,
            e,
            FontId::proportional(14.0),
            Color32::LIGHT_RED,
        );
        return;
    }
    if let Some((tex, _)) = &cache.texture {
        let [w, h] = tex.size();
        let rect = egui::Rect::from_min_size(area.min, egui::vec2(w as f32, h as f32));
        let uv = egui::Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
        painter.image(tex.id(), rect, uv, Color32::WHITE);
        if let Some(frame) = &cache.frame {
            super::step::paint_on_diagram(&painter, doc, frame, area.min);
        }
    }
    if cache.pending {
        painter.text(
            area.right_top() + egui::vec2(-8.0, 6.0),
            Align2::RIGHT_TOP,
            "drawing…",
            FontId::proportional(13.0),
            Color32::from_gray(200),
        );
    }
}

fn colour(c: Rgba) -> Color32 {
    Color32::from_rgba_unmultiplied(c.0, c.1, c.2, c.3)
}

/// Paint a display list with its canvas origin at `origin` (one canvas pixel = one point).
pub fn paint(painter: &egui::Painter, origin: Pos2, prims: &[Prim]) {
    let mut shapes = Vec::new();
    prim_shapes(origin, prims, &mut shapes);
    painter.extend(shapes);
    paint_texts(painter, origin, prims);
}

/// The lines, fills and circles of a display list as egui shapes (labels apart).
fn prim_shapes(origin: Pos2, prims: &[Prim], out: &mut Vec<Shape>) {
    let at = |p: glam::DVec2| pos2(origin.x + p.x as f32, origin.y + p.y as f32);
    for prim in prims {
        match prim {
            Prim::Fill { points, color } => {
                let pts = points.iter().map(|p| at(*p)).collect();
                out.push(Shape::convex_polygon(pts, colour(*color), Stroke::NONE));
            }
            Prim::Stroke {
                points,
                color,
                width,
                dash,
                closed,
            } => {
                let mut pts: Vec<Pos2> = points.iter().map(|p| at(*p)).collect();
                if *closed && let Some(first) = pts.first().copied() {
                    pts.push(first);
                }
                let stroke = Stroke::new(*width as f32, colour(*color));
                match dash {
                    Some([d, g]) => {
                        out.extend(Shape::dashed_line(&pts, stroke, *d as f32, *g as f32));
                    }
                    None => out.push(Shape::line(pts, stroke)),
                }
            }
            Prim::Circle {
                center,
                radius,
                fill,
                stroke,
            } => {
                if let Some(f) = fill {
                    out.push(Shape::circle_filled(
                        at(*center),
                        *radius as f32,
                        colour(*f),
                    ));
                }
                if let Some((c, w)) = stroke {
                    let s = Stroke::new(*w as f32, colour(*c));
                    out.push(Shape::circle_stroke(at(*center), *radius as f32, s));
                }
            }
            Prim::Text { .. } => {}
        }
    }
}

/// The labels of a display list.
fn paint_texts(painter: &egui::Painter, origin: Pos2, prims: &[Prim]) {
    let at = |p: glam::DVec2| pos2(origin.x + p.x as f32, origin.y + p.y as f32);
    for prim in prims {
        if let Prim::Text {
            pos,
            text,
            size,
            color,
            anchor,
            ..
        } = prim
        {
            let align = match anchor {
                Anchor::Start => Align2::LEFT_BOTTOM,
                Anchor::Middle => Align2::CENTER_BOTTOM,
                Anchor::End => Align2::RIGHT_BOTTOM,
            };
            // The baseline is a little above the bottom of egui's text box.
            let p = at(*pos) + egui::vec2(0.0, *size as f32 * 0.22);
            painter.text(
                p,
                align,
                text,
                FontId::proportional(*size as f32),
                colour(*color),
            );
        }
    }
}
