//! The thin lens ([`Film::lens_ray`]): it focuses on the plane at `focus_distance`, and points
//! off that plane spread over the circle of confusion.

use super::{Camera, Scene};
use glam::{DVec2, DVec3};

fn camera(aperture_radius: f64, focus_distance: f64) -> Camera {
    let mut c = Scene::default_scene().camera.with_size(320, 180);
    c.aperture_radius = aperture_radius;
    c.focus_distance = focus_distance;
    c
}

/// Lens samples over the square (interior, edges and the centre), through the concentric map.
fn lens_samples() -> Vec<DVec2> {
    let mut v = Vec::new();
    for i in 0..=16 {
        for j in 0..=16 {
            let u = DVec2::new(f64::from(i) / 16.0, f64::from(j) / 16.0);
            v.push(u.min(DVec2::splat(1.0 - f64::EPSILON / 2.0)));
        }
    }
    v
}

/// The film position at which point `p` is seen through the lens point of sample `u`: the ray
/// from the lens point through `p` meets the focus plane at `q`, and `q` is on the pinhole ray
/// of that film position (similar triangles). Checked against [`Film::lens_ray`] by the caller.
fn project(c: &Camera, p: DVec3, u: DVec2) -> (f64, f64) {
    let lens = c.aperture_radius * crate::sampling::warp::square_to_concentric_disk(u);
    let on_lens = lens.x * c.right + lens.y * c.up;
    let d = p - c.position - on_lens;
    let q = on_lens + d * (c.focus_distance / d.dot(c.forward));
    let (pu, pv) = (
        q.dot(c.right) / c.focus_distance,
        q.dot(c.up) / c.focus_distance,
    );
    let half_h = (c.fov_y.to_radians() * 0.5).tan();
    let half_w = half_h * f64::from(c.width) / f64::from(c.height);
    (
        (pu / half_w + 1.0) * 0.5 * f64::from(c.width),
        (1.0 - pv / half_h) * 0.5 * f64::from(c.height),
    )
}

/// Distance from `p` to the line of `ray`.
fn miss(ray: &crate::math::Ray, p: DVec3) -> f64 {
    let d = p - ray.origin;
    (d - d.dot(ray.direction) * ray.direction).length()
}

/// The ray of film position `(fx, fy)` and lens sample `u` passes through the focus-plane point
/// of the pinhole ray of `(fx, fy)`, for every lens sample: that point is in focus.
#[test]
fn every_lens_sample_of_a_film_position_meets_on_the_focus_plane() {
    let c = camera(0.2, 6.5);
    let film = c.film();
    for (fx, fy) in [(160.0, 90.0), (0.25, 3.5), (319.9, 179.1), (40.5, 150.25)] {
        let pin = film.ray(fx, fy);
        let focus_point =
            c.position + pin.direction * (c.focus_distance / pin.direction.dot(c.forward));
        for u in lens_samples() {
            let r = film.lens_ray(fx, fy, u);
            assert!((r.direction.length() - 1.0).abs() < 1e-15);
            // The origin is on the lens disk, in the plane through the eye.
            let o = r.origin - c.position;
            assert!(o.dot(c.forward).abs() < 1e-15 && o.length() <= 0.2 * (1.0 + 1e-15));
            assert!(
                miss(&r, focus_point) < 1e-12,
                "({fx}, {fy}) {u}: {}",
                miss(&r, focus_point)
            );
        }
    }
}

/// A point on the focus plane projects to the same film position (so the same pixel) from every
/// lens sample; the lens ray of that position and sample passes through the point.
#[test]
fn a_point_on_the_focus_plane_projects_to_one_film_position() {
    let c = camera(0.3, 5.0);
    let film = c.film();
    for (a, b) in [(0.0, 0.0), (1.3, -0.4), (-2.0, 0.9)] {
        let p = c.position + 5.0 * c.forward + a * c.right + b * c.up;
        let centre = project(&c, p, DVec2::splat(0.5));
        for u in lens_samples() {
            let (fx, fy) = project(&c, p, u);
            assert!(
                (fx - centre.0).abs() < 1e-9 && (fy - centre.1).abs() < 1e-9,
                "{u}"
            );
            assert!(miss(&film.lens_ray(fx, fy, u), p) < 1e-12);
        }
    }
}

/// A point at depth `z` off the focus plane `f` is seen at film positions offset from its
/// lens-centre position by `lens * (1/f - 1/z) * height / (2 tan(fov/2))` pixels: over the
/// lens disk of radius `A` a circle of confusion of diameter `2 A |1/f - 1/z|` on the image
/// plane at distance 1 (the thin-lens circle of confusion by similar triangles; pbrt-v4
/// section 5.2.3, Potmesil and Chakravarty 1981).
#[test]
fn points_off_the_focus_plane_spread_by_the_circle_of_confusion() {
    let (a, f) = (0.25, 5.0);
    let c = camera(a, f);
    let film = c.film();
    let px_per_unit = f64::from(c.height) / (2.0 * (c.fov_y.to_radians() * 0.5).tan());
    for z in [2.0, 4.0, 5.0, 7.5, 40.0] {
        let p = c.position + z * c.forward + 0.3 * z * c.right - 0.1 * z * c.up;
        let centre = project(&c, p, DVec2::splat(0.5));
        let mut widest: f64 = 0.0;
        for u in lens_samples() {
            let (fx, fy) = project(&c, p, u);
            // The projection is right: the thin lens's own ray passes through p.
            assert!(miss(&film.lens_ray(fx, fy, u), p) < 1e-9 * z);
            let lens = crate::sampling::warp::square_to_concentric_disk(u);
            let want = a * lens.length() * (1.0 / f - 1.0 / z).abs() * px_per_unit;
            let got = (fx - centre.0).hypot(fy - centre.1);
            assert!((got - want).abs() < 1e-9, "z {z} u {u}: {got} vs {want}");
            widest = widest.max(got);
        }
        // The rim samples reach the formula's radius: the diameter is 2 A |1/f - 1/z|.
        let coc = 2.0 * a * (1.0 / f - 1.0 / z).abs() * px_per_unit;
        assert!(
            (2.0 * widest - coc).abs() < 1e-9 * coc.max(1.0),
            "z {z}: {widest} {coc}"
        );
        if z == f {
            assert!(widest < 1e-9);
        }
    }
}

/// Aperture 0 is the pinhole: the lens ray equals the pinhole ray bit for bit.
#[test]
fn a_zero_aperture_lens_ray_is_the_pinhole_ray() {
    let c = camera(0.0, 3.0);
    let film = c.film();
    assert!(!film.has_lens());
    for (fx, fy) in [(160.0, 90.0), (0.25, 3.5), (319.9, 179.1)] {
        let pin = film.ray(fx, fy);
        for u in lens_samples() {
            let r = film.lens_ray(fx, fy, u);
            assert_eq!(r.origin, pin.origin);
            // The focus point is the pinhole direction scaled, so the direction may differ in
            // the last bit after normalisation; the render never calls lens_ray at aperture 0.
            assert!((r.direction - pin.direction).length() < 1e-15);
        }
    }
}
