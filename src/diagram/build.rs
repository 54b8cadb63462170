//! Building the diagram: rays to 3D segments, framing, projection onto the canvas.

use super::all_samples::Others;
use super::framing::Fit;
use super::layout::plural;
use super::layout::{self, Pending};
use super::legend::{self, Legend, LegendSource};
use super::marks::{camera_mark, light_marks};
use super::model::{
    Anchor, CameraMark, Diagram, HitMark, Inset, LabelRole, LightMark, ObjectSlice, RayEnd,
    RaySegment, Rect,
};
use super::plane::PlaneFrame;
use super::segments::{Seg3, clip_to, project, seg3};
use super::share::Kept;
use super::{
    DiagramError, DiagramOptions, PlaneSpec, annotate, framing, inset, objects, plane, plane_pick,
    share,
};
use crate::scene::{Camera, Scene};
use crate::tree::{NodeId, RayKind, RayTree, SampleRecord};
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
        check_size(opts)?;
        let sel = Selection::new(scene, tree, opts)?;
        let (w, h) = (f64::from(opts.width), f64::from(opts.height));
        let fs = font_size(w, h);
        let Framed {
            frame,
            plane_text,
            others,
            legend,
            view,
        } = sel.frame(scene, tree, opts, (w, h, fs));
        let figure = Figure {
            scene,
            tree,
            opts,
            segs: &sel.segs,
            frame: &frame,
            view: &view,
            extent3: sel.extent3,
            fs,
        };
        let rays = figure.rays(&others);
        let mut pending: Vec<Pending> = legend.pending;
        pending.extend(title_label(opts, fs));
        let pixel = sel.camera_drawn.then_some(PixelOnFilm {
            point: sel.pixel3,
            film: sel.sample.film,
        });
        let Marks {
            objects,
            hits,
            lights,
            camera,
            insets,
        } = figure.marks(&rays[others.segs.len()..], pixel, &mut pending);
        let mut placed_boxes: Vec<Rect> = insets.iter().map(|i| i.rect).collect();
        placed_boxes.push(legend.rect);
        let labels = layout::place(
            pending,
            Rect::new(DVec2::ZERO, DVec2::new(w, h)),
            placed_boxes,
            &label_obstacles(&rays, &hits),
        );
        let off_plane_rays = rays.iter().filter(|r| r.off_plane).count();
        Ok(Diagram {
            width: w,
            height: h,
            frame,
            view,
            plane_text,
            objects,
            rays,
            hits,
            lights,
            camera,
            insets,
            legend_rect: legend.rect,
            legend: legend.entries,
            labels,
            off_plane_rays,
            dropped_rays: sel.kept.dropped,
            dropped_share: sel.kept.dropped_share,
            other_samples_left_out: others.left_out_samples,
        })
    }
}

/// What a figure draws of the tree: the chosen sample, the rays it keeps and their segments,
/// whether the camera ray is among them, the traced pixel on the image plane and the size of
/// everything finite the segments (and the camera) touch.
struct Selection<'a> {
    sample: &'a SampleRecord,
    kept: Kept,
    segs: Vec<Seg3<'a>>,
    camera_drawn: bool,
    pixel3: DVec3,
    extent3: f64,
}

/// A figure's plane and frame: the plane (scaled and centred) and its description, the other
/// samples' segments, the legend and where the scene is drawn.
struct Framed<'a> {
    frame: PlaneFrame,
    plane_text: String,
    others: Others<'a>,
    legend: Legend,
    view: Rect,
}

