//! Generated meshes for tests and benchmarks.

use super::{Face, MeshData};
use crate::Scene;
use glam::DVec3;
use std::collections::HashMap;

/// A unit icosphere at the origin: an icosahedron whose faces are split into 4 `subdivisions`
/// times, vertices pushed onto the sphere. `20 * 4^subdivisions` triangles, counter-clockwise
/// seen from outside, closed and watertight (shared edges share vertices).
#[must_use]
pub fn icosphere(subdivisions: u32) -> MeshData {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, p: &mut Vec<DVec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push((p[a as usize] + p[b as usize]).normalize());
                (p.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    MeshData {
        positions,
        normals: Vec::new(),
        faces: faces
            .into_iter()
            .map(|vertices| Face {
                vertices,
                normals: None,
            })
            .collect(),
    }
}

/// The mesh benchmarks' scene (`cargo bench --bench mesh`, `examples/primary.rs`, and the
/// view `benches/embree.py` gives Embree): the unit [`icosphere`] of `level` subdivisions, seen
/// by a `size` x `size` camera at `(0, 0, distance)` looking at its centre with a 40 degree
/// field of view (at distance 3 it fills most of the view), one diffuse material and a point
/// light.
///
/// # Panics
/// If `size` is 0 or `distance` is not a finite number above 1 (the camera would be inside).
#[must_use]
pub fn icosphere_scene(level: u32, size: u32, distance: f64) -> Scene {
    assert!(size > 0 && distance.is_finite() && distance > 1.0);
    let json = format!(
        r#"{{"camera": {{"position": [0, 0, {distance}], "look_at": [0, 0, 0], "fov_y": 40,
             "width": {size}, "height": {size}}},
            "materials": {{"m": {{"diffuse": [0.8, 0.8, 0.8]}}}},
            "objects": [{{"type": "mesh", "file": "ico", "material": "m"}}],
            "lights": [{{"type": "point", "position": [2, 2, 4], "intensity": [20, 20, 20]}}]}}"#
    );
    let data = icosphere(level);
    Scene::from_json_with(&json, &mut |_| Ok::<MeshData, String>(data.clone()))
        .expect("the benchmark scene is valid")
}
