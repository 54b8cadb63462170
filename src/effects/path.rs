//! `raytree effects` under the path integrator.

use super::EffectLine;
use crate::integrator::plan::nonzero;
use crate::scene::{Material, Scene};

/// The names of the used materials a predicate holds for (`EffectPlan::explain`'s `names`).
pub(super) type Names<'a> = &'a dyn Fn(&dyn Fn(&Material) -> bool) -> String;

/// The Whitted lines the path integrator reads differently, restated for it: it always uses
/// exact Fresnel, samples area lights by next-event estimation (one light sample per bounce,
/// not `settings.light_samples`) and rough lobes by its one BSDF sample per bounce (not
/// `settings.glossy_samples`); the translucent-shadow and Blinn-Phong lines are dropped, as
/// [`lines`] says that it ignores them.
pub(super) fn restate(out: &mut Vec<EffectLine>, scene: &Scene) {
    let s = &scene.settings;
    out.retain(|l| l.effect != "translucent shadows" && l.effect != "Blinn-Phong highlights");
    for l in out.iter_mut() {
        match l.effect.as_str() {
            "Fresnel" if l.reason != "no transmissive material" => {
                l.on = true;
                l.reason = format!(
                    "exact at transmissive surfaces (the path integrator's; settings.fresnel \
                     {} is the Whitted integrator's)",
                    format!("{:?}", s.fresnel).to_lowercase()
                );
            }
            "area lights" => {
                let list = l.reason.split(';').next().unwrap_or_default().to_string();
                l.on = !list.starts_with("no emissive");
                l.reason = format!(
                    "{list}; next-event estimation, one light sample per bounce \
                     (settings.light_samples is the Whitted integrator's)"
                );
            }
            "glossy (rough lobes)" if l.on => {
                l.reason = format!(
                    "{}; GGX lobes sampled by each bounce's BSDF sample, exact Fresnel \
                     (settings.glossy_samples is the Whitted integrator's)",
                    l.reason.split(';').next().unwrap_or_default()
                );
            }
            _ => {}
        }
    }
}

/// What the path integrator does with the scene, for `raytree effects`: it samples lights and
/// BSDFs at every hit, and ignores Whitted's approximations (ambient, Blinn-Phong, translucent
/// shadows).
pub(super) fn lines(scene: &Scene, names: Names<'_>) -> Vec<EffectLine> {
    let s = &scene.settings;
    let line = |effect: &str, on: bool, reason: String| EffectLine {
        effect: effect.to_string(),
        on,
        reason,
    };
    let emitters = (0..scene.objects.len())
        .filter(|&i| scene.area_light(i).is_some())
        .count();
    vec![
        line(
            "path integrator",
            true,
            format!(
                "next-event estimation over {} lights ({} point/directional, {emitters} \
                 emissive spheres/quads/triangles), BSDF sampling, MIS (power heuristic), \
                 Russian roulette from bounce {}, max depth {}{}",
                scene.lights.len() + emitters,
                scene.lights.len(),
                s.rr_depth,
                s.max_depth,
                super::dark_note(scene)
            ),
        ),
        line(
            "ambient (path integrator ignores it)",
            false,
            if scene.ambient.max_element() > 0.0 {
                "scene ambient > 0: a Whitted approximation of indirect light, which the path \
                 integrator computes"
                    .to_string()
            } else {
                "scene ambient is 0".to_string()
            },
        ),
        line(
            "Blinn-Phong specular (path integrator ignores it)",
            false,
            format!(
                "specular/shininess are Whitted's highlight: {}",
                names(&|m| nonzero(m.specular))
            ),
        ),
        line(
            "translucent shadows (path integrator ignores them)",
            false,
            format!(
                "shadow rays are visibility tests; light through glass arrives by BSDF \
                 sampling (caustics); shadows {:?}",
                s.shadows
            )
            .to_lowercase()
            .replace("bsdf", "BSDF"),
        ),
    ]
}
