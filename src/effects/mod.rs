//! Which effects a scene calls for, and why, in words (`raytree effects`, the inspector's scene
//! line): the report of the integrators' [`EffectPlan`] (`crate::integrator::plan`).

use crate::integrator::plan::{max_ior_step, nonzero};
use crate::math::critical_angle;
use crate::scene::Scene;

pub use crate::integrator::EffectPlan;

mod dark;
mod path;
pub use dark::{DARK_PROBE, dark_emitters};

/// One line of the plan: an effect, whether it runs, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EffectLine {
    /// Effect name.
    pub effect: String,
    /// Whether the tracer runs it.
    pub on: bool,
    /// The materials, lights or settings that decide it.
    pub reason: String,
}

impl EffectPlan {
    /// The plan as lines with reasons, for `raytree effects`.
    #[must_use]
    pub fn explain(&self, scene: &Scene) -> Vec<EffectLine> {
        let names = |pred: &dyn Fn(&crate::scene::Material) -> bool| material_names(scene, pred);
        let mut out = self.transport_lines(scene, &names);
        out.extend(self.sampling_lines(scene, &names));
        out.extend(material_lines(scene, &names));
        match scene.settings.integrator {
            crate::scene::IntegratorKind::Path => {
                path::restate(&mut out, scene);
                out.extend(path::lines(scene, &names));
            }
            crate::scene::IntegratorKind::Light => {
                path::restate(&mut out, scene);
                path::restate_light(&mut out);
                out.extend(path::light_lines(scene, &names));
            }
            crate::scene::IntegratorKind::Bdpt => {
                path::restate(&mut out, scene);
                out.extend(path::bdpt_lines(scene, &names));
            }
            crate::scene::IntegratorKind::Whitted => {}
        }
        out.extend(unused_materials_line(scene));
        out.extend(self.shadow_ray_lines(scene));
        out
    }

    /// The lines of what the rays do at a surface: reflection, refraction, Fresnel, total
    /// internal reflection, absorption, translucent shadows and highlights.
    fn transport_lines(&self, scene: &Scene, names: path::Names<'_>) -> Vec<EffectLine> {
        let s = &scene.settings;
        vec![
            line(
                "reflection",
                self.reflection,
                format!(
                    "reflectivity > 0: {}; Fresnel/TIR reflection of transmissive: {}",
                    names(&|m| nonzero(m.reflectivity)),
                    names(&|m| m.is_transmissive())
                ),
            ),
            line(
                "refraction (Snell)",
                self.refraction,
                format!("transmissivity > 0: {}", names(&|m| m.is_transmissive())),
            ),
            line(
                "Fresnel",
                self.fresnel,
                if self.refraction {
                    format!("model {:?} at transmissive surfaces", s.whitted.fresnel).to_lowercase()
                } else {
                    "no transmissive material".to_string()
                },
            ),
            line(
                "total internal reflection",
                self.tir,
                match max_ior_step(scene) {
                    Some((n1, n2)) if self.refraction => format!(
                        "n1 {n1} > n2 {n2}: critical angle {:.2} deg",
                        critical_angle(n1, n2).unwrap_or(0.0).to_degrees()
                    ),
                    _ => "no interface with n1 > n2".to_string(),
                },
            ),
            line(
                "Beer absorption",
                self.absorption,
                format!(
                    "absorption > 0 in a transmissive material: {}",
                    names(&|m| m.is_transmissive() && nonzero(m.absorption))
                ),
            ),
            line(
                "translucent shadows",
                self.translucent_shadows,
                format!(
                    "shadows {:?}, transmissive: {}",
                    s.whitted.shadows,
                    names(&|m| m.is_transmissive())
                )
                .to_lowercase(),
            ),
            line(
                "Blinn-Phong highlights",
                self.specular,
                format!("specular > 0: {}", names(&|m| nonzero(m.specular))),
            ),
        ]
    }

