//! `--zoom-offsets`: insets magnifying spawn points so that the offset epsilon is visible, for
//! debugging self-intersection.

use super::layout::Pending;
use super::model::{Anchor, Inset, LabelRole, Rect};
use super::plane::PlaneFrame;
use super::segments::{Seg3, exit_param};
use crate::scene::Scene;
use crate::tree::{RayKind, RayTree};
use glam::{DVec2, DVec3};

/// At most this many insets (one per corner of the view).
const MAX_INSETS: usize = 4;

/// One inset per distinct spawn point (shallowest first, up to four).
pub(super) fn insets(
    scene: &Scene,
    tree: &RayTree,
    segs: &[Seg3],
    frame: &PlaneFrame,
    view: &Rect,
    fs: f64,
    pending: &mut Vec<Pending>,
) -> Vec<Inset> {
    let groups = spawn_groups(segs);
    let size = (view.size().min_element() * 0.32).clamp(120.0, 300.0);
    let m = 0.5 * fs;
    let corners = [
        DVec2::new(view.max.x - size - m, view.min.y + m),
        DVec2::new(view.min.x + m, view.min.y + m),
        DVec2::new(view.max.x - size - m, view.max.y - size - m),
        DVec2::new(view.min.x + m, view.max.y - size - m),
    ];
    let drawer = InsetDrawer {
        tree,
        frame,
        size,
        fs,
        small: (0.85 * fs).max(11.0),
        eps: scene.settings.offset.epsilon,
    };
    let mut out = Vec::new();
    for (group, corner) in groups.into_iter().zip(corners) {
        out.extend(drawer.inset(&group, corner, pending));
    }
    out
}

/// The drawn rays spawned at one point.
struct SpawnGroup<'s, 'a> {
    point: DVec3,
    segs: Vec<&'s Seg3<'a>>,
}

/// The non-camera segments grouped by spawn point, shallowest first, at most [`MAX_INSETS`]
/// points.
fn spawn_groups<'s, 'a>(segs: &'s [Seg3<'a>]) -> Vec<SpawnGroup<'s, 'a>> {
    let mut groups: Vec<SpawnGroup> = Vec::new();
    let mut order: Vec<&Seg3> = segs
        .iter()
        .filter(|s| s.node.kind != RayKind::Camera)
        .collect();
    order.sort_by_key(|s| s.node.depth);
    for s in order {
        if let Some(i) = groups.iter().position(|g| g.point == s.node.spawn_point) {
            groups[i].segs.push(s);
        } else if groups.len() < MAX_INSETS {
            groups.push(SpawnGroup {
                point: s.node.spawn_point,
                segs: vec![s],
            });
        }
    }
    groups
}

/// What every inset of a figure shares: the tree, the plane, the inset's side in pixels, the
/// font size and the insets' smaller one, and the scene's offset epsilon.
struct InsetDrawer<'a> {
    tree: &'a RayTree,
    frame: &'a PlaneFrame,
    size: f64,
    fs: f64,
    small: f64,
    eps: f64,
}

impl InsetDrawer<'_> {
    /// The inset of `group` at `corner`, with its labels; none where the group's parent did
    /// not hit.
    fn inset(
        &self,
        group: &SpawnGroup,
        corner: DVec2,
        pending: &mut Vec<Pending>,
    ) -> Option<Inset> {
        let (frame, size, p) = (self.frame, self.size, group.point);
        let parent = group.segs[0].node.parent.map(|id| self.tree.node(id))?;
        let hit = parent.hit.as_ref()?;
        let rect = Rect::new(corner, corner + DVec2::splat(size));
        let c = (rect.min + rect.max) * 0.5;
        let reach = group
            .segs
            .iter()
            .map(|s| s.node.offset.length().max(s.node.t_min))
            .fold(self.eps, f64::max)
            .max(1e-300);
        let world_per_px = reach / (0.3 * size);
        let map = |x: DVec3| c + frame.dir_to_canvas(x - p) / world_per_px;
        let nc = frame
            .dir_to_canvas(hit.normal)
            .try_normalize()
            .unwrap_or(DVec2::new(0.0, -1.0));
        let t = DVec2::new(-nc.y, nc.x);
        let surface = (
            c + t * exit_param(c, t, &rect),
            c - t * exit_param(c, -t, &rect),
        );
        let mut rays = Vec::new();
        let mut self_hit = None;
        for s in &group.segs {
            let o = map(s.node.origin);
            let d = frame
                .dir_to_canvas(s.node.direction)
                .try_normalize()
                .unwrap_or(DVec2::ZERO);
            rays.push((s.node.kind, o, o + d * exit_param(o, d, &rect)));
            if let Some(h) = &s.node.hit
                && h.object == hit.object
                && h.t < 100.0 * reach
            {
                self_hit = Some(h.t);
            }
        }
        let off = group.segs[0].node.offset.length();
        let tmin = group.segs[0].node.t_min;
        let mut lines = vec![format!("|offset| = {off:.1e}, t_min = {tmin:.1e}")];
        lines.push(format!("inset width = {:.1e} units", world_per_px * size));
        if let Some(th) = self_hit {
            lines.push(format!("SELF-HIT at t = {th:.1e}"));
        }
        self.labels(&rect, &lines, rays.first().map(|(_, o, _)| *o), pending);
        Some(Inset {
            rect,
            anchor: frame.to_canvas(p),
            surface,
            inside: c - nc * 0.25 * size,
            hit: c,
            rays,
            world_per_px,
        })
    }

    /// An inset's labels: its `lines` in its top left corner, P at the hit (the centre) and O
    /// at the first ray's `origin` unless it is on P.
    fn labels(
        &self,
        rect: &Rect,
        lines: &[String],
        origin: Option<DVec2>,
        pending: &mut Vec<Pending>,
    ) {
        let (fs, small) = (self.fs, self.small);
        let c = (rect.min + rect.max) * 0.5;
        for (k, text) in lines.iter().enumerate() {
            let pos = DVec2::new(
                rect.min.x + 0.4 * fs,
                rect.min.y + (k as f64 + 1.0) * 1.15 * small,
            );
            pending.push(Pending::fixed(
                pos,
                Anchor::Start,
                text,
                small,
                LabelRole::Inset,
            ));
        }
        pending.push(Pending::fixed(
            c + DVec2::new(-0.5 * fs, 1.4 * fs),
            Anchor::End,
            "P (hit)",
            small,
            LabelRole::Inset,
        ));
        if let Some(o) = origin
            && (o - c).length() > 4.0
        {
            pending.push(Pending::fixed(
                o + DVec2::new(0.6 * fs, -0.5 * fs),
                Anchor::Start,
                "O (origin)",
                small,
                LabelRole::Inset,
            ));
        }
    }
}