impl<'a> Selection<'a> {
    /// What `opts` selects of `tree`; an error for a sample or a plane ray it does not have.
    fn new(
        scene: &Scene,
        tree: &'a RayTree,
        opts: &DiagramOptions,
    ) -> Result<Selection<'a>, DiagramError> {
        let sample = chosen_sample(tree, opts)?;
        let plane_ray = plane_ray(tree, opts)?;
        let always: Vec<NodeId> = opts.highlight.into_iter().chain(plane_ray).collect();
        let kept = share::keep(tree, opts.sample, opts.min_share, &always);
        let segs = drawn_segments(scene, tree, opts, &kept, sample.root);
        let camera_drawn = segs.iter().any(|s| s.node.kind == RayKind::Camera);
        let cam = &scene.camera;
        let pixel3 = pixel_in_world(cam, sample.film);
        let extent3 = extent_of(&segs, camera_drawn.then_some([cam.position, pixel3]));
        Ok(Selection {
            sample,
            kept,
            segs,
            camera_drawn,
            pixel3,
            extent3,
        })
    }

    /// Choose the plane, lay out the legend at the bottom of the `w` x `h` canvas (font size
    /// `fs`), and frame the region of the plane to show in the view above it.
    fn frame(
        &self,
        scene: &Scene,
        tree: &'a RayTree,
        opts: &DiagramOptions,
        (w, h, fs): (f64, f64, f64),
    ) -> Framed<'a> {
        let (segs, extent3) = (&self.segs, self.extent3);
        let shares = share::shares(tree);
        let (mut frame, plane_text) = choose_plane(scene, tree, opts, segs, &shares, extent3);
        // The other samples (all_samples) under the chosen one, faded by their value.
        let others = super::all_samples::other_segs(scene, tree, opts);
        let others_note = others_note(&others);
        let legend = legend::legend(
            &LegendSource {
                segs,
                frame: &frame,
                extent3,
                plane_text: &plane_text,
                others_note: others_note.as_deref(),
                kept: &self.kept,
                opts,
            },
            (w, h, fs),
        );
        let view = view_rect(w, fs, opts, &legend.rect);
        let eye = self.camera_drawn.then_some(scene.camera.position);
        let extras = framed_extras(segs, eye);
        let fit = framing::choose(scene, segs, &frame, &extras, &shares, extent3);
        place_frame(&mut frame, &fit, &view, extent3, fs, opts);
        Framed {
            frame,
            plane_text,
            others,
            legend,
            view,
        }
    }
}

/// The image size must be 64 to 16384 pixels each way.
fn check_size(opts: &DiagramOptions) -> Result<(), DiagramError> {
    let (wi, hi) = (opts.width, opts.height);
    if !(64..=16384).contains(&wi) || !(64..=16384).contains(&hi) {
        return Err(DiagramError::BadSize(wi, hi));
    }
    Ok(())
}

/// The sample `opts.sample` of the tree.
fn chosen_sample<'a>(
    tree: &'a RayTree,
    opts: &DiagramOptions,
) -> Result<&'a SampleRecord, DiagramError> {
    tree.samples
        .get(opts.sample)
        .ok_or(DiagramError::NoSuchSample {
            sample: opts.sample,
            count: tree.samples.len(),
        })
}

/// The ray the plane is asked to contain, if any: it must be a node of the tree.
fn plane_ray(tree: &RayTree, opts: &DiagramOptions) -> Result<Option<NodeId>, DiagramError> {
    match opts.plane {
        PlaneSpec::Ray(id) if id.index() >= tree.nodes.len() => Err(DiagramError::NoSuchNode {
            node: id.0,
            count: tree.nodes.len(),
        }),
        PlaneSpec::Ray(id) => Ok(Some(id)),
        _ => Ok(None),
    }
}

/// The segments of the chosen sample (rooted at `root`) the figure draws, depth first: kept by
/// the share threshold, of a chosen kind, within the draw depth.
fn drawn_segments<'a>(
    scene: &Scene,
    tree: &'a RayTree,
    opts: &DiagramOptions,
    kept: &Kept,
    root: NodeId,
) -> Vec<Seg3<'a>> {
    tree.depth_first(root)
        .into_iter()
        .filter(|id| kept.kept[id.index()])
        .map(|id| tree.node(id))
        .filter(|n| opts.kinds.contains(&n.kind))
        .filter(|n| opts.max_depth.is_none_or(|d| n.depth <= d))
        .map(|n| seg3(scene, n))
        .collect()
}

