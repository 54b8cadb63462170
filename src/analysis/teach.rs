//! Teacher-facing numbers for one recorded node (issue 17): angles in degrees beside the
//! cosines, the critical angle at a dielectric interface, a secondary ray's weight split into
//! its factors, medium names, and the point `R(t) = A + t d` along a ray (the lecture's
//! `R(t) = A + (P - A) t` with `A` the ray's origin and `d` its unit direction). Pure: read
//! from the tree and the scene it was traced in.

use crate::math::Rgb;
use crate::scene::Scene;
use crate::tree::{Interface, NodeId, RayKind, RayNode, RayTree};
use glam::DVec3;

/// How close a recomputed weight must be to the recorded one for its factors to be shown.
const WEIGHT_TOL: f64 = 1e-12;

/// The angle of a cosine in degrees (the cosine clamped to [-1, 1]; NaN stays NaN).
#[must_use]
pub fn deg(cos: f64) -> f64 {
    cos.clamp(-1.0, 1.0).acos().to_degrees()
}

/// The critical angle in degrees going from index `n1` into `n2`, where there is one
/// (`n1 > n2`, both positive and finite).
#[must_use]
pub fn critical_angle(n1: f64, n2: f64) -> Option<f64> {
    let ok = n1.is_finite() && n2.is_finite() && n2 > 0.0 && n1 > n2;
    ok.then(|| (n2 / n1).asin().to_degrees())
}

/// The interface's angles in words: `theta_i 63.0 deg > theta_c 41.8 deg: total internal
/// reflection`, or `theta_i 4.5 deg, theta_t 3.0 deg (n 1.000 -> 1.500, no critical angle)`.
#[must_use]
pub fn incidence_text(i: &Interface) -> String {
    let ti = deg(i.cos_i);
    let crit = critical_angle(i.n1, i.n2);
    match (i.tir, crit) {
        (true, Some(c)) => format!(
            "theta_i {ti:.1} deg > theta_c {c:.1} deg: total internal reflection (n {:.3} -> {:.3})",
            i.n1, i.n2
        ),
        (true, None) => format!("theta_i {ti:.1} deg: total internal reflection"),
        (false, c) => {
            let tt = i
                .cos_t
                .map_or(String::new(), |ct| format!(", theta_t {:.1} deg", deg(ct)));
            let crit = c.map_or(", no critical angle".to_string(), |c| {
                format!(", theta_i < theta_c {c:.1} deg")
            });
            format!(
                "theta_i {ti:.1} deg{tt} (n {:.3} -> {:.3}{crit})",
                i.n1, i.n2
            )
        }
    }
}

/// The name of the object a Beer segment lies in (`#index` if the scene has no such object).
#[must_use]
pub fn medium_name(scene: &Scene, medium: usize) -> String {
    scene
        .objects
        .get(medium)
        .map_or(format!("#{medium}"), |o| o.name.clone())
}

/// A colour as one number when its channels are equal, else `[r, g, b]`, `digits` decimals.
fn value(c: Rgb, digits: usize) -> String {
    if c.x == c.y && c.y == c.z {
        format!("{:.digits$}", c.x)
    } else {
        format!("[{:.digits$}, {:.digits$}, {:.digits$}]", c.x, c.y, c.z)
    }
}

