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
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};
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
    let spp = tree.samples.len().max(1) as f64;
    let pixel_lum = luminance(tree.radiance);
    let mut sentences = Vec::new();

    // What the pixel sees.
    let mut shares: Vec<Share> = Vec::new();
    for n in tree.nodes.iter().filter(|n| n.kind != RayKind::Shadow) {
        let value = node_term(tree, n);
        if value == Rgb::ZERO {
            continue;
        }
        let path = path_words(tree, n.id);
        match shares.iter_mut().find(|s| s.path == path) {
            Some(s) => {
                s.value += value;
                s.nodes.push(n.id);
            }
            None => shares.push(Share {
                path,
                value,
                fraction: 0.0,
                nodes: vec![n.id],
            }),
        }
    }
    for s in &mut shares {
        s.fraction = if pixel_lum > 0.0 {
            luminance(s.value) / pixel_lum
        } else {
            0.0
        };
    }
    shares.sort_by(|a, b| luminance(b.value).total_cmp(&luminance(a.value)));
    if shares.is_empty() {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "the pixel is black: no path brings light to the eye{}",
                outside_spots(tree, scene)
            ),
            nodes: tree.samples.iter().map(|s| s.root).collect(),
        });
    }
    let (big, small): (Vec<&Share>, Vec<&Share>) = shares
        .iter()
        .partition(|s| s.fraction >= SMALL_SHARE || pixel_lum <= 0.0);
    for s in &big {
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!("{}: {:.1}% {}", s.path, 100.0 * s.fraction, rgb(s.value)),
            nodes: ids(&s.nodes),
        });
    }
    if !small.is_empty() {
        let value = small.iter().fold(Rgb::ZERO, |a, s| a + s.value);
        let nodes: Vec<NodeId> = small.iter().flat_map(|s| s.nodes.clone()).collect();
        sentences.push(Sentence {
            kind: SentenceKind::Sees,
            text: format!(
                "{} other paths, each under {:.1}%: {:.1}% {}",
                small.len(),
                100.0 * SMALL_SHARE,
                100.0 * luminance(value) / pixel_lum,
                rgb(value)
            ),
            nodes: ids(&nodes),
        });
    }

    // Total internal reflection.
    let tir: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.interface.as_ref().is_some_and(|i| i.tir))
        .collect();
    if let Some(first) = tir.first() {
        let i = first.interface.as_ref().expect("filtered on interface");
        let crit = (i.n2 / i.n1).clamp(-1.0, 1.0).asin().to_degrees();
        let mut objects: Vec<&str> = tir
            .iter()
            .filter_map(|n| n.hit.as_ref().map(|h| h.object_name.as_str()))
            .collect();
        objects.dedup();
        sentences.push(Sentence {
            kind: SentenceKind::Event,
            text: format!(
                "total internal reflection at {} ray{} inside the {} (first at #{}: theta_i {:.1} deg > critical angle {:.1} deg, n {:.3} -> {:.3})",
                tir.len(),
                if tir.len() == 1 { "" } else { "s" },
                objects.join(", the "),
                first.id.0,
                deg(i.cos_i),
                crit,
                i.n1,
                i.n2
            ),
            nodes: tir.iter().map(|n| n.id).collect(),
        });
    }

    // Russian roulette instead of the split at weak dielectric hits.
    let rouletted: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| n.interface.as_ref().is_some_and(|i| i.roulette.is_some()))
        .collect();
    if !rouletted.is_empty() {
        let why = match (
            tree.settings.whitted.roulette_below,
            tree.settings.whitted.dielectric_roulette,
        ) {
            (_, Some(d)) => format!("from depth {d} (settings.dielectric_roulette)"),
            (Some(w), None) => format!("where the throughput was below {w:.2e}"),
            (None, None) => String::new(),
        };
        sentences.push(Sentence {
            kind: SentenceKind::Event,
            text: format!(
                "Russian roulette at {} glass hit{} {why}: one of the reflected and refracted rays followed, its weight divided by its probability (exact in expectation; the other ray is not traced)",
                rouletted.len(),
                if rouletted.len() == 1 { "" } else { "s" },
            ),
            nodes: rouletted.iter().map(|n| n.id).collect(),
        });
    }

    // Where energy went: weight cut.
    let st = &tree.settings;
    for (reason, what) in [
        (EndReason::MaxDepth, format!("max depth {}", st.max_depth)),
        (
            EndReason::MinWeight,
            match scene.settings.whitted.min_weight {
                None => format!(
                    "the automatic min weight {:.2e}",
                    st.whitted.min_weight.unwrap_or(0.0)
                ),
                Some(w) => format!("min weight {w:.2e}"),
            },
        ),
        (
            EndReason::RayBudget,
            format!("the ray budget of {} rays per sample", st.max_rays),
        ),
    ] {
        let cut: Vec<&RayNode> = tree.nodes.iter().filter(|n| n.end == reason).collect();
        if cut.is_empty() {
            continue;
        }
        let weight = cut.iter().fold(Rgb::ZERO, |a, n| {
            a + n.throughput * atten(n) * n.truncated / spp
        });
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text: format!(
                "cut by {what}: {} ray{} spawned no secondary rays, leaving path weight {} untraced (the share of the pixel's paths that was not followed)",
                cut.len(),
                if cut.len() == 1 { "" } else { "s" },
                num(luminance(weight))
            ),
            nodes: cut.iter().map(|n| n.id).collect(),
        });
    }

    // Absorbed by Beer's law, per medium.
    let mut absorbed: Vec<(usize, Rgb, Vec<NodeId>)> = Vec::new();
    for n in &tree.nodes {
        let Some(a) = &n.attenuation else { continue };
        if a.factor == Rgb::ONE || n.kind == RayKind::Shadow {
            continue;
        }
        let carried = match n.hit {
            Some(_) => {
                n.local
                    + n.children
                        .iter()
                        .map(|c| tree.node(*c))
                        .filter(|c| c.kind != RayKind::Shadow)
                        .fold(Rgb::ZERO, |s, c| s + c.weight * c.radiance)
            }
            None => scene.background,
        };
        let lost = n.throughput * (Rgb::ONE - a.factor) * carried / spp;
        match absorbed.iter_mut().find(|x| x.0 == a.medium) {
            Some(x) => {
                x.1 += lost;
                x.2.push(n.id);
            }
            None => absorbed.push((a.medium, lost, vec![n.id])),
        }
    }
    for (medium, lost, nodes) in absorbed {
        let name = scene
            .objects
            .get(medium)
            .map_or("an absorbing object", |o| o.name.as_str());
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text: format!(
                "absorbed by Beer's law in the {name}: {} of pixel value on {} ray segment{}",
                rgb(lost),
                nodes.len(),
                if nodes.len() == 1 { "" } else { "s" }
            ),
            nodes,
        });
    }

    // Shadow rays blocked.
    let blocked: Vec<&RayNode> = tree
        .nodes
        .iter()
        .filter(|n| matches!(n.end, EndReason::Blocked | EndReason::Attenuated))
        .collect();
    if !blocked.is_empty() {
        let mut lost = Rgb::ZERO;
        let mut by: Vec<&str> = Vec::new();
        for n in &blocked {
            let Some(sh) = &n.shadow else { continue };
            let surface = n.parent.map(|p| tree.node(p));
            let carry = surface.map_or(Rgb::ONE, |s| s.throughput * atten(s));
            lost += carry * n.weight * sh.irradiance * (Rgb::ONE - sh.transmittance) / spp;
            for b in &sh.blockers {
                if !by.contains(&b.object_name.as_str()) {
                    by.push(&b.object_name);
                }
            }
        }
        let text = if lost == Rgb::ZERO {
            format!(
                "{} shadow ray{} blocked or dimmed (by the {}), none of which would have lit its surface (BRDF x cos is 0 there)",
                blocked.len(),
                if blocked.len() == 1 { "" } else { "s" },
                by.join(", the ")
            )
        } else {
            format!(
                "{} shadow ray{} blocked or dimmed by the {}: unblocked they would add {} to the pixel",
                blocked.len(),
                if blocked.len() == 1 { "" } else { "s" },
                by.join(", the "),
                rgb(lost)
            )
        };
        sentences.push(Sentence {
            kind: SentenceKind::Energy,
            text,
            nodes: blocked.iter().map(|n| n.id).collect(),
        });
    }

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
mod words;

use suspicious::suspicious;
pub use text::{explanation_text, node_list};
use words::path_words;
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
