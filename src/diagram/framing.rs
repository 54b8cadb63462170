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

/// The interaction points of the drawn rays with their depths and the objects they are on:
/// spawn points, hits, opaque blockers, and where shadow rays cross translucent blockers.
fn interactions(segs: &[Seg3]) -> Vec<(u32, DVec3, Option<usize>, NodeId)> {
    let mut out = Vec::new();
    for s in segs {
        let n = s.node;
        if n.kind != RayKind::Camera {
            out.push((n.depth, s.start, None, n.id));
        }
        if let Some(e) = s
            .end
            .filter(|_| matches!(s.end_kind, RayEnd::Hit | RayEnd::Blocked))
        {
            let on = n.hit.as_ref().map(|h| h.object);
            out.push((n.depth, e, on, n.id));
        }
        if let Some(sh) = &n.shadow {
            for b in &sh.blockers {
                for t in [b.t, b.t + b.chord] {
                    if t.is_finite() {
                        out.push((n.depth, n.origin + t * n.direction, Some(b.object), n.id));
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
    let q = |p: DVec3| frame.plane_coords(p);
    let mut pts = interactions(segs);
    let first = segs
        .first()
        .filter(|s| s.end_kind == RayEnd::Hit)
        .and_then(|s| s.end.map(|e| (s, e)));
    // An object's size in the figure: its slice's, else its bounds' (planes have none).
    let object_size = |o: usize| {
        let b = slice_box(scene, frame, o);
        let bounds = scene
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
    };
    let first_object = first
        .and_then(|(s, _)| s.node.hit.as_ref())
        .map(|h| h.object);
    let mut core = Box2::EMPTY;
    if let Some((_, e)) = first {
        core.add(q(e));
    }
    // Depth by depth, nearest first.
    let origin = first.map_or(DVec3::ZERO, |(_, e)| e);
    pts.sort_by(|a, b| {
        a.0.cmp(&b.0)
            .then((a.1 - origin).length().total_cmp(&(b.1 - origin).length()))
    });
    // The first object's size sets the scale; an unbounded one (a floor) hands over to the
    // first bounded object met next (a ball the shadow ray crosses), else to the distance to
    // the nearest interaction.
    let seed_size = first_object
        .and_then(object_size)
        .or_else(|| pts.iter().find_map(|(_, _, o, _)| o.and_then(object_size)))
        .unwrap_or_else(|| {
            pts.iter()
                .map(|(_, p, _, _)| (*p - origin).length())
                .filter(|d| *d > 1e-9 * extent3)
                .fold(f64::INFINITY, f64::min)
        });
    let seed_size = if seed_size.is_finite() {
        seed_size
    } else {
        extent3 * 0.1
    };
    let seed_size = seed_size.max(extent3 * 1e-3);
    // Measured from the first hit and its object's slice, not from the growing region: a
    // chain of bounces must not walk the frame out to the far floor.
    let mut seed = core;
    if let Some(b) = first_object.map(|o| slice_box(scene, frame, o))
        && !b.is_empty()
        && b.size() <= 3.0 * seed_size
    {
        seed.add(b.lo);
        seed.add(b.hi);
    }
    let mut touched: Vec<usize> = first_object.into_iter().collect();
    for (_, p, o, id) in &pts {
        let near = if shares.get(id.index()).is_some_and(|s| *s >= MAJOR) {
            NEAR_MAJOR
        } else {
            NEAR
        };
        if seed.is_empty() || seed.distance(q(*p)) <= near * seed_size {
            core.add(q(*p));
            touched.extend(*o);
        }
    }
    // The whole slice of the bounded objects the rays meet (a ball, not just its chord),
    // unless one is much larger than the region (a room's walls).
    let limit = 3.0 * core.size().max(seed_size);
    let mut objects = core;
    touched.sort_unstable();
    touched.dedup();
    for o in touched {
        let b = slice_box(scene, frame, o);
        if !b.is_empty() && b.size() <= limit {
            objects.add(b.lo);
            objects.add(b.hi);
        }
    }
    let core = objects;
    let mut fit = core;
    // The camera ray comes in over at least half the first object's size.
    if let Some((s, e)) = first {
        let back = (e - s.start).length().min(0.5 * seed_size);
        fit.add(q(e - s.node.direction * back));
    }
    // Measured in sizes of the first object, like the interactions.
    let size = seed_size;
    for (p, near) in extras {
        if core.is_empty() || core.distance(q(*p)) <= near * size {
            fit.add(q(*p));
        }
    }
    let mut reach = fit;
    let far = 10.0 * fit.size().max(extent3 * 1e-3);
    for s in segs {
        reach.add(q(s.start));
        match s.end {
            Some(e) => reach.add(q(e)),
            None if s.end_kind != RayEnd::LightBehind => {
                reach.add(q(s.start + s.node.direction * far));
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
