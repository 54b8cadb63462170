//! Building the diagram: rays to 3D segments, framing, projection onto the canvas.

use super::layout::{self, Pending};
use super::model::{
    Anchor, CameraMark, Diagram, LabelRole, LightMark, Point, RayEnd, RaySegment, Rect,
};
use super::{DiagramError, DiagramOptions, annotate, inset, objects, plane};
use crate::scene::{LightKind, Scene};
use crate::tree::{EndReason, RayKind, RayNode, RayTree};
use glam::{DVec2, DVec3};

/// A ray as a 3D segment before projection.
pub(super) struct Seg3<'a> {
    pub node: &'a RayNode,
    pub start: DVec3,
    /// Finite end point, `None` for rays that leave the scene.
    pub end: Option<DVec3>,
    pub end_kind: RayEnd,
}

fn seg3<'a>(scene: &Scene, n: &'a RayNode) -> Seg3<'a> {
    let start = if n.kind == RayKind::Camera {
        n.origin
    } else {
        n.spawn_point
    };
    let (end, end_kind) = match (&n.shadow, &n.hit) {
        (Some(s), _) => match n.end {
            EndReason::LightBehind => (None, RayEnd::LightBehind),
            EndReason::Blocked => {
                let b = s
                    .blockers
                    .iter()
                    .find(|b| b.factor == DVec3::ZERO)
                    .or(s.blockers.first());
                let t = b.map_or(0.0, |b| b.t);
                (Some(n.origin + t * n.direction), RayEnd::Blocked)
            }
            _ => match scene.lights.get(s.light).map(|l| &l.kind) {
                Some(LightKind::Point { position, .. }) => (Some(*position), RayEnd::Light),
                _ => (None, RayEnd::Light),
            },
        },
        (None, Some(h)) => (Some(h.point), RayEnd::Hit),
        (None, None) => (None, RayEnd::Miss),
    };
    Seg3 {
        node: n,
        start,
        end,
        end_kind,
    }
}

/// Font size for `width x height`: 17 px at 1280x720, never below 11.
fn font_size(w: f64, h: f64) -> f64 {
    (w.min(h * 16.0 / 9.0) / 1280.0 * 17.0).max(11.0)
}

/// The ray parameter where the canvas ray `from + t * dir` leaves `rect` (`t >= 0`).
pub(super) fn exit_param(from: Point, dir: Point, rect: &Rect) -> f64 {
    let mut t = f64::INFINITY;
    for (p, d, lo, hi) in [
        (from.x, dir.x, rect.min.x, rect.max.x),
        (from.y, dir.y, rect.min.y, rect.max.y),
    ] {
        if d > 0.0 {
            t = t.min((hi - p) / d);
        } else if d < 0.0 {
            t = t.min((lo - p) / d);
        }
    }
    if t.is_finite() { t.max(0.0) } else { 0.0 }
}

