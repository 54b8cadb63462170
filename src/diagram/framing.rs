//! Framing: which part of the plane the figure shows.
//!
//! The figure is about where the kept rays interact (hits, spawn points, blockers). That
//! region grows from the camera ray's first hit, depth by depth: an interaction joins when it
//! lies within twice the region's size (at least the size of the object first hit) of it, so a
//! bounce that ends on the floor ten units away does not shrink the glass to a dot; its ray
//! leaves through the frame. The eye, the pixel and the lights are framed when they are within
//! three times the region's size of it; farther out, their rays enter or leave through the
//! frame. The view's spare room (the region is rarely of the view's aspect) goes where the
//! rays go: a figure on a floor gets the room above the floor, not an empty floor below it.

use super::model::RayEnd;
use super::plane::PlaneFrame;
use super::segments::Seg3;
use super::slice::{PlaneSlice, slice};
use crate::scene::Scene;
use crate::tree::{NodeId, RayKind};
use glam::{DVec2, DVec3};

/// A box in plane coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Box2 {
    pub lo: DVec2,
    pub hi: DVec2,
}

impl Box2 {
    const EMPTY: Self = Self {
        lo: DVec2::INFINITY,
        hi: DVec2::NEG_INFINITY,
    };
    fn add(&mut self, q: DVec2) {
        if q.is_finite() {
            self.lo = self.lo.min(q);
            self.hi = self.hi.max(q);
        }
    }
    fn is_empty(&self) -> bool {
        self.lo.x.partial_cmp(&self.hi.x).is_none_or(|o| o.is_gt())
    }
    fn size(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.hi - self.lo).max_element()
        }
    }
    /// Distance from `q` to the box (0 inside).
    fn distance(&self, q: DVec2) -> f64 {
        let d = (self.lo - q).max(q - self.hi).max(DVec2::ZERO);
        d.length()
    }
}

/// Where a drawn ray interacts with the scene.
#[derive(Clone, Copy, Debug)]
struct Interaction {
    /// The ray's depth.
    depth: u32,
    /// The point, in world space.
    point: DVec3,
    /// The object it lies on, if known.
    object: Option<usize>,
    /// The ray.
    node: NodeId,
}

/// The interaction points of the drawn rays with their depths and the objects they are on:
/// spawn points, hits, opaque blockers, and where shadow rays cross translucent blockers.
fn interactions(segs: &[Seg3]) -> Vec<Interaction> {
    let mut out = Vec::new();
    for s in segs {
        let n = s.node;
        let at = |point: DVec3, object: Option<usize>| Interaction {
            depth: n.depth,
            point,
            object,
            node: n.id,
        };
        if n.kind != RayKind::Camera {
            out.push(at(s.start, None));
        }
        if let Some(e) = s
            .end
            .filter(|_| matches!(s.end_kind, RayEnd::Hit | RayEnd::Blocked))
        {
            let on = n.hit.as_ref().map(|h| h.object);
            out.push(at(e, on));
        }
        if let Some(sh) = &n.shadow {
            for b in &sh.blockers {
                for t in [b.t, b.t + b.chord] {
                    if t.is_finite() {
                        out.push(at(n.origin + t * n.direction, Some(b.object)));
                    }
                }
            }
        }
    }
    out
}

/// How far from the first hit and its object an interaction may lie to be framed, in sizes
/// of that object.
const NEAR: f64 = 1.5;
/// The same for the rays carrying a major share of the pixel ([`MAJOR`]): where the light
/// the pixel sees comes from (the floor seen through a glass ball) is worth a smaller figure.
const NEAR_MAJOR: f64 = 4.0;
/// A major share of the pixel.
const MAJOR: f64 = 0.2;
/// How far from the region the eye (and the pixel) may lie to be framed, in sizes of the
/// first object.
pub(super) const EYE_NEAR: f64 = 1.5;
/// How far from the region a light may lie to be framed, in sizes of the first object.
pub(super) const LIGHT_NEAR: f64 = 1.0;

