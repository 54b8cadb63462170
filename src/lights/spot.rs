//! Spot lights: a point light whose intensity falls from its axis to zero at the edge of a
//! cone, with the three falloff curves of the formats raytree reads (issue 29):
//!
//! - [`SpotProfile::Smoothstep`], pbrt-v4's `SpotLight::I`: `smoothstep(cos_cone, cos_falloff,
//!   cos theta)` (Pharr, Jakob, Humphreys, *Physically Based Rendering*, 4th ed., section 12.1.1);
//! - [`SpotProfile::Linear`], Mitsuba 3's `spot` `falloff_curve`: 1 inside the beam width, then
//!   linear in the angle, `(theta_cone - theta) / (theta_cone - theta_falloff)`;
//! - [`SpotProfile::Gltf`], glTF's `KHR_lights_punctual` (the extension's recommended
//!   implementation): `clamp((cos theta - cos_outer) / max(1e-3, cos_inner - cos_outer))^2`.
//!
//! Each has its solid-angle integral in closed form ([`Spot::solid_angle`]), which makes the
//! light's flux `I * solid_angle` (pbrt-v4 `SpotLight::Phi` for the first). Emitted rays are
//! drawn uniformly in the cone (pbrt-v4 `SpotLight::SampleLe`).

use crate::sampling::warp::{orthonormal_basis, square_to_uniform_cone};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// How a spot light's intensity falls from the edge of its beam to the edge of its cone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SpotProfile {
    /// pbrt-v4: a smoothstep in the cosine.
    #[default]
    Smoothstep,
    /// Mitsuba 3: linear in the angle.
    Linear,
    /// glTF `KHR_lights_punctual`: the square of a linear ramp in the cosine.
    Gltf,
}

impl SpotProfile {
    /// The profile's name in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SpotProfile::Smoothstep => "smoothstep",
            SpotProfile::Linear => "linear",
            SpotProfile::Gltf => "gltf",
        }
    }
}

/// The smallest cosine interval of the glTF ramp (the extension's `max(0.001, ...)`).
const GLTF_MIN_RAMP: f64 = 1e-3;

/// A spot light's cone around its axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Unit axis, the direction the light points in.
    pub axis: DVec3,
    /// Half-angle (radians) of the cone outside which nothing is emitted, in (0, pi).
    pub cone: f64,
    /// Half-angle (radians) inside which the full intensity is emitted, in [0, `cone`].
    pub falloff: f64,
    /// The curve between them.
    pub profile: SpotProfile,
}