impl Diagram {
    /// Build the diagram of `tree` (recorded from `scene`) with `opts`.
    pub fn build(
        scene: &Scene,
        tree: &RayTree,
        opts: &DiagramOptions,
    ) -> Result<Diagram, DiagramError> {
        let (wi, hi) = (opts.width, opts.height);
        if !(64..=16384).contains(&wi) || !(64..=16384).contains(&hi) {
            return Err(DiagramError::BadSize(wi, hi));
        }
        let sample = tree
            .samples
            .get(opts.sample)
            .ok_or(DiagramError::NoSuchSample {
                sample: opts.sample,
                count: tree.samples.len(),
            })?;
        let (w, h) = (f64::from(wi), f64::from(hi));
        let fs = font_size(w, h);
        let (mut frame, plane_text) = plane::choose(opts.plane, scene, tree, opts.sample);
        let segs: Vec<Seg3> = tree
            .depth_first(sample.root)
            .into_iter()
            .map(|id| tree.node(id))
            .filter(|n| opts.kinds.contains(&n.kind))
            .filter(|n| opts.max_depth.is_none_or(|d| n.depth <= d))
            .map(|n| seg3(scene, n))
            .collect();
        let camera_drawn = segs.iter().any(|s| s.node.kind == RayKind::Camera);
        let cam = &scene.camera;
        let pixel3 = {
            let [fx, fy] = sample.film;
            let (u, v) = cam.film_to_plane(fx, fy);
            cam.position + cam.forward + u * cam.right + v * cam.up
        };
        // Framing: everything finite the tree touches, the camera and the image plane.
        let mut pts: Vec<DVec3> = Vec::new();
        for s in &segs {
            pts.push(s.start);
            pts.extend(s.end);
        }
        if camera_drawn {
            pts.extend([cam.position, pixel3]);
        }
        let extent3 = pts
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let extent3 = (extent3.1 - extent3.0).max_element().max(1e-9);
        let (legend_pending, legend_entries, legend_rect) =
            layout::legend(&segs, &frame, extent3, &plane_text, opts, w, h, fs);
        let top = if opts.title.is_empty() { fs } else { fs * 2.4 };
        let view = Rect::new(
            DVec2::new(fs, top),
            DVec2::new(w - fs, legend_rect.min.y - fs * 0.5),
        );
        let bounds = |pts: &mut dyn Iterator<Item = DVec3>| {
            pts.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
                let q = frame.plane_coords(p);
                (lo.min(q), hi.max(q))
            })
        };
        let (lo, hi) = bounds(&mut pts.iter().copied());
        // Where the rays interact (hits, blockers, spawn points). When the eye or a light is
        // far away, frame on this part and let those rays enter or leave through the frame.
        let mut core = segs.iter().flat_map(|s| {
            let start = (s.node.kind != RayKind::Camera).then_some(s.start);
            let end = s
                .end
                .filter(|_| matches!(s.end_kind, RayEnd::Hit | RayEnd::Blocked));
            start.into_iter().chain(end)
        });
        let (clo, chi) = bounds(&mut core);
        let zoomed = clo.x.is_finite()
            && (hi - lo).max_element() > 3.0 * (chi - clo).max_element().max(extent3 * 0.02);
        let (lo, hi) = if zoomed { (clo, chi) } else { (lo, hi) };
        let (lo, hi) = if lo.x.is_finite() {
            (lo, hi)
        } else {
            (DVec2::splat(-1.0), DVec2::ONE)
        };
        let pad = 3.0 * fs;
        let size = (hi - lo).max(DVec2::splat(extent3 * 0.05));
        let avail = (view.size() - DVec2::splat(2.0 * pad)).max(DVec2::splat(10.0));
        frame.scale = (avail.x / size.x).min(avail.y / size.y);
        frame.plane_center = (lo + hi) * 0.5;
        frame.canvas_center = (view.min + view.max) * 0.5;

        let mut rays = Vec::with_capacity(segs.len());
        for s in &segs {
            let mut r = project(s, &frame, &view, extent3, fs, opts);
            r.tir = s.node.kind == RayKind::Reflected
                && s.node
                    .parent
                    .is_some_and(|p| tree.node(p).interface.as_ref().is_some_and(|i| i.tir));
            if zoomed {
                clip_to(&mut r, &view);
            }
            rays.push(r);
        }
        let mut pending: Vec<Pending> = legend_pending;
        if !opts.title.is_empty() {
            pending.push(Pending::fixed(
                DVec2::new(fs, fs * 1.6),
                Anchor::Start,
                &opts.title,
                fs * 1.15,
                LabelRole::Title,
            ));
        }
        let objs = objects::slices(scene, &frame, &view, fs, &mut pending);
        let hits = annotate::hits(tree, &segs, &rays, &frame, fs, opts, &mut pending);
        let lights = light_marks(scene, &segs, &rays, &frame, extent3, fs, &mut pending);
        let eye_visible = view.contains_rect(&Rect::new(
            frame.to_canvas(cam.position),
            frame.to_canvas(cam.position),
        ));
        let camera = (camera_drawn && eye_visible).then(|| {
            camera_mark(
                scene,
                pixel3,
                (sample.film[0], sample.film[1]),
                &frame,
                fs,
                &mut pending,
            )
        });
        let insets = if opts.zoom_offsets {
            inset::insets(scene, tree, &segs, &frame, &view, fs, &mut pending)
        } else {
            Vec::new()
        };
        let mut placed_boxes: Vec<Rect> = insets.iter().map(|i| i.rect).collect();
        placed_boxes.push(legend_rect);
        let labels = layout::place(
            pending,
            Rect::new(DVec2::ZERO, DVec2::new(w, h)),
            placed_boxes,
        );
        let off_plane_rays = rays.iter().filter(|r| r.off_plane).count();
        Ok(Diagram {
            width: w,
            height: h,
            frame,
            view,
            plane_text,
            objects: objs,
            rays,
            hits,
            lights,
            camera,
            insets,
            legend_rect,
            legend: legend_entries,
            labels,
            off_plane_rays,
        })
    }
}

