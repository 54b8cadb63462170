//! Closed-form irradiance, chi-square and consistency tests of the light samplers.

use super::*;
use crate::sampling::SplitMix64;
use crate::sampling::chi2::test_directions;
use std::f64::consts::PI;

/// Mean and standard error of `L max(0, n.wi) / pdf` over `n` samples (failures count 0).
fn irradiance(
    n_samples: usize,
    seed: u64,
    n: DVec3,
    mut f: impl FnMut(DVec2) -> Option<LightSample>,
) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n_samples {
        let e = f(rng.next_2d()).map_or(0.0, |ls| ls.weight().x * ls.direction.dot(n).max(0.0));
        s += e;
        s2 += e * e;
    }
    let m = s / n_samples as f64;
    (
        m,
        ((s2 / n_samples as f64 - m * m).max(0.0) / n_samples as f64).sqrt(),
    )
}

#[test]
fn sphere_irradiance_is_pi_l_sin2() {
    let l = 3.0;
    let center = DVec3::new(0.5, 4.0, -1.0);
    for (i, (radius, tilt_deg)) in [(1.0, 0.0), (2.5, 0.0), (0.01, 0.0), (1.0, 50.0)]
        .into_iter()
        .enumerate()
    {
        let p = DVec3::ZERO;
        let axis = center.normalize();
        let (s, _) = orthonormal_basis(axis);
        let tilt = f64::to_radians(tilt_deg);
        let n = (axis * tilt.cos() + s * tilt.sin()).normalize();
        let sin2 = radius * radius / center.length_squared();
        let exact = PI * l * sin2 * tilt.cos();
        let (m, se) = irradiance(100_000, 1000 + i as u64, n, |u| {
            sample_sphere(p, center, radius, Rgb::splat(l), u)
        });
        assert!(
            (m - exact).abs() <= 4.0 * se + 1e-12 * exact,
            "r {radius} tilt {tilt_deg}: {m} +- {se} vs {exact}"
        );
        // Normal along the axis: every sample has the same cos-weighted value up to the cone:
        // the estimate is tight.
        assert!(se <= 0.01 * exact, "{se} vs {exact}");
    }
}

