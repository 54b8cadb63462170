//! The lights next-event estimation chooses among, built once per integrator (not found by a
//! scan of the objects per sample), and the choice in proportion to power: pbrt-v4's
//! `PowerLightSampler` (Pharr, Jakob, Humphreys, *Physically Based Rendering*, 4th ed.,
//! section 12.6.2), with a cumulative table searched by bisection instead of its alias table
//! (the same probabilities; scenes have few lights).
//!
//! The power of a light is its emitted flux `Phi` averaged over the RGB channels (pbrt-v4
//! `Light::Phi`, `SampledSpectrum::Average`): `4 pi I` for a point light, `pi r^2 E` for a
//! directional light over the disc of the scene's bounding sphere (radius `r`,
//! `DistantLight::Phi`), `pi A Le` for a one-sided diffuse emitter of area `A`
//! (`DiffuseAreaLight::Phi`; a sphere's area `4 pi r^2`, a mesh's the sum of its triangles).
//! A light of zero power is never chosen (it adds nothing); a scene whose lights all have
//! zero (or non-finite) power falls back to choosing uniformly.

use crate::lights::PreparedEmitter;
use crate::math::Rgb;
use crate::scene::{AreaEmitter, LightKind, Scene};
use std::f64::consts::PI;

/// One light: a point or directional light (index into [`Scene::lights`]) or an emissive
/// object with its sampling geometry and emission. (An area source is large, with its
/// prepared emitter; the table holds a few and hands them out by reference.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug)]
pub(crate) enum Source<'a> {
    /// `scene.lights[k]`.
    Delta(usize),
    /// An emissive sphere, quad, triangle or mesh.
    Area {
        /// Object index.
        object: usize,
        /// Sampling geometry.
        emitter: AreaEmitter<'a>,
        /// The same, with what does not depend on the shading point computed once.
        prepared: PreparedEmitter<'a>,
        /// Emitted radiance (outer side).
        emission: Rgb,
    },
}

/// The scene's lights in order (point and directional lights, then emissive objects by object
/// index), their selection probabilities and a cumulative table to draw from.
#[derive(Clone, Debug, Default)]
pub(crate) struct LightTable<'a> {
    sources: Vec<Source<'a>>,
    /// Selection probability of each source.
    pmf: Vec<f64>,
    /// `cdf[i]` = sum of `pmf[..=i]`; the last is 1.
    cdf: Vec<f64>,
    /// Per object: the index of its area light in `sources` (`u32::MAX` when it is none).
    object_source: Vec<u32>,
}

impl<'a> LightTable<'a> {
    /// The lights of `scene`, chosen in proportion to power.
    pub(crate) fn new(scene: &'a Scene) -> Self {
        let mut sources: Vec<Source<'a>> = (0..scene.lights.len()).map(Source::Delta).collect();
        for object in 0..scene.objects.len() {
            if let Some((emitter, emission)) = scene.area_light(object) {
                sources.push(Source::Area {
                    object,
                    emitter,
                    prepared: PreparedEmitter::new(emitter),
                    emission,
                });
            }
        }
        let radius = scene_radius(scene);
        let power: Vec<f64> = sources.iter().map(|s| power(scene, s, radius)).collect();
        Self::with_power(scene.objects.len(), sources, &power)
    }

    /// The table of `sources` with selection weights `power` (uniform when they do not sum to
    /// a positive finite number).
    fn with_power(objects: usize, sources: Vec<Source<'a>>, power: &[f64]) -> Self {
        let n = sources.len();
        let total: f64 = power.iter().sum();
        // Powers near f64::MAX (clamped there by `power`) whose sum overflows: the same
        // proportions from powers scaled by the largest (the plain division otherwise, bit for
        // bit as before).
        let top = power.iter().copied().fold(0.0, f64::max);
        let pmf: Vec<f64> = if total > 0.0 && total.is_finite() {
            power.iter().map(|p| p / total).collect()
        } else if top > 0.0 && top.is_finite() {
            let scaled: f64 = power.iter().map(|p| p / top).sum();
            power.iter().map(|p| p / top / scaled).collect()
        } else {
            vec![1.0 / n as f64; n]
        };
        let mut cdf = Vec::with_capacity(n);
        let mut acc = 0.0;
        for p in &pmf {
            acc += p;
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let mut object_source = vec![u32::MAX; objects];
        for (i, s) in sources.iter().enumerate() {
            if let Source::Area { object, .. } = *s {
                object_source[object] = i as u32;
            }
        }
        Self {
            sources,
            pmf,
            cdf,
            object_source,
        }
    }

    /// Whether there is no light to choose.
    pub(crate) fn is_empty(&self) -> bool {
        self.sources.is_empty()
    }

    /// The light chosen by `u` in `[0, 1)`: its index, the source and its probability. The
    /// first index whose cumulative probability exceeds `u`, so a light of probability 0 is
    /// never chosen.
    #[inline]
    pub(crate) fn choose(&self, u: f64) -> (usize, &Source<'a>, f64) {
        let k = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.cdf.len() - 1);
        (k, &self.sources[k], self.pmf[k])
    }

