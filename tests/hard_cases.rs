//! Closed-form optics that must stay numerically stable, after Mitsuba 3's `test_fresnel.py`:
//! normal, Brewster, critical and grazing incidence from both sides, index-matched interfaces,
//! cosines that round above 1, Beer's law limits, and proptest sweeps of Snell/Fresnel and of
//! unnormalized ray directions (regressions in `hard_cases.proptest-regressions`).

use glam::DVec3;
use proptest::prelude::*;
use raytree::geometry::Shape;
use raytree::math::{
    FresnelModel, Ray, Rgb, beer, brewster_angle, critical_angle, fresnel, fresnel_exact, reflect,
    refract,
};

const IORS: [(f64, f64); 4] = [(1.0, 1.5), (1.5, 1.0), (1.0, 1.333), (1.333, 1.5)];

fn incident(theta: f64) -> DVec3 {
    DVec3::new(theta.sin(), -theta.cos(), 0.0)
}

fn exact(n1: f64, n2: f64, theta: f64) -> Option<(f64, f64, f64)> {
    let t = refract(incident(theta), DVec3::Y, n1 / n2)?;
    let (rs, rp) = fresnel_exact(n1, n2, theta.cos(), t.cos_t);
    Some((
        rs,
        rp,
        fresnel(FresnelModel::Exact, n1, n2, theta.cos(), t.cos_t).r,
    ))
}

#[test]
fn normal_incidence_from_both_sides() {
    for (n1, n2) in IORS {
        let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
        let (rs, rp, r) = exact(n1, n2, 0.0).unwrap();
        assert!((rs - r0).abs() < 1e-15 && (rp - r0).abs() < 1e-15 && (r - r0).abs() < 1e-15);
        let t = refract(-DVec3::Y, DVec3::Y, n1 / n2).unwrap();
        assert_eq!(t.direction, -DVec3::Y);
    }
}

#[test]
fn brewster_angle_from_both_sides_has_zero_rp() {
    for (n1, n2) in IORS {
        let (rs, rp, _) = exact(n1, n2, brewster_angle(n1, n2)).unwrap();
        assert!(rp < 1e-15, "{n1}->{n2}: rp {rp}");
        assert!(rs > 0.0);
    }
}

#[test]
fn critical_angle_is_the_edge_of_total_internal_reflection() {
    for (n1, n2) in [(1.5, 1.0), (1.333, 1.0), (1.5, 1.333)] {
        let c = critical_angle(n1, n2).unwrap();
        let below = exact(n1, n2, c - 1e-9).unwrap();
        assert!(below.2 < 1.0 && below.2 > 0.99, "{below:?}");
        assert!(refract(incident(c + 1e-9), DVec3::Y, n1 / n2).is_none());
        // Exactly at the critical angle: either TIR or a grazing transmission with R = 1.
        match refract(incident(c), DVec3::Y, n1 / n2) {
            None => {}
            Some(t) => {
                assert!(t.cos_t < 1e-7 && t.direction.is_finite());
                let f = fresnel(FresnelModel::Exact, n1, n2, c.cos(), t.cos_t);
                assert!(f.r > 0.999 && f.r <= 1.0 && (f.r + f.t - 1.0).abs() < 1e-15);
            }
        }
    }
    assert_eq!(critical_angle(1.0, 1.5), None);
}

#[test]
fn grazing_incidence_reflects_everything_without_nan() {
    for (n1, n2) in IORS {
        for model in [FresnelModel::Exact, FresnelModel::Schlick] {
            let cos_t = refract(incident(std::f64::consts::FRAC_PI_2), DVec3::Y, n1 / n2)
                .map_or(0.0, |t| t.cos_t);
            let f = fresnel(model, n1, n2, 0.0, cos_t);
            assert!(
                f.r.is_finite() && (f.r - 1.0).abs() < 1e-12,
                "{model:?} {n1}->{n2}: {f:?}"
            );
        }
    }
}