#[test]
fn quad_and_triangle_irradiance_match_lamberts_formula() {
    let l = 2.0;
    let p = DVec3::new(0.2, 0.0, 0.1);
    let n = DVec3::Y;
    // A ceiling quad facing down (u x v = -y) and a tilted one.
    let quads = [
        PlanarEmitter::quad(
            DVec3::new(-1.0, 2.0, -1.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
        ),
        PlanarEmitter::quad(
            DVec3::new(1.0, 1.0, -1.0),
            DVec3::new(0.0, 0.0, 1.5),
            DVec3::new(-0.5, 1.0, 0.0),
        ),
    ];
    for (i, q) in quads.into_iter().enumerate() {
        let verts = [
            q.corner,
            q.corner + q.edge_u,
            q.corner + q.edge_u + q.edge_v,
            q.corner + q.edge_v,
        ];
        let exact = polygon_irradiance(p, n, &verts, l);
        let (m, se) = irradiance(200_000, 1100 + i as u64, n, |u| {
            q.sample(p, Rgb::splat(l), u)
        });
        assert!(
            (m - exact).abs() <= 4.0 * se,
            "quad {i}: {m} +- {se} vs {exact}"
        );
        assert!(se < 0.01 * exact);
        let t = PlanarEmitter::triangle(verts[0], verts[1], verts[2]);
        let exact = polygon_irradiance(p, n, &verts[..3], l);
        let (m, se) = irradiance(200_000, 1200 + i as u64, n, |u| {
            t.sample(p, Rgb::splat(l), u)
        });
        assert!(
            (m - exact).abs() <= 4.0 * se,
            "triangle {i}: {m} +- {se} vs {exact}"
        );
    }
}

/// Chi-square of a light sampler in the frame whose `z` is `axis`, over the band `z >= z_min`.
fn chi2_light(
    axis: DVec3,
    z_min: f64,
    seed: u64,
    sample: impl Fn(DVec2) -> Option<LightSample>,
    pdf: impl Fn(DVec3) -> f64,
) -> crate::sampling::chi2::Chi2 {
    let (s, t) = orthonormal_basis(axis);
    test_directions(
        (z_min, 1.0),
        seed,
        |rng| {
            sample(rng.next_2d()).map(|ls| {
                DVec3::new(
                    ls.direction.dot(s),
                    ls.direction.dot(t),
                    ls.direction.dot(axis),
                )
            })
        },
        |w| pdf(w.x * s + w.y * t + w.z * axis),
    )
}

#[test]
fn light_samplers_match_their_solid_angle_pdfs() {
    let p = DVec3::new(0.1, -0.2, 0.3);
    let (center, radius) = (DVec3::new(1.0, 2.0, 0.5), 1.2);
    let axis = (center - p).normalize();
    let cos_max = (1.0 - radius * radius / (center - p).length_squared()).sqrt();
    chi2_light(
        axis,
        cos_max,
        1300,
        |u| sample_sphere(p, center, radius, Rgb::ONE, u),
        |w| sphere_pdf(p, center, radius, w),
    )
    .assert_passes("sphere");
    let q = PlanarEmitter::quad(
        DVec3::new(-1.0, 1.0, -1.0),
        DVec3::new(1.5, 0.3, 0.0),
        DVec3::new(0.0, 0.0, 2.5),
    );
    let down = -q.normal().unwrap();
    chi2_light(
        down,
        0.0,
        1301,
        |u| q.sample(p, Rgb::ONE, u),
        |w| q.pdf(p, w),
    )
    .assert_passes("quad");
    let t = PlanarEmitter::triangle(
        DVec3::new(-1.0, 1.0, -1.0),
        DVec3::new(1.5, 0.8, 0.0),
        DVec3::new(-1.0, 1.2, 2.0),
    );
    let down = -t.normal().unwrap();
    chi2_light(
        down,
        0.0,
        1302,
        |u| t.sample(p, Rgb::ONE, u),
        |w| t.pdf(p, w),
    )
    .assert_passes("triangle");
    // The conversion matters: the area pdf (1 / area) as if it were per solid angle is rejected.
    let r = chi2_light(
        down,
        0.0,
        1303,
        |u| t.sample(p, Rgb::ONE, u),
        |w| {
            if t.pdf(p, w) > 0.0 {
                1.0 / t.area()
            } else {
                0.0
            }
        },
    );
    assert!(!r.passes(), "{r:?}");
}

#[test]
fn samples_hit_the_emitter_at_their_distance_and_agree_with_pdf() {
    let mut rng = SplitMix64::new(1400);
    let p = DVec3::new(0.3, 0.1, -0.4);
    let (center, radius) = (DVec3::new(0.0, 3.0, 0.0), 0.7);
    let q = PlanarEmitter::quad(
        DVec3::new(-1.0, 2.0, -1.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
    );
    let t = PlanarEmitter::triangle(
        DVec3::new(-1.0, 2.0, -1.0),
        DVec3::new(1.0, 2.0, -1.0),
        DVec3::new(-1.0, 2.0, 1.0),
    );
    for _ in 0..1000 {
        let u = rng.next_2d();
        let s = sample_sphere(p, center, radius, Rgb::ONE, u).unwrap();
        let hit = p + s.distance * s.direction;
        assert!(((hit - center).length() - radius).abs() < 1e-9);
        assert!((s.pdf / sphere_pdf(p, center, radius, s.direction) - 1.0).abs() < 1e-9);
        for e in [q, t] {
            let s = e.sample(p, Rgb::ONE, u).unwrap();
            assert!((s.pdf / e.pdf(p, s.direction) - 1.0).abs() < 1e-9, "{e:?}");
            assert!(
                ((p + s.distance * s.direction - e.corner).dot(e.normal().unwrap())).abs() < 1e-9
            );
        }
    }
}

#[test]
fn back_sides_and_insides_emit_nothing() {
    let u = DVec2::splat(0.3);
    assert!(sample_sphere(DVec3::ZERO, DVec3::X * 0.5, 1.0, Rgb::ONE, u).is_none());
    assert_eq!(sphere_pdf(DVec3::ZERO, DVec3::X * 0.5, 1.0, DVec3::X), 0.0);
    // Quad facing -y, point above it: its back.
    let q = PlanarEmitter::quad(
        DVec3::new(-1.0, 2.0, -1.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 2.0),
    );
    let above = DVec3::new(0.0, 3.0, 0.0);
    assert!(q.sample(above, Rgb::ONE, u).is_none());
    assert_eq!(q.pdf(above, -DVec3::Y), 0.0);
    // Degenerate edges: no sample, no NaN.
    let d = PlanarEmitter::quad(DVec3::ZERO, DVec3::X, DVec3::X * 2.0);
    assert!(d.sample(DVec3::Y, Rgb::ONE, u).is_none());
    assert_eq!(d.pdf(DVec3::Y, -DVec3::Y), 0.0);
    // A tiny far sphere keeps a finite pdf.
    let s = sample_sphere(DVec3::ZERO, DVec3::new(0.0, 0.0, 1e6), 1e-3, Rgb::ONE, u).unwrap();
    assert!(s.pdf.is_finite() && s.pdf > 0.0 && s.distance.is_finite());
}

#[test]
fn delta_lights_match_the_scene_lights() {
    let p = DVec3::new(1.0, 2.0, 3.0);
    let light = Light::Point {
        position: DVec3::new(1.0, 6.0, 3.0),
        intensity: Rgb::splat(32.0),
        spot: None,
    };
    let s = light.sample_li(p, (0.5, 0.5)).unwrap();
    assert_eq!(
        s,
        sample_point_light(p, DVec3::new(1.0, 6.0, 3.0), Rgb::splat(32.0))
    );
    assert!(s.delta && s.pdf == 1.0 && s.distance == 4.0 && s.radiance == Rgb::splat(2.0));
    let sun = Light::Directional {
        direction: -DVec3::Y,
        irradiance: Rgb::ONE,
        center: DVec3::ZERO,
        radius: 1.0,
    };
    assert_eq!(
        sun.sample_li(p, (0.5, 0.5)),
        Some(sample_directional_light(-DVec3::Y, Rgb::ONE))
    );
    assert_eq!(sun.pdf_li(p, DVec3::Y), 0.0, "no direction has a density");
}
