//! A mesh as an area light (issue 14: "quads and triangles (and mesh triangles) uniformly by
//! area converted to solid angle"): a triangle is chosen in proportion to its area from the
//! cumulative areas stored with the mesh ([`Mesh::pick_triangle`]), then a point uniform in it,
//! so the point is uniform over the whole mesh's area `A` and its solid-angle pdf is
//! `d^2 / (cos_light A)` (pbrt-v4 section 6.5.3 samples one triangle uniformly by area; choosing
//! the triangle by area first is Mitsuba 3's `Mesh::sample_position` with its area
//! distribution). Emission leaves each triangle's outer side (its winding, as for a lone
//! `triangle`).

use super::{LightSample, PlanarEmitter};
use crate::bvh::TraversalCost;
use crate::math::{Ray, Rgb};
use crate::mesh::Mesh;
use glam::{DVec2, DVec3};

/// The triangle `u.x` picks as a planar emitter, its area, the mesh's area and the rescaled `u`.
fn pick(m: &Mesh, u: DVec2) -> Option<(PlanarEmitter, f64, f64, DVec2)> {
    let ([v0, v1, v2], a, total, u) = m.pick_triangle(u)?;
    Some((PlanarEmitter::triangle(v0, v1, v2), a, total, u))
}

/// A direction from `p` to a point uniform over the mesh's area (`u.x` picks the triangle by
/// area and is rescaled into the triangle's own sample), its pdf in solid angle over the whole
/// mesh; `None` when the chosen triangle turns its back on `p` (that sample carries nothing;
/// the estimator stays unbiased).
#[must_use]
pub fn sample(m: &Mesh, p: DVec3, radiance: Rgb, u: DVec2) -> Option<LightSample> {
    let (e, a, total, u) = pick(m, u)?;
    let s = e.sample(p, radiance, u)?;
    // The triangle's pdf d^2 / (cos a) times the chance a / A of having chosen it.
    Some(LightSample {
        pdf: s.pdf * (a / total),
        ..s
    })
}

/// A point uniform over the mesh's area and the outward (geometric) normal of its triangle:
/// `u.x` picks the triangle by area as [`sample`] does and is rescaled into the triangle's own
/// sample. `None` for a mesh of no area.
#[must_use]
pub fn sample_point(m: &Mesh, u: DVec2) -> Option<(DVec3, DVec3)> {
    let (e, _, _, u) = pick(m, u)?;
    Some((e.sample_point(u), e.normal()?))
}

