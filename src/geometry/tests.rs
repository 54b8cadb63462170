//! Shape unit tests: sphere hits from outside and inside (and a tiny sphere far away), the plane
//! and its half-space, triangle hit and miss, box faces.

use super::*;

fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
    Ray::new(DVec3::from(o), DVec3::from(d).normalize(), 0.0)
}

#[test]
fn sphere_front_and_back() {
    let s = Shape::Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    };
    let h = s
        .intersect(&ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), f64::INFINITY)
        .unwrap();
    assert_eq!(h.t, 4.0);
    assert_eq!(h.normal, -DVec3::Z);
    let h = s
        .intersect(&ray([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), f64::INFINITY)
        .unwrap();
    assert_eq!(h.t, 1.0);
    assert_eq!(h.normal, DVec3::Z);
    assert!(
        s.intersect(&ray([0.0, 2.0, -5.0], [0.0, 0.0, 1.0]), f64::INFINITY)
            .is_none()
    );
}

#[test]
fn tiny_sphere_far_away_is_precise() {
    let center = DVec3::new(1e5, 0.0, 0.0);
    let s = Shape::Sphere {
        center,
        radius: 1e-3,
    };
    let h = s
        .intersect(&ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
        .unwrap();
    assert!((h.t - (1e5 - 1e-3)).abs() < 1e-9, "{}", h.t);
}

#[test]
fn plane_and_half_space() {
    let p = Shape::Plane {
        point: DVec3::ZERO,
        normal: DVec3::Y,
    };
    let r = ray([0.0, 2.0, 0.0], [0.0, -1.0, 0.0]);
    assert_eq!(p.intersect(&r, f64::INFINITY).unwrap().t, 2.0);
    assert_eq!(p.inside_interval(&r), Some((2.0, f64::INFINITY)));
}

#[test]
fn triangle_hit_and_miss() {
    let v = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let t = Shape::Triangle {
        vertices: v,
        normal: DVec3::Z,
    };
    assert_eq!(
        t.intersect(&ray([0.2, 0.2, 1.0], [0.0, 0.0, -1.0]), f64::INFINITY)
            .unwrap()
            .t,
        1.0
    );
    assert!(
        t.intersect(&ray([0.8, 0.8, 1.0], [0.0, 0.0, -1.0]), f64::INFINITY)
            .is_none()
    );
}

#[test]
fn box_faces() {
    let b = Shape::Box {
        min: DVec3::splat(-1.0),
        max: DVec3::splat(1.0),
    };
    let h = b
        .intersect(&ray([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]), f64::INFINITY)
        .unwrap();
    assert_eq!((h.t, h.normal), (4.0, DVec3::Y));
    let h = b
        .intersect(&ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
        .unwrap();
    assert_eq!((h.t, h.normal), (1.0, DVec3::X));
    // Axis-parallel ray on no face plane.
    assert!(
        b.intersect(&ray([0.0, 2.0, 0.0], [1.0, 0.0, 0.0]), f64::INFINITY)
            .is_none()
    );
}
