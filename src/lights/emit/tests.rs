//! `sample_le` / `pdf_le` (issue 28/30): chi-square of origins and directions against their
//! densities, the densities `pdf_le` gives back, and flux = the integral of emitted radiance.

use super::*;
use crate::lights::PlanarEmitter;
use crate::mesh::{Mesh, MeshNormals, obj::parse_obj};
use crate::sampling::SplitMix64;
use crate::sampling::chi2::{test_directions, test_plane};
use glam::DAffine3;

fn quad() -> Light<'static> {
    Light::Area {
        object: 0,
        shape: AreaShape::planar(PlanarEmitter::quad(
            DVec3::new(-1.0, 2.0, -0.5),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.5),
        )),
        emission: Rgb::new(1.0, 2.0, 3.0),
    }
}

/// `w` in the frame whose z axis is `n` (the frame `sample_le` uses).
fn local(w: DVec3, n: DVec3) -> DVec3 {
    let (t, b) = orthonormal_basis(n);
    DVec3::new(w.dot(t), w.dot(b), w.dot(n))
}

fn draw(e: &Light<'_>, rng: &mut SplitMix64) -> Option<EmittedRay> {
    let (a, b) = (rng.next_2d(), rng.next_2d());
    e.sample_le(a, b)
}

#[test]
fn a_point_light_emits_uniformly_over_the_sphere() {
    let e = Light::Point {
        position: DVec3::new(0.5, 1.0, -2.0),
        intensity: Rgb::splat(3.0),
        spot: None,
    };
    test_directions(
        (-1.0, 1.0),
        1,
        |rng| draw(&e, rng).map(|r| r.direction),
        |_| 1.0 / (4.0 * PI),
    )
    .assert_passes("point light directions");
    let r = e
        .sample_le(DVec2::splat(0.3), DVec2::new(0.2, 0.9))
        .unwrap();
    assert!((r.weight().x - 4.0 * PI * 3.0).abs() < 1e-12, "flux 4 pi I");
    assert_eq!(
        e.pdf_le(r.origin, None, r.direction),
        (r.pdf_pos, r.pdf_dir)
    );
    assert!(r.delta_pos && !r.delta_dir);
}

#[test]
fn an_area_light_emits_uniformly_by_area_and_by_cosine_in_direction() {
    let e = quad();
    let (corner, eu, ev) = (
        DVec3::new(-1.0, 2.0, -0.5),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 1.5),
    );
    let n = eu.cross(ev).normalize();
    // Origins in the quad's (s, t) coordinates: uniform, density 1 there.
    test_plane(
        (DVec2::ZERO, DVec2::ONE),
        2,
        |rng| {
            draw(&e, rng).map(|r| {
                let d = r.origin - corner;
                DVec2::new(
                    d.dot(eu) / eu.length_squared(),
                    d.dot(ev) / ev.length_squared(),
                )
            })
        },
        |_| 1.0,
    )
    .assert_passes("quad origins");
    test_directions(
        (0.0, 1.0),
        3,
        |rng| draw(&e, rng).map(|r| local(r.direction, n)),
        |w| w.z.max(0.0) / PI,
    )
    .assert_passes("quad directions");
    let mut rng = SplitMix64::new(4);
    for _ in 0..1000 {
        let r = draw(&e, &mut rng).unwrap();
        let flux = PI * 3.0 * Rgb::new(1.0, 2.0, 3.0);
        assert!(
            (r.weight() - flux).abs().max_element() < 1e-9,
            "flux pi A L"
        );
        assert_eq!(
            e.pdf_le(r.origin, None, r.direction),
            (r.pdf_pos, r.pdf_dir)
        );
        assert_eq!(e.pdf_le(r.origin, None, -r.direction), (0.0, 0.0), "behind");
        assert!(r.direction.dot(n) > 0.0);
    }
}

