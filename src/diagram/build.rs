//! Building the diagram: rays to 3D segments, framing, projection onto the canvas.

use super::layout::{self, Pending};
use super::marks::{camera_mark, light_marks};
use super::model::{Anchor, Diagram, LabelRole, RayEnd, Rect};
use super::segments::{Seg3, clip_to, project, seg3};
use super::{DiagramError, DiagramOptions, annotate, inset, objects, plane};
use crate::scene::Scene;
use crate::tree::{RayKind, RayTree};
use glam::{DVec2, DVec3};

/// Font size for `width x height`: 17 px at 1280x720, never below 11.
fn font_size(w: f64, h: f64) -> f64 {
    (w.min(h * 16.0 / 9.0) / 1280.0 * 17.0).max(11.0)
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
        // Interactions far from those of the labelled depths (a deep bounce's hit a hundred
        // units away) leave through the frame too: the figure is about the first bounces.
        let interactions = || {
            segs.iter().flat_map(|s| {
                let start = (s.node.kind != RayKind::Camera).then_some(s.start);
                let end = s
                    .end
                    .filter(|_| matches!(s.end_kind, RayEnd::Hit | RayEnd::Blocked));
                start.into_iter().chain(end).map(|p| (s.node.depth, p))
            })
        };
        let (nlo, nhi) = bounds(
            &mut interactions()
                .filter(|&(depth, _)| depth <= opts.label_depth)
                .map(|(_, p)| p),
        );
        let margin = 3.0 * (nhi - nlo).max_element().max(extent3 * 0.02);
        let near = |p: DVec3| {
            let q = frame.plane_coords(p);
            !nlo.x.is_finite() || (q.cmpge(nlo - margin).all() && q.cmple(nhi + margin).all())
        };
        let (clo, chi) = bounds(&mut interactions().map(|(_, p)| p).filter(|&p| near(p)));
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