    /// The area light of `object` and the probability of choosing it (`None` when the object
    /// is no area light): the selection part of the light-sampling pdf that MIS weighs
    /// emission found by BSDF sampling with.
    #[inline]
    pub(crate) fn area(&self, object: usize) -> Option<(&PreparedEmitter<'a>, f64)> {
        let i = *self.object_source.get(object)? as usize;
        match self.sources.get(i)? {
            Source::Area { prepared, .. } => Some((prepared, self.pmf[i])),
            Source::Delta(_) => None,
        }
    }

    /// Every source with its selection probability (tests and the docs' figures).
    #[cfg(test)]
    pub(crate) fn probabilities(&self) -> impl Iterator<Item = (Source<'a>, f64)> + '_ {
        self.sources.iter().copied().zip(self.pmf.iter().copied())
    }
}

/// The radius of a sphere around every bounded object (1 when there is none): the disc a
/// directional light's flux is counted over.
fn scene_radius(scene: &Scene) -> f64 {
    crate::lights::bounding_sphere(scene).1
}

/// The mean over RGB of the flux of `s` (see the module doc), as computed: infinite when it
/// overflows.
fn raw_power(scene: &Scene, s: &Source<'_>, radius: f64) -> f64 {
    let mean = |c: Rgb| (c.x + c.y + c.z) / 3.0;
    match *s {
        Source::Delta(k) => match scene.lights[k].kind {
            LightKind::Point { intensity, .. } => 4.0 * PI * mean(intensity),
            LightKind::Directional { irradiance, .. } => PI * radius * radius * mean(irradiance),
        },
        Source::Area {
            emitter, emission, ..
        } => {
            let area = match emitter {
                AreaEmitter::Sphere { radius, .. } => 4.0 * PI * radius * radius,
                AreaEmitter::Planar(e) => e.area(),
                AreaEmitter::Mesh(m) => m.area(),
            };
            PI * area * mean(emission)
        }
    }
}

/// The selection power of `s`: [`raw_power`], where a flux that overflows (a point light of
/// 1.7e308: 4 pi I = inf) is the brightest there is, not nothing: clamped to the largest finite
/// power (issue 27; [`overflowing`] names such lights for a warning). NaN cannot come from
/// validated lights; it would count as 0.
fn power(scene: &Scene, s: &Source<'_>, radius: f64) -> f64 {
    let phi = raw_power(scene, s, radius);
    if phi.is_nan() {
        0.0
    } else {
        phi.clamp(0.0, f64::MAX)
    }
}

/// The names of the lights (point, directional, emissive objects) whose flux overflows a
/// 64-bit float, so that light sampling chooses them by a clamped power.
#[must_use]
pub fn overflowing(scene: &Scene) -> Vec<String> {
    let table = LightTable::new(scene);
    let radius = scene_radius(scene);
    table
        .sources
        .iter()
        .filter(|s| raw_power(scene, s, radius).is_infinite())
        .map(|s| match *s {
            Source::Delta(k) => scene.lights[k].name.clone(),
            Source::Area { object, .. } => scene.objects[object].name.clone(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(json: &str) -> Scene {
        Scene::from_json(json).unwrap()
    }

    /// Probabilities in proportion to the fluxes written out by hand; the draw by `u`
    /// follows the cumulative table; a zero-power light is never chosen.
    #[test]
    fn lights_are_chosen_in_proportion_to_their_flux() {
        let s = scene(
            r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
            "materials": {"lamp": {"emission": [2, 2, 2]}, "dim": {"emission": [0.5, 1, 1.5]}, "off": {"diffuse": [1, 1, 1]}},
            "objects": [
              {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "lamp"},
              {"type": "quad", "corner": [-1, 2, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 3], "material": "dim"},
              {"type": "sphere", "center": [3, 0, 0], "radius": 1, "material": "off"}],
            "lights": [{"type": "point", "position": [0, 4, 0], "intensity": [3, 3, 3]}]}"#,
        );
        let t = LightTable::new(&s);
        let phi = [4.0 * PI * 3.0, PI * (4.0 * PI * 0.25) * 2.0, PI * 6.0 * 1.0];
        let total: f64 = phi.iter().sum();
        let got: Vec<f64> = t.probabilities().map(|(_, p)| p).collect();
        assert_eq!(got.len(), 3);
        for (g, w) in got.iter().zip(phi) {
            assert!((g - w / total).abs() < 1e-12, "{got:?}");
        }
        assert_eq!(t.area(0).map(|a| a.1), Some(got[1]));
        assert_eq!(t.area(1).map(|a| a.1), Some(got[2]));
        assert!(t.area(2).is_none());
        assert_eq!(t.choose(0.0).0, 0);
        assert_eq!(t.choose(got[0] - 1e-9).0, 0);
        assert_eq!(t.choose(got[0] + 1e-9).0, 1);
        assert_eq!(t.choose(0.999_999).0, 2);
        // Relative frequencies of a fine grid of u match the probabilities.
        let mut count = [0u32; 3];
        for i in 0..100_000 {
            count[t.choose((f64::from(i) + 0.5) / 100_000.0).0] += 1;
        }
        for (c, p) in count.iter().zip(&got) {
            assert!((f64::from(*c) / 100_000.0 - p).abs() < 2e-5, "{count:?}");
        }
        // A zero-power light is never chosen; all zero falls back to uniform.
        let z = LightTable::with_power(0, vec![Source::Delta(0); 3], &[1.0, 0.0, 1.0]);
        assert!((0..1000).all(|i| z.choose(f64::from(i) / 1000.0).0 != 1));
        let u = LightTable::with_power(0, vec![Source::Delta(0); 4], &[0.0; 4]);
        assert!(u.probabilities().all(|(_, p)| p == 0.25));
    }

    /// Issue 27: a point light of 1.7e308 has an infinite flux; it is the brightest light, so
    /// it takes (nearly) all of the choice, and it is named for the warning.
    #[test]
    fn a_light_whose_power_overflows_is_chosen_not_dropped() {
        let s = scene(
            r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
            "lights": [{"type": "point", "name": "sun", "position": [0, 4, 0], "intensity": [1.7e308, 1.7e308, 1.7e308]},
                       {"type": "point", "name": "lamp", "position": [0, 4, 1], "intensity": [3, 3, 3]}]}"#,
        );
        let t = LightTable::new(&s);
        let p: Vec<f64> = t.probabilities().map(|(_, p)| p).collect();
        assert!(p[0] > 0.999_999 && p[0] <= 1.0, "{p:?}");
        assert!(p.iter().all(|p| p.is_finite()) && (p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert_eq!(overflowing(&s), vec!["sun".to_string()]);
        // Two such lights share the choice equally.
        let both = LightTable::with_power(0, vec![Source::Delta(0); 2], &[f64::MAX, f64::MAX]);
        assert!(both.probabilities().all(|(_, p)| (p - 0.5).abs() < 1e-15));
    }

    /// Issue 27: copies of one emitting triangle are one light (the camera sees one; equal
    /// distances go to the lowest index), so the light table is the single triangle's.
    #[test]
    fn coincident_copies_of_an_emitter_are_one_light() {
        let tri = r#"{"type": "triangle", "vertices": [[-1, 2, -1], [1, 2, -1], [0, 2, 1]], "material": "lamp"}"#;
        let json = |n: usize| {
            format!(
                r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3}},
                "materials": {{"lamp": {{"emission": [2, 2, 2]}}}},
                "objects": [{}]}}"#,
                vec![tri; n].join(",")
            )
        };
        let one = scene(&json(1));
        let many = scene(&json(100));
        let (a, b) = (LightTable::new(&one), LightTable::new(&many));
        assert_eq!(a.probabilities().count(), 1);
        assert_eq!(b.probabilities().count(), 1, "100 copies are one light");
        assert!(many.area_light(0).is_some());
        assert!((1..100).all(|i| many.area_light(i).is_none()));
    }

