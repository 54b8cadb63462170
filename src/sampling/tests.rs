//! Chi-square tests of every warp and filter against its own pdf (fixed seeds).

use super::chi2::{test_directions, test_plane};
use super::{PixelFilter, warp};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

#[test]
fn cosine_hemisphere_matches_its_pdf() {
    test_directions(
        (0.0, 1.0),
        10,
        |rng| Some(warp::square_to_cosine_hemisphere(rng.next_2d())),
        warp::cosine_hemisphere_pdf,
    )
    .assert_passes("cosine hemisphere");
}

#[test]
fn uniform_sphere_matches_its_pdf() {
    test_directions(
        (-1.0, 1.0),
        11,
        |rng| Some(warp::square_to_uniform_sphere(rng.next_2d())),
        |_| 0.25 / PI,
    )
    .assert_passes("uniform sphere");
}

#[test]
fn cones_match_their_pdf_wide_and_narrow() {
    for (i, theta) in [1.4f64, 0.6, 0.05, 1e-3].into_iter().enumerate() {
        let (c, s2) = (theta.cos(), theta.sin().powi(2));
        test_directions(
            (c, 1.0),
            20 + i as u64,
            |rng| Some(warp::square_to_uniform_cone(rng.next_2d(), c, s2)),
            |w| warp::uniform_cone_pdf(w, c, s2),
        )
        .assert_passes(&format!("cone theta_max {theta}"));
    }
}

#[test]
fn concentric_disk_matches_its_pdf() {
    test_plane(
        (DVec2::splat(-1.0), DVec2::splat(1.0)),
        30,
        |rng| Some(warp::square_to_concentric_disk(rng.next_2d())),
        warp::concentric_disk_pdf,
    )
    .assert_passes("concentric disk");
}

#[test]
fn triangle_barycentrics_are_uniform() {
    // Points in the triangle (0,0), (1,0), (0,1) from barycentrics (b0 at the origin).
    test_plane(
        (DVec2::ZERO, DVec2::ONE),
        31,
        |rng| {
            let b = warp::square_to_triangle_barycentrics(rng.next_2d());
            Some(DVec2::new(b.y, b.z))
        },
        |p| if p.x + p.y <= 1.0 { 2.0 } else { 0.0 },
    )
    .assert_passes("triangle");
}

#[test]
fn every_filter_matches_its_pdf() {
    let filters = [
        PixelFilter::Box,
        PixelFilter::Tent { radius: 1.0 },
        PixelFilter::Tent { radius: 2.5 },
        PixelFilter::Gaussian {
            sigma: 0.5,
            radius: 1.5,
        },
        PixelFilter::Gaussian {
            sigma: 1.0,
            radius: 1.0,
        },
        PixelFilter::Gaussian {
            sigma: 0.2,
            radius: 2.0,
        },
    ];
    for (i, f) in filters.into_iter().enumerate() {
        let r = f.radius();
        test_plane(
            (DVec2::splat(-r), DVec2::splat(r)),
            40 + i as u64,
            |rng| Some(f.sample(rng.next_2d())),
            |p| f.pdf(p),
        )
        .assert_passes(&format!("{f:?}"));
    }
}

#[test]
fn warps_are_finite_at_the_corners_of_the_square() {
    let edge = 1.0 - f64::EPSILON / 2.0;
    for x in [0.0, 0.5, edge] {
        for y in [0.0, 0.5, edge] {
            let u = DVec2::new(x, y);
            let w = warp::square_to_cosine_hemisphere(u);
            assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0);
            assert!(warp::square_to_uniform_sphere(u).is_finite());
            let c = warp::square_to_uniform_cone(u, 1.0, 0.0);
            assert_eq!(c, DVec3::new(0.0, 0.0, 1.0).with_x(c.x).with_y(c.y));
            assert!(c.is_finite());
            assert!(warp::square_to_triangle_barycentrics(u).min_element() >= 0.0);
        }
    }
}

#[test]
fn narrow_cone_pdf_is_finite_where_one_minus_cos_rounds_to_zero() {
    let theta: f64 = 1e-9;
    let (c, s2) = (theta.cos(), theta.sin().powi(2));
    assert_eq!(c, 1.0);
    let pdf = warp::uniform_cone_pdf(DVec3::Z, c, s2);
    assert!(pdf.is_finite() && pdf > 0.0);
    // 1 / (2 pi (1 - cos)) ~ 1 / (pi theta^2).
    assert!((pdf * PI * theta * theta - 1.0).abs() < 1e-6);
}

proptest::proptest! {
    #[test]
    fn orthonormal_basis_is_orthonormal(x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0) {
        let n = DVec3::new(x, y, z);
        proptest::prop_assume!(n.length() > 1e-3);
        let n = n.normalize();
        let (s, t) = warp::orthonormal_basis(n);
        proptest::prop_assert!((s.length() - 1.0).abs() < 1e-12 && (t.length() - 1.0).abs() < 1e-12);
        proptest::prop_assert!(s.dot(t).abs() < 1e-12 && s.dot(n).abs() < 1e-12 && t.dot(n).abs() < 1e-12);
        proptest::prop_assert!((s.cross(t) - n).length() < 1e-12);
    }

    #[test]
    fn cosine_hemisphere_is_unit_and_above(ux in 0.0f64..1.0, uy in 0.0f64..1.0) {
        let w = warp::square_to_cosine_hemisphere(DVec2::new(ux, uy));
        proptest::prop_assert!((w.length() - 1.0).abs() < 1e-12 && w.z >= 0.0);
    }
}

/// Through the render's seam the Sobol sampler gives the same stream as built directly.
#[test]
fn the_sobol_sampler_through_the_seam_restarts_each_sample() {
    use super::{PixelSampler, SobolSampler};
    let mut seam = SobolSampler::new(9, (0, 0), 0);
    for (pixel, index) in [((3, 4), 0), ((3, 4), 5), ((100, 7), 2)] {
        seam.start_sample(pixel, index);
        let mut direct = SobolSampler::new(9, pixel, index);
        for _ in 0..6 {
            let (x, y) = PixelSampler::next_2d(&mut seam);
            let d = direct.next_2d();
            assert_eq!((x.to_bits(), y.to_bits()), (d.x.to_bits(), d.y.to_bits()));
        }
        assert_eq!(
            PixelSampler::next_1d(&mut seam).to_bits(),
            direct.next_1d().to_bits()
        );
    }
}