#[test]
fn index_matched_interface_is_invisible() {
    for theta in [0.0, 0.3, 1.0, 1.5] {
        let d = incident(theta);
        let t = refract(d, DVec3::Y, 1.0).unwrap();
        assert!((t.direction - d).length() < 1e-15);
        let f = fresnel(FresnelModel::Exact, 1.333, 1.333, theta.cos(), t.cos_t);
        assert!(f.r < 1e-20 && (f.r + f.t - 1.0).abs() < 1e-15, "{f:?}");
    }
}

#[test]
fn cosines_rounding_above_one_stay_in_range() {
    // A direction a hair longer than unit: -n.d rounds above 1.
    let d = -DVec3::Y * (1.0 + 2.0 * f64::EPSILON);
    assert!(-d.dot(DVec3::Y) > 1.0);
    for (n1, n2) in IORS {
        let t = refract(d, DVec3::Y, n1 / n2).unwrap();
        assert!(t.cos_t <= 1.0 && t.direction.is_finite());
        for cos_i in [1.0 + f64::EPSILON, 1.0] {
            let f = fresnel(FresnelModel::Exact, n1, n2, cos_i.min(1.0), t.cos_t);
            assert!((0.0..=1.0).contains(&f.r), "{f:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Random interfaces: R in [0, 1], R + T = 1, unit directions and Snell's law.
    #[test]
    fn fresnel_and_snell_sweep(n1 in 1.0f64..3.0, n2 in 1.0f64..3.0, theta in 0.0..std::f64::consts::FRAC_PI_2, phi in 0.0..std::f64::consts::TAU) {
        let d = DVec3::new(theta.sin() * phi.cos(), -theta.cos(), theta.sin() * phi.sin());
        let r = reflect(d, DVec3::Y);
        prop_assert!((r.length() - 1.0).abs() < 1e-14);
        if let Some(t) = refract(d, DVec3::Y, n1 / n2) {
            prop_assert!((t.direction.length() - 1.0).abs() < 1e-14);
            let sin_t = t.direction.cross(DVec3::Y).length();
            prop_assert!((n1 * theta.sin() - n2 * sin_t).abs() < 1e-12);
            for model in [FresnelModel::Exact, FresnelModel::Schlick] {
                let f = fresnel(model, n1, n2, theta.cos(), t.cos_t);
                prop_assert!((0.0..=1.0).contains(&f.r) && (f.r + f.t - 1.0).abs() < 1e-15);
            }
        } else {
            prop_assert!(n1 > n2 && n1 * theta.sin() > n2 * (1.0 - 1e-12));
        }
    }

    /// Intersections do not assume unit directions: the hit point is the same.
    #[test]
    fn unnormalized_directions_hit_the_same_point(len in 1e-3f64..1e3, x in -0.1f64..0.1, y in -0.1f64..0.1) {
        let dir = DVec3::new(x, y, 1.0).normalize();
        let o = DVec3::new(0.0, 0.0, -5.0);
        for shape in [
            Shape::Sphere { center: DVec3::ZERO, radius: 1.0 },
            Shape::Triangle { vertices: [DVec3::new(-2.0, -2.0, 0.0), DVec3::new(2.0, -2.0, 0.0), DVec3::new(0.0, 2.0, 0.0)], normal: -DVec3::Z },
            Shape::Box { min: DVec3::splat(-1.0), max: DVec3::splat(1.0) },
        ] {
            let a = shape.intersect(&Ray::new(o, dir, 0.0), f64::INFINITY).unwrap();
            let b = shape.intersect(&Ray::new(o, dir * len, 0.0), f64::INFINITY).unwrap();
            let (pa, pb) = (o + dir * a.t, o + dir * len * b.t);
            prop_assert!((pa - pb).length() < 1e-12, "{shape:?}: {pa} vs {pb}");
        }
    }
}

#[test]
fn beer_law_limits_give_no_nan() {
    let c = Rgb::new(0.5, 0.0, 2.0);
    assert_eq!(beer(c, 0.0), Rgb::ONE);
    assert_eq!(beer(Rgb::ZERO, f64::INFINITY), Rgb::ONE);
    assert_eq!(beer(c, f64::INFINITY), Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(beer(Rgb::ZERO, 0.0), Rgb::ONE);
}
