//! [`Bsdf::reset_at`]: one BSDF reset in place at hit after hit equals the BSDF built afresh
//! at each.

use super::*;
use crate::interaction::SurfaceInteraction;
use crate::media::MediaStack;
use crate::scene::Scene;

/// A path's hits in turn: a three-lobe rough glass, a diffuse wall, a glass seen from inside
/// (eta from the media stack), a black absorber. A reset that kept the previous hit's lobes,
/// count or frame fails the comparison with `Bsdf::at`.
#[test]
fn reset_at_equals_a_fresh_bsdf_at_every_hit() {
    let scene = Scene::from_json(
        r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3},
        "materials": {
          "glass": {"diffuse": [0.1, 0.1, 0.1], "reflectivity": [0.2, 0.2, 0.2], "transmissivity": [0.7, 0.7, 0.7], "ior": 1.5, "roughness": 0.3},
          "wall": {"diffuse": [0.6, 0.3, 0.2]},
          "smooth": {"transmissivity": [1, 1, 1], "ior": 1.33},
          "black": {}},
        "objects": [
          {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"},
          {"type": "sphere", "center": [3, 0, 0], "radius": 1, "material": "wall"},
          {"type": "sphere", "center": [-3, 0, 0], "radius": 1, "material": "smooth"},
          {"type": "sphere", "center": [0, 3, 0], "radius": 1, "material": "black"}]}"#,
    )
    .unwrap();
    let inside = MediaStack::AIR.entered(0, 1.5).entered(2, 1.33);
    let hits = [
        (0, true, DVec3::new(0.3, 0.4, 0.866), &MediaStack::AIR),
        (1, true, DVec3::new(0.0, 1.0, 0.0), &MediaStack::AIR),
        (2, false, DVec3::new(-0.6, 0.0, 0.8), &inside),
        (3, true, DVec3::new(0.0, 0.0, 1.0), &MediaStack::AIR),
        (0, true, DVec3::new(0.0, 0.6, 0.8), &MediaStack::AIR),
    ];
    let mut reused = Bsdf::EMPTY;
    let mut lobe_counts = Vec::new();
    for (object, entering, normal, media) in hits {
        let si = SurfaceInteraction {
            p: DVec3::new(0.1, 0.2, 0.3),
            wo: normal,
            entering,
            n: normal,
            ns: normal,
            smooth: None,
            cos_i: 1.0,
            object,
            triangle: None,
            material: scene.material_of(object),
            media,
        };
        let roughness = si.material.roughness;
        let fresh = Bsdf::at(&si, roughness);
        reused.reset_at(&si, roughness);
        assert_eq!(reused, fresh, "object {object}");
        assert_eq!(reused.frame(), fresh.frame());
        let (wo, wi) = (normal, DVec3::new(0.2, -0.3, 0.93).normalize());
        assert_eq!(reused.eval(wo, wi), fresh.eval(wo, wi));
        assert_eq!(reused.pdf(wo, wi), fresh.pdf(wo, wi));
        lobe_counts.push(reused.lobes().count());
    }
    assert_eq!(lobe_counts, [3, 1, 1, 0, 3]);
}
