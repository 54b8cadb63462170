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
                    format!("{:?}", s.whitted.fresnel).to_lowercase()
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
                s.path.rr_depth,
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
                s.whitted.shadows
            )
            .to_lowercase()
            .replace("bsdf", "BSDF"),
        ),
    ]
}

/// What light tracing does with the scene, for `raytree effects`: [`lines`] with its own
/// first line (light paths, camera connections, what it cannot see) and the same ignored
/// approximations.
pub(super) fn light_lines(scene: &Scene, names: Names<'_>) -> Vec<EffectLine> {
    let s = &scene.settings;
    let emitters = (0..scene.objects.len())
        .filter(|&i| scene.area_light(i).is_some())
        .count();
    let filter = if matches!(s.filter, crate::scene::FilterDesc::Box {}) {
        String::new()
    } else {
        "; splats use the box filter (settings.filter is the camera integrators')".to_string()
    };
    let adaptive = if s.adaptive.is_some() {
        "; settings.adaptive is ignored (every pixel's splats are divided by spp)"
    } else {
        ""
    };
    let mut out = lines(scene, names);
    for l in &mut out {
        l.effect = l.effect.replace("path integrator", "light tracing");
        l.reason = l.reason.replace("the path integrator", "light tracing");
    }
    if scene.background.max_element() > 0.0 {
        out.push(EffectLine {
            effect: "background as a light (light tracing ignores it)".to_string(),
            on: false,
            reason: "the camera sees the background directly, but light paths start only on \
                     the scene's lights: the sky lights nothing here (under path escaping rays \
                     gather it)"
                .to_string(),
        });
    }
    let unbounded = scene.objects.iter().any(|o| o.shape.bounds().is_none());
    let directional = scene
        .lights
        .iter()
        .any(|l| matches!(l.kind, crate::scene::LightKind::Directional { .. }));
    if unbounded && directional {
        let (c, r) = scene.bounding_sphere();
        out.push(EffectLine {
            effect: "directional lights over unbounded shapes".to_string(),
            on: false,
            reason: format!(
                "directional light paths start on a disc over the bounded objects' sphere \
                 (centre [{:.3}, {:.3}, {:.3}], radius {:.3}): an infinite plane beyond it is \
                 unlit by them (use a quad)",
                c.x, c.y, c.z, r
            ),
        });
    }
    out[0].reason = format!(
        "one light path per pixel sample from {} lights chosen by power ({} point/directional, \
         {emitters} emissive spheres/quads/triangles); every vertex on a non-specular surface \
         connects to the camera and is splatted to the pixel it lands in; what the camera sees \
         directly comes from one camera ray per sample; light seen through glass or in a \
         mirror is not found (no connection reaches the camera through a specular surface: \
         use path); Russian roulette from bounce {}, max depth {}{filter}{adaptive}{}",
        scene.lights.len() + emitters,
        scene.lights.len(),
        s.path.rr_depth,
        s.max_depth,
        super::dark_note(scene)
    );
    out
}

/// [`restate`]'s area-light line as light tracing reads it: its paths start on the lights.
pub(super) fn restate_light(out: &mut [EffectLine]) {
    for l in out {
        if l.effect == "area lights" {
            l.reason = l.reason.replace(
                "next-event estimation, one light sample per bounce",
                "light paths start on them (points by area, directions by cosine)",
            );
        }
    }
}

/// What bidirectional path tracing does with the scene, for `raytree effects`: [`lines`] with
/// its own first line and the same ignored approximations.
pub(super) fn bdpt_lines(scene: &Scene, names: Names<'_>) -> Vec<EffectLine> {
    let s = &scene.settings;
    let mut out = lines(scene, names);
    for l in &mut out {
        l.effect = l
            .effect
            .replace("path integrator", "bidirectional path tracing");
        l.reason = l
            .reason
            .replace("the path integrator", "bidirectional path tracing");
    }
    out[0].reason = format!(
        "a camera subpath and a light subpath per pixel sample, joined by every strategy \
         (s, t) up to {} scattering vertices: the camera subpath finding an emitter (s = 0), a \
         light sampled from its vertices (s = 1), light-subpath vertices connected to the \
         camera and splatted (t = 1), and visibility rays between the two; weighted by the \
         balance heuristic over all strategies (delta vertices excluded); Russian roulette \
         from bounce {} on both subpaths; the background lights nothing from the light's \
         side (only escaping camera subpaths see it){}",
        s.max_depth + 1,
        s.path.rr_depth,
        super::dark_note(scene)
    );
    if !matches!(s.filter, crate::scene::FilterDesc::Box {}) || s.adaptive.is_some() {
        out[0].reason.push_str(
            "; its splats use the box filter and every pixel's splats are divided by spp \
             (settings.filter and settings.adaptive are the camera integrators')",
        );
    }
    out
}
