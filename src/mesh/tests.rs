//! Mesh unit tests: BVH against brute force, watertightness, normals, transforms, slices.

use super::generate::icosphere;
use super::triangle::triangle_t;
use super::*;
use crate::bvh::TraversalCost;
use crate::math::Ray;

/// A tiny seeded generator (SplitMix64), so the tests need no dependency.
pub(crate) struct Rng(pub u64);

impl Rng {
    pub(crate) fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    pub(crate) fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.next_f64(), self.next_f64(), self.next_f64()) * 2.0 - 1.0;
            if let Some(u) = v.try_normalize().filter(|_| v.length_squared() <= 1.0) {
                return u;
            }
        }
    }
}

fn sphere_mesh(level: u32) -> Mesh {
    let t = Transform {
        translate: DVec3::new(0.3, -0.2, 0.1),
        rotate_deg: DVec3::new(10.0, 20.0, 30.0),
        scale: DVec3::new(1.0, 0.7, 1.3),
    };
    Mesh::new(&icosphere(level), &t.world_from_object(), MeshNormals::Flat).unwrap()
}

#[test]
fn bvh_closest_hit_equals_brute_force() {
    let mesh = sphere_mesh(4);
    let mut rng = Rng(7);
    let mut hits = 0;
    for _ in 0..2000 {
        let origin = rng.unit() * (0.2 + 2.0 * rng.next_f64());
        let ray = Ray::new(origin, rng.unit(), 0.0);
        let brute = (0..mesh.triangle_count())
            .filter_map(|i| triangle_t(&mesh.triangle(i), &ray).map(|t| (t, i)))
            .filter(|&(t, _)| t > 0.0)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let bvh = mesh.intersect(&ray, f64::INFINITY, &mut TraversalCost::default());
        assert_eq!(bvh.map(|h| h.0), brute.map(|h| h.0), "ray {ray:?}");
        hits += usize::from(bvh.is_some());
        let any = mesh.occludes(&ray, f64::INFINITY, &mut TraversalCost::default());
        assert_eq!(any, brute.is_some());
    }
    assert!(hits > 500, "{hits}");
}

#[test]
fn closed_mesh_is_watertight() {
    // Every line through the inside crosses the surface an even, non-zero number of times.
    let mesh = sphere_mesh(5);
    let mut rng = Rng(11);
    for _ in 0..5000 {
        let inside = rng.unit() * 0.6 * rng.next_f64() + DVec3::new(0.3, -0.2, 0.1);
        let ray = Ray::new(inside, rng.unit(), 0.0);
        let n = mesh.crossings(&ray, &mut TraversalCost::default()).len();
        assert!(n >= 2 && n.is_multiple_of(2), "{n} crossings for {ray:?}");
        assert!(
            mesh.intersect(&ray, f64::INFINITY, &mut TraversalCost::default())
                .is_some()
        );
    }
}

#[test]
fn cost_grows_slowly_with_triangle_count() {
    let ray = Ray::new(DVec3::new(0.01, 0.02, -5.0), DVec3::Z, 0.0);
    let cost = |level| {
        let mut c = TraversalCost::default();
        sphere_mesh(level)
            .intersect(&ray, f64::INFINITY, &mut c)
            .unwrap();
        c.total()
    };
    let (small, large) = (cost(2), cost(6));
    // 256x the triangles; a linear scan would test 256x as many.
    assert!(large < 8 * small, "{small} -> {large}");
}

#[test]
fn outward_normals_and_mirroring() {
    for scale in [DVec3::ONE, DVec3::new(-1.0, 1.0, 1.0)] {
        let t = Transform {
            scale,
            ..Transform::default()
        };
        for normals in [MeshNormals::Flat, MeshNormals::Smooth] {
            let m = Mesh::new(&icosphere(2), &t.world_from_object(), normals).unwrap();
            for i in 0..m.triangle_count() {
                let [a, b, c] = m.triangle(i);
                let centre = (a + b + c) / 3.0;
                assert!(
                    m.geometric_normal(i).dot(centre) > 0.0,
                    "{scale} {normals:?}"
                );
                if let Some(ns) = m.shading_normal(i, centre) {
                    assert!((ns - centre.normalize()).length() < 0.05);
                }
            }
        }
    }
}

#[test]
fn file_normals_decide_the_winding() {
    // One triangle wound clockwise seen from +z, with normals pointing to +z.
    let data = MeshData {
        positions: vec![DVec3::ZERO, DVec3::Y, DVec3::X],
        normals: vec![DVec3::Z],
        faces: vec![Face {
            vertices: [0, 1, 2],
            normals: Some([0, 0, 0]),
        }],
    };
    let m = Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::File).unwrap();
    assert_eq!(m.geometric_normal(0), DVec3::Z);
    let flat = Mesh::new(&data, &DAffine3::IDENTITY, MeshNormals::Flat).unwrap();
    assert_eq!(flat.geometric_normal(0), -DVec3::Z);
    assert_eq!(flat.shading_normal(0, DVec3::splat(0.2)), None);
}

#[test]
fn slice_of_a_sphere_is_a_closed_loop_on_the_sphere() {
    let m = Mesh::new(&icosphere(3), &DAffine3::IDENTITY, MeshNormals::Flat).unwrap();
    let segs = m.slice(DVec3::new(0.0, 0.25, 0.0), DVec3::Y);
    assert!(segs.len() > 20);
    let r = (1.0f64 - 0.25 * 0.25).sqrt();
    let mut ends = Vec::new();
    for [a, b] in &segs {
        for p in [a, b] {
            assert!((p.y - 0.25).abs() < 1e-12);
            let rho = (p.x * p.x + p.z * p.z).sqrt();
            assert!(rho <= r + 1e-12 && rho > 0.95 * r, "{rho}");
            ends.push(*p);
        }
    }
    // Closed: every end point is shared by exactly two segments.
    for p in &ends {
        let n = ends.iter().filter(|q| (**q - *p).length() < 1e-12).count();
        assert_eq!(n, 2, "{p}");
    }
    assert!(m.slice(DVec3::new(0.0, 2.0, 0.0), DVec3::Y).is_empty());
}

#[test]
fn segment_inside_gives_chords() {
    let m = Mesh::new(&icosphere(4), &DAffine3::IDENTITY, MeshNormals::Flat).unwrap();
    let ray = Ray::new(DVec3::new(0.0, 0.0, -3.0), DVec3::Z, 0.0);
    let mut c = TraversalCost::default();
    let (t, chord) = m.segment_inside(&ray, 10.0, &mut c).unwrap();
    assert!(
        (t - 2.0).abs() < 0.01 && (chord - 2.0).abs() < 0.02,
        "{t} {chord}"
    );
    // Starting inside: the chord runs from t_min to the exit.
    let ray = Ray::new(DVec3::ZERO, DVec3::Z, 0.0);
    let (t, chord) = m.segment_inside(&ray, 10.0, &mut c).unwrap();
    assert_eq!(t, 0.0);
    assert!((chord - 1.0).abs() < 0.01);
    assert!(
        m.segment_inside(&ray, 0.5, &mut c)
            .is_some_and(|(_, l)| l == 0.5)
    );
    let away = Ray::new(DVec3::new(0.0, 0.0, 3.0), DVec3::Z, 0.0);
    assert_eq!(m.segment_inside(&away, 10.0, &mut c), None);
}
