//! The light sampler: a scene's lights in one list (point and directional lights in order, then
//! the area lights in object order) and the choice among them in proportion to power, pbrt-v4's
//! `PowerLightSampler` (Pharr, Jakob, Humphreys, *Physically Based Rendering*, 4th ed., section
//! 12.6.2), with a cumulative table searched by bisection instead of its alias table (the same
//! probabilities; scenes have few lights). Built once per integrator, not per sample.
//!
//! The power of a light is [`Light::power`], its flux averaged over RGB. A light of zero power
//! is never chosen (it adds nothing); a scene whose lights all have zero (or non-finite) power
//! falls back to choosing uniformly. A flux that overflows (a point light of 1.7e308: 4 pi I =
//! inf) is the brightest there is, not nothing: clamped to the largest finite power (issue 27;
//! [`LightSampler::overflowing`] names such lights for a warning).

use super::Light;

/// The lights of a scene and their selection probabilities.
#[derive(Clone, Debug, Default)]
pub struct LightSampler<'a> {
    lights: Vec<Light<'a>>,
    /// How many of `lights` are point and directional lights (they come first).
    delta: usize,
    /// Selection probability of each light.
    pmf: Vec<f64>,
    /// `cdf[i]` = sum of `pmf[..=i]`; the last is 1.
    cdf: Vec<f64>,
    /// Per object: the index of its area light in `lights` (`u32::MAX` when it is none).
    object_light: Vec<u32>,
}

/// The selection power of `light`: [`Light::power`] clamped to `[0, f64::MAX]` (NaN, which
/// validated lights cannot give, counts as 0).
fn selection_power(light: &Light<'_>) -> f64 {
    let phi = light.power();
    if phi.is_nan() {
        0.0
    } else {
        phi.clamp(0.0, f64::MAX)
    }
}

impl<'a> LightSampler<'a> {
    /// The sampler of `lights` (the delta lights first, then area lights by object index) in a
    /// scene of `objects` objects, chosen in proportion to power.
    #[must_use]
    pub fn new(lights: Vec<Light<'a>>, objects: usize) -> Self {
        let power: Vec<f64> = lights.iter().map(selection_power).collect();
        Self::with_power(lights, objects, &power)
    }

    /// The sampler of `lights` with selection weights `power` (uniform when they do not sum to
    /// a positive finite number).
    #[must_use]
    pub fn with_power(lights: Vec<Light<'a>>, objects: usize, power: &[f64]) -> Self {
        let n = lights.len();
        let total: f64 = power.iter().sum();
        // Powers near f64::MAX whose sum overflows: the same proportions from powers scaled by
        // the largest (the plain division otherwise, bit for bit).
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
        let mut object_light = vec![u32::MAX; objects];
        for (i, l) in lights.iter().enumerate() {
            if let Some(o) = l.object().filter(|&o| o < objects) {
                object_light[o] = i as u32;
            }
        }
        let delta = lights.iter().take_while(|l| l.is_delta()).count();
        Self {
            lights,
            delta,
            pmf,
            cdf,
            object_light,
        }
    }

    /// Whether there is no light to choose.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Every light, in order.
    #[must_use]
    pub fn lights(&self) -> &[Light<'a>] {
        &self.lights
    }

    /// The point and directional lights (`scene.lights[k]` is `delta_lights()[k]`).
    #[inline]
    #[must_use]
    pub fn delta_lights(&self) -> &[Light<'a>] {
        &self.lights[..self.delta]
    }

    /// The area lights, by object index.
    #[inline]
    #[must_use]
    pub fn area_lights(&self) -> &[Light<'a>] {
        &self.lights[self.delta..]
    }

    /// The light chosen by `u` in `[0, 1)`: its index, the light and its probability. The
    /// first index whose cumulative probability exceeds `u`, so a light of probability 0 is
    /// never chosen.
    #[inline]
    #[must_use]
    pub fn choose(&self, u: f64) -> (usize, &Light<'a>, f64) {
        let k = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.cdf.len() - 1);
        (k, &self.lights[k], self.pmf[k])
    }

    /// The area light of `object` and the probability of choosing it (`None` when the object
    /// is no area light): the selection part of the light-sampling pdf that MIS weighs
    /// emission found by BSDF sampling with.
    #[inline]
    #[must_use]
    pub fn area(&self, object: usize) -> Option<(&Light<'a>, f64)> {
        let i = *self.object_light.get(object)? as usize;
        Some((self.lights.get(i)?, self.pmf[i]))
    }

    /// The probability of choosing light `i`.
    #[must_use]
    pub fn probability(&self, i: usize) -> f64 {
        self.pmf[i]
    }

    /// The indices of the lights whose flux overflows a 64-bit float (chosen by a clamped
    /// power).
    #[must_use]
    pub fn overflowing(&self) -> Vec<usize> {
        (0..self.lights.len())
            .filter(|&i| self.lights[i].power().is_infinite())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;
    use std::f64::consts::PI;

    fn point() -> Light<'static> {
        Light::Point {
            position: glam::DVec3::ZERO,
            intensity: crate::math::Rgb::ONE,
            spot: None,
        }
    }

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
        let t = s.light_sampler();
        let phi = [4.0 * PI * 3.0, PI * (4.0 * PI * 0.25) * 2.0, PI * 6.0 * 1.0];
        let total: f64 = phi.iter().sum();
        let got: Vec<f64> = (0..t.lights().len()).map(|i| t.probability(i)).collect();
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
        let z = LightSampler::with_power(vec![point(); 3], 0, &[1.0, 0.0, 1.0]);
        assert!((0..1000).all(|i| z.choose(f64::from(i) / 1000.0).0 != 1));
        let u = LightSampler::with_power(vec![point(); 4], 0, &[0.0; 4]);
        assert!((0..4).all(|i| u.probability(i) == 0.25));
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
        let t = s.light_sampler();
        let p: Vec<f64> = (0..t.lights().len()).map(|i| t.probability(i)).collect();
        assert!(p[0] > 0.999_999 && p[0] <= 1.0, "{p:?}");
        assert!(p.iter().all(|p| p.is_finite()) && (p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert_eq!(s.overflowing_lights(), vec!["sun".to_string()]);
        // Two such lights share the choice equally.
        let both = LightSampler::with_power(vec![point(); 2], 0, &[f64::MAX, f64::MAX]);
        assert!((0..2).all(|i| (both.probability(i) - 0.5).abs() < 1e-15));
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
        let (a, b) = (one.light_sampler(), many.light_sampler());
        assert_eq!(a.lights().len(), 1);
        assert_eq!(b.lights().len(), 1, "100 copies are one light");
        assert!(many.area_light(0).is_some());
        assert!((1..100).all(|i| many.area_light(i).is_none()));
    }

    /// The power light sampling chooses by is the flux of the emitted rays
    /// ([`Light::sample_le`]): `le |cos| / (pdf_pos pdf_dir)` averaged over RGB, for every
    /// kind of light, so light tracing and light selection agree.
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
        let sampler = s.light_sampler();
        assert_eq!(sampler.lights().len(), 5);
        for (i, l) in sampler.lights().iter().enumerate() {
            let r = l
                .sample_le(glam::DVec2::new(0.3, 0.6), glam::DVec2::new(0.8, 0.1))
                .unwrap();
            let w = r.weight();
            let flux = (w.x + w.y + w.z) / 3.0;
            let p = selection_power(l);
            assert!((flux - p).abs() <= 1e-9 * p, "light {i}: {flux} vs {p}");
        }
    }
}