/// Whether a 3D distance from the plane counts as "off the plane": more than 1/1000 of the
/// figure's extent (about a pixel at 1280 wide), so rounding and near-planar bounces stay solid.
pub(super) fn is_off(d: f64, extent3: f64) -> bool {
    d.abs() > 1e-3 * extent3
}

/// Opacity for a distance from the plane: 1 on it, fading to 0.3.
pub(super) fn fade(d: f64, extent3: f64) -> f64 {
    if is_off(d, extent3) {
        (0.85 - 1.5 * d.abs() / extent3).max(0.3)
    } else {
        1.0
    }
}

fn project(
    s: &Seg3,
    frame: &plane::PlaneFrame,
    view: &Rect,
    extent3: f64,
    fs: f64,
    opts: &DiagramOptions,
) -> RaySegment {
    let n = s.node;
    let from = frame.to_canvas(s.start);
    let dc = frame.dir_to_canvas(n.direction) * frame.scale;
    let (to, end3) = match s.end {
        Some(e) => (frame.to_canvas(e), e),
        None if s.end_kind == RayEnd::LightBehind => {
            let d = dc.try_normalize().unwrap_or(DVec2::ZERO) * 1.5 * fs;
            (from + d, s.start + n.direction * (1.5 * fs / frame.scale))
        }
        None => {
            if dc.length() * 1e6 < frame.scale {
                (from, s.start)
            } else {
                let t = exit_param(from, dc, view);
                (from + t * dc, s.start + t * n.direction)
            }
        }
    };
    let d = [frame.distance(s.start), frame.distance(end3)];
    let far = if d[0].abs() > d[1].abs() { d[0] } else { d[1] };
    let throughput = if n.kind == RayKind::Shadow {
        // Shadow rays carry the throughput of the surface they leave.
        n.parent.map_or(1.0, |_| n.throughput.max_element())
    } else {
        n.throughput.max_element()
    };
    RaySegment {
        node: n.id,
        kind: n.kind,
        depth: n.depth,
        from,
        to,
        end: s.end_kind,
        throughput: throughput.clamp(0.0, 1.0),
        plane_distance: d,
        off_plane: is_off(far, extent3),
        fade: fade(far, extent3),
        tir: false,
        highlighted: opts.highlight == Some(n.id),
    }
}

