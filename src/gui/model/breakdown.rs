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

/// What node `id` adds to the pixel value (divided by the sample count). For a reflected or
/// refracted ray that is `throughput x radiance`; for a shadow ray it is its share of its
/// surface's local term, `throughput x Beer x weight (BRDF cos) x radiance (irradiance)`, with the
/// surface's throughput and Beer factor, not the light's irradiance on its own.
#[must_use]
pub fn pixel_contribution(tree: &RayTree, id: NodeId) -> Rgb {
    let spp = tree.samples.len().max(1) as f64;
    let n = tree.node(id);
    let value = match (n.kind, n.parent) {
        (RayKind::Shadow, Some(p)) => {
            let surface = tree.node(p);
            let atten = surface.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
            surface.throughput * atten * n.weight * n.radiance
        }
        _ => n.contribution(),
    };
    value / spp
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn shadow_rays_contribute_their_share_of_the_local_term() {
        let scene = Scene::default_scene();
        for (x, y) in [(400, 200), (300, 200), (250, 300)] {
            let tree = crate::trace_pixel(&scene, x, y).unwrap();
            for n in tree.nodes.iter().filter(|n| n.kind != RayKind::Shadow) {
                let Some(h) = &n.hit else { continue };
                let _ = h;
                let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
                // The local term's direct part is the sum of its shadow rays' shares.
                let direct: Rgb = n
                    .children
                    .iter()
                    .filter(|c| tree.node(**c).kind == RayKind::Shadow)
                    .fold(Rgb::ZERO, |acc, c| acc + pixel_contribution(&tree, *c));
                let want = n.throughput * atten * (n.local - n.emitted - n.ambient);
                assert!(
                    (direct - want).abs().max_element() < 1e-9,
                    "{x},{y} #{}",
                    n.id.0
                );
                for c in &n.children {
                    let c = tree.node(*c);
                    // Never more than the whole pixel, unlike the light's irradiance.
                    if c.kind == RayKind::Shadow {
                        let share = pixel_contribution(&tree, c.id).max_element();
                        assert!(share <= tree.radiance.max_element() + 1e-12);
                    }
                }
            }
        }
    }

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