/// The bounds of object `o`'s slice (empty for planes and objects the plane misses).
fn slice_box(scene: &Scene, frame: &PlaneFrame, o: usize) -> Box2 {
    let mut b = Box2::EMPTY;
    let Some(sl) = scene.objects.get(o).and_then(|o| slice(&o.shape, frame)) else {
        return b;
    };
    match sl {
        PlaneSlice::Circle { center, radius } => {
            b.add(center - radius);
            b.add(center + radius);
        }
        PlaneSlice::Polygon(p) => p.into_iter().for_each(|p| b.add(p)),
        PlaneSlice::Segment(p, r) => [p, r].into_iter().for_each(|p| b.add(p)),
        PlaneSlice::Segments(s) => s.into_iter().for_each(|(p, r)| {
            b.add(p);
            b.add(r);
        }),
        PlaneSlice::HalfPlane { .. } => {}
    }
    b
}

/// What to fit in the view (`fit`) and where the rays reach (`reach`), in plane coordinates.
pub(super) struct Fit {
    pub fit: Box2,
    pub reach: Box2,
}

/// Choose the region to frame. `extras` are the eye, the pixel and the lights (framed when
/// near); `extent3` is the size of everything the tree touches.
pub(super) fn choose(
    scene: &Scene,
    segs: &[Seg3],
    frame: &PlaneFrame,
    extras: &[(DVec3, f64)],
    shares: &[f64],
    extent3: f64,
) -> Fit {
    let framer = Framer { scene, frame };
    let mut pts = interactions(segs);
    let first = first_hit(segs);
    let first_object = first
        .and_then(|f| f.seg.node.hit.as_ref())
        .map(|h| h.object);
    let mut core = Box2::EMPTY;
    if let Some(f) = first {
        core.add(framer.q(f.point));
    }
    // Depth by depth, nearest first.
    let origin = first.map_or(DVec3::ZERO, |f| f.point);
    pts.sort_by(|a, b| {
        a.depth.cmp(&b.depth).then(
            (a.point - origin)
                .length()
                .total_cmp(&(b.point - origin).length()),
        )
    });
    let seed_size = framer.seed_size(first_object, &pts, origin, extent3);
    let seed = framer.seed(core, first_object, seed_size);
    let mut touched: Vec<usize> = first_object.into_iter().collect();
    for i in &pts {
        let near = if shares.get(i.node.index()).is_some_and(|s| *s >= MAJOR) {
            NEAR_MAJOR
        } else {
            NEAR
        };
        if seed.is_empty() || seed.distance(framer.q(i.point)) <= near * seed_size {
            core.add(framer.q(i.point));
            touched.extend(i.object);
        }
    }
    let core = framer.with_objects(core, touched, seed_size);
    let fit = framer.fit(core, first, seed_size, extras);
    framer.reach(fit, segs, extent3)
}

/// The camera ray's first hit, if the first drawn segment is a hit: the segment and the point.
#[derive(Clone, Copy)]
struct FirstHit<'a, 's> {
    seg: &'s Seg3<'a>,
    point: DVec3,
}

fn first_hit<'a, 's>(segs: &'s [Seg3<'a>]) -> Option<FirstHit<'a, 's>> {
    segs.first()
        .filter(|s| s.end_kind == RayEnd::Hit)
        .and_then(|s| s.end.map(|point| FirstHit { seg: s, point }))
}

/// The scene and the plane a region is framed in.
struct Framer<'a> {
    scene: &'a Scene,
    frame: &'a PlaneFrame,
}

