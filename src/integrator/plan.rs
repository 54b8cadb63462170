//! Which effects a scene calls for: the Whitted integrator runs only these (the path tracer
//! runs [`EffectPlan::everything`]). The words that explain the plan are `crate::effects`.

use crate::math::{FresnelModel, Rgb};
use crate::scene::{LightKind, Scene, ShadowMode};

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

/// Some channel of `c` is positive.
pub(crate) fn nonzero(c: Rgb) -> bool {
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
            fresnel: s.whitted.fresnel != FresnelModel::None,
            tir: true,
            absorption: true,
            translucent_shadows: s.whitted.shadows == ShadowMode::Translucent,
            specular: true,
            lights: u64::MAX,
            recursion: s.max_depth > 0,
            supersampling: s.spp > 1,
            area_lights: s.whitted.light_samples.is_some(),
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
        let fresnel = transmissive && s.whitted.fresnel != FresnelModel::None;
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
            translucent_shadows: s.whitted.shadows == ShadowMode::Translucent && transmissive,
            specular: mats.iter().any(|m| nonzero(m.specular)),
            lights,
            recursion: s.max_depth > 0 && (reflection || transmissive),
            supersampling: s.spp > 1,
            area_lights: s.whitted.light_samples.is_some()
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
}

/// The largest drop in index a ray can meet, `(n1, n2)` with `n1 > n2`, if any. Media: air
/// (1.0) and every transmissive material with an ior that some object uses.
pub(crate) fn max_ior_step(scene: &Scene) -> Option<(f64, f64)> {
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