    /// The lines of how many rays are traced: recursion, glass roulette, supersampling, area
    /// lights and glossy lobes.
    fn sampling_lines(&self, scene: &Scene, names: path::Names<'_>) -> Vec<EffectLine> {
        let s = &scene.settings;
        vec![
            line(
                "recursion",
                self.recursion,
                if self.direct_only() {
                    format!(
                        "max_depth {}, but nothing reflects or refracts: each camera ray ends at \
                         its first hit (direct-only render path, lights only)",
                        s.max_depth
                    )
                } else {
                    format!("max_depth {}", s.max_depth)
                },
            ),
            {
                let (on, why) = crate::integrator::bound::carried::roulette_note(scene);
                line("glass roulette", on, why)
            },
            line(
                "supersampling",
                self.supersampling,
                crate::render::antialiasing_note(&crate::integrator::SceneIntegrator::new(scene)),
            ),
            line("area lights", self.area_lights, area_lights_reason(scene)),
            line(
                "glossy (rough lobes)",
                self.glossy,
                if self.glossy {
                    format!(
                        "roughness > 0 on reflectivity or transmissivity: {}; {} GGX-sampled rays per rough \
                         lobe at a path's first rough hit, 1 below it; glossy highlight from \
                         point and directional lights; exact Fresnel",
                        names(&crate::scene::Material::is_rough),
                        s.whitted.glossy_samples
                    )
                } else {
                    "no material with roughness > 0 on reflectivity or transmissivity".to_string()
                },
            ),
        ]
    }

    /// One line per light: whether shadow rays are traced to it, and a spot light's cone.
    fn shadow_ray_lines(&self, scene: &Scene) -> Vec<EffectLine> {
        let mut out = Vec::new();
        for (i, l) in scene.lights.iter().enumerate() {
            let on = self.light_on(i);
            out.push(line(
                &format!("shadow rays to {}", l.name),
                on,
                if on {
                    let cone = match l.kind {
                        crate::scene::LightKind::Point {
                            spot: Some(c), ..
                        } => format!(
                            " (a spot light: full within {:.1} deg of its axis, none beyond {:.1} deg, {} falloff)",
                            c.falloff.to_degrees(),
                            c.cone.to_degrees(),
                            c.profile.name()
                        ),
                        _ => String::new(),
                    };
                    format!("emits, and some material has diffuse or specular{cone}")
                } else {
                    "zero power, or no material is lit by lights".to_string()
                },
            ));
        }
        out
    }
}

/// One line of the plan.
fn line(effect: &str, on: bool, reason: String) -> EffectLine {
    EffectLine {
        effect: effect.to_string(),
        on,
        reason,
    }
}

/// The names of the used materials that `pred` holds for, or "no material".
fn material_names(scene: &Scene, pred: &dyn Fn(&crate::scene::Material) -> bool) -> String {
    let v: Vec<&str> = scene
        .used_materials()
        .filter(|m| pred(m))
        .map(|m| m.name.as_str())
        .collect();
    if v.is_empty() {
        "no material".to_string()
    } else {
        v.join(", ")
    }
}

/// The emissive objects, the dark ones, and how many shadow rays each light gets per hit.
fn area_lights_reason(scene: &Scene) -> String {
    let emitters: Vec<&str> = (0..scene.objects.len())
        .filter(|&i| scene.area_light(i).is_some())
        .map(|i| scene.objects[i].name.as_str())
        .collect();
    let list = if emitters.is_empty() {
        "no emissive sphere, quad or triangle".to_string()
    } else {
        format!("emissive: {}", emitters.join(", "))
    };
    let list = format!("{list}{}", dark_note(scene));
    match scene.settings.whitted.light_samples {
        Some(n) => format!("{list}; {n} shadow rays per light per hit"),
        None => format!("{list}; settings.light_samples absent (seen, not sampled)"),
    }
}

