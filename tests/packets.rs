//! Camera rays traced as packets (tiles of 8x8, used by the render for scenes with meshes)
//! give the single rays' hits and the per-pixel render's image, bit for bit.

use glam::DVec3;
use raytree::SceneIntegrator;
use raytree::bvh::TraversalCost;
use raytree::effects::EffectPlan;
use raytree::math::Ray;
use raytree::mesh::MeshData;
use raytree::mesh::generate::icosphere;
use raytree::render::RenderOptions;
use raytree::render::render_pixel;
use raytree::sampling::SceneSampler;
use raytree::scene::Hit;
use raytree::{NoopRecorder, RayCounts, Scene, render};

fn scene(objects: &str, w: u32, h: u32, spp: u32) -> Scene {
    let json = format!(
        r#"{{"camera": {{"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 45, "width": {w}, "height": {h}}},
  "background": [0.3, 0.5, 0.8], "ambient": [0.05, 0.05, 0.05],
  "materials": {{
    "glass": {{"transmissivity": [0.9, 0.9, 0.9], "ior": 1.5, "specular": [0.5, 0.5, 0.5], "shininess": 50, "absorption": [0.2, 0.1, 0.0]}},
    "mirror": {{"reflectivity": [0.8, 0.8, 0.8], "diffuse": [0.1, 0.1, 0.1]}},
    "matte": {{"diffuse": [0.7, 0.6, 0.5]}}
  }},
  "objects": [
    {{"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "matte"}},
    {objects}
  ],
  "lights": [{{"type": "point", "position": [3, 5, 4], "intensity": [60, 60, 60]}}],
  "settings": {{"max_depth": 8, "spp": {spp}}}}}"#
    );
    let data = icosphere(3);
    Scene::from_json_with(&json, &mut |_| Ok::<MeshData, String>(data.clone())).unwrap()
}

const MESHES: &str = r#"{"type": "mesh", "file": "ico", "translate": [0, 0.4, 0], "normals": "smooth", "material": "glass"},
    {"type": "sphere", "center": [1.5, 0, -1], "radius": 0.6, "material": "mirror"},
    {"type": "mesh", "file": "ico", "translate": [-1.6, 0.2, -1], "scale": [0.6, 1, 0.6], "material": "matte"}"#;