fn light_marks(
    scene: &Scene,
    segs: &[Seg3],
    rays: &[RaySegment],
    frame: &plane::PlaneFrame,
    extent3: f64,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> Vec<LightMark> {
    let mut out: Vec<LightMark> = Vec::new();
    for (s, r) in segs.iter().zip(rays) {
        let Some(info) = &s.node.shadow else { continue };
        if out.iter().any(|m| m.light == info.light) {
            continue;
        }
        let Some(light) = scene.lights.get(info.light) else {
            continue;
        };
        let (point, directional, dist) = match light.kind {
            LightKind::Point { position, .. } => {
                let p = frame.to_canvas(position);
                // A light outside the frame is marked where its shadow ray leaves it.
                let p = if (p - r.to).length() > 1.0 && r.end == RayEnd::Light {
                    r.to
                } else {
                    p
                };
                (p, None, frame.distance(position))
            }
            LightKind::Directional { direction, .. } => {
                if matches!(r.end, RayEnd::Light) {
                    let d = frame.dir_to_canvas(direction).try_normalize();
                    (r.to, d, 0.0)
                } else {
                    continue;
                }
            }
        };
        let f = fade(dist, extent3);
        let mut text = light.name.clone();
        if is_off(dist, extent3) {
            text = format!("{text} ({dist:+.2} off plane)");
        }
        pending.push(Pending::new(
            vec![
                (point + DVec2::new(0.9 * fs, -0.6 * fs), Anchor::Start),
                (point + DVec2::new(-0.9 * fs, -0.6 * fs), Anchor::End),
                (point + DVec2::new(0.0, 1.6 * fs), Anchor::Middle),
            ],
            &text,
            fs,
            LabelRole::Light,
            0,
        ));
        out.push(LightMark {
            light: info.light,
            point,
            directional,
            plane_distance: dist,
            fade: f,
        });
    }
    out
}

fn camera_mark(
    scene: &Scene,
    pixel3: DVec3,
    film: (f64, f64),
    frame: &plane::PlaneFrame,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> CameraMark {
    let cam = &scene.camera;
    let corner = |fx: f64, fy: f64| {
        let (u, v) = cam.film_to_plane(fx, fy);
        cam.position + cam.forward + u * cam.right + v * cam.up
    };
    let (w, h) = (f64::from(cam.width), f64::from(cam.height));
    let image = [
        corner(0.0, 0.0),
        corner(w, 0.0),
        corner(w, h),
        corner(0.0, h),
    ];
    let (px, py) = (film.0.floor(), film.1.floor());
    let pixel = [
        corner(px, py),
        corner(px + 1.0, py),
        corner(px + 1.0, py + 1.0),
        corner(px, py + 1.0),
    ];
    let cut = |q: &[DVec3; 4]| {
        let p = objects::cut_quad(q, frame);
        p.map(|(a, b)| (frame.plane_to_canvas(a), frame.plane_to_canvas(b)))
    };
    let eye = frame.to_canvas(cam.position);
    let p = frame.to_canvas(pixel3);
    pending.push(Pending::new(
        vec![
            (eye + DVec2::new(-0.6 * fs, 1.5 * fs), Anchor::End),
            (eye + DVec2::new(0.0, -0.9 * fs), Anchor::Middle),
            (eye + DVec2::new(0.0, 1.8 * fs), Anchor::Middle),
        ],
        "A (eye)",
        fs,
        LabelRole::Camera,
        0,
    ));
    pending.push(Pending::new(
        vec![
            (p + DVec2::new(0.5 * fs, -0.7 * fs), Anchor::Start),
            (p + DVec2::new(0.5 * fs, 1.4 * fs), Anchor::Start),
            (p + DVec2::new(-0.5 * fs, -0.7 * fs), Anchor::End),
        ],
        "P (pixel centre)",
        fs,
        LabelRole::Camera,
        0,
    ));
    CameraMark {
        eye,
        image_plane: cut(&image),
        pixel: p,
        pixel_span: cut(&pixel),
    }
}

/// Clip a segment to `rect` (Liang-Barsky); a segment entirely outside keeps zero length at
/// its start so it still appears once in the model.
fn clip_to(r: &mut RaySegment, rect: &Rect) {
    let d = r.to - r.from;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, r.from.x - rect.min.x),
        (d.x, rect.max.x - r.from.x),
        (-d.y, r.from.y - rect.min.y),
        (d.y, rect.max.y - r.from.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                t1 = -1.0;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    if t0 > t1 {
        r.to = r.from;
        return;
    }
    let from = r.from + d * t0;
    r.to = r.from + d * t1;
    r.from = from;
}
