//! Planes that follow a ray: the plane through a chosen ray and its parent
//! ([`PlaneSpec::Ray`]), and the automatic choice ([`PlaneSpec::Auto`]) between the plane of
//! incidence and the planes of the first bounce's rays.

use super::plane::{PlaneFrame, PlaneSpec, choose};
use super::segments::{is_off, seg3};
use crate::scene::Scene;
use crate::tree::{NodeId, RayKind, RayTree};
use glam::DVec3;

/// How much more of the pixel (a share, summed over the rays in the plane) another plane must
/// hold before the automatic choice leaves the plane of incidence.
const SWITCH: f64 = 0.05;

/// The plane through ray `id` and its parent ray, through the ray's spawn point, with the
/// parent drawn left to right. A camera ray gets the plane of incidence at its hit.
#[must_use]
pub fn through_ray(scene: &Scene, tree: &RayTree, id: NodeId) -> (PlaneFrame, String) {
    let n = tree.node(id);
    let Some(pid) = n.parent else {
        let sample = tree.samples.iter().position(|s| s.root == id).unwrap_or(0);
        let (f, text) = choose(PlaneSpec::Incidence, scene, tree, sample);
        return (f, format!("{text} (through camera ray #{})", id.0));
    };
    let p = tree.node(pid);
    let name = format!("{} ray #{}", n.kind.name(), id.0);
    let normal = p.direction.cross(n.direction);
    if normal.length() > 1e-6 {
        return (
            PlaneFrame::new(n.spawn_point, normal, DVec3::Y, p.direction),
            format!("through the {name} and its parent #{}", pid.0),
        );
    }
    // Collinear with its parent: the surface normal at the spawn point, else the camera's up.
    let surface = p.hit.as_ref().map(|h| h.normal).unwrap_or(DVec3::ZERO);
    let (normal, why) = match n.direction.cross(surface) {
        c if c.length() > 1e-6 => (c, "the surface normal"),
        _ => (
            n.direction
                .cross(scene.camera.up)
                .try_normalize()
                .unwrap_or(scene.camera.right),
            "the camera's up vector",
        ),
    };
    (
        PlaneFrame::new(n.spawn_point, normal, DVec3::Y, n.direction),
        format!(
            "through the {name} and {why} (the ray continues its parent #{} straight)",
            pid.0
        ),
    )
}

/// The part of the pixel held by the kept rays lying in plane `f` (both ends within the
/// off-plane tolerance), each ray counted by its share (at most 1).
fn held(
    f: &PlaneFrame,
    scene: &Scene,
    tree: &RayTree,
    ids: &[NodeId],
    shares: &[f64],
    extent3: f64,
) -> f64 {
    ids.iter()
        .map(|id| {
            let s = seg3(scene, tree.node(*id));
            let end = s.end.unwrap_or(s.start + s.node.direction * extent3);
            let on = !is_off(f.distance(s.start), extent3) && !is_off(f.distance(end), extent3);
            if on { shares[id.index()].min(1.0) } else { 0.0 }
        })
        .sum()
}

/// The automatic plane: the plane of incidence at the camera ray's hit, unless the plane
/// through one of the first bounce's kept rays and the camera ray holds clearly more of the
/// pixel (by `SWITCH`). `ids` are the kept rays of the sample, `shares` every node's share.
#[must_use]
pub fn auto(
    scene: &Scene,
    tree: &RayTree,
    sample: usize,
    ids: &[NodeId],
    shares: &[f64],
    extent3: f64,
) -> (PlaneFrame, String) {
    let (f0, text0) = choose(PlaneSpec::Incidence, scene, tree, sample);
    let Some(root) = tree.samples.get(sample).map(|s| s.root) else {
        return (f0, text0);
    };
    let base = held(&f0, scene, tree, ids, shares, extent3);
    let mut best: Option<(f64, NodeId)> = None;
    for c in &tree.node(root).children {
        let n = tree.node(*c);
        let useful = n.kind != RayKind::Shadow || n.shadow.is_some();
        if !ids.contains(c)
            || !useful
            || n.direction.cross(tree.node(root).direction).length() < 1e-6
        {
            continue;
        }
        let (f, _) = through_ray(scene, tree, *c);
        let h = held(&f, scene, tree, ids, shares, extent3);
        if h > base + SWITCH && best.is_none_or(|(b, _)| h > b) {
            best = Some((h, *c));
        }
    }
    match best {
        Some((h, id)) => {
            let (f, text) = through_ray(scene, tree, id);
            (f, format!("{text}, {}", why_chosen(tree, sample, h, base)))
        }
        None => (f0, text0),
    }
}

/// Why the automatic choice left the plane of incidence, in words that are true of what
/// [`held`] measured: the summed shares of the rays lying in each plane, shares of the chosen
/// sample's light, or of its rays' throughput when the sample is black ([`super::share`]).
fn why_chosen(tree: &RayTree, sample: usize, held: f64, base: f64) -> String {
    let s = &tree.samples[sample];
    let whose = if tree.samples.len() == 1 {
        "the pixel's".to_string()
    } else {
        format!("sample {}'s", s.index)
    };
    let lum = crate::bsdf::luminance(s.radiance);
    let what = if lum > 0.0 && lum.is_finite() {
        format!("more of {whose} light")
    } else {
        format!(
            "more of {whose} throughput ({} is black)",
            &whose[..whose.len() - 2]
        )
    };
    format!(
        "chosen over the plane of incidence: its rays carry {what} (summed shares {held:.2} against {base:.2})"
    )
}