/// A reflected or refracted ray's weight as the product the tracer formed, when the tree and
/// the scene agree on it (the recomputed weight equals the recorded one within 1e-12):
/// `0.0380 = R 0.0400 x transmissivity 0.9500`, `0.9120 = T 0.9600 x transmissivity 0.9500`,
/// `0.8000 = reflectivity 0.8000` (a mirror), `0.1380 = reflectivity 0.1000 + R 0.0400 x
/// transmissivity 0.9500`. A shadow ray's weight is `BRDF x cos theta`. `None` for a camera
/// ray (weight 1) or when the numbers do not agree.
#[must_use]
pub fn weight_factors(scene: &Scene, tree: &RayTree, id: NodeId) -> Option<String> {
    let n = tree.node(id);
    let parent = tree.node(n.parent?);
    let w = value(n.weight, 4);
    if n.kind == RayKind::Shadow {
        let s = n.shadow.as_ref()?;
        let want = s.brdf * s.cos_theta.max(0.0);
        return close(want, n.weight).then(|| {
            format!(
                "{w} = BRDF {} x cos theta {:.4} (theta {:.1} deg)",
                value(s.brdf, 4),
                s.cos_theta,
                deg(s.cos_theta)
            )
        });
    }
    let hit = parent.hit.as_ref()?;
    let m = scene
        .objects
        .get(hit.object)
        .and_then(|o| scene.materials.get(o.material))?;
    let (want, text) = match (n.kind, &parent.interface) {
        (RayKind::Reflected, None) => match m.conductor {
            None => (
                m.reflectivity,
                format!("reflectivity {}", value(m.reflectivity, 4)),
            ),
            Some(ior) => {
                // A smooth conductor: the mirror ray carries the conductor Fresnel per channel.
                let f = ior.fresnel(hit.cos_i);
                let text = format!(
                    "conductor Fresnel {} at cos_i {:.4}",
                    value(f, 4),
                    hit.cos_i
                );
                let text = if m.reflectivity == Rgb::ONE {
                    text
                } else {
                    format!("{text} x scale {}", value(m.reflectivity, 4))
                };
                (m.reflectivity * f, text)
            }
        },
        (RayKind::Reflected, Some(i)) => {
            let dielectric = format!(
                "R {:.4} x transmissivity {}",
                i.fresnel.r,
                value(m.transmissivity, 4)
            );
            let text = if m.reflectivity == Rgb::ZERO {
                dielectric
            } else {
                format!("reflectivity {} + {dielectric}", value(m.reflectivity, 4))
            };
            (m.reflectivity + m.transmissivity * i.fresnel.r, text)
        }
        (RayKind::Refracted, Some(i)) => (
            m.transmissivity * i.fresnel.t,
            format!(
                "T {:.4} x transmissivity {}",
                i.fresnel.t,
                value(m.transmissivity, 4)
            ),
        ),
        _ => return None,
    };
    let (want, text) = match parent.interface.as_ref().and_then(|i| i.roulette) {
        Some(c) => (
            want / c.probability,
            format!(
                "({text}) / {:.4}, its Russian-roulette probability",
                c.probability
            ),
        ),
        None => (want, text),
    };
    close(want, n.weight).then(|| format!("{w} = {text}"))
}

fn close(a: Rgb, b: Rgb) -> bool {
    (a - b).abs().max_element() <= WEIGHT_TOL * a.abs().max_element().max(1.0)
}

/// The ray's parameter range for stepping: from 0 (its origin) to its hit's `t`, a shadow ray's
/// light distance, or for a miss `fallback`.
#[must_use]
pub fn t_end(n: &RayNode, fallback: f64) -> f64 {
    let end = match (&n.hit, &n.shadow) {
        (Some(h), _) => h.t,
        (None, Some(s)) => s.distance,
        (None, None) => fallback,
    };
    if end.is_finite() && end > 0.0 {
        end
    } else {
        fallback
    }
}