/// The sample's film position on the camera's image plane, in world space.
fn pixel_in_world(cam: &Camera, film: [f64; 2]) -> DVec3 {
    let [fx, fy] = film;
    let (u, v) = cam.film_to_plane(fx, fy);
    cam.position + cam.forward + u * cam.right + v * cam.up
}

/// The size of everything finite the tree touches, with the eye and the pixel when the camera
/// ray is drawn (`camera`): the largest side of their bounding box, at least 1e-9.
fn extent_of(segs: &[Seg3], camera: Option<[DVec3; 2]>) -> f64 {
    let mut pts: Vec<DVec3> = Vec::new();
    for s in segs {
        pts.push(s.start);
        pts.extend(s.end);
    }
    if let Some(eye_and_pixel) = camera {
        pts.extend(eye_and_pixel);
    }
    let extent3 = pts
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    (extent3.1 - extent3.0).max_element().max(1e-9)
}

/// The legend's note on the other samples left out by the ray bound, if any.
fn others_note(others: &Others) -> Option<String> {
    (others.left_out_samples > 0).then(|| {
        format!(
            "{} dimmest other sample{} ({} rays) not drawn: a figure draws at most {} rays of other samples.",
            others.left_out_samples,
            plural(others.left_out_samples),
            others.left_out_rays,
            super::all_samples::MAX_OTHER_RAYS
        )
    })
}

/// Where the scene is drawn: inside a margin of one font size, below the title if there is
/// one, above the legend.
fn view_rect(w: f64, fs: f64, opts: &DiagramOptions, legend_rect: &Rect) -> Rect {
    let top = if opts.title.is_empty() { fs } else { fs * 2.4 };
    Rect::new(
        DVec2::new(fs, top),
        DVec2::new(w - fs, legend_rect.min.y - fs * 0.5),
    )
}

/// The points framed when near, with how near: the eye (`eye`, when the camera ray is drawn)
/// and where rays reach a light.
fn framed_extras(segs: &[Seg3], eye: Option<DVec3>) -> Vec<(DVec3, f64)> {
    let mut extras: Vec<(DVec3, f64)> = Vec::new();
    if let Some(eye) = eye {
        // The pixel lies between the eye and the first hit: framed with the eye.
        extras.push((eye, framing::EYE_NEAR));
    }
    for s in segs {
        if s.end_kind == RayEnd::Light {
            extras.extend(s.end.map(|p| (p, framing::LIGHT_NEAR)));
        }
    }
    extras
}

/// Scale and centre `frame` so that `fit` fills `view` (with a padding of three font sizes),
/// then apply the zoom and pan of `opts`.
fn place_frame(
    frame: &mut PlaneFrame,
    fit: &Fit,
    view: &Rect,
    extent3: f64,
    fs: f64,
    opts: &DiagramOptions,
) {
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
        fit,
        view.size() / frame.scale,
        DVec2::splat(pad / frame.scale),
    );
    frame.scale *= zoom;
    let pan = DVec2::from(opts.pan);
    frame.plane_center = centre + if pan.is_finite() { pan } else { DVec2::ZERO };
    frame.canvas_center = (view.min + view.max) * 0.5;
}

/// The plane: the one `opts.plane` asks for, or with [`PlaneSpec::Auto`] the one that shows
/// the drawn segments `segs` best.
fn choose_plane(
    scene: &Scene,
    tree: &RayTree,
    opts: &DiagramOptions,
    segs: &[Seg3],
    shares: &[f64],
    extent3: f64,
) -> (PlaneFrame, String) {
    match opts.plane {
        PlaneSpec::Auto => {
            let ids: Vec<NodeId> = segs.iter().map(|s| s.node.id).collect();
            plane_pick::auto(scene, tree, opts.sample, &ids, shares, extent3)
        }
        spec => plane::choose(spec, scene, tree, opts.sample),
    }
}

/// A framed figure: what it draws (the chosen sample's segments `segs`), its plane, where the
/// scene is drawn on the canvas, the size of the scene the tree touches and the font size.
struct Figure<'a> {
    scene: &'a Scene,
    tree: &'a RayTree,
    opts: &'a DiagramOptions,
    segs: &'a [Seg3<'a>],
    frame: &'a PlaneFrame,
    view: &'a Rect,
    extent3: f64,
    fs: f64,
}