/// The materials no object uses, if any.
fn unused_materials_line(scene: &Scene) -> Option<EffectLine> {
    let unused: Vec<&str> = (0..scene.materials.len())
        .filter(|&m| !scene.material_used(m))
        .map(|m| scene.materials[m].name.as_str())
        .collect();
    (!unused.is_empty()).then(|| {
        line(
            "unused materials",
            false,
            format!(
                "no object uses {}: they call for nothing",
                unused.join(", ")
            ),
        )
    })
}

/// The lines of the conductor, coating, thin sheet, Beckmann and anisotropic lobes, present only where some used
/// material has them (explanations: they change a lobe's formulas, not which rays are traced).
fn material_lines(scene: &Scene, names: path::Names<'_>) -> Vec<EffectLine> {
    let mats: Vec<&crate::scene::Material> = scene.used_materials().collect();
    let mut out = Vec::new();
    let mut push = |effect: &str, pred: &dyn Fn(&crate::scene::Material) -> bool, what: &str| {
        if mats.iter().any(|m| pred(m)) {
            out.push(EffectLine {
                effect: effect.to_string(),
                on: true,
                reason: format!("{}: {what}", names(pred)),
            });
        }
    };
    push(
        "conductor Fresnel",
        &|m| m.conductor.is_some() && nonzero(m.reflectivity),
        "the mirror lobe's reflectance is the exact unpolarised Fresnel of a complex index eta + i k \
         per RGB channel (pbrt-v4 FrComplex) times conductor.scale; smooth: a mirror ray of \
         weight F(cos) per channel, rough: F at each sampled microfacet",
    );
    push(
        "dielectric coating",
        &|m| m.coating.is_some(),
        "a plastic: a dielectric coating over the diffuse base (Mitsuba 3 plastic/roughplastic, \
         Weidlich & Wilkie 2007): the coating reflects coating.scale times its exact Fresnel \
         (a mirror ray when smooth, sampled microfacets when rough) and the base is seen \
         through its transmittance t(cos_i) t(cos_o) / (eta^2 (1 - F_dr,int))",
    );
    push(
        "thin dielectric",
        &|m| m.thin.is_some() && nonzero(m.transmissivity),
        "a thin sheet (Mitsuba 3 thindielectric): it reflects 2R/(1+R) of the light, R the exact \
         Fresnel of one face at the incident angle, and passes the rest straight through, \
         unrefracted (a reflected and a transmitted ray under Whitted, one chosen by that \
         probability under path tracing)",
    );
    push(
        "Beckmann microfacets",
        &|m| m.is_rough() && m.distribution == crate::bsdf::Distribution::Beckmann,
        "rough lobes use the Beckmann distribution (exact Smith Lambda, visible normals sampled \
         by Heitz & d'Eon 2014) instead of GGX",
    );
    push(
        "anisotropic roughness",
        &|m| m.is_rough() && m.is_anisotropic(),
        "roughness along the tangent, roughness_v across it (anisotropic visible normals, Heitz \
         2018); the tangent follows the material's tangent direction",
    );
    out
}

