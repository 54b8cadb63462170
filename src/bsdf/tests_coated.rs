//! The coated (plastic) lobe: the diffuse Fresnel reflectance in closed-form relations and
//! against Mitsuba's fits, the smooth lobe's exact directional albedo, the rough
//! transmittance table, chi-square of its sampling, reciprocity and a white furnace.

use super::coated::fractions_for_tests;
use super::*;
use crate::sampling::SplitMix64;
use crate::sampling::chi2::test_directions;

fn plastic(rho: f64, s: f64, eta: f64, alpha: Option<(Distribution, f64)>) -> Lobe {
    let dist = alpha.map(|(k, a)| Microfacet::with(k, a, a));
    Lobe::Plastic {
        diffuse: Rgb::splat(rho),
        specular: Rgb::splat(s),
        coating: Coating::new(eta, dist),
        dist: dist.unwrap_or(Microfacet::new(0.0)),
    }
}

fn bsdf(lobe: Lobe) -> Bsdf {
    Bsdf::new(Frame::from_normal(DVec3::Z), &[lobe])
}

fn dir(theta_deg: f64) -> DVec3 {
    let t = theta_deg.to_radians();
    DVec3::new(t.sin() * 0.3f64.cos(), t.sin() * 0.3f64.sin(), t.cos())
}