/// The solid-angle pdf of [`sample`] for direction `wi` from `p`: where the ray from `p` first
/// meets the mesh, `d^2 / (cos_light A)` if it meets a triangle's outer side, else 0.
#[must_use]
pub fn pdf(m: &Mesh, p: DVec3, wi: DVec3) -> f64 {
    let total = m.area();
    let ray = Ray::new(p, wi, 0.0);
    let mut cost = TraversalCost::default();
    let Some((t, i)) = m.intersect(&ray, f64::INFINITY, &mut cost) else {
        return 0.0;
    };
    let n = m.geometric_normal(i);
    let cos_light = -wi.dot(n);
    if cos_light <= 0.0 || total <= 0.0 {
        return 0.0;
    }
    t * t / (cos_light * total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::mesh::{MeshNormals, obj::parse_obj};
    use crate::sampling::SplitMix64;
    use crate::sampling::chi2::test_directions;
    use glam::DAffine3;

    /// Three triangles of unequal areas and orientations turning their outer side to the test
    /// point (0.1, 0, 0.2) below them, and one (the last) turning its back on it; seen from
    /// the point none hides another.
    const OBJ: &str = "v -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\nv 2 1.5 -1\nv 2 1.5 1\n\
                       v -2 3 0\nv -3 2 1\nv -2 2 -2\n\
                       f 1 2 3\nf 1 3 4\nf 2 5 6\nf 7 9 8\n";

    fn mesh() -> Mesh {
        let data = parse_obj(OBJ).unwrap();
        Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::Flat).unwrap()
    }

    /// The irradiance at `(p, n)` from a uniform triangle of radiance `l` (Lambert's formula,
    /// [`crate::lights::polygon_irradiance`]); 0 when it turns its back on `p`.
    fn lambert_triangle(p: DVec3, n: DVec3, [a, b, c]: [DVec3; 3], l: f64) -> f64 {
        if (p - a).dot((b - a).cross(c - a)) <= 0.0 {
            return 0.0;
        }
        crate::lights::polygon_irradiance(p, n, &[a, b, c], l)
    }

    #[test]
    fn irradiance_is_the_sum_of_lamberts_formula_over_the_front_triangles() {
        let m = mesh();
        let (p, n) = (DVec3::new(0.1, 0.0, 0.2), DVec3::Y);
        let l = 1.5;
        let exact: f64 = (0..m.triangle_count())
            .map(|i| lambert_triangle(p, n, m.triangle(i), l))
            .sum();
        let mut rng = SplitMix64::new(77);
        let (mut s, mut s2, k) = (0.0, 0.0, 400_000);
        for _ in 0..k {
            let e = sample(&m, p, Rgb::splat(l), rng.next_2d())
                .map_or(0.0, |ls| ls.weight().x * ls.direction.dot(n).max(0.0));
            s += e;
            s2 += e * e;
        }
        let mean = s / f64::from(k);
        let se = ((s2 / f64::from(k) - mean * mean) / f64::from(k)).sqrt();
        assert!(exact > 0.1 && se < 0.01 * exact, "{exact} {se}");
        assert!(
            (mean - exact).abs() <= 5.0 * se,
            "{mean} +- {se} vs {exact}"
        );
    }

    #[test]
    fn samples_match_the_solid_angle_pdf() {
        let m = mesh();
        let p = DVec3::new(0.1, 0.0, 0.2);
        let r = test_directions(
            (-1.0, 1.0),
            4242,
            |rng| sample(&m, p, Rgb::ONE, rng.next_2d()).map(|ls| ls.direction),
            |w| pdf(&m, p, w),
        );
        r.assert_passes("mesh emitter");
        // The area pdf (1 / A) taken as a solid-angle pdf is rejected.
        let wrong = test_directions(
            (-1.0, 1.0),
            4243,
            |rng| sample(&m, p, Rgb::ONE, rng.next_2d()).map(|ls| ls.direction),
            |w| {
                if pdf(&m, p, w) > 0.0 {
                    1.0 / m.area()
                } else {
                    0.0
                }
            },
        );
        assert!(!wrong.passes(), "{wrong:?}");
    }

    #[test]
    fn samples_land_on_the_mesh_at_their_pdf_and_back_sides_emit_nothing() {
        let m = mesh();
        let p = DVec3::new(0.1, 0.0, 0.2);
        let mut rng = SplitMix64::new(5);
        let mut none = 0;
        for _ in 0..2000 {
            match sample(&m, p, Rgb::ONE, rng.next_2d()) {
                Some(ls) => {
                    let pdf = pdf(&m, p, ls.direction);
                    assert!((pdf / ls.pdf - 1.0).abs() < 1e-9, "{pdf} {}", ls.pdf);
                    let hit = m.intersect(
                        &Ray::new(p, ls.direction, 0.0),
                        f64::INFINITY,
                        &mut TraversalCost::default(),
                    );
                    assert!((hit.unwrap().0 / ls.distance - 1.0).abs() < 1e-9);
                }
                None => none += 1,
            }
        }
        // The back-facing triangle holds this share of the area; its samples carry nothing.
        let back: f64 = (0..m.triangle_count())
            .map(|i| m.triangle(i))
            .filter(|&[a, b, c]| (p - a).dot((b - a).cross(c - a)) <= 0.0)
            .map(|[a, b, c]| 0.5 * (b - a).cross(c - a).length() / m.area())
            .sum();
        assert!(back > 0.1, "{back}");
        let share = f64::from(none) / 2000.0;
        assert!(
            (share - back).abs() < 5.0 * (back * (1.0 - back) / 2000.0).sqrt(),
            "{share} {back}"
        );
        // Seen from above, every triangle but the last turns its back.
        let q = DVec3::new(0.0, 10.0, 0.0);
        assert_eq!(pdf(&m, q, DVec3::NEG_Y), 0.0);
    }
}
