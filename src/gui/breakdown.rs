//! How a pixel's value adds up: each surface's local shading (emission, ambient, direct light)
//! and each miss's background, weighted by the path throughput that carries it to the eye.

use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayTree};

/// One term of the pixel value.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// The node that contributes.
    pub node: NodeId,
    /// Human-readable source ("mirror ball: local", "background").
    pub label: String,
    /// Contribution to the pixel (already divided by the sample count).
    pub value: Rgb,
}

/// The terms whose sum is the pixel radiance, largest first. Shadow rays are inside their
/// surface's local term, so they do not appear on their own.
#[must_use]
pub fn breakdown(tree: &RayTree) -> Vec<Term> {
    let spp = tree.samples.len().max(1) as f64;
    let mut terms: Vec<Term> = tree
        .nodes
        .iter()
        .filter(|n| n.kind != RayKind::Shadow)
        .map(|n| {
            let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
            let (label, source) = match &n.hit {
                Some(h) => (
                    format!("{} #{}: local", h.object_name, n.id.0),
                    atten * n.local,
                ),
                None => (format!("background via #{}", n.id.0), n.radiance),
            };
            Term {
                node: n.id,
                label,
                value: n.throughput * source / spp,
            }
        })
        .filter(|t| t.value != Rgb::ZERO)
        .collect();
    terms.sort_by(|a, b| b.value.element_sum().total_cmp(&a.value.element_sum()));
    terms
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn the_terms_add_up_to_the_pixel() {
        let mut scene = Scene::default_scene();
        for spp in [1, 4] {
            scene.settings.spp = spp;
            for (x, y) in [(300, 200), (420, 170), (5, 5), (330, 150), (250, 300)] {
                let tree = crate::trace_pixel(&scene, x, y).unwrap();
                let sum = breakdown(&tree)
                    .iter()
                    .fold(Rgb::ZERO, |acc, t| acc + t.value);
                assert!(
                    (sum - tree.radiance).abs().max_element() < 1e-9,
                    "{x},{y}: {sum} vs {}",
                    tree.radiance
                );
            }
        }
    }
}
