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
    let mut groups: Vec<(DVec3, Vec<&Seg3>)> = Vec::new();
    let mut order: Vec<&Seg3> = segs
        .iter()
        .filter(|s| s.node.kind != RayKind::Camera)
        .collect();
    order.sort_by_key(|s| s.node.depth);
    for s in order {
        if let Some(i) = groups.iter().position(|(p, _)| *p == s.node.spawn_point) {
            groups[i].1.push(s);
        } else if groups.len() < MAX_INSETS {
            groups.push((s.node.spawn_point, vec![s]));
        }
    }
    let size = (view.size().min_element() * 0.32).clamp(120.0, 300.0);
    let m = 0.5 * fs;
    let corners = [
        DVec2::new(view.max.x - size - m, view.min.y + m),
        DVec2::new(view.min.x + m, view.min.y + m),
        DVec2::new(view.max.x - size - m, view.max.y - size - m),
        DVec2::new(view.min.x + m, view.max.y - size - m),
    ];
    let small = (0.85 * fs).max(11.0);
    let eps = scene.settings.offset.epsilon;
    let mut out = Vec::new();
    for ((p, group), corner) in groups.into_iter().zip(corners) {
        let Some(parent) = group[0].node.parent.map(|id| tree.node(id)) else {
            continue;
        };
        let Some(hit) = &parent.hit else { continue };
        let rect = Rect::new(corner, corner + DVec2::splat(size));
        let c = (rect.min + rect.max) * 0.5;
        let reach = group
            .iter()
            .map(|s| s.node.offset.length().max(s.node.t_min))
            .fold(eps, f64::max)
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
        for s in &group {
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
        let off = group[0].node.offset.length();
        let tmin = group[0].node.t_min;
        let mut lines = vec![format!("|offset| = {off:.1e}, t_min = {tmin:.1e}")];
        lines.push(format!("inset width = {:.1e} units", world_per_px * size));
        if let Some(th) = self_hit {
            lines.push(format!("SELF-HIT at t = {th:.1e}"));
        }
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
        if let Some((_, o, _)) = rays.first()
            && (*o - c).length() > 4.0
        {
            pending.push(Pending::fixed(
                *o + DVec2::new(0.6 * fs, -0.5 * fs),
                Anchor::Start,
                "O (origin)",
                small,
                LabelRole::Inset,
            ));
        }
        out.push(Inset {
            rect,
            anchor: frame.to_canvas(p),
            surface,
            inside: c - nc * 0.25 * size,
            hit: c,
            rays,
            world_per_px,
        });
    }
    out
}