/// The traced pixel, for the camera mark: its point on the image plane (world space) and its
/// film position.
#[derive(Clone, Copy)]
struct PixelOnFilm {
    point: DVec3,
    film: [f64; 2],
}

/// Everything drawn besides the rays.
struct Marks {
    objects: Vec<ObjectSlice>,
    hits: Vec<HitMark>,
    lights: Vec<LightMark>,
    camera: Option<CameraMark>,
    insets: Vec<Inset>,
}

impl Figure<'_> {
    /// The drawn rays, clipped to the view: the other samples' first (faded by their sample's
    /// value), then the chosen sample's (marking reflections by total internal reflection).
    fn rays(&self, others: &Others) -> Vec<RaySegment> {
        let tree = self.tree;
        let fades = super::all_samples::sample_fades(tree);
        let mut rays = Vec::with_capacity(others.segs.len() + self.segs.len());
        for (k, s) in &others.segs {
            let mut r = self.project(s);
            r.fade *= fades[*k];
            clip_to(&mut r, self.view);
            rays.push(r);
        }
        for s in self.segs {
            let mut r = self.project(s);
            r.tir = s.node.kind == RayKind::Reflected
                && s.node
                    .parent
                    .is_some_and(|p| tree.node(p).interface.as_ref().is_some_and(|i| i.tir));
            clip_to(&mut r, self.view);
            rays.push(r);
        }
        rays
    }

    fn project(&self, s: &Seg3) -> RaySegment {
        project(s, self.frame, self.view, self.extent3, self.fs, self.opts)
    }

    /// The objects' slices, the hits, the lights, the camera (when its ray is drawn, `pixel`,
    /// and the eye is in view) and the insets, in that order, with their labels pushed onto
    /// `pending`. `rays` are the chosen sample's, in the order of `segs`.
    fn marks(
        &self,
        rays: &[RaySegment],
        pixel: Option<PixelOnFilm>,
        pending: &mut Vec<Pending>,
    ) -> Marks {
        let (scene, tree, segs, frame, view, fs) = (
            self.scene, self.tree, self.segs, self.frame, self.view, self.fs,
        );
        let objects = objects::slices(scene, frame, view, fs, pending);
        let hits = annotate::hits(tree, segs, rays, frame, fs, self.opts, pending);
        let lights = light_marks(scene, segs, rays, frame, self.extent3, fs, pending);
        let eye = scene.camera.position;
        let eye_visible =
            view.contains_rect(&Rect::new(frame.to_canvas(eye), frame.to_canvas(eye)));
        let camera = pixel
            .filter(|_| eye_visible)
            .map(|p| camera_mark(scene, p.point, (p.film[0], p.film[1]), frame, fs, pending));
        let insets = if self.opts.zoom_offsets {
            inset::insets(scene, tree, segs, frame, view, fs, pending)
        } else {
            Vec::new()
        };
        Marks {
            objects,
            hits,
            lights,
            camera,
            insets,
        }
    }
}

/// The title's label, if the figure has a title.
fn title_label(opts: &DiagramOptions, fs: f64) -> Option<Pending> {
    (!opts.title.is_empty()).then(|| {
        Pending::fixed(
            DVec2::new(fs, fs * 1.6),
            Anchor::Start,
            &opts.title,
            fs * 1.15,
            LabelRole::Title,
        )
    })
}

/// What labels avoid: the rays, the normals and the hit points (a label over another ray's
/// vertex reads as that ray's).
fn label_obstacles(rays: &[RaySegment], hits: &[HitMark]) -> Vec<(DVec2, DVec2)> {
    rays.iter()
        .filter(|r| r.to != r.from)
        .map(|r| (r.from, r.to))
        .chain(hits.iter().flat_map(|h| {
            let n = h.normal * h.normal_len;
            [(h.point - n, h.point + n), (h.point, h.point)]
        }))
        .collect()
}