/// The point `R(t) = A + t d` of the node's ray (origin `A`, unit direction `d`).
#[must_use]
pub fn point_at(n: &RayNode, t: f64) -> DVec3 {
    n.origin + n.direction * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Scene, trace_pixel};

    #[test]
    fn the_critical_angle_of_glass_is_41_8_degrees() {
        let c = critical_angle(1.5, 1.0).unwrap();
        assert!((c - 41.81).abs() < 0.01, "{c}");
        assert_eq!(critical_angle(1.0, 1.5), None);
        assert_eq!(critical_angle(1.5, f64::NAN), None);
        assert_eq!(critical_angle(1.5, 0.0), None);
        assert!((deg(0.5) - 60.0).abs() < 1e-12);
        assert!(deg(f64::NAN).is_nan());
    }

    #[test]
    fn tir_is_named_with_both_angles_on_the_tir_block() {
        let scene = Scene::from_json(include_str!("../../fixtures/tir-block.json")).unwrap();
        let tree = trace_pixel(&scene, 320, 230).unwrap();
        let tir = tree
            .nodes
            .iter()
            .find_map(|n| n.interface.as_ref().filter(|i| i.tir))
            .expect("a TIR event");
        let text = incidence_text(tir);
        assert!(
            text.starts_with("theta_i 63.0 deg > theta_c 41.8 deg: total internal reflection"),
            "{text}"
        );
    }

    #[test]
    fn weights_split_into_the_factors_the_tracer_multiplied() {
        let mut scene = Scene::default_scene();
        // With the suggested roulette weight (opt-in), deep weak hits follow one ray.
        scene.settings.whitted.roulette_below = Some(
            crate::integrator::bound::carried::auto_roulette_below(&scene, &scene.settings),
        );
        let tree = trace_pixel(&scene, 400, 200).unwrap();
        // The glass ball's reflected ray: R 0.04 x transmissivity 0.95.
        let reflected = tree.node(NodeId(2));
        assert_eq!(reflected.kind, RayKind::Reflected);
        let text = weight_factors(&scene, &tree, NodeId(2)).unwrap();
        assert!(
            text.starts_with("0.0380 = R 0.0400 x transmissivity 0.9500"),
            "{text}"
        );
        let (mut refracted, mut rouletted) = (0, 0);
        for n in &tree.nodes {
            let f = weight_factors(&scene, &tree, n.id);
            assert_eq!(f.is_some(), n.parent.is_some(), "#{}: {f:?}", n.id.0);
            refracted += usize::from(n.kind == RayKind::Refracted);
            let f = f.unwrap_or_default();
            if n.kind == RayKind::Refracted {
                assert!(f.contains("T 0.9600 x transmissivity 0.9500"), "{f}");
            }
            // Deep, weak hits follow one ray: its weight is divided by its probability.
            if f.contains("Russian-roulette probability") {
                rouletted += 1;
                let i = tree.node(n.parent.unwrap()).interface.as_ref().unwrap();
                let p = i.roulette.unwrap().probability;
                assert!(f.contains(&format!("/ {p:.4}")), "{f}");
            }
        }
        assert!(refracted > 0 && rouletted > 0, "{refracted} {rouletted}");
        // A tampered weight no longer matches its factors: nothing is claimed.
        let mut bad = tree.clone();
        bad.nodes[2].weight = Rgb::splat(0.5);
        assert_eq!(weight_factors(&scene, &bad, NodeId(2)), None);
    }

    #[test]
    fn a_conductor_mirror_weight_is_its_fresnel() {
        let src = r#"{
          "camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 9, "height": 9},
          "background": [1, 1, 1],
          "materials": {"cu": {"conductor": {"metal": "Cu"}}},
          "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "cu"}]
        }"#;
        let scene = Scene::from_json(src).unwrap();
        let tree = trace_pixel(&scene, 5, 4).unwrap();
        let n = tree
            .nodes
            .iter()
            .find(|n| n.kind == RayKind::Reflected)
            .expect("a reflected ray");
        let text = weight_factors(&scene, &tree, n.id).unwrap();
        assert!(text.contains("conductor Fresnel ["), "{text}");
        // The red channel of copper reflects most.
        let w = n.weight;
        assert!(w.x > w.y && w.y > w.z && w.x > 0.9, "{w:?}");
    }

    #[test]
    fn mirror_weights_are_the_reflectivity_and_points_move_along_the_ray() {
        let scene = Scene::default_scene();
        let tree = trace_pixel(&scene, 250, 200).unwrap();
        let n = tree
            .nodes
            .iter()
            .find(|n| n.kind == RayKind::Reflected)
            .unwrap();
        let text = weight_factors(&scene, &tree, n.id).unwrap();
        assert!(text.contains("= reflectivity "), "{text}");
        let root = tree.node(NodeId(0));
        let hit = root.hit.as_ref().unwrap();
        assert_eq!(t_end(root, 10.0), hit.t);
        assert!((point_at(root, hit.t) - hit.point).length() < 1e-9);
        assert_eq!(point_at(root, 0.0), root.origin);
        assert_eq!(medium_name(&scene, 1), scene.objects[1].name);
        assert_eq!(medium_name(&scene, 99), "#99");
    }
}