#[test]
fn a_sphere_light_emits_from_its_whole_surface_outwards() {
    let center = DVec3::new(0.0, 1.0, 0.0);
    let e = Light::Area {
        object: 0,
        shape: AreaShape::Sphere {
            center,
            radius: 0.5,
        },
        emission: Rgb::ONE,
    };
    test_directions(
        (-1.0, 1.0),
        5,
        |rng| draw(&e, rng).map(|r| (r.origin - center).normalize()),
        |_| 1.0 / (4.0 * PI),
    )
    .assert_passes("sphere origins");
    test_directions(
        (0.0, 1.0),
        6,
        |rng| draw(&e, rng).map(|r| local(r.direction, r.normal.unwrap())),
        |w| w.z.max(0.0) / PI,
    )
    .assert_passes("sphere directions about the normal");
    let r = e
        .sample_le(DVec2::new(0.1, 0.7), DVec2::new(0.4, 0.4))
        .unwrap();
    assert!(
        (r.weight().x - PI * PI).abs() < 1e-9,
        "pi (4 pi r^2) L with r = 1/2"
    );
    let (pp, pd) = e.pdf_le(r.origin, None, r.direction);
    assert!((pp - r.pdf_pos).abs() < 1e-12 && (pd - r.pdf_dir).abs() < 1e-12);
}

#[test]
fn a_directional_light_emits_from_a_disc_across_the_scene() {
    let direction = DVec3::new(0.3, -1.0, 0.2).normalize();
    let (center, radius) = (DVec3::new(1.0, 0.0, -1.0), 2.0);
    let e = Light::Directional {
        direction,
        irradiance: Rgb::splat(5.0),
        center,
        radius,
    };
    let (t, b) = orthonormal_basis(direction);
    test_plane(
        (DVec2::splat(-radius), DVec2::splat(radius)),
        7,
        |rng| {
            draw(&e, rng).map(|r| {
                let d = r.origin - (center - radius * direction);
                assert!(d.dot(direction).abs() < 1e-9, "on the disc's plane");
                DVec2::new(d.dot(t), d.dot(b))
            })
        },
        |p| {
            if p.length() <= radius {
                1.0 / (PI * radius * radius)
            } else {
                0.0
            }
        },
    )
    .assert_passes("directional origins");
    let r = e.sample_le(DVec2::splat(0.6), DVec2::ZERO).unwrap();
    assert_eq!(r.direction, direction);
    assert!(
        (r.weight().x - 5.0 * PI * radius * radius).abs() < 1e-9,
        "flux pi R^2 E"
    );
}

#[test]
fn a_mesh_light_emits_uniformly_over_its_area() {
    // Two triangles in the plane y = 2 facing down, of areas 2 and 1.
    let obj = "v 0 2 0\nv 0 2 2\nv 2 2 0\nv 2 2 2\nv 3 2 2\nf 1 3 2\nf 3 5 4\n";
    let data = parse_obj(obj).unwrap();
    let m = Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::Flat).unwrap();
    let area = m.area();
    assert!((area - 3.0).abs() < 1e-12);
    let e = Light::Area {
        object: 0,
        shape: AreaShape::Mesh(&m),
        emission: Rgb::splat(2.0),
    };
    let inside = |p: DVec2| {
        let t1 = p.x >= 0.0 && p.y >= 0.0 && p.x + p.y <= 2.0;
        let t2 = p.x >= 2.0 && p.x <= 3.0 && p.y >= 2.0 * (p.x - 2.0) && p.y <= 2.0;
        t1 || t2
    };
    test_plane(
        (DVec2::ZERO, DVec2::new(3.0, 2.0)),
        8,
        |rng| draw(&e, rng).map(|r| DVec2::new(r.origin.x, r.origin.z)),
        |p| if inside(p) { 1.0 / area } else { 0.0 },
    )
    .assert_passes("mesh origins");
    let mut rng = SplitMix64::new(9);
    for _ in 0..200 {
        let r = draw(&e, &mut rng).unwrap();
        assert!(r.direction.y < 0.0, "emits from the outer side");
        assert!((r.weight().x - PI * area * 2.0).abs() < 1e-9);
        assert_eq!(
            e.pdf_le(r.origin, r.normal, r.direction),
            (r.pdf_pos, r.pdf_dir)
        );
    }
}

