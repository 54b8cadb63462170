//! Scenes built in code, for benchmarks and examples.

use super::Scene;
use crate::mesh::MeshData;
use crate::mesh::generate::icosphere;

/// The mesh benchmarks' scene (`cargo bench --bench mesh`, `examples/primary.rs`, and the
/// view `benches/embree.py` gives Embree): the unit [`icosphere`](crate::mesh::generate::icosphere) of `level` subdivisions, seen
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
