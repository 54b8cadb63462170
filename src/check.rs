//! Invariants every recorded tree must satisfy; used by tests on every fixture.

use crate::math::Rgb;
use crate::tree::{RayKind, RayTree};

/// Relative tolerance for recomputed sums (the tracer adds in the same order, so differences
/// are rounding at most).
const TOL: f64 = 1e-12;

fn close(a: Rgb, b: Rgb) -> bool {
    (a - b).abs().max_element() <= TOL * (1.0 + a.abs().max_element().max(b.abs().max_element()))
}

/// Check the tree's invariants; returns every violation found.
///
/// - the pixel radiance is the mean of the sample radiances;
/// - every value is finite (distances may be infinite for misses);
/// - `local = emitted + ambient + sum(shadow weight * radiance)`;
/// - `radiance = attenuation * (local + sum(secondary weight * radiance))` (misses: background);
/// - a child's throughput is its parent's times the parent's attenuation times its weight;
/// - `R + T = 1` and `0 <= R <= 1` at every dielectric hit; TIR has no transmitted ray.
#[must_use]
pub fn tree_violations(tree: &RayTree, background: Rgb) -> Vec<String> {
    let mut v = Vec::new();
    let spp = tree.samples.len().max(1) as f64;
    let mean = tree.samples.iter().fold(Rgb::ZERO, |s, x| s + x.radiance) / spp;
    if mean != tree.radiance {
        v.push(format!(
            "pixel radiance {} != sample mean {}",
            tree.radiance, mean
        ));
    }
    for n in &tree.nodes {
        let id = n.id.0;
        for (what, x) in [
            ("radiance", n.radiance),
            ("weight", n.weight),
            ("throughput", n.throughput),
            ("local", n.local),
        ] {
            if !x.is_finite() {
                v.push(format!("node {id}: {what} {x} is not finite"));
            }
        }
        let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
        if n.kind == RayKind::Shadow {
            continue;
        }
        let mut local = n.emitted + n.ambient;
        let mut secondary = Rgb::ZERO;
        for c in &n.children {
            let c = tree.node(*c);
            if c.kind == RayKind::Shadow {
                local += c.weight * c.radiance;
            } else {
                secondary += c.weight * c.radiance;
                let expect = n.throughput * atten * c.weight;
                if !close(c.throughput, expect) {
                    v.push(format!(
                        "node {}: throughput {} != {}",
                        c.id.0, c.throughput, expect
                    ));
                }
            }
        }
        let expect = if n.hit.is_some() {
            if !close(n.local, local) {
                v.push(format!(
                    "node {id}: local {} != sum of parts {}",
                    n.local, local
                ));
            }
            atten * (n.local + secondary)
        } else {
            atten * background
        };
        if !close(n.radiance, expect) {
            v.push(format!("node {id}: radiance {} != {}", n.radiance, expect));
        }
        if let Some(i) = &n.interface {
            let f = &i.fresnel;
            if (f.r + f.t - 1.0).abs() > TOL || !(0.0..=1.0).contains(&f.r) {
                v.push(format!("node {id}: R {} + T {} != 1", f.r, f.t));
            }
            let refracted = n
                .children
                .iter()
                .any(|c| tree.node(*c).kind == RayKind::Refracted);
            if i.tir && refracted {
                v.push(format!("node {id}: TIR but a refracted ray was spawned"));
            }
        }
    }
    v
}