impl Spot {
    /// The share of the axis intensity emitted along unit direction `w` (from the light).
    #[must_use]
    pub fn falloff(&self, w: DVec3) -> f64 {
        let cos = w.dot(self.axis);
        let (cos_cone, cos_in) = (self.cone.cos(), self.falloff.cos());
        match self.profile {
            SpotProfile::Smoothstep => smoothstep(cos_cone, cos_in, cos),
            SpotProfile::Linear => {
                if cos >= cos_in {
                    1.0
                } else if cos > cos_cone {
                    let theta = cos.clamp(-1.0, 1.0).acos();
                    ((self.cone - theta) / (self.cone - self.falloff)).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
            SpotProfile::Gltf => {
                let ramp = (cos_in - cos_cone).max(GLTF_MIN_RAMP);
                ((cos - cos_cone) / ramp).clamp(0.0, 1.0).powi(2)
            }
        }
    }

    /// The integral of [`Spot::falloff`] over the sphere of directions (steradians): the flux
    /// is the axis intensity times this.
    #[must_use]
    pub fn solid_angle(&self) -> f64 {
        let (cos_cone, cos_in) = (self.cone.cos(), self.falloff.cos());
        let over_cos = match self.profile {
            // smoothstep integrates to half its interval.
            SpotProfile::Smoothstep => (1.0 - cos_in) + 0.5 * (cos_in - cos_cone),
            // int_{tb}^{tc} (tc - t)/(tc - tb) sin t dt = cos tb - (sin tc - sin tb)/(tc - tb).
            SpotProfile::Linear => {
                let w = self.cone - self.falloff;
                if w > 0.0 {
                    1.0 - (self.cone.sin() - self.falloff.sin()) / w
                } else {
                    1.0 - cos_cone
                }
            }
            // int_{co}^{end} ((c - co)/r)^2 dc = (end - co)^3 / (3 r^2), then 1 up to cos 0.
            SpotProfile::Gltf => {
                let ramp = (cos_in - cos_cone).max(GLTF_MIN_RAMP);
                let end = (cos_cone + ramp).min(1.0);
                (end - cos_cone).powi(3) / (3.0 * ramp * ramp) + (1.0 - end)
            }
        };
        2.0 * PI * over_cos
    }

    /// A direction drawn uniformly in the cone from `u`, with its solid-angle pdf.
    #[must_use]
    pub fn sample(&self, u: DVec2) -> (DVec3, f64) {
        let (cos_max, sin_max) = (self.cone.cos(), self.cone.sin());
        let local = square_to_uniform_cone(u, cos_max, sin_max * sin_max);
        let (t, b) = orthonormal_basis(self.axis);
        let w = (local.x * t + local.y * b + local.z * self.axis).normalize();
        (w, self.pdf(w))
    }

    /// The solid-angle density of [`Spot::sample`] for unit `w`: uniform inside the cone, 0
    /// outside it.
    #[must_use]
    pub fn pdf(&self, w: DVec3) -> f64 {
        if w.dot(self.axis) >= self.cone.cos() {
            let one_minus = 2.0 * (0.5 * self.cone).sin().powi(2);
            1.0 / (2.0 * PI * one_minus)
        } else {
            0.0
        }
    }
}

/// pbrt-v4 `SmoothStep(a, b, x)`: 0 below `a`, 1 above `b`, `t^2 (3 - 2t)` between (a step at
/// `a` when `a == b`).
fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SplitMix64;
    use crate::sampling::chi2::test_directions;

    fn spot(profile: SpotProfile, cone: f64, falloff: f64) -> Spot {
        Spot {
            axis: DVec3::new(1.0, 2.0, -2.0) / 3.0,
            cone: cone.to_radians(),
            falloff: falloff.to_radians(),
            profile,
        }
    }

    const PROFILES: [SpotProfile; 3] = [
        SpotProfile::Smoothstep,
        SpotProfile::Linear,
        SpotProfile::Gltf,
    ];

    /// The closed-form solid angle against midpoint rules in theta (1e5 steps a piece).
    #[test]
    fn the_solid_angle_is_the_falloff_integrated_over_the_sphere() {
        let (t, _) = orthonormal_basis(DVec3::new(1.0, 2.0, -2.0) / 3.0);
        for profile in PROFILES {
            for (cone, falloff) in [
                (30.0, 25.0),
                (60.0, 0.0),
                (20.0, 20.0),
                (150.0, 90.0),
                (10.0, 9.99),
            ] {
                let s = spot(profile, cone, falloff);
                // Midpoint rules on the pieces between the profile's kinks and steps.
                let n = 100_000;
                let ends = [0.0, s.falloff, s.cone, PI];
                let sum: f64 = ends
                    .windows(2)
                    .map(|ab| {
                        let dt = (ab[1] - ab[0]) / f64::from(n);
                        (0..n)
                            .map(|i| {
                                let theta = ab[0] + (f64::from(i) + 0.5) * dt;
                                let w = theta.cos() * s.axis + theta.sin() * t;
                                s.falloff(w) * theta.sin() * dt
                            })
                            .sum::<f64>()
                    })
                    .sum();
                let numeric = 2.0 * PI * sum;
                let closed = s.solid_angle();
                assert!(
                    (numeric - closed).abs() < 1e-6 * closed.max(1e-3),
                    "{profile:?} {cone}/{falloff}: {numeric} vs {closed}"
                );
            }
        }
    }

    /// pbrt-v4's `SpotLight::Phi` factor, written out; a hard-edged cone is its cap's solid
    /// angle; the profiles' values at the axis, the beam edge, the midpoint and the cone edge.
    #[test]
    fn the_profiles_match_their_sources_at_closed_form_points() {
        let s = spot(SpotProfile::Smoothstep, 30.0, 25.0);
        let (ce, cs) = (30f64.to_radians().cos(), 25f64.to_radians().cos());
        let phi = 2.0 * PI * ((1.0 - cs) + (cs - ce) / 2.0);
        assert!((s.solid_angle() - phi).abs() < 1e-15);
        let hard = spot(SpotProfile::Linear, 40.0, 40.0);
        assert!((hard.solid_angle() - 2.0 * PI * (1.0 - 40f64.to_radians().cos())).abs() < 1e-15);
        let (t, _) = orthonormal_basis(s.axis);
        let at = |deg: f64| {
            let a = f64::to_radians(deg);
            a.cos() * s.axis + a.sin() * t
        };
        for profile in PROFILES {
            let s = Spot { profile, ..s };
            assert_eq!(s.falloff(s.axis), 1.0);
            assert!((s.falloff(at(24.999)) - 1.0).abs() < 1e-9, "{profile:?}");
            assert_eq!(s.falloff(at(30.001)), 0.0);
            assert_eq!(s.falloff(-s.axis), 0.0);
        }
        // Linear in the angle: half-way at 27.5 degrees.
        let lin = Spot {
            profile: SpotProfile::Linear,
            ..s
        };
        assert!((lin.falloff(at(27.5)) - 0.5).abs() < 1e-12);
        // Smoothstep: 1/2 where the cosine is half-way.
        let mid = (0.5 * (ce + cs)).acos().to_degrees();
        assert!((s.falloff(at(mid)) - 0.5).abs() < 1e-9);
        // glTF: a quarter where the cosine is half-way.
        let g = Spot {
            profile: SpotProfile::Gltf,
            ..s
        };
        assert!((g.falloff(at(mid)) - 0.25).abs() < 1e-9);
    }

    /// Chi-square of the emitted directions against their pdf (about `+z`, binned over the
    /// cone's own range of cosines); about a tilted axis, the directions stay in its cone.
    #[test]
    fn spot_directions_are_uniform_in_the_cone() {
        for cone in [5.0, 30.0, 100.0, 170.0] {
            let s = Spot {
                axis: DVec3::Z,
                ..spot(SpotProfile::Smoothstep, cone, 0.5 * cone)
            };
            let cos = s.cone.cos();
            test_directions(
                (cos, 1.0),
                1,
                |rng: &mut SplitMix64| Some(s.sample(rng.next_2d()).0),
                |w| s.pdf(w),
            )
            .assert_passes(&format!("spot cone {cone}"));
            let tilted = spot(SpotProfile::Linear, cone, 0.0);
            let mut rng = SplitMix64::new(7);
            for _ in 0..1000 {
                let (w, pdf) = tilted.sample(rng.next_2d());
                assert!(w.dot(tilted.axis) >= cos - 1e-12 && pdf == tilted.pdf(w));
            }
        }
    }
}
