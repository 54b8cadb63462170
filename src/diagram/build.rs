//! Building the diagram: rays to 3D segments, framing, projection onto the canvas.

use super::layout::plural;
use super::layout::{self, Pending};
use super::marks::{camera_mark, light_marks};
use super::model::{Anchor, Diagram, LabelRole, RayEnd, Rect};
use super::segments::{Seg3, clip_to, project, seg3};
use super::{
    DiagramError, DiagramOptions, PlaneSpec, annotate, framing, inset, objects, plane, plane_pick,
    share,
};
use crate::scene::Scene;
use crate::tree::{NodeId, RayKind, RayTree};
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
        let plane_ray = match opts.plane {
            PlaneSpec::Ray(id) if id.index() >= tree.nodes.len() => {
                return Err(DiagramError::NoSuchNode {
                    node: id.0,
                    count: tree.nodes.len(),
                });
            }
            PlaneSpec::Ray(id) => Some(id),
            _ => None,
        };
        let always: Vec<NodeId> = opts.highlight.into_iter().chain(plane_ray).collect();
        let kept = share::keep(tree, opts.sample, opts.min_share, &always);
        let segs: Vec<Seg3> = tree
            .depth_first(sample.root)
            .into_iter()
            .filter(|id| kept.kept[id.index()])
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
        let shares = share::shares(tree);
        let (mut frame, plane_text) = match opts.plane {
            PlaneSpec::Auto => {
                let ids: Vec<NodeId> = segs.iter().map(|s| s.node.id).collect();
                plane_pick::auto(scene, tree, opts.sample, &ids, &shares, extent3)
            }
            spec => plane::choose(spec, scene, tree, opts.sample),
        };
        // The other samples (all_samples) under the chosen one, faded by their value.
        let others = super::all_samples::other_segs(scene, tree, opts);
        let others_note = (others.left_out_samples > 0).then(|| {
            format!(
                "{} dimmest other sample{} ({} rays) not drawn: a figure draws at most {} rays of other samples.",
                others.left_out_samples,
                plural(others.left_out_samples),
                others.left_out_rays,
                super::all_samples::MAX_OTHER_RAYS
            )
        });
        let (legend_pending, legend_entries, legend_rect) = layout::legend(
            &segs,
            &frame,
            extent3,
            &plane_text,
            others_note.as_deref(),
            &kept,
            opts,
            (w, h, fs),
        );
        let top = if opts.title.is_empty() { fs } else { fs * 2.4 };
        let view = Rect::new(
            DVec2::new(fs, top),
            DVec2::new(w - fs, legend_rect.min.y - fs * 0.5),
        );
        let mut extras: Vec<(DVec3, f64)> = Vec::new();
        if camera_drawn {
            // The pixel lies between the eye and the first hit: framed with the eye.
            extras.push((cam.position, framing::EYE_NEAR));
        }
        for s in &segs {
            if s.end_kind == RayEnd::Light {
                extras.extend(s.end.map(|p| (p, framing::LIGHT_NEAR)));
            }
        }
        let fit = framing::choose(scene, &segs, &frame, &extras, &shares, extent3);
        let pad = 3.0 * fs;
        let size = (fit.fit.hi - fit.fit.lo).max(DVec2::splat(extent3 * 0.05));
        let avail = (view.size() - DVec2::splat(2.0 * pad)).max(DVec2::splat(10.0));
        let zoom = if opts.zoom.is_finite() && opts.zoom > 0.0 {
            opts.zoom
        } else {
            1.0
        };
        frame.scale = (avail.x / size.x).min(avail.y / size.y);
        let centre = framing::centre(
            &fit,
            view.size() / frame.scale,
            DVec2::splat(pad / frame.scale),
        );
        frame.scale *= zoom;
        let pan = DVec2::from(opts.pan);
        frame.plane_center = centre + if pan.is_finite() { pan } else { DVec2::ZERO };
        frame.canvas_center = (view.min + view.max) * 0.5;

        let fades = super::all_samples::sample_fades(tree);
        let mut rays = Vec::with_capacity(others.segs.len() + segs.len());
        for (k, s) in &others.segs {
            let mut r = project(s, &frame, &view, extent3, fs, opts);
            r.fade *= fades[*k];
            clip_to(&mut r, &view);
            rays.push(r);
        }
        let first = others.segs.len();
        for s in &segs {
            let mut r = project(s, &frame, &view, extent3, fs, opts);
            r.tir = s.node.kind == RayKind::Reflected
                && s.node
                    .parent
                    .is_some_and(|p| tree.node(p).interface.as_ref().is_some_and(|i| i.tir));
            clip_to(&mut r, &view);
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
        let hits = annotate::hits(tree, &segs, &rays[first..], &frame, fs, opts, &mut pending);
        let lights = light_marks(
            scene,
            &segs,
            &rays[first..],
            &frame,
            extent3,
            fs,
            &mut pending,
        );
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
        // Labels avoid the rays, the normals and the hit points (a label over another ray's
        // vertex reads as that ray's).
        let lines: Vec<(DVec2, DVec2)> = rays
            .iter()
            .filter(|r| r.to != r.from)
            .map(|r| (r.from, r.to))
            .chain(hits.iter().flat_map(|h| {
                let n = h.normal * h.normal_len;
                [(h.point - n, h.point + n), (h.point, h.point)]
            }))
            .collect();
        let labels = layout::place(
            pending,
            Rect::new(DVec2::ZERO, DVec2::new(w, h)),
            placed_boxes,
            &lines,
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
            dropped_rays: kept.dropped,
            dropped_share: kept.dropped_share,
            other_samples_left_out: others.left_out_samples,
        })
    }
}
