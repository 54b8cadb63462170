use super::*;
use crate::formats::xform::Xf;

fn surface() -> Surface {
    Surface {
        material: "m".into(),
        name: None,
        flip: false,
    }
}

#[test]
fn materials_are_named_uniquely_and_shared_when_equal() {
    let mut b = Builder::new(100);
    let a = b.material("x", crate::formats::material_map::diffuse([0.5; 3]));
    let same = b.material("x", crate::formats::material_map::diffuse([0.5; 3]));
    let other = b.material("x", crate::formats::material_map::diffuse([0.2; 3]));
    assert_eq!(
        (a.as_str(), same.as_str(), other.as_str()),
        ("x", "x", "x#2")
    );
}

#[test]
fn spheres_survive_similarities_and_mirrors_flip_quads_back() {
    let mut b = Builder::new(100_000);
    let r = Xf::rotate(30.0, DVec3::new(1.0, 2.0, 3.0)).unwrap();
    let s = Xf::scale(DVec3::new(-2.0, 2.0, 2.0)).unwrap();
    let m = r.then(&s).affine().unwrap();
    b.sphere(DVec3::ZERO, 1.5, &m, &surface()).unwrap();
    assert!(
        matches!(b.objects[0], ObjectDesc::Sphere { radius, .. } if (radius - 3.0).abs() < 1e-12)
    );
    // Mirror x: the object-space +z normal stays +z; the quad's edges are swapped to keep it.
    let mirror = Xf::scale(DVec3::new(-1.0, 1.0, 1.0))
        .unwrap()
        .affine()
        .unwrap();
    b.quad(DVec3::ZERO, DVec3::X, DVec3::Y, &mirror, &surface());
    let ObjectDesc::Quad { edge_u, edge_v, .. } = b.objects[1] else {
        panic!()
    };
    assert!(DVec3::from(edge_u).cross(DVec3::from(edge_v)).z > 0.0);
    assert!(b.sphere(DVec3::ZERO, -1.0, &m, &surface()).is_err());
}

#[test]
fn the_vertex_limit_is_enforced() {
    let mut b = Builder::new(5);
    let (p, t) = box_triangles(DVec3::ZERO, DVec3::ONE);
    let e = b
        .mesh(&p, &t, None, &DAffine3::IDENTITY, &surface())
        .unwrap_err();
    assert!(e.contains("limit"), "{e}");
}

#[test]
fn recognition_only_takes_exact_quads_and_boxes() {
    let mut b = Builder::new(1000);
    // Not a parallelogram: stays a mesh.
    let p = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.5, 0.0), DVec3::Y];
    b.mesh(
        &p,
        &[[0, 1, 2], [0, 2, 3]],
        None,
        &DAffine3::IDENTITY,
        &surface(),
    )
    .unwrap();
    assert!(matches!(b.objects[0], ObjectDesc::Trimesh { .. }));
    // A box with one face wound inward stays a mesh.
    let (p, mut t) = box_triangles(DVec3::ZERO, DVec3::ONE);
    t[0].swap(1, 2);
    b.mesh(&p, &t, None, &DAffine3::IDENTITY, &surface())
        .unwrap();
    assert!(matches!(b.objects[1], ObjectDesc::Trimesh { .. }));
}

#[test]
fn disks_and_normals() {
    let (p, t) = disk_triangles(1.0, 0.0, 0.0);
    let area: f64 = t
        .iter()
        .map(|&[a, b, c]| {
            0.5 * (p[b as usize] - p[a as usize])
                .cross(p[c as usize] - p[a as usize])
                .z
        })
        .sum();
    let n = f64::from(DISK_SEGMENTS);
    let want = 0.5 * n * (std::f64::consts::TAU / n).sin();
    assert!((area - want).abs() < 1e-12 && area > 0.0, "{area}");
    // The angle-weighted normals of a closed box point along the corner diagonals.
    let (p, t) = box_triangles(-DVec3::ONE, DVec3::ONE);
    let ns = vertex_normals(&p, &t);
    for (v, n) in p.iter().zip(&ns) {
        assert!(n.abs_diff_eq(v.normalize(), 1e-12), "{v} {n}");
    }
}
