//! Conductor, Beckmann and anisotropic lobes: exact delta weights, furnace tests against a
//! quadrature of the masking loss, two independent estimators, reciprocity (fixed seeds).

use super::*;
use crate::sampling::SplitMix64;
use crate::sampling::warp::square_to_uniform_sphere;
use std::f64::consts::PI;

fn local(lobes: &[Lobe]) -> Bsdf {
    Bsdf::new(Frame::from_normal(DVec3::Z), lobes)
}

fn dir(theta_deg: f64, phi: f64) -> DVec3 {
    let t = theta_deg.to_radians();
    DVec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

/// Mean and standard error per channel of the sample weights `f |cos| / pdf`, and the
/// largest channel of any single weight.
fn albedo_rgb(b: &Bsdf, wo: DVec3, n: usize, seed: u64) -> (Rgb, Rgb, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2, mut max) = (Rgb::ZERO, Rgb::ZERO, 0.0f64);
    for _ in 0..n {
        let uc = rng.next_f64();
        let w = b
            .sample_local(wo, uc, rng.next_2d())
            .map_or(Rgb::ZERO, |x| x.weight(x.wi.z));
        s += w;
        s2 += w * w;
        max = max.max(w.max_element());
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(Rgb::ZERO);
    (mean, (var / n as f64).powf(0.5), max)
}

/// Uniform-sphere estimate of the albedo's luminance: `eval |cos| 4 pi`.
fn albedo_uniform(b: &Bsdf, wo: DVec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let wi = square_to_uniform_sphere(rng.next_2d());
        let w = luminance(b.eval_local(wo, wi)) * wi.z.abs() * 4.0 * PI;
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

/// The single-scattering albedo of a rough mirror with `F = 1`, by quadrature over microfacet
/// normals: `E(wo) = integral D_wo(wm) G1(wi) [wi above] dwm` with `wi` the reflection of `wo`
/// about `wm` (Heitz 2014 eq. 17 with the separable G2; the energy lost is the masking of the
/// reflected ray). Midpoint rule in `(cos theta_m, phi_m)`.
fn masking_albedo(m: Microfacet, wo: DVec3) -> f64 {
    let n = 1200;
    let mut sum = 0.0;
    for i in 0..n {
        let z = (i as f64 + 0.5) / n as f64;
        let r = (1.0 - z * z).sqrt();
        for j in 0..n {
            let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
            let wm = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            let wi = -wo + 2.0 * wo.dot(wm) * wm;
            if wi.z > 0.0 {
                sum += m.d_visible(wo, wm) * m.g1(wi);
            }
        }
    }
    sum * 2.0 * PI / (n * n) as f64
}

#[test]
fn smooth_conductor_weight_is_the_fresnel_per_channel() {
    let ior = ComplexIor::metal("Cu").unwrap();
    let tint = Rgb::new(1.0, 0.9, 0.8);
    let b = local(&[Lobe::Conductor { weight: tint, ior }]);
    for theta in [0.0, 40.0, 80.0, 89.0] {
        let wo = dir(theta, 0.3);
        let s = b.sample_local(wo, 0.5, DVec2::new(0.3, 0.7)).unwrap();
        assert!(s.delta && s.kind == LobeKind::SpecularReflection && s.pdf == 1.0);
        assert!((s.wi - DVec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-15);
        let want = tint * ior.fresnel(wo.z);
        assert!(
            (s.weight(s.wi.z) - want).abs().max_element() < 1e-14,
            "{theta}"
        );
    }
    // Not a constant: towards grazing every channel rises to nearly 1.
    let w = |t: f64| ior.fresnel(t.to_radians().cos());
    let (f0, f90) = (w(0.0), w(89.9));
    assert!(
        f90.x > f0.x && f90.y > f0.y && f90.z > f0.z,
        "{f0:?} {f90:?}"
    );
    assert!(f90.min_element() > 0.97, "{f90:?}");
    assert_eq!(b.eval_local(dir(30.0, 0.0), dir(30.0, PI)), Rgb::ZERO);
}

#[test]
fn f_one_furnace_matches_the_masking_loss() {
    // A rough mirror (F = 1) loses exactly the energy masked on the way out: the sampled
    // albedo equals the quadrature of E(wo), every weight is G1(wi) <= 1.
    let cases = [
        (Distribution::Beckmann, 0.5, 0.5, 60.0),
        (Distribution::Beckmann, 0.9, 0.9, 0.0),
        (Distribution::Beckmann, 0.2, 0.7, 70.0),
        (Distribution::Ggx, 0.3, 0.8, 50.0),
        (Distribution::Ggx, 1.0, 1.0, 80.0),
    ];
    for (i, (kind, ax, ay, theta)) in cases.into_iter().enumerate() {
        let m = Microfacet::with(kind, ax, ay);
        let wo = dir(theta, 0.6);
        let b = local(&[Lobe::RoughMirror {
            weight: Rgb::ONE,
            dist: m,
        }]);
        let (mean, se, max) = albedo_rgb(&b, wo, 200_000, 1000 + i as u64);
        let want = masking_albedo(m, wo);
        assert!(max <= 1.0 + 1e-12, "{kind:?}: weight {max}");
        assert!(want < 1.0 && want > 0.5, "{kind:?}: {want}");
        let t = (mean.x - want) / se.x.max(1e-12);
        assert!(
            t.abs() < 4.0,
            "{kind:?} ({ax}, {ay}) {theta}: sampled {} +- {} vs quadrature {want}",
            mean.x,
            se.x
        );
    }
    // Rougher loses more (at 70 degrees, isotropic Beckmann).
    let e = |a: f64| {
        masking_albedo(
            Microfacet::with(Distribution::Beckmann, a, a),
            dir(70.0, 0.0),
        )
    };
    assert!(e(0.9) < e(0.5) && e(0.5) < e(0.1) && e(0.1) > 0.99);
}

#[test]
fn rough_conductor_albedo_is_below_its_fresnel_and_tends_to_it() {
    let ior = ComplexIor::metal("Au").unwrap();
    for (i, (kind, a)) in [
        (Distribution::Ggx, 0.6),
        (Distribution::Beckmann, 0.4),
        (Distribution::Ggx, 0.002),
        (Distribution::Beckmann, 0.002),
    ]
    .into_iter()
    .enumerate()
    {
        let wo = dir(50.0, 0.2);
        let b = local(&[Lobe::RoughConductor {
            weight: Rgb::ONE,
            ior,
            dist: Microfacet::with(kind, a, a),
        }]);
        let (mean, se, max) = albedo_rgb(&b, wo, 100_000, 1100 + i as u64);
        assert!(max <= 1.0 + 1e-12, "{kind:?} {a}: weight {max}");
        // Single scattering with F <= 1 at every microfacet: at most 1 per channel.
        assert!((mean - 4.0 * se).max_element() <= 1.0, "{mean:?}");
        if a < 0.01 {
            // Nearly smooth: the albedo is the Fresnel of the macro surface.
            let f = ior.fresnel(wo.z);
            assert!(
                (mean - f).abs().max_element() < 2e-3,
                "{kind:?}: {mean:?} vs {f:?}"
            );
        }
    }
}

#[test]
fn importance_and_uniform_estimators_agree_for_the_new_lobes() {
    let au = ComplexIor::metal("Au").unwrap();
    let cases = [
        Lobe::RoughConductor {
            weight: Rgb::ONE,
            ior: au,
            dist: Microfacet::with(Distribution::Beckmann, 0.3, 0.6),
        },
        Lobe::RoughConductor {
            weight: Rgb::new(0.9, 0.8, 0.7),
            ior: au,
            dist: Microfacet::with(Distribution::Ggx, 0.5, 0.15),
        },
        Lobe::RoughDielectric {
            weight: Rgb::ONE,
            eta: 1.5,
            dist: Microfacet::with(Distribution::Beckmann, 0.4, 0.4),
        },
    ];
    for (i, lobe) in cases.into_iter().enumerate() {
        let b = local(&[lobe]);
        let wo = dir(40.0, 1.0);
        let (m1, s1, _) = albedo_rgb(&b, wo, 200_000, 1200 + i as u64);
        let (m1, s1) = (luminance(m1), luminance(s1));
        let (m2, s2) = albedo_uniform(&b, wo, 400_000, 1300 + i as u64);
        let t = (m1 - m2) / (s1 * s1 + s2 * s2).sqrt();
        assert!(
            t.abs() < 4.0,
            "case {i}: {m1} +- {s1} vs {m2} +- {s2}, t = {t}"
        );
    }
}

#[test]
fn conductor_lobes_are_reciprocal() {
    let ior = ComplexIor::metal("Cu").unwrap();
    let mut rng = SplitMix64::new(77);
    for kind in [Distribution::Ggx, Distribution::Beckmann] {
        let lobe = Lobe::RoughConductor {
            weight: Rgb::ONE,
            ior,
            dist: Microfacet::with(kind, 0.25, 0.55),
        };
        for _ in 0..200 {
            let a = square_to_uniform_sphere(rng.next_2d());
            let b = square_to_uniform_sphere(rng.next_2d());
            let (f, g) = (lobe.eval(a, b), lobe.eval(b, a));
            assert!((f - g).abs().max_element() <= 1e-12 * f.max_element().max(1.0));
        }
    }
}

#[test]
fn a_material_builds_the_conductor_lobes() {
    use crate::scene::{Material, Texture};
    let mut m = Material {
        name: "cu".into(),
        diffuse: Texture::Solid(Rgb::ZERO),
        specular: Rgb::ZERO,
        shininess: 0.0,
        reflectivity: Rgb::ONE,
        transmissivity: Rgb::ZERO,
        ior: None,
        absorption: Rgb::ZERO,
        emission: Rgb::ZERO,
        roughness: 0.0,
        roughness_v: 0.0,
        tangent: DVec3::X,
        distribution: Distribution::Ggx,
        conductor: ComplexIor::metal("Cu"),
        coating: None,
        thin: None,
    };
    let frame = Frame::from_normal(DVec3::Z);
    let b = Bsdf::from_material(&m, DVec3::ZERO, frame, m.roughness, 1.0);
    assert!(b.is_delta());
    assert!(matches!(
        b.lobes().next(),
        Some((Lobe::Conductor { .. }, _))
    ));
    m.roughness = 0.3;
    m.roughness_v = 0.1;
    m.distribution = Distribution::Beckmann;
    let b = Bsdf::from_material(&m, DVec3::ZERO, frame, m.roughness, 1.0);
    match b.lobes().next() {
        Some((Lobe::RoughConductor { dist, .. }, _)) => {
            assert_eq!(
                (dist.kind, dist.alpha_x, dist.alpha_y),
                (Distribution::Beckmann, 0.3, 0.1)
            );
        }
        other => panic!("{other:?}"),
    }
}