/// [`MESHES`] and 12 spheres: more than 8 objects, so the scene uses its object BVH.
fn many_objects() -> Scene {
    let spheres: Vec<String> = (0..12)
        .map(|i| {
            let x = f64::from(i) * 0.4 - 2.4;
            format!(r#"{{"type": "sphere", "center": [{x}, -0.6, 1], "radius": 0.25, "material": "mirror"}}"#)
        })
        .collect();
    scene(&format!("{MESHES},\n{}", spheres.join(",\n")), 37, 21, 1)
}

/// Packets of camera rays (and some others) against `Scene::intersect_counted`, ray by ray.
fn packets_match(scene: &Scene) -> usize {
    let cam = &scene.camera;
    let mut hits = 0;
    for y0 in (0..cam.height).step_by(8) {
        for x0 in (0..cam.width).step_by(8) {
            let mut rays = Vec::new();
            for y in y0..(y0 + 8).min(cam.height) {
                for x in x0..(x0 + 8).min(cam.width) {
                    rays.push(cam.ray(f64::from(x) + 0.3, f64::from(y) + 0.7));
                }
            }
            // An incoherent ray in every packet, from inside the glass mesh.
            rays[0] = Ray::new(
                DVec3::new(0.0, 0.4, 0.0),
                DVec3::new(0.3, -0.2, 0.9).normalize(),
                0.0,
            );
            let mut got = vec![None; rays.len()];
            let mut cost = vec![TraversalCost::default(); rays.len()];
            scene.intersect_packet(&rays, &mut got, &mut cost);
            for (i, ray) in rays.iter().enumerate() {
                let want: Option<Hit> =
                    scene.intersect_counted(ray, f64::INFINITY, &mut TraversalCost::default());
                assert_eq!(got[i], want, "{ray:?}");
                assert!(cost[i].prims > 0);
                hits += usize::from(want.is_some());
            }
        }
    }
    hits
}

#[test]
fn scene_packets_equal_single_rays_with_and_without_the_object_bvh() {
    let few = scene(MESHES, 37, 21, 1);
    assert!(packets_match(&few) > 500);
    // More than 8 objects: the object BVH.
    let many = many_objects();
    assert!(packets_match(&many) > 500);
}

/// Shadow rays of a tile's hits towards the light, as one packet, against
/// `Scene::occluded` ray by ray; returns (blocked, free).
fn shadow_packets_match(scene: &Scene) -> (usize, usize) {
    let cam = &scene.camera;
    let light = DVec3::new(3.0, 5.0, 4.0);
    let (mut blocked, mut free) = (0, 0);
    for y0 in (0..cam.height).step_by(8) {
        for x0 in (0..cam.width).step_by(8) {
            let (mut rays, mut t_max) = (Vec::new(), Vec::new());
            for y in y0..(y0 + 8).min(cam.height) {
                for x in x0..(x0 + 8).min(cam.width) {
                    let ray = cam.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
                    let cost = &mut TraversalCost::default();
                    let Some(hit) = scene.intersect_counted(&ray, f64::INFINITY, cost) else {
                        continue;
                    };
                    let p = ray.at(hit.t) + 1e-4 * hit.normal;
                    rays.push(Ray::new(p, (light - p).normalize(), 0.0));
                    t_max.push((light - p).length());
                }
            }
            let mut got = vec![true; rays.len()];
            scene.occluded_packet(&rays, &t_max, &mut got);
            for (i, ray) in rays.iter().enumerate() {
                let want = scene.occluded(ray, t_max[i], &mut TraversalCost::default());
                assert_eq!(got[i], want, "{ray:?} to {}", t_max[i]);
                (blocked, free) = if want {
                    (blocked + 1, free)
                } else {
                    (blocked, free + 1)
                };
            }
        }
    }
    (blocked, free)
}

#[test]
fn shadow_packets_equal_single_shadow_rays_with_and_without_the_object_bvh() {
    let few = scene(MESHES, 37, 21, 1);
    let (blocked, free) = shadow_packets_match(&few);
    assert!(blocked > 50 && free > 200, "{blocked} blocked, {free} free");
    let many = many_objects();
    let (blocked, free) = shadow_packets_match(&many);
    assert!(blocked > 50 && free > 200, "{blocked} blocked, {free} free");
}

/// The render (packets for scenes with meshes) equals pixel-by-pixel tracing bit for bit:
/// several samples per pixel, tiles cut by the image edge, glass with Beer's law, and a scene
/// whose plan takes the direct-only path.
#[test]
fn packet_render_equals_per_pixel_render_bit_for_bit() {
    let diffuse = r#"{"type": "mesh", "file": "ico", "translate": [0, 0.4, 0], "normals": "smooth", "material": "matte"}"#;
    // Direct-only plans (shadow rays in packets too): one mesh, and two meshes and a sphere.
    let all_matte = MESHES.replace("glass", "matte").replace("mirror", "matte");
    for (objects, spp, w, h, direct) in [
        (MESHES, 4, 29, 19, false),
        (MESHES, 1, 29, 19, false),
        (diffuse, 2, 61, 45, true),
        (&all_matte, 1, 61, 45, true),
    ] {
        let mut scene = scene(objects, w, h, spp);
        // Packets trace uniform renders (automatic antialiasing probes pixel by pixel).
        scene.settings.antialiasing = raytree::scene::Antialiasing::Uniform;
        assert_eq!(EffectPlan::for_scene(&scene).direct_only(), direct);
        let (image, stats, _) = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        let mut counts = RayCounts::default();
        for y in 0..h {
            for x in 0..w {
                let l = render_pixel(
                    &SceneIntegrator::new(&scene),
                    &mut SceneSampler::for_settings(&scene.settings),
                    (x, y),
                    &mut NoopRecorder,
                    &mut counts,
                    |_| {},
                )
                .0;
                assert_eq!(image.get(x, y), l, "pixel {x},{y}, spp {spp}");
            }
        }
        assert_eq!(stats.rays, counts);
        assert_eq!(counts.camera, u64::from(w * h * spp));
    }
}
