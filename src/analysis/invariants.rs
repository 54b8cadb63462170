//! Invariants every recorded tree must satisfy; used by tests on every fixture.

use crate::math::Rgb;
use crate::tree::{Interface, RayKind, RayNode, RayTree};

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
/// - `R + T = 1` and `0 <= R <= 1` at every dielectric hit; TIR has no transmitted ray;
/// - path integrator: a sample's radiance is the sum of its nodes' recorded contributions (in
///   depth-first order, the order the integrator adds them), each node's light path expression
///   extends its parent's, and a Russian-roulette kill has no continuation;
/// - light tracing: the pixel is the sample mean plus the splats' sum over `spp`, each splat
///   recorded on its connection node (`splat_violations`).
#[must_use]
pub fn tree_violations(tree: &RayTree, background: Rgb) -> Vec<String> {
    let mut v = Vec::new();
    let bidirectional = tree.settings.integrator == crate::scene::IntegratorKind::Bdpt;
    // The path integrator drops a sample that is not finite (black in the pixel's mean).
    let path = tree.nodes.iter().any(|n| n.path.is_some());
    let mean = sample_mean(tree, path);
    if tree.splats.is_empty() && mean != tree.radiance {
        v.push(format!(
            "pixel radiance {} != sample mean {}",
            tree.radiance, mean
        ));
    }
    if !tree.splats.is_empty() {
        splat_violations(tree, mean, &mut v);
    }
    if path {
        path_violations(tree, &mut v);
    }
    for n in &tree.nodes {
        finite_violations(n, &mut v);
        // A light subpath carries flux forwards: its nodes answer to the splat checks. Under
        // bidirectional path tracing a camera vertex's light arrives by weighted strategies,
        // not as Whitted-shaped sums: its samples answer to the contribution sums.
        if matches!(
            n.kind,
            RayKind::Shadow | RayKind::Light | RayKind::Connection
        ) || bidirectional
        {
            continue;
        }
        sum_violations(tree, n, background, &mut v);
        if let Some(i) = &n.interface {
            interface_violations(tree, n, i, &mut v);
        }
    }
    v
}

/// The mean of the sample radiances (a sample that is not finite counts as black when `path`).
fn sample_mean(tree: &RayTree, path: bool) -> Rgb {
    let spp = tree.samples.len().max(1) as f64;
    tree.samples.iter().fold(Rgb::ZERO, |s, x| {
        if path && !x.radiance.is_finite() {
            s
        } else {
            s + x.radiance
        }
    }) / spp
}

/// Every value of node `n` is finite.
fn finite_violations(n: &RayNode, v: &mut Vec<String>) {
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
}

/// The sums at a Whitted-shaped node `n`: its children's throughputs, its local term and its
/// radiance (a miss: the attenuated `background`).
fn sum_violations(tree: &RayTree, n: &RayNode, background: Rgb, v: &mut Vec<String>) {
    let id = n.id.0;
    let atten = n.attenuation.as_ref().map_or(Rgb::ONE, |a| a.factor);
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
}