/// `; emitter X emits towards nothing ...` for the area lights that light no surface
/// ([`dark_emitters`]), else empty.
#[must_use]
pub fn dark_note(scene: &Scene) -> String {
    let dark = dark_emitters(scene);
    if dark.is_empty() {
        return String::new();
    }
    let (who, verb) = if dark.len() == 1 {
        ("emitter", "emits")
    } else {
        ("emitters", "emit")
    };
    format!(
        "; {who} {} {verb} towards nothing (none of {} rays leaving its emitting side meets a surface): it lights no surface, only its own face can be seen",
        dark.join(", "),
        DARK_PROBE
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::FresnelModel;
    use crate::scene::ShadowMode;

    #[test]
    fn classic_plan() {
        let s = Scene::default_scene();
        let p = EffectPlan::for_scene(&s);
        assert!(p.reflection && p.refraction && p.fresnel && p.tir && p.specular && p.recursion);
        assert!(!p.absorption && !p.translucent_shadows && !p.supersampling);
        assert!(p.light_on(0));
        let lines = p.explain(&s);
        let tir = lines
            .iter()
            .find(|l| l.effect.starts_with("total"))
            .unwrap();
        assert!(tir.reason.contains("41.81"), "{}", tir.reason);
    }

    #[test]
    fn unused_materials_call_for_nothing() {
        let json = r#"{"camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov_y": 45,
            "width": 8, "height": 6},
          "materials": {
            "glass": {"transmissivity": [0.9, 0.9, 0.9], "ior": 1.5, "absorption": [0.2, 0, 0]},
            "mirror": {"reflectivity": [0.8, 0.8, 0.8], "specular": [1, 1, 1]},
            "matte": {"diffuse": [0.7, 0.6, 0.5]}},
          "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "matte"}],
          "lights": [{"type": "point", "position": [3, 5, 4], "intensity": [60, 60, 60]}]}"#;
        let mut s = Scene::from_json(json).unwrap();
        let p = EffectPlan::for_scene(&s);
        assert!(
            p.direct_only() && !p.specular && !p.tir && p.light_on(0),
            "{p:?}"
        );
        let lines = p.explain(&s);
        let unused = lines
            .iter()
            .find(|l| l.effect == "unused materials")
            .unwrap();
        assert!(unused.reason.contains("glass, mirror"), "{}", unused.reason);
        let refraction = lines
            .iter()
            .find(|l| l.effect.starts_with("refraction"))
            .unwrap();
        assert!(
            refraction.reason.contains("no material"),
            "{}",
            refraction.reason
        );
        // Once an object uses the glass, it calls for refraction, Beer's law and TIR.
        s.objects[0].material = 0;
        let p = EffectPlan::for_scene(&s);
        assert!(
            p.refraction && p.absorption && p.tir && !p.direct_only(),
            "{p:?}"
        );
        assert!(
            !p.explain(&s)
                .iter()
                .any(|l| l.reason.contains("glass, mirror"))
        );
    }

    /// Under the path integrator the lines say what it does, not Whitted's settings: exact
    /// Fresnel whatever `settings.fresnel`, area lights by next-event estimation, and no
    /// Whitted translucent-shadow or Blinn-Phong line beside the path lines that say they are
    /// ignored (they once stood side by side, one "on", one "off").
    #[test]
    fn path_lines_state_what_the_path_integrator_does() {
        let mut s = Scene::from_json(include_str!("../../fixtures/caustic.json")).unwrap();
        s.settings.whitted.fresnel = FresnelModel::Schlick;
        s.settings.whitted.shadows = ShadowMode::Translucent;
        s.settings.whitted.light_samples = Some(4);
        let find = |lines: &[EffectLine], e: &str| lines.iter().find(|l| l.effect == e).cloned();
        let lines = EffectPlan::for_scene(&s).explain(&s);
        let fresnel = find(&lines, "Fresnel").unwrap();
        assert!(
            fresnel.on && fresnel.reason.starts_with("exact"),
            "{fresnel:?}"
        );
        let area = find(&lines, "area lights").unwrap();
        assert!(
            area.on && area.reason.contains("one light sample per bounce"),
            "{area:?}"
        );
        assert!(find(&lines, "translucent shadows").is_none());
        assert!(find(&lines, "Blinn-Phong highlights").is_none());
        assert!(
            !find(&lines, "translucent shadows (path integrator ignores them)")
                .unwrap()
                .on
        );
        // The same scene under Whitted: its own lines, as set.
        s.settings.integrator = crate::scene::IntegratorKind::Whitted;
        let lines = EffectPlan::for_scene(&s).explain(&s);
        assert!(find(&lines, "Fresnel").unwrap().reason.contains("schlick"));
        assert!(find(&lines, "translucent shadows").unwrap().on);
        assert!(
            find(&lines, "area lights")
                .unwrap()
                .reason
                .contains("4 shadow rays")
        );
    }
}
