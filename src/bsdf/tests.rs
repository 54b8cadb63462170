//! BSDF energy, reciprocity, consistency and degenerate-case tests (fixed seeds).

use super::*;
use crate::math::{self, FresnelModel};
use crate::sampling::SplitMix64;
use crate::sampling::warp::square_to_uniform_sphere;
use proptest::prelude::*;
use std::f64::consts::PI;

fn local(lobes: &[Lobe]) -> Bsdf {
    Bsdf::new(Frame::from_normal(DVec3::Z), lobes)
}

fn dir(theta_deg: f64) -> DVec3 {
    let t = theta_deg.to_radians();
    DVec3::new(t.sin(), 0.0, t.cos())
}

/// Mean and standard error of the sample weights (luminance of `f |cos| / pdf`); a failed
/// sample counts as 0. Also returns the largest single weight.
fn albedo(bsdf: &Bsdf, wo: DVec3, n: usize, seed: u64) -> (f64, f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2, mut max) = (0.0, 0.0, 0.0f64);
    for _ in 0..n {
        let uc = rng.next_f64();
        let w = bsdf
            .sample_local(wo, uc, rng.next_2d())
            .map_or(0.0, |x| luminance(x.weight(x.wi.z)));
        s += w;
        s2 += w * w;
        max = max.max(w);
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt(), max)
}

