//! Chi-square tests of GGX visible-normal sampling and of every non-delta BSDF's `sample`
//! against its own `pdf` (several `wo`, alphas and indices; fixed seeds).

use super::{Bsdf, Frame, Ggx, Lobe};
use crate::math::Rgb;
use crate::sampling::chi2::test_directions;
use glam::DVec3;

/// A direction at polar angle `theta_deg` from `+z` (negative: from below), azimuth 0.3 rad.
fn dir(theta_deg: f64) -> DVec3 {
    let t = theta_deg.to_radians();
    DVec3::new(t.sin() * 0.3f64.cos(), t.sin() * 0.3f64.sin(), t.cos())
}

fn chi2_bsdf(lobes: &[Lobe], wo: DVec3, seed: u64, what: &str) {
    let bsdf = Bsdf::new(Frame::from_normal(DVec3::Z), lobes);
    test_directions(
        (-1.0, 1.0),
        seed,
        |rng| {
            let uc = rng.next_f64();
            bsdf.sample_local(wo, uc, rng.next_2d()).map(|s| s.wi)
        },
        |wi| bsdf.pdf_local(wo, wi),
    )
    .assert_passes(what);
}

#[test]
fn ggx_visible_normals_match_their_density() {
    let mut seed = 100;
    for alpha in [0.1, 0.3, 0.8] {
        for theta in [0.0, 45.0, 80.0, 89.9, 135.0] {
            let g = Ggx::new(alpha);
            let w = dir(theta);
            seed += 1;
            test_directions(
                (0.0, 1.0),
                seed,
                |rng| Some(g.sample_visible(w, rng.next_2d())),
                |wm| g.d_visible(w, wm),
            )
            .assert_passes(&format!("VNDF alpha {alpha} theta {theta}"));
        }
    }
}

#[test]
fn a_vndf_pdf_without_its_masking_term_is_rejected() {
    // D(wm) |w.wm| / cos(w) (G1 left out) integrates above 1 and has the wrong shape.
    let g = Ggx::new(0.6);
    let w = dir(70.0);
    let r = test_directions(
        (0.0, 1.0),
        99,
        |rng| Some(g.sample_visible(w, rng.next_2d())),
        |wm| g.d(wm) * w.dot(wm).abs() / w.z.abs(),
    );
    assert!(!r.passes(), "{r:?}");
}

#[test]
fn lambert_sample_matches_pdf_from_both_sides() {
    let albedo = Rgb::splat(0.7);
    for (i, theta) in [10.0, 60.0, 150.0].into_iter().enumerate() {
        chi2_bsdf(
            &[Lobe::Lambert { albedo }],
            dir(theta),
            200 + i as u64,
            "lambert",
        );
    }
}

#[test]
fn rough_mirror_sample_matches_pdf() {
    let mut seed = 300;
    for alpha in [0.15, 0.4, 1.0] {
        for theta in [0.0, 50.0, 85.0, 120.0] {
            seed += 1;
            let lobe = Lobe::RoughMirror {
                weight: Rgb::ONE,
                ggx: Ggx::new(alpha),
            };
            chi2_bsdf(
                &[lobe],
                dir(theta),
                seed,
                &format!("rough mirror a {alpha} th {theta}"),
            );
        }
    }
}

#[test]
fn rough_dielectric_sample_matches_pdf() {
    let mut seed = 400;
    for eta in [1.5, 1.0 / 1.33] {
        for alpha in [0.2, 0.5, 0.9] {
            // Outside, near grazing, and from inside below and beyond the critical angle.
            for theta in [0.0, 40.0, 80.0, 160.0, 130.0] {
                seed += 1;
                let lobe = Lobe::RoughDielectric {
                    weight: Rgb::ONE,
                    eta,
                    ggx: Ggx::new(alpha),
                };
                let what = format!("rough dielectric eta {eta} a {alpha} th {theta}");
                chi2_bsdf(&[lobe], dir(theta), seed, &what);
            }
        }
    }
}

#[test]
fn lobe_mixture_sample_matches_combined_pdf() {
    let ggx = Ggx::new(0.35);
    let lobes = [
        Lobe::Lambert {
            albedo: Rgb::new(0.5, 0.2, 0.1),
        },
        Lobe::RoughMirror {
            weight: Rgb::splat(0.3),
            ggx,
        },
        Lobe::RoughDielectric {
            weight: Rgb::splat(0.6),
            eta: 1.5,
            ggx,
        },
    ];
    for (i, theta) in [20.0, 70.0, 140.0].into_iter().enumerate() {
        chi2_bsdf(&lobes, dir(theta), 500 + i as u64, "mixture");
    }
}
