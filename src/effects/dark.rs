//! Area lights that light nothing (issue 32): probed with emitted rays
//! ([`crate::lights::Light::sample_le`]).

use crate::Scene;
use glam::DVec2;

/// Emitted rays a probe of [`dark_emitters`] traces per area light (an 8 x 8 grid of origins,
/// each with its own direction).
pub const DARK_PROBE: u32 = 64;

/// The names of the area lights of `scene` that light nothing: none of [`DARK_PROBE`] emitted
/// rays (origins stratified over the light, cosine-weighted directions from its emitting side)
/// meets a surface. Such a lamp faces away from everything (issue 32: an area light whose
/// emitting side sees no surface got no warning; only its directly seen face shows).
#[must_use]
pub fn dark_emitters(scene: &Scene) -> Vec<String> {
    let side = f64::from(DARK_PROBE).sqrt() as u32;
    (0..scene.objects.len())
        .filter_map(|i| scene.area_light(i))
        .filter(|e| {
            !(0..DARK_PROBE).any(|k| {
                let cell = DVec2::new(f64::from(k % side), f64::from(k / side));
                let u_pos = (cell + 0.5) / f64::from(side);
                // A second, shuffled grid for the directions (golden-ratio steps).
                let u_dir = DVec2::new(
                    (f64::from(k) * 0.618_033_988_749_895 + 0.25).fract(),
                    (f64::from(k) + 0.5) / f64::from(DARK_PROBE),
                );
                e.sample_le(u_pos, u_dir).is_some_and(|r| {
                    let t_min = 1e-7 * (1.0 + r.origin.abs().max_element());
                    let ray = crate::math::Ray::new(r.origin, r.direction, t_min);
                    scene.intersect(&ray, f64::INFINITY).is_some()
                })
            })
        })
        .filter_map(|e| Some(scene.objects[e.object()?].name.clone()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 32: a lamp whose emitting side faces away from every surface is named; one facing the
    /// floor is not.
    #[test]
    fn a_lamp_facing_away_from_everything_is_dark() {
        let scene = |edge_v: &str| {
            crate::Scene::from_json(&format!(
                r#"{{"camera": {{"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov_y": 60, "width": 8, "height": 8}},
                "materials": {{"lamp": {{"emission": [4, 4, 4]}}, "grey": {{"diffuse": [0.5, 0.5, 0.5]}}}},
                "objects": [{{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "grey"}},
                            {{"type": "quad", "name": "lamp", "corner": [-0.5, 2, -0.5], "edge_u": [1, 0, 0], "edge_v": {edge_v}, "material": "lamp"}}]}}"#
            ))
            .unwrap()
        };
        // edge_u x edge_v: (1,0,0) x (0,0,1) = (0,-1,0) faces the floor; (0,0,-1) faces the sky.
        assert!(dark_emitters(&scene("[0, 0, 1]")).is_empty());
        assert_eq!(
            dark_emitters(&scene("[0, 0, -1]")),
            vec!["lamp".to_string()]
        );
        let note = crate::effects::dark_note(&scene("[0, 0, -1]"));
        assert!(note.contains("lamp emits towards nothing"), "{note}");
    }
}
