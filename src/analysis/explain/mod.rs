//! Explain a pixel in a few sentences generated from its ray tree (issue 17): what the pixel
//! sees and through what, by share of the pixel value; where energy went (cut by max depth, by
//! the min weight, by the ray budget, absorbed by Beer's law, blocked shadow rays); and what is
//! suspicious (self-hits, leaks, TIR chains ending at max depth, a value clipped on display, a
//! non-finite value). Every sentence carries the ids of the nodes it is about.
//!
//! The shares are exact: each non-shadow node contributes `throughput x Beer x local` (a miss:
//! `throughput x radiance`, its attenuated background), divided by the sample count, and these
//! terms add up to the pixel value (the tree's invariants). Terms are grouped by their path:
//! the object names and ray kinds from the eye to the node.

use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use serde::Serialize;

/// Shares below this fraction of the pixel are gathered into one "other paths" sentence.
const SMALL_SHARE: f64 = 0.005;

/// What a sentence is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SentenceKind {
    /// What the pixel sees and through what, with its share of the pixel value.
    Sees,
    /// A noteworthy optical event (total internal reflection).
    Event,
    /// Where energy went: cut, absorbed, blocked.
    Energy,
    /// Something a renderer engineer should look at.
    Suspicious,
}

/// One generated sentence.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sentence {
    /// What it is about.
    pub kind: SentenceKind,
    /// The sentence.
    pub text: String,
    /// The nodes it is about.
    pub nodes: Vec<NodeId>,
}

/// One path group's part of the pixel value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Share {
    /// The path in words ("floor seen through the glass ball").
    pub path: String,
    /// Its part of the pixel value (the shares add up to the pixel value).
    pub value: Rgb,
    /// Its fraction of the pixel's luminance (0 when the pixel is black).
    pub fraction: f64,
    /// The contributing nodes.
    pub nodes: Vec<NodeId>,
}

/// The explanation of one pixel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Explanation {
    /// Pixel coordinates.
    pub pixel: [u32; 2],
    /// The pixel value.
    pub radiance: Rgb,
    /// Every path group, largest first; their values add up to `radiance`.
    pub shares: Vec<Share>,
    /// The sentences, in order: sees, events, energy, suspicious.
    pub sentences: Vec<Sentence>,
}

/// Rec. 709 luminance, the measure of a share.
fn luminance(c: Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Four decimals, or three significant digits in scientific notation below 1e-3.
fn num(v: f64) -> String {
    if v == 0.0 || v.abs() >= 1e-3 || !v.is_finite() {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

fn rgb(c: Rgb) -> String {
    format!("[{}, {}, {}]", num(c.x), num(c.y), num(c.z))
}

fn atten(n: &RayNode) -> Rgb {
    n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor)
}

fn deg(cos: f64) -> f64 {
    cos.clamp(-1.0, 1.0).acos().to_degrees()
}

/// What a non-shadow node adds to the pixel value: its surface's local term (a miss: the
/// background) carried to the eye, divided by the sample count.
#[must_use]
pub fn node_term(tree: &RayTree, n: &RayNode) -> Rgb {
    let spp = tree.samples.len().max(1) as f64;
    let source = match n.hit {
        Some(_) => atten(n) * n.local,
        None => n.radiance,
    };
    n.throughput * source / spp
}

fn ids(nodes: &[NodeId]) -> Vec<NodeId> {
    let mut v = nodes.to_vec();
    v.sort_unstable();
    v.dedup();
    v
}

/// Explain the pixel whose tree is `tree`, traced in `scene`.
#[must_use]
pub fn explain(tree: &RayTree, scene: &Scene) -> Explanation {
    if tree.nodes.iter().any(|n| n.path.is_some()) {
        return path::explain_path(tree, scene);
    }
    let mut sentences = Vec::new();
    let shares = whitted::shares(tree);
    whitted::sees(tree, scene, &shares, &mut sentences);
    whitted::total_internal_reflection(tree, &mut sentences);
    whitted::roulette(tree, &mut sentences);
    whitted::cuts(tree, scene, &mut sentences);
    whitted::absorbed(tree, scene, &mut sentences);
    whitted::blocked(tree, &mut sentences);
    suspicious(tree, &mut sentences);
    Explanation {
        pixel: tree.pixel,
        radiance: tree.radiance,
        shares,
        sentences,
    }
}

mod path;
mod suspicious;
mod text;
mod whitted;
mod words;

use suspicious::suspicious;
pub use text::{explanation_text, node_list};
/// For a black pixel: the spot lights whose cone leaves out every point the pixel's camera rays
/// hit (", outside the cone of key spot (58.3 deg from its axis, its cone 24.0 deg)"); empty
/// when there is none, or a camera ray hit nothing.
pub(super) fn outside_spots(tree: &RayTree, scene: &Scene) -> String {
    let hits: Vec<glam::DVec3> = tree
        .nodes
        .iter()
        .filter(|n| n.kind == RayKind::Camera)
        .filter_map(|n| n.hit.as_ref().map(|h| h.point))
        .collect();
    if hits.is_empty() || hits.len() < tree.samples.len() {
        return String::new();
    }
    let outside: Vec<String> = scene
        .lights
        .iter()
        .filter_map(|l| {
            let crate::scene::LightKind::Point {
                position,
                spot: Some(cone),
                ..
            } = l.kind
            else {
                return None;
            };
            let dirs: Vec<glam::DVec3> = hits
                .iter()
                .filter_map(|&p| (p - position).try_normalize())
                .collect();
            if dirs.len() < hits.len() || dirs.iter().any(|&w| cone.falloff(w) > 0.0) {
                return None;
            }
            let angle = dirs[0].dot(cone.axis).clamp(-1.0, 1.0).acos().to_degrees();
            Some(format!(
                "{} ({angle:.1} deg from its axis, its cone {:.1} deg)",
                l.name,
                cone.cone.to_degrees()
            ))
        })
        .collect();
    if outside.is_empty() {
        String::new()
    } else {
        format!(
            "; the surface lies outside the cone of {}",
            outside.join(", ")
        )
    }
}

#[cfg(test)]
mod tests;