/// Fresnel at node `n`'s interface `i`: `R + T = 1`, `0 <= R <= 1`, no refracted ray under TIR.
fn interface_violations(tree: &RayTree, n: &RayNode, i: &Interface, v: &mut Vec<String>) {
    let id = n.id.0;
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

/// Light tracing's invariants ([`tree_violations`]): the pixel is the sample mean plus the
/// splats' sum (in their order) over `splat_divisor`, bit for bit; each splat's connection is
/// a `connection` node whose recorded contribution is the splat's, below a `light` ray of its
/// own light path; its light path expression runs from the camera to the light.
fn splat_violations(tree: &RayTree, mean: Rgb, v: &mut Vec<String>) {
    let sum = crate::render::splat::splat_sum(&tree.splats);
    let expect = crate::render::splat::with_splats(mean, sum, tree.splat_divisor);
    if expect != tree.radiance {
        v.push(format!(
            "pixel radiance {} != sample mean + splats / {} = {}",
            tree.radiance, tree.splat_divisor, expect
        ));
    }
    for (i, s) in tree.splats.iter().enumerate() {
        let (Some(c), Some(root)) = (
            tree.nodes.get(s.connection.index()),
            tree.nodes.get(s.root.index()),
        ) else {
            v.push(format!("splat {i}: its nodes are not in the tree"));
            continue;
        };
        let recorded = c.path.as_ref().map(|p| p.contribution);
        if c.kind != RayKind::Connection || recorded != Some(s.contribution) {
            v.push(format!(
                "splat {i}: connection node {} ({}) does not record its contribution {}",
                c.id.0,
                c.kind.name(),
                s.contribution
            ));
        }
        if root.kind != RayKind::Light || root.parent.is_some() {
            v.push(format!(
                "splat {i}: root {} is not a light path's first ray",
                root.id.0
            ));
        }
        if !(s.lpe.starts_with('C') && s.lpe.ends_with('L')) {
            v.push(format!("splat {i}: light path expression {:?}", s.lpe));
        }
        if !s.contribution.is_finite() {
            v.push(format!(
                "splat {i}: contribution {} is not finite",
                s.contribution
            ));
        }
    }
}

/// The path integrator's per-sample invariants ([`tree_violations`]).
fn path_violations(tree: &RayTree, v: &mut Vec<String>) {
    for s in &tree.samples {
        let mut sum = Rgb::ZERO;
        for id in tree.depth_first(s.root) {
            let n = tree.node(id);
            let Some(p) = &n.path else {
                v.push(format!("node {}: no path record in a path tree", id.0));
                continue;
            };
            sum += p.contribution;
            // A light subpath's expressions read from the light; a connection that carried
            // nothing (blocked) names no path.
            let unnamed = n.kind == RayKind::Connection && p.contribution == Rgb::ZERO;
            if n.kind == RayKind::Light || unnamed {
                continue;
            }
            if let Some(parent) = n.parent.and_then(|q| tree.node(q).path.as_ref()) {
                let stem = parent.lpe.trim_end_matches(['L', 'B']);
                if !p.lpe.starts_with(stem) {
                    v.push(format!(
                        "node {}: LPE {} does not extend its parent's {}",
                        id.0, p.lpe, parent.lpe
                    ));
                }
            }
            let killed = p.roulette.is_some_and(|r| !r.survived);
            let continued = n.children.iter().any(|c| {
                !matches!(
                    tree.node(*c).kind,
                    RayKind::Shadow | RayKind::Connection | RayKind::Light
                )
            });
            if killed && continued {
                v.push(format!("node {}: killed by roulette but continued", id.0));
            }
        }
        if s.radiance.is_finite() && sum != s.radiance && !close(sum, s.radiance) {
            v.push(format!(
                "sample {}: radiance {} != sum of contributions {}",
                s.index, s.radiance, sum
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::tree_violations;
    use crate::math::Rgb;
    use crate::tree::{RayKind, RayTree};
    use crate::{Scene, trace_pixel};

    /// The classic scene's glass-ball pixel: reflection, refraction, shadows, an interface.
    fn glass_pixel() -> (RayTree, Rgb) {
        let scene = Scene::default_scene();
        let tree = trace_pixel(&scene, 400, 200).expect("pixel inside the image");
        (tree, scene.background)
    }

    fn first(tree: &RayTree, kind: RayKind) -> usize {
        tree.nodes
            .iter()
            .position(|n| n.kind == kind)
            .expect("the glass pixel has one")
    }

    #[test]
    fn a_traced_tree_is_clean() {
        let (tree, bg) = glass_pixel();
        assert!(tree.nodes.len() > 5, "a real tree");
        assert_eq!(tree_violations(&tree, bg), Vec::<String>::new());
    }

    /// Each corruption is one the checker exists to catch; each must be reported.
    #[test]
    fn every_corruption_is_reported() {
        type Corrupt = fn(&mut RayTree);
        let cases: [(&str, &str, Corrupt); 8] = [
            ("sample mean", "sample mean", |t| {
                t.radiance += Rgb::splat(1e-3)
            }),
            ("not finite", "not finite", |t| {
                t.nodes[0].weight = Rgb::splat(f64::NAN)
            }),
            ("local", "local", |t| t.nodes[0].local += Rgb::splat(0.1)),
            ("radiance", "radiance", |t| {
                let i = first(t, RayKind::Reflected);
                t.nodes[i].radiance += Rgb::splat(0.1);
            }),
            ("throughput", "throughput", |t| {
                let i = first(t, RayKind::Refracted);
                t.nodes[i].throughput *= 0.5;
            }),
            ("shadow weight", "sum of parts", |t| {
                let i = first(t, RayKind::Shadow);
                t.nodes[i].weight += Rgb::splat(0.25);
                t.nodes[i].radiance = Rgb::ONE;
            }),
            ("R + T", "+ T", |t| {
                let i = t.nodes.iter().position(|n| n.interface.is_some()).unwrap();
                t.nodes[i].interface.as_mut().unwrap().fresnel.r += 0.1;
            }),
            ("TIR with refraction", "TIR but", |t| {
                let i = t.nodes.iter().position(|n| n.interface.is_some()).unwrap();
                t.nodes[i].interface.as_mut().unwrap().tir = true;
            }),
        ];
        for (what, expect, corrupt) in cases {
            let (mut tree, bg) = glass_pixel();
            corrupt(&mut tree);
            let v = tree_violations(&tree, bg);
            assert!(
                v.iter().any(|m| m.contains(expect)),
                "{what}: corruption not reported as {expect:?}: {v:?}"
            );
        }
    }
}