/// The same albedo by uniform sphere sampling of `eval |cos| * 4 pi`: an independent estimator.
fn albedo_uniform(bsdf: &Bsdf, wo: DVec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let wi = square_to_uniform_sphere(rng.next_2d());
        let w = luminance(bsdf.eval_local(wo, wi)) * wi.z.abs() * 4.0 * PI;
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    (
        mean,
        ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

fn rough_mirror(alpha: f64) -> Lobe {
    Lobe::RoughMirror {
        weight: Rgb::ONE,
        dist: Microfacet::new(alpha),
    }
}

fn rough_glass(alpha: f64, eta: f64) -> Lobe {
    Lobe::RoughDielectric {
        weight: Rgb::ONE,
        eta,
        dist: Microfacet::new(alpha),
    }
}

#[test]
fn fr_dielectric_is_the_lectures_exact_fresnel() {
    // Normal incidence on glass: ((1.5 - 1) / 2.5)^2 = 0.04, from either side.
    assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-15);
    assert!((fr_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-15);
    // Same value as math::fresnel for an oblique ray.
    let cos_i = 0.6f64;
    let t = math::refract(DVec3::new(0.8, 0.0, -0.6), DVec3::Z, 1.0 / 1.5).unwrap();
    let want = math::fresnel(FresnelModel::Exact, 1.0, 1.5, cos_i, t.cos_t).r;
    assert!((fr_dielectric(cos_i, 1.5) - want).abs() < 1e-15);
    // Inside glass beyond the critical angle (41.8 deg): total internal reflection.
    assert_eq!(fr_dielectric(-(50f64.to_radians().cos()), 1.5), 1.0);
    assert!(fr_dielectric(-(40f64.to_radians().cos()), 1.5) < 1.0);
}

#[test]
fn ggx_d_is_normalised_in_projected_area() {
    // Integral of D(wm) cos(theta_m) over the hemisphere is 1 (Walter 2007 eq. 4); midpoint rule
    // in (cos theta, phi).
    for alpha in [0.2, 0.5, 1.0] {
        let g = Microfacet::new(alpha);
        let (nz, nphi) = (4000, 8);
        let mut sum = 0.0;
        for i in 0..nz {
            let z = (i as f64 + 0.5) / nz as f64;
            for j in 0..nphi {
                let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
                let r = (1.0 - z * z).sqrt();
                sum += g.d(DVec3::new(r * phi.cos(), r * phi.sin(), z)) * z;
            }
        }
        sum *= 2.0 * PI / (nz * nphi) as f64;
        assert!((sum - 1.0).abs() < 1e-3, "alpha {alpha}: {sum}");
    }
}

#[test]
fn rough_mirror_white_furnace_is_at_most_one_and_tends_to_one_as_alpha_vanishes() {
    let n = 200_000;
    let mut last = 0.0;
    for (i, alpha) in [0.9, 0.5, 0.2, 0.05, 0.002].into_iter().enumerate() {
        let b = local(&[rough_mirror(alpha)]);
        let (mean, se, max) = albedo(&b, dir(60.0), n, 600 + i as u64);
        // With visible-normal sampling each weight is G1(wi) <= 1 (Heitz 2018 section 2).
        assert!(max <= 1.0 + 1e-12, "alpha {alpha}: weight {max}");
        assert!(mean <= 1.0, "alpha {alpha}: albedo {mean} +- {se}");
        assert!(
            mean + 4.0 * se >= last,
            "albedo should grow as alpha falls: {mean} < {last}"
        );
        last = mean;
    }
    assert!(last > 0.999, "alpha 0.002: albedo {last}");
}

#[test]
fn rough_dielectric_reflects_plus_transmits_at_most_one() {
    for (i, (alpha, eta, theta)) in [
        (0.3, 1.5, 30.0),
        (0.8, 1.5, 75.0),
        (0.5, 1.5, 160.0),
        (0.5, 1.0 / 1.33, 45.0),
        (0.05, 1.5, 0.0),
    ]
    .into_iter()
    .enumerate()
    {
        let b = local(&[rough_glass(alpha, eta)]);
        let (mean, se, max) = albedo(&b, dir(theta), 200_000, 700 + i as u64);
        assert!(max <= 1.0 + 1e-9, "{alpha} {eta} {theta}: weight {max}");
        assert!(mean <= 1.0, "R+T = {mean} +- {se}");
        // Nearly smooth glass at normal incidence loses almost nothing.
        if alpha < 0.1 {
            assert!(mean > 0.99, "{mean}");
        }
    }
}

#[test]
fn importance_and_uniform_estimators_of_the_albedo_agree() {
    // Welch t-test between two independent estimators of the same integral.
    let cases = [
        (local(&[rough_glass(0.5, 1.5)]), dir(35.0)),
        (local(&[rough_glass(0.6, 1.5)]), dir(150.0)),
        (local(&[rough_mirror(0.4)]), dir(70.0)),
        (
            local(&[
                Lobe::Lambert {
                    albedo: Rgb::splat(0.8),
                },
                rough_mirror(0.5),
            ]),
            dir(20.0),
        ),
    ];
    for (i, (b, wo)) in cases.iter().enumerate() {
        let (m1, s1, _) = albedo(b, *wo, 200_000, 800 + i as u64);
        let (m2, s2) = albedo_uniform(b, *wo, 400_000, 900 + i as u64);
        let t = (m1 - m2) / (s1 * s1 + s2 * s2).sqrt();
        assert!(
            t.abs() < 4.0,
            "case {i}: {m1} +- {s1} vs {m2} +- {s2}, t = {t}"
        );
    }
}

#[test]
fn smooth_dielectric_splits_like_the_whitted_tracer() {
    let w = Rgb::new(0.9, 0.8, 0.7);
    let b = local(&[Lobe::Dielectric {
        weight: w,
        eta: 1.5,
    }]);
    let wo = dir(50.0);
    let f = fr_dielectric(wo.z, 1.5);
    let r = b.sample_local(wo, 0.0, DVec2::ZERO).unwrap();
    assert_eq!(r.kind, LobeKind::SpecularReflection);
    assert!(r.delta);
    // Each event is chosen with its Fresnel probability and carries the whole weight, so the
    // expected contributions are w F and w (1 - F), the Whitted tracer's reflect and refract
    // weights.
    assert!((r.pdf - f).abs() < 1e-15);
    assert!((r.weight(r.wi.z) - w).abs().max_element() < 1e-12);
    let t = b.sample_local(wo, 0.999, DVec2::ZERO).unwrap();
    assert_eq!(t.kind, LobeKind::SpecularTransmission);
    assert!((t.pdf - (1.0 - f)).abs() < 1e-15);
    assert!((t.weight(t.wi.z) - w).abs().max_element() < 1e-12);
    // Snell: sin(theta_t) = sin(50 deg) / 1.5.
    let sin_t = (t.wi.x * t.wi.x + t.wi.y * t.wi.y).sqrt();
    assert!((sin_t - 50f64.to_radians().sin() / 1.5).abs() < 1e-12 && t.wi.z < 0.0);
    // From inside past the critical angle every sample reflects with weight w.
    let tir = b.sample_local(dir(130.0), 0.999, DVec2::ZERO).unwrap();
    assert_eq!(tir.kind, LobeKind::SpecularReflection);
    assert!((tir.weight(tir.wi.z) - w).abs().max_element() < 1e-12);
}

#[test]
fn thin_sheet_reflects_its_summed_fresnel_and_passes_the_rest_straight_on() {
    // R' = 2R / (1 + R): the series R + T^2 R + T^2 R^3 + ... of the two faces.
    let r0 = 0.04;
    assert!((thin_reflectance(1.0, 1.5) - 2.0 * r0 / (1.0 + r0)).abs() < 1e-15);
    for theta in [0.0f64, 30.0, 60.0, 85.0] {
        let c = theta.to_radians().cos();
        let r = fr_dielectric(c, 1.5);
        let t = 1.0 - r;
        let series: f64 = r + (0..200).map(|k| t * t * r.powi(2 * k + 1)).sum::<f64>();
        assert!((thin_reflectance(c, 1.5) - series).abs() < 1e-12, "{theta}");
    }
    // A sheet of index 1 is invisible.
    assert!(thin_reflectance(0.3, 1.0).abs() < 1e-15);
    let w = Rgb::new(0.9, 0.8, 0.7);
    let b = local(&[Lobe::ThinDielectric {
        weight: w,
        eta: 1.5,
    }]);
    assert!(b.is_delta());
    for wo in [dir(50.0), dir(130.0)] {
        let rp = thin_reflectance(wo.z.abs(), 1.5);
        let r = b.sample_local(wo, 0.0, DVec2::ZERO).unwrap();
        assert_eq!(r.kind, LobeKind::SpecularReflection);
        assert!((r.pdf - rp).abs() < 1e-15 && r.wi.z * wo.z > 0.0);
        assert!((r.weight(r.wi.z) - w).abs().max_element() < 1e-12);
        let t = b.sample_local(wo, 0.999, DVec2::ZERO).unwrap();
        assert_eq!(t.kind, LobeKind::SpecularTransmission);
        assert!((t.pdf - (1.0 - rp)).abs() < 1e-15);
        // Undeviated: the two refractions cancel.
        assert!((t.wi + wo).length() < 1e-15);
        assert!((t.weight(t.wi.z) - w).abs().max_element() < 1e-12);
        assert_eq!(b.eval_local(wo, t.wi), Rgb::ZERO);
        assert_eq!(b.pdf_local(wo, t.wi), 0.0);
    }
}

#[test]
fn from_material_reads_the_material_as_whitted_does() {
    let scene = crate::scene::Scene::from_json(include_str!("../../fixtures/classic.json"));
    let scene = scene.expect("classic fixture");
    let frame = Frame::from_normal(DVec3::Z);
    for m in &scene.materials {
        let b = Bsdf::from_material(m, DVec3::ZERO, frame, 0.0, 1.5);
        let kinds: Vec<_> = b.lobes().map(|(l, _)| *l).collect();
        assert_eq!(
            kinds.iter().any(|l| matches!(l, Lobe::Lambert { .. })),
            !m.diffuse.is_black()
        );
        assert_eq!(
            kinds.iter().any(|l| matches!(l, Lobe::Mirror { .. })),
            m.reflectivity != Rgb::ZERO
        );
        assert_eq!(
            kinds.iter().any(|l| matches!(l, Lobe::Dielectric { .. })),
            m.is_transmissive()
        );
        let p: f64 = b.lobes().map(|(_, p)| p).sum();
        assert!(b.lobes().count() == 0 || (p - 1.0).abs() < 1e-12);
        // Rough: the same lobes, GGX; index-matched transmission stays a pass-through.
        let rough = Bsdf::from_material(m, DVec3::ZERO, frame, 0.3, 1.5);
        assert_eq!(rough.lobes().count(), b.lobes().count());
        assert!(!rough.lobes().any(|(l, _)| matches!(l, Lobe::Mirror { .. })));
        let matched = Bsdf::from_material(m, DVec3::ZERO, frame, 0.3, 1.0);
        assert!(
            !matched
                .lobes()
                .any(|(l, _)| matches!(l, Lobe::RoughDielectric { .. }))
        );
    }
}

#[test]
fn degenerate_directions_give_no_nan() {
    let ggx = Microfacet::new(0.3);
    let lobes = [
        Lobe::Lambert { albedo: Rgb::ONE },
        Lobe::Mirror { weight: Rgb::ONE },
        Lobe::Dielectric {
            weight: Rgb::ONE,
            eta: 1.5,
        },
        rough_mirror(0.3),
        rough_glass(0.3, 1.5),
        rough_glass(SMOOTH_ALPHA, 1.0 / 1.5),
        Lobe::RoughMirror {
            weight: Rgb::ONE,
            dist: ggx,
        },
    ];
    let dirs = [
        DVec3::X,
        -DVec3::X,
        DVec3::Z,
        -DVec3::Z,
        DVec3::new(1.0, 0.0, 1e-300).normalize(),
        DVec3::new(1.0, 0.0, -1e-17).normalize(),
        DVec3::new(0.0, 1.0, 1e-9).normalize(),
    ];
    for lobe in lobes {
        let b = local(&[lobe]);
        for wo in dirs {
            for wi in dirs {
                assert!(b.eval_local(wo, wi).is_finite(), "{lobe:?} {wo} {wi}");
                let p = b.pdf_local(wo, wi);
                assert!(p.is_finite() && p >= 0.0, "{lobe:?} {wo} {wi}");
            }
            for uc in [0.0, 0.5, 1.0 - f64::EPSILON] {
                for u in [
                    DVec2::ZERO,
                    DVec2::splat(0.5),
                    DVec2::splat(1.0 - f64::EPSILON),
                ] {
                    if let Some(s) = b.sample_local(wo, uc, u) {
                        assert!(s.wi.is_finite() && s.value.is_finite(), "{lobe:?} {wo}");
                        assert!(s.pdf.is_finite() && s.pdf > 0.0, "{lobe:?} {wo}");
                        assert!(s.weight(s.wi.z).is_finite());
                    }
                }
            }
        }
    }
}

#[test]
fn surface_interaction_eta_follows_the_media_stack() {
    let scene = crate::scene::Scene::from_json(include_str!("../../fixtures/classic.json"));
    let scene = scene.expect("classic fixture");
    let glass = scene
        .materials
        .iter()
        .find(|m| m.ior.is_some())
        .expect("glass");
    let air = crate::media::MediaStack::AIR;
    let inside = air.entered(3, glass.ior.unwrap());
    let si = |entering: bool, media| crate::interaction::SurfaceInteraction {
        p: DVec3::ZERO,
        wo: DVec3::Z,
        entering,
        n: DVec3::Z,
        ns: DVec3::Z,
        smooth: None,
        cos_i: 1.0,
        object: 3,
        triangle: None,
        material: glass,
        media,
    };
    let ior = glass.ior.unwrap();
    assert!((si(true, &air).eta() - ior).abs() < 1e-15);
    assert!((si(false, &inside).eta() - ior).abs() < 1e-15);
    // The frame's z is the outward shading normal from either side.
    assert_eq!(si(true, &air).frame().n, DVec3::Z);
    assert_eq!(si(false, &inside).frame().n, -DVec3::Z);
    // Bsdf::at reads the interaction as from_material is given it by hand.
    let wo = DVec3::new(0.3, 0.1, 0.9).normalize();
    let wi = DVec3::new(-0.2, 0.4, 0.8).normalize();
    let by_hand = Bsdf::from_material(glass, DVec3::ZERO, si(false, &inside).frame(), 0.3, ior);
    let at = Bsdf::at(&si(false, &inside), 0.3);
    assert_eq!(at.eval(wo, wi), by_hand.eval(wo, wi));
    assert_eq!(at.pdf(wo, wi), by_hand.pdf(wo, wi));
}

fn any_lobe() -> impl Strategy<Value = Lobe> {
    (0usize..3, 0.05f64..1.0, 1.1f64..2.5, proptest::bool::ANY).prop_map(|(k, a, ior, inv)| {
        let eta = if inv { 1.0 / ior } else { ior };
        match k {
            0 => Lobe::Lambert {
                albedo: Rgb::splat(0.5),
            },
            1 => rough_mirror(a),
            _ => rough_glass(a, eta),
        }
    })
}

fn unit() -> impl Strategy<Value = DVec3> {
    (0.0f64..1.0, 0.0f64..1.0).prop_map(|(a, b)| square_to_uniform_sphere(DVec2::new(a, b)))
}

proptest! {
    #[test]
    fn reflection_is_reciprocal(lobe in any_lobe(), wo in unit(), wi in unit()) {
        prop_assume!(wo.z * wi.z > 0.0);
        let b = local(&[lobe]);
        let (f1, f2) = (b.eval_local(wo, wi), b.eval_local(wi, wo));
        prop_assert!((f1 - f2).abs().max_element() <= 1e-9 * f1.max_element().max(1.0), "{f1} {f2}");
    }

    #[test]
    fn pdf_is_positive_wherever_eval_is(lobe in any_lobe(), wo in unit(), wi in unit()) {
        let b = local(&[lobe]);
        if b.eval_local(wo, wi).max_element() > 0.0 {
            prop_assert!(b.pdf_local(wo, wi) > 0.0);
        }
    }

    #[test]
    fn samples_agree_with_eval_and_pdf(
        lobe in any_lobe(), wo in unit(), uc in 0.0f64..1.0, ux in 0.0f64..1.0, uy in 0.0f64..1.0,
    ) {
        let b = local(&[lobe]);
        if let Some(s) = b.sample_local(wo, uc, DVec2::new(ux, uy)) {
            prop_assert!((s.wi.length() - 1.0).abs() < 1e-9);
            prop_assert!(s.pdf > 0.0 && s.pdf.is_finite());
            prop_assert_eq!(s.value, b.eval_local(wo, s.wi));
            prop_assert_eq!(s.pdf, b.pdf_local(wo, s.wi));
            prop_assert!(luminance(s.weight(s.wi.z)) <= 1.0 + 1e-9);
        }
    }
}

/// The reverse density is the density of the swapped pair, and a rough dielectric's
/// transmission densities differ from it by the half-vector Jacobian (`eta^2`-scaled): a
/// bidirectional estimator that took `pdf` for both directions would weigh its strategies
/// wrongly through glass. Over `wo`, for a fixed `wi`, the reverse density integrates to the
/// probability that sampling from `wi` succeeds (at most 1; uniform-sphere estimate).
#[test]
fn the_reverse_density_is_the_swapped_pair_and_integrates_over_wo() {
    let glass = Bsdf::new(Frame::from_normal(DVec3::Z), &[rough_glass(0.3, 1.5)]);
    // wi near the refraction of wo (20 degrees in air, 13 in glass).
    let (wo, wi) = (dir(20.0), -dir(10.0));
    assert_eq!(glass.pdf_rev(wo, wi).to_bits(), glass.pdf(wi, wo).to_bits());
    let (fwd, rev) = (glass.pdf(wo, wi), glass.pdf_rev(wo, wi));
    assert!(
        fwd > 0.0 && rev > 0.0 && (fwd / rev - 1.0).abs() > 0.1,
        "{fwd} {rev}"
    );
    let mut rng = SplitMix64::new(7);
    let n = 400_000;
    let total: f64 = (0..n)
        .map(|_| glass.pdf_rev(square_to_uniform_sphere(rng.next_2d()), wi) * 4.0 * PI)
        .sum::<f64>()
        / n as f64;
    assert!(total > 0.9 && total < 1.02, "{total}");
}