    /// The power light sampling chooses by is the flux of the emitted rays
    /// (`crate::lights::Emitter::sample_le`): `le |cos| / (pdf_pos pdf_dir)` averaged over RGB,
    /// for every kind of light, so light tracing and light selection agree.
    #[test]
    fn selection_power_is_the_flux_of_the_emitted_rays() {
        let s = scene(
            r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
            "materials": {"lamp": {"emission": [2, 2, 2]}, "dim": {"emission": [0.5, 1, 1.5]}},
            "objects": [
              {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "lamp"},
              {"type": "quad", "corner": [-1, 2, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 3], "material": "dim"},
              {"type": "triangle", "vertices": [[0, 3, 0], [1, 3, 0], [0, 3, 1]], "material": "lamp"}],
            "lights": [{"type": "point", "position": [0, 4, 0], "intensity": [3, 3, 3]},
                       {"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 2, 3]}]}"#,
        );
        let table = LightTable::new(&s);
        let emitters = crate::lights::emitters(&s);
        assert_eq!(table.sources.len(), emitters.len());
        let radius = scene_radius(&s);
        for (src, (name, e)) in table.sources.iter().zip(&emitters) {
            let r = e
                .sample_le(glam::DVec2::new(0.3, 0.6), glam::DVec2::new(0.8, 0.1))
                .unwrap();
            let w = r.weight();
            let flux = (w.x + w.y + w.z) / 3.0;
            let p = power(&s, src, radius);
            assert!((flux - p).abs() <= 1e-9 * p, "{name}: {flux} vs {p}");
        }
    }
}
