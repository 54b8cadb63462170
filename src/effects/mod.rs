//! Which effects a scene calls for, and why: the tracer runs only these.

use crate::math::{FresnelModel, Rgb, critical_angle};
use crate::scene::{LightKind, Scene, ShadowMode};

mod dark;
mod path;
pub use dark::{DARK_PROBE, dark_emitters};

/// The effects the tracer evaluates for one scene and its settings. Computed once per tracer.
///
/// Two kinds of flag: *switches* remove code from the per-ray path when off (`reflection`,
/// `refraction`, `absorption`, `translucent_shadows`, `specular`, `lights`, and through
/// [`EffectPlan::direct_only`] the whole recursion); *explanations* are read only by
/// [`EffectPlan::explain`] (`fresnel`, `tir`, `recursion`, `supersampling`), because their cost
/// already vanishes without a switch: Fresnel and TIR are evaluated only at dielectric hits,
/// which exist only when `refraction` is on; recursion stops at `max_depth` or when no
/// secondary ray is spawned; one sample per pixel is simply one iteration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EffectPlan {
    /// Some material reflects (mirror reflectivity, or Fresnel/TIR reflection of a dielectric).
    pub reflection: bool,
    /// Some material transmits: Snell refraction and the media stack.
    pub refraction: bool,
    /// Fresnel weights are evaluated (refraction on and a model other than `none`).
    /// Explanation only (see the type's doc).
    pub fresnel: bool,
    /// Total internal reflection is possible: some interface has n1 > n2. Explanation only.
    pub tir: bool,
    /// Beer's law: some transmissive material absorbs.
    pub absorption: bool,
    /// Shadow rays pass translucent blockers (mode translucent and something transmits).
    pub translucent_shadows: bool,
    /// Some material has a Blinn-Phong highlight.
    pub specular: bool,
    /// Lights that can light something: bit i for light i (lights past 64 are always on).
    pub lights: u64,
    /// Recursion happens (max_depth > 0 and something reflects or refracts). Explanation only.
    pub recursion: bool,
    /// More than one sample per pixel. Explanation only.
    pub supersampling: bool,
    /// Emissive spheres, quads and triangles are sampled as area lights
    /// (`settings.light_samples` is set, something is shaded, and such an emitter exists).
    pub area_lights: bool,
    /// Some material has a rough (GGX) `reflectivity` or `transmissivity` lobe
    /// (`roughness >= bsdf::SMOOTH_ALPHA`): its rays are sampled (`settings.glossy_samples`)
    /// and point and directional lights give it a glossy highlight.
    pub glossy: bool,
}

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

fn nonzero(c: Rgb) -> bool {
    c.max_element() > 0.0
}

impl EffectPlan {
    /// Every effect the settings allow switched on, whether the scene uses it or not (to check
    /// that switching unused effects off changes nothing).
    #[must_use]
    pub fn everything(scene: &Scene) -> Self {
        let s = &scene.settings;
        Self {
            reflection: true,
            refraction: true,
            fresnel: s.fresnel != FresnelModel::None,
            tir: true,
            absorption: true,
            translucent_shadows: s.shadows == ShadowMode::Translucent,
            specular: true,
            lights: u64::MAX,
            recursion: s.max_depth > 0,
            supersampling: s.spp > 1,
            area_lights: s.light_samples.is_some(),
            glossy: true,
        }
    }

    /// The plan for `scene` with its settings.
    #[must_use]
    pub fn for_scene(scene: &Scene) -> Self {
        let s = &scene.settings;
        // Materials no object uses call for nothing.
        let mats: Vec<&crate::scene::Material> = scene.used_materials().collect();
        let transmissive = mats.iter().any(|m| m.is_transmissive());
        let reflective = mats.iter().any(|m| nonzero(m.reflectivity));
        let fresnel = transmissive && s.fresnel != FresnelModel::None;
        let tir = transmissive && max_ior_step(scene).is_some();
        let glossy = mats.iter().any(|m| m.is_rough());
        let shaded = mats
            .iter()
            .any(|m| !m.diffuse.is_black() || nonzero(m.specular));
        let mut lights = 0u64;
        for (i, l) in scene.lights.iter().enumerate() {
            let power = match l.kind {
                LightKind::Point { intensity, .. } => intensity,
                LightKind::Directional { irradiance, .. } => irradiance,
            };
            if (shaded || glossy) && nonzero(power) || i >= 64 {
                lights |= 1 << i.min(63);
            }
        }
        let reflection = reflective || fresnel || tir;
        Self {
            reflection,
            refraction: transmissive,
            fresnel,
            tir,
            absorption: mats
                .iter()
                .any(|m| m.is_transmissive() && nonzero(m.absorption)),
            translucent_shadows: s.shadows == ShadowMode::Translucent && transmissive,
            specular: mats.iter().any(|m| nonzero(m.specular)),
            lights,
            recursion: s.max_depth > 0 && (reflection || transmissive),
            supersampling: s.spp > 1,
            area_lights: s.light_samples.is_some()
                && shaded
                && (0..scene.objects.len()).any(|i| scene.area_light(i).is_some()),
            glossy,
        }
    }