/// The flux by an estimator independent of `sample_le`'s: uniform origins and uniform
/// hemisphere directions, `L cos / (p_A p_w)` averaged, against `pi A L`.
#[test]
fn the_flux_is_the_integral_of_emitted_radiance() {
    let mut rng = SplitMix64::new(10);
    let n = DVec3::new(0.0, -1.0, 0.0);
    let (a, l, count) = (3.0, 2.0, 200_000);
    let mut sum = 0.0;
    let mut sq = 0.0;
    for _ in 0..count {
        let u = rng.next_2d();
        let z = u.x;
        let w = crate::sampling::chi2::direction(z, 2.0 * PI * u.y);
        let cos = local(w, n).z.abs();
        let v = l * cos * a * (2.0 * PI);
        sum += v;
        sq += v * v;
    }
    let mean = sum / f64::from(count);
    let se = ((sq / f64::from(count) - mean * mean) / f64::from(count)).sqrt();
    let flux = PI * a * l;
    assert!((mean - flux).abs() < 4.0 * se, "{mean} vs {flux} (se {se})");
    let r = quad()
        .sample_le(DVec2::splat(0.5), DVec2::splat(0.5))
        .unwrap();
    assert!(
        (r.weight().x - flux / l * 1.0).abs() < 1e-9,
        "sample_le's weight is pi A L"
    );
}

/// A spot light emits only inside its cone, uniformly there; its rays' mean weight is its flux
/// `I * solid_angle` (what `power` weighs it by), `pdf_le` gives back the sample's densities,
/// and `sample_li` delivers `I falloff / r^2` inside the cone and nothing outside it.
#[test]
fn a_spot_light_emits_its_falloff_inside_its_cone() {
    use crate::lights::{Spot, SpotProfile};
    let cone = Spot {
        axis: DVec3::new(0.0, -1.0, 0.5).normalize(),
        cone: 35f64.to_radians(),
        falloff: 15f64.to_radians(),
        profile: SpotProfile::Smoothstep,
    };
    let position = DVec3::new(0.5, 3.0, -2.0);
    let e = Light::Point {
        position,
        intensity: Rgb::new(2.0, 3.0, 4.0),
        spot: Some(cone),
    };
    let mut rng = SplitMix64::new(11);
    let n = 200_000;
    let mut sum = 0.0;
    let mut sq = 0.0;
    for _ in 0..n {
        let r = draw(&e, &mut rng).unwrap();
        assert!(r.direction.dot(cone.axis) >= cone.cone.cos() - 1e-12);
        assert_eq!(
            e.pdf_le(r.origin, None, r.direction),
            (r.pdf_pos, r.pdf_dir)
        );
        assert!(r.delta_pos && !r.delta_dir && r.origin == position);
        let w = (r.weight().x + r.weight().y + r.weight().z) / 3.0;
        sum += w;
        sq += w * w;
    }
    let mean = sum / f64::from(n);
    let se = ((sq / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
    let power = e.power();
    assert!((power - 3.0 * cone.solid_angle()).abs() < 1e-12 * power);
    assert!(
        (mean - power).abs() < 5.0 * se,
        "flux {mean} +- {se} vs {power}"
    );
    assert_eq!(e.pdf_le(position, None, -cone.axis), (1.0, 0.0));
    // Towards a point on the axis: the full intensity over r^2; outside the cone: nothing.
    let below = position + 2.0 * cone.axis;
    let ls = e.sample_li(below, (0.5, 0.5)).unwrap();
    assert!(
        (ls.radiance - Rgb::new(2.0, 3.0, 4.0) / 4.0)
            .abs()
            .max_element()
            < 1e-12
    );
    assert!(
        e.sample_li(position - 2.0 * cone.axis, (0.5, 0.5))
            .is_none()
    );
}