/// Mean and standard error of `f |cos| / pdf` (luminance) over `n` samples.
fn albedo(b: &Bsdf, wo: DVec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let uc = rng.next_f64();
        let w = b
            .sample_local(wo, uc, rng.next_2d())
            .map_or(0.0, |x| luminance(x.weight(x.wi.z)));
        s += w;
        s2 += w * w;
    }
    let mean = s / n as f64;
    let var = (s2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

#[test]
fn diffuse_fresnel_obeys_reciprocity_and_matches_the_published_fits() {
    for eta in [1.2, 1.49, 1.5, 2.0] {
        let (ext, int) = (diffuse_fresnel(eta), diffuse_fresnel(1.0 / eta));
        // The inside value against a direct midpoint integration across the critical
        // cosine (total reflection below it), independent of the identity it is built on.
        let n = 400_000;
        let direct: f64 = (0..n)
            .map(|k| {
                let mu = (k as f64 + 0.5) / n as f64;
                2.0 * mu * fr_dielectric(mu, 1.0 / eta)
            })
            .sum::<f64>()
            / n as f64;
        assert!((int - direct).abs() < 1e-6, "{eta}: {int} vs {direct}");
        assert!(ext > 0.0 && ext < int, "{eta}: {ext} {int}");
    }
    // Mitsuba 3's fresnel_diffuse_reflectance at eta 1.5: d'Eon and Irving 2011's polynomial
    // in 1/eta outside (0.091774), Egan and Hilgeman 1973's inside (0.596811).
    assert!((diffuse_fresnel(1.5) - 0.091_774).abs() < 1e-3);
    assert!((diffuse_fresnel(1.0 / 1.5) - 0.596_811).abs() < 2e-3);
    // No interface, no reflection.
    assert!(diffuse_fresnel(1.0).abs() < 1e-12);
}

#[test]
fn smooth_plastic_albedo_is_the_coatings_fresnel_plus_the_rest_times_the_base() {
    // s F(cos_o) + (1 - F(cos_o)) rho, exactly (module docs); a white base and coating: 1.
    let mut seed = 10;
    for (rho, s) in [(1.0, 1.0), (0.5, 1.0), (0.2, 0.6), (0.0, 1.0)] {
        for theta in [0.0, 40.0, 75.0, 89.0, 130.0] {
            seed += 1;
            let wo = dir(theta);
            let f = fr_dielectric(wo.z.abs(), 1.5);
            let want = s * f + (1.0 - f) * rho;
            let (got, se) = albedo(&bsdf(plastic(rho, s, 1.5, None)), wo, 200_000, seed);
            assert!(
                (got - want).abs() <= 5.0 * se + 1e-12,
                "rho {rho} s {s} theta {theta}: {got} +- {se}, want {want}"
            );
        }
    }
}

#[test]
fn rough_transmittance_tends_to_the_smooth_one_and_conserves_energy() {
    for (kind, alpha) in [(Distribution::Ggx, 0.3), (Distribution::Beckmann, 0.1)] {
        let d = Microfacet::with(kind, alpha, alpha);
        for mu in [0.05, 0.3, 0.7, 1.0] {
            let (r, t) = fractions_for_tests(1.5, d, mu);
            assert!(r >= 0.0 && t >= 0.0 && r + t <= 1.0 + 1e-9, "{mu}: {r} {t}");
        }
    }
    let d = Microfacet::new(0.01);
    for mu in [0.3, 0.6, 1.0] {
        let (r, t) = fractions_for_tests(1.5, d, mu);
        let f = fr_dielectric(mu, 1.5);
        assert!(
            (r - f).abs() < 2e-3 && (t - (1.0 - f)).abs() < 2e-3,
            "{mu}: {r} {t} {f}"
        );
    }
    // The table's internal reflectance tends to the smooth F_dr,int.
    let rough = Coating::new(1.5, Some(Microfacet::new(0.01)));
    assert!(
        (rough.internal - diffuse_fresnel(1.0 / 1.5)).abs() < 5e-3,
        "{rough:?}"
    );
}

/// Directional albedos of Mitsuba 3's `roughplastic` (3.9.1, `scalar_rgb`, `int_ior` 1.5,
/// `ext_ior` 1; 400 000 `sample` calls per direction, standard error about 5e-4), at
/// theta 0, 50 and 80 degrees: (distribution, alpha, rho, s, albedos). Single scattering in
/// the coating loses energy (0.54 for a white base at alpha 0.5): the model does, not the
/// sampling; the smooth coating's white furnace is exact (the smooth test above).
const MITSUBA_ROUGHPLASTIC: [(Distribution, f64, f64, f64, [f64; 3]); 4] = [
    (Distribution::Ggx, 0.5, 1.0, 1.0, [0.5403, 0.5158, 0.4432]),
    (Distribution::Ggx, 0.05, 1.0, 1.0, [0.9566, 0.9568, 0.9459]),
    (
        Distribution::Beckmann,
        0.2,
        0.5,
        0.8,
        [0.4770, 0.4834, 0.5159],
    ),
    (Distribution::Ggx, 0.3, 0.2, 1.0, [0.1668, 0.1740, 0.2219]),
];

/// Mitsuba's `F_dr,int` of a rough coating: twice the plain mean of `mu R(mu)` over its 64
/// table cosines `i / 63` (endpoints included, `mu = 1e-6` for `i = 0`), where we integrate.
fn mitsuba_internal(kind: Distribution, alpha: f64) -> f64 {
    let d = Microfacet::with(kind, alpha, alpha);
    let sum: f64 = (0..64)
        .map(|i| {
            let mu = (i as f64 / 63.0).max(1e-6);
            mu * fractions_for_tests(1.0 / 1.5, d, mu).0
        })
        .sum();
    2.0 * sum / 64.0
}

#[test]
fn rough_plastic_albedo_agrees_with_mitsuba_3() {
    let mut seed = 40;
    for (kind, alpha, rho, s, want) in MITSUBA_ROUGHPLASTIC {
        let ours = plastic(rho, s, 1.5, Some((kind, alpha)));
        let Lobe::Plastic { coating, .. } = ours else {
            unreachable!()
        };
        // Mitsuba's sum underestimates F_dr,int (by 0.009 at eta 1.5, near smooth), which
        // darkens its base by up to 2%; with its value in our lobe the two agree to 0.5%.
        let theirs = match ours {
            Lobe::Plastic {
                diffuse,
                specular,
                dist,
                ..
            } => Lobe::Plastic {
                diffuse,
                specular,
                dist,
                coating: Coating {
                    internal: mitsuba_internal(kind, alpha),
                    ..coating
                },
            },
            other => other,
        };
        assert!(coating.internal > mitsuba_internal(kind, alpha));
        for (theta, want) in [0.0, 50.0, 80.0].into_iter().zip(want) {
            for (lobe, tol) in [(theirs, 0.005), (ours, 0.025)] {
                seed += 1;
                let (got, se) = albedo(&bsdf(lobe), dir(theta), 200_000, seed);
                assert!(
                    (got - want).abs() < tol * want + 5.0 * se,
                    "{kind:?} alpha {alpha} rho {rho} s {s} theta {theta} ({tol}): \
                     {got} +- {se}, Mitsuba {want}"
                );
                assert!(got <= 1.0 + 5.0 * se);
            }
        }
    }
}

#[test]
fn plastic_samples_match_their_density() {
    let mut seed = 600;
    for alpha in [
        None,
        Some((Distribution::Ggx, 0.2)),
        Some((Distribution::Ggx, 0.7)),
        Some((Distribution::Beckmann, 0.1)),
    ] {
        for theta in [0.0, 45.0, 80.0, 140.0] {
            seed += 1;
            let b = bsdf(plastic(0.6, 0.8, 1.5, alpha));
            let wo = dir(theta);
            test_directions(
                (-1.0, 1.0),
                seed,
                |rng| {
                    let uc = rng.next_f64();
                    // Delta (smooth coating) events have no density: left out, as the
                    // chi-square of a mirror-plus-diffuse mixture does.
                    b.sample_local(wo, uc, rng.next_2d())
                        .filter(|s| !s.delta)
                        .map(|s| s.wi)
                },
                |wi| b.pdf_local(wo, wi),
            )
            .assert_passes(&format!("plastic {alpha:?} theta {theta}"));
        }
    }
}

#[test]
fn plastic_is_reciprocal_and_its_samples_agree_with_eval_and_pdf() {
    let mut rng = SplitMix64::new(7);
    for alpha in [
        None,
        Some((Distribution::Ggx, 0.3)),
        Some((Distribution::Beckmann, 0.2)),
    ] {
        let b = bsdf(plastic(0.4, 0.9, 1.6, alpha));
        for _ in 0..2000 {
            let wo = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
            let wi = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
            let (f1, f2) = (b.eval_local(wo, wi), b.eval_local(wi, wo));
            assert!((f1 - f2).abs().max_element() <= 1e-12 * f1.max_element().max(1.0));
            if f1.max_element() > 0.0 {
                assert!(b.pdf_local(wo, wi) > 0.0, "{wo} {wi}");
            }
            let uc = rng.next_f64();
            if let Some(s) = b.sample_local(wo, uc, rng.next_2d()) {
                assert!(s.value.is_finite() && s.pdf > 0.0 && s.pdf.is_finite());
                if !s.delta {
                    assert_eq!(s.value, b.eval_local(wo, s.wi));
                    assert_eq!(s.pdf, b.pdf_local(wo, s.wi));
                }
            }
        }
    }
}

#[test]
fn a_coated_material_is_one_plastic_lobe_and_whitted_reads_its_fresnel() {
    let rough = Coating::new(1.5, None);
    let mut m = crate::scene::Material {
        name: "plastic".into(),
        diffuse: Texture::Solid(Rgb::splat(0.5)),
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
        conductor: None,
        coating: Some(rough),
        thin: None,
    };
    let frame = Frame::from_normal(DVec3::Z);
    let b = Bsdf::from_material(&m, DVec3::ZERO, frame, 0.0, 1.0);
    assert_eq!(b.lobes().count(), 1);
    assert!(matches!(b.lobes().next(), Some((Lobe::Plastic { .. }, _))));
    // The base factor at normal incidence: (1 - R0)^2 / (eta^2 (1 - F_dr,int)).
    let r0 = 0.04;
    let want = (1.0 - r0) * (1.0 - r0) / (2.25 * (1.0 - diffuse_fresnel(1.0 / 1.5)));
    assert!((m.base_factor(1.0, 1.0) - want).abs() < 1e-12);
    // The reflection lobe alone is the coating's Fresnel mirror.
    let mirror = Bsdf::new(frame, &[m.reflection_lobe(false)]);
    let s = mirror
        .sample_local(dir(60.0), 0.5, DVec2::splat(0.5))
        .unwrap();
    let f = fr_dielectric(60f64.to_radians().cos(), 1.5);
    assert!((s.weight(s.wi.z) - Rgb::splat(f)).abs().max_element() < 1e-12);
    m.coating = None;
    assert_eq!(m.base_factor(0.3, 0.7), 1.0);
}

/// Mitsuba 3.9.1's `roughplastic` with `nonlinear` true (as [`MITSUBA_ROUGHPLASTIC`], s = 1).
const MITSUBA_NONLINEAR: [(Distribution, f64, f64, [f64; 3]); 2] = [
    (Distribution::Ggx, 0.3, 0.5, [0.2777, 0.2808, 0.3102]),
    (Distribution::Beckmann, 0.1, 0.8, [0.6208, 0.6281, 0.7078]),
];

fn nonlinear(rho: f64, kind: Distribution, alpha: f64, internal: Option<f64>) -> Lobe {
    let dist = Microfacet::with(kind, alpha, alpha);
    let base = Coating::new(1.5, Some(dist));
    let coating = Coating {
        nonlinear: true,
        internal: internal.unwrap_or(base.internal),
        ..base
    };
    Lobe::Plastic {
        diffuse: coating.effective(Rgb::splat(rho)),
        specular: Rgb::ONE,
        coating,
        dist,
    }
}

#[test]
fn nonlinear_coatings_absorb_at_every_inner_bounce_and_agree_with_mitsuba_3() {
    // Smooth: s F + (1 - F) rho (1 - F_dr,int) / (1 - rho F_dr,int), exactly.
    let fi = diffuse_fresnel(1.0 / 1.5);
    let mut seed = 900;
    for rho in [0.2, 0.5, 1.0] {
        let c = Coating {
            nonlinear: true,
            ..Coating::smooth(1.5)
        };
        let lobe = Lobe::Plastic {
            diffuse: c.effective(Rgb::splat(rho)),
            specular: Rgb::ONE,
            coating: c,
            dist: Microfacet::new(0.0),
        };
        for theta in [0.0f64, 60.0] {
            seed += 1;
            let f = fr_dielectric(theta.to_radians().cos(), 1.5);
            let want = f + (1.0 - f) * rho * (1.0 - fi) / (1.0 - rho * fi);
            let (got, se) = albedo(&bsdf(lobe), dir(theta), 200_000, seed);
            assert!(
                (got - want).abs() <= 5.0 * se + 1e-12,
                "{rho} {theta}: {got} {want}"
            );
        }
    }
    // A white base: the same as the linear model.
    let c = Coating {
        nonlinear: true,
        ..Coating::smooth(1.5)
    };
    assert_eq!(c.effective(Rgb::ONE), Rgb::ONE);
    for (kind, alpha, rho, want) in MITSUBA_NONLINEAR {
        let theirs = nonlinear(rho, kind, alpha, Some(mitsuba_internal(kind, alpha)));
        let ours = nonlinear(rho, kind, alpha, None);
        for (theta, want) in [0.0, 50.0, 80.0].into_iter().zip(want) {
            for (lobe, tol) in [(theirs, 0.005), (ours, 0.025)] {
                seed += 1;
                let (got, se) = albedo(&bsdf(lobe), dir(theta), 200_000, seed);
                assert!(
                    (got - want).abs() < tol * want + 5.0 * se,
                    "{kind:?} {alpha} {rho} {theta} ({tol}): {got} +- {se}, Mitsuba {want}"
                );
            }
        }
    }
}