impl Framer<'_> {
    /// `p` in plane coordinates.
    fn q(&self, p: DVec3) -> DVec2 {
        self.frame.plane_coords(p)
    }

    /// An object's size in the figure: its slice's, else its bounds' (planes have none).
    fn object_size(&self, o: usize) -> Option<f64> {
        let b = slice_box(self.scene, self.frame, o);
        let bounds = self
            .scene
            .objects
            .get(o)
            .and_then(|o| o.shape.bounds())
            .map(|(lo, hi)| (hi - lo).max_element());
        let size = if b.is_empty() {
            bounds
        } else {
            bounds.map(|_| b.size())
        };
        size.filter(|v| v.is_finite() && *v > 0.0)
    }

    /// The scale distances are measured in. The first object's size sets it; an unbounded one
    /// (a floor) hands over to the first bounded object met next (a ball the shadow ray
    /// crosses), else to the distance from `origin` to the nearest interaction.
    fn seed_size(
        &self,
        first_object: Option<usize>,
        pts: &[Interaction],
        origin: DVec3,
        extent3: f64,
    ) -> f64 {
        let seed_size = first_object
            .and_then(|o| self.object_size(o))
            .or_else(|| {
                pts.iter()
                    .find_map(|i| i.object.and_then(|o| self.object_size(o)))
            })
            .unwrap_or_else(|| {
                pts.iter()
                    .map(|i| (i.point - origin).length())
                    .filter(|d| *d > 1e-9 * extent3)
                    .fold(f64::INFINITY, f64::min)
            });
        let seed_size = if seed_size.is_finite() {
            seed_size
        } else {
            extent3 * 0.1
        };
        seed_size.max(extent3 * 1e-3)
    }

    /// What interactions are measured from: the first hit (`core`) and its object's slice,
    /// not the growing region, so that a chain of bounces does not walk the frame out to the
    /// far floor.
    fn seed(&self, core: Box2, first_object: Option<usize>, seed_size: f64) -> Box2 {
        let mut seed = core;
        if let Some(b) = first_object.map(|o| slice_box(self.scene, self.frame, o))
            && !b.is_empty()
            && b.size() <= 3.0 * seed_size
        {
            seed.add(b.lo);
            seed.add(b.hi);
        }
        seed
    }

    /// `core` with the whole slice of the bounded objects the rays meet (`touched`: a ball, not
    /// just its chord), unless one is much larger than the region (a room's walls).
    fn with_objects(&self, core: Box2, mut touched: Vec<usize>, seed_size: f64) -> Box2 {
        let limit = 3.0 * core.size().max(seed_size);
        let mut objects = core;
        touched.sort_unstable();
        touched.dedup();
        for o in touched {
            let b = slice_box(self.scene, self.frame, o);
            if !b.is_empty() && b.size() <= limit {
                objects.add(b.lo);
                objects.add(b.hi);
            }
        }
        objects
    }

    /// What to fit: `core`, the camera ray coming in over at least half the first object's
    /// size, and the `extras` near enough, measured in sizes of the first object like the
    /// interactions.
    fn fit(
        &self,
        core: Box2,
        first: Option<FirstHit>,
        seed_size: f64,
        extras: &[(DVec3, f64)],
    ) -> Box2 {
        let mut fit = core;
        if let Some(f) = first {
            let back = (f.point - f.seg.start).length().min(0.5 * seed_size);
            fit.add(self.q(f.point - f.seg.node.direction * back));
        }
        let size = seed_size;
        for (p, near) in extras {
            if core.is_empty() || core.distance(self.q(*p)) <= near * size {
                fit.add(self.q(*p));
            }
        }
        fit
    }

    /// `fit` and where the rays reach (a ray that leaves the scene, ten times the fit's size);
    /// a unit box around the origin for both if nothing is to fit.
    fn reach(&self, mut fit: Box2, segs: &[Seg3], extent3: f64) -> Fit {
        let mut reach = fit;
        let far = 10.0 * fit.size().max(extent3 * 1e-3);
        for s in segs {
            reach.add(self.q(s.start));
            match s.end {
                Some(e) => reach.add(self.q(e)),
                None if s.end_kind != RayEnd::LightBehind => {
                    reach.add(self.q(s.start + s.node.direction * far));
                }
                None => {}
            }
        }
        if fit.is_empty() {
            fit = Box2 {
                lo: DVec2::splat(-1.0),
                hi: DVec2::ONE,
            };
            reach = fit;
        }
        Fit { fit, reach }
    }
}

/// The plane point to put at the view's centre: `fit` stays inside the window of size `win`
/// (with `pad` on each side), and the window covers as much of `reach` as it can.
pub(super) fn centre(f: &Fit, win: DVec2, pad: DVec2) -> DVec2 {
    let mut c = DVec2::ZERO;
    for i in 0..2 {
        let lo = f.fit.hi[i] + pad[i] - win[i] * 0.5;
        let hi = f.fit.lo[i] - pad[i] + win[i] * 0.5;
        let mid = (f.fit.lo[i] + f.fit.hi[i]) * 0.5;
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (mid, mid) };
        let want = (f.reach.lo[i].max(f.fit.lo[i] - win[i])
            + f.reach.hi[i].min(f.fit.hi[i] + win[i]))
            * 0.5;
        // max/min, not clamp: no panic on a non-finite bound (the figure degrades, never
        // aborts).
        c[i] = want.max(lo).min(hi);
        if !c[i].is_finite() {
            c[i] = if mid.is_finite() { mid } else { 0.0 };
        }
    }
    c
}