    /// No secondary rays and nothing along a camera ray's segment: the radiance of a camera
    /// ray is the local term at its first hit, which the tracer computes on its direct-only
    /// path.
    #[must_use]
    pub fn direct_only(&self) -> bool {
        !(self.reflection || self.refraction || self.absorption || self.translucent_shadows)
    }

    /// Whether light `i` is traced.
    #[must_use]
    pub fn light_on(&self, i: usize) -> bool {
        self.lights & (1 << i.min(63)) != 0
    }

    /// The plan as lines with reasons, for `raytree effects`.
    #[must_use]
    pub fn explain(&self, scene: &Scene) -> Vec<EffectLine> {
        let names = |pred: &dyn Fn(&crate::scene::Material) -> bool| {
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
        };
        let s = &scene.settings;
        let line = |effect: &str, on: bool, reason: String| EffectLine {
            effect: effect.to_string(),
            on,
            reason,
        };
        let mut out = vec![
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
                    format!("model {:?} at transmissive surfaces", s.fresnel).to_lowercase()
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
                    s.shadows,
                    names(&|m| m.is_transmissive())
                )
                .to_lowercase(),
            ),
            line(
                "Blinn-Phong highlights",
                self.specular,
                format!("specular > 0: {}", names(&|m| nonzero(m.specular))),
            ),
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
            line("area lights", self.area_lights, {
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
                match s.light_samples {
                    Some(n) => format!("{list}; {n} shadow rays per light per hit"),
                    None => format!("{list}; settings.light_samples absent (seen, not sampled)"),
                }
            }),
            line(
                "glossy (rough lobes)",
                self.glossy,
                if self.glossy {
                    format!(
                        "roughness > 0 on reflectivity or transmissivity: {}; {} GGX-sampled rays per rough \
                         lobe at a path's first rough hit, 1 below it; glossy highlight from \
                         point and directional lights; exact Fresnel",
                        names(&crate::scene::Material::is_rough),
                        s.glossy_samples
                    )
                } else {
                    "no material with roughness > 0 on reflectivity or transmissivity".to_string()
                },
            ),
        ];
        out.extend(material_lines(scene, &names));
        if s.integrator == crate::scene::IntegratorKind::Path {
            path::restate(&mut out, scene);
            out.extend(path::lines(scene, &names));
        }
        let unused: Vec<&str> = (0..scene.materials.len())
            .filter(|&m| !scene.material_used(m))
            .map(|m| scene.materials[m].name.as_str())
            .collect();
        if !unused.is_empty() {
            out.push(line(
                "unused materials",
                false,
                format!(
                    "no object uses {}: they call for nothing",
                    unused.join(", ")
                ),
            ));
        }
        for (i, l) in scene.lights.iter().enumerate() {
            let on = self.light_on(i);
            out.push(line(
                &format!("shadow rays to {}", l.name),
                on,
                if on {
                    "emits, and some material has diffuse or specular".to_string()
                } else {
                    "zero power, or no material is lit by lights".to_string()
                },
            ));
        }
        out
    }
}

/// The lines of the conductor, Beckmann and anisotropic lobes, present only where some used
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

/// The largest drop in index a ray can meet, `(n1, n2)` with `n1 > n2`, if any. Media: air
/// (1.0) and every transmissive material with an ior that some object uses.
fn max_ior_step(scene: &Scene) -> Option<(f64, f64)> {
    let iors = scene
        .used_materials()
        .filter(|m| m.is_transmissive())
        .filter_map(|m| m.ior)
        .chain(std::iter::once(1.0));
    let (lo, hi) = iors.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), n| {
        (lo.min(n), hi.max(n))
    });
    (hi > lo).then_some((hi, lo))
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
        s.settings.fresnel = FresnelModel::Schlick;
        s.settings.shadows = ShadowMode::Translucent;
        s.settings.light_samples = Some(4);
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
