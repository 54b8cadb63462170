//! Issue 14's area lights in the Whitted integrator: closed-form irradiance from a spherical and
//! a quad light (tolerances from the measured standard error, fixed seeds), a monotone
//! penumbra, tree == pixel bit for bit, and rejected `quad` / `light_samples` values.

use glam::DVec3;
use raytree::SceneIntegrator;
use raytree::lights::polygon_irradiance;
use raytree::render::RenderOptions;
use raytree::{Scene, render, trace_pixel};
use std::f64::consts::PI;

const ALBEDO: f64 = 0.5;

/// A white Lambertian floor (y = 0) under `light` (one JSON object), a 1x1 camera looking at
/// the origin from `(0, 1, 3)`.
fn one_point(light: &str, samples: u32, seed: u64) -> Scene {
    let src = format!(
        r#"{{
  "camera": {{"position": [0, 1, 3], "look_at": [0, 0, 0], "fov_y": 1, "width": 1, "height": 1}},
  "materials": {{"floor": {{"diffuse": [{ALBEDO}, {ALBEDO}, {ALBEDO}]}}, "lamp": {{"emission": [2, 2, 2]}}}},
  "objects": [
    {{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}},
    {light}
  ],
  "settings": {{"light_samples": {samples}, "seed": {seed}}}
}}"#
    );
    Scene::from_json(&src).unwrap()
}

/// Mean and standard error of the pixel over `runs` seeds.
fn estimate(light: &str, samples: u32, runs: u64) -> (f64, f64) {
    let v: Vec<f64> = (0..runs)
        .map(|seed| {
            render(
                &SceneIntegrator::new(&one_point(light, samples, seed)),
                &RenderOptions::new(),
                &|_| {},
            )
            .image
            .get(0, 0)
            .x
        })
        .collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn check(light: &str, exact: f64) {
    let (mean, se) = estimate(light, 256, 40);
    assert!(se > 0.0 && se < 0.01 * exact, "s.e. {se} vs {exact}");
    assert!(
        (mean - exact).abs() < 4.0 * se,
        "mean {mean} vs exact {exact} (s.e. {se})"
    );
}

/// Irradiance from a sphere of radiance L subtending half-angle a, centred on the normal, is
/// pi L sin^2 a; the Lambertian floor reflects albedo/pi of it.
#[test]
fn sphere_light_gives_pi_l_sin2() {
    for (h, r) in [(2.0, 0.5), (1.5, 1.0), (4.0, 0.1)] {
        let light = format!(
            r#"{{"type": "sphere", "center": [0, {h}, 0], "radius": {r}, "material": "lamp"}}"#
        );
        let sin2 = (r / h) * (r / h);
        check(&light, ALBEDO / PI * PI * 2.0 * sin2);
    }
}

#[test]
fn quad_and_triangle_lights_follow_lamberts_formula() {
    let (c, u, v) = (
        DVec3::new(-0.3, 1.5, -0.8),
        DVec3::new(1.0, 0.2, 0.0),
        DVec3::new(0.0, 0.0, 1.4),
    );
    let quad = format!(
        r#"{{"type": "quad", "corner": [{}, {}, {}], "edge_u": [{}, {}, {}], "edge_v": [{}, {}, {}], "material": "lamp"}}"#,
        c.x, c.y, c.z, u.x, u.y, u.z, v.x, v.y, v.z
    );
    let e = polygon_irradiance(DVec3::ZERO, DVec3::Y, &[c, c + u, c + u + v, c + v], 2.0);
    check(&quad, ALBEDO / PI * e);
    // Facing down: the triangle (c, c + u, c + v) has normal u x v (downwards).
    let tri = format!(
        r#"{{"type": "triangle", "vertices": [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]], "material": "lamp"}}"#,
        c.x,
        c.y,
        c.z,
        c.x + u.x,
        c.y + u.y,
        c.z + u.z,
        c.x + v.x,
        c.y + v.y,
        c.z + v.z
    );
    let e = polygon_irradiance(DVec3::ZERO, DVec3::Y, &[c, c + u, c + v], 2.0);
    check(&tri, ALBEDO / PI * e);
}

/// An emissive mesh is an area light too (sampled uniformly over its area). Two squares facing
/// down, the small one 0.5 below the big one and hiding part of it from the floor point: the
/// small one shows exactly the solid angle it hides, at the same radiance, so the irradiance
/// is the big square's alone by Lambert's formula. Counting the hidden samples as seen (the
/// shadow ray stopped at the mesh's first hit) would add the small square's share again.
#[test]
fn an_emissive_mesh_lights_like_its_visible_triangles() {
    let obj = "v -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\n\
               v -0.3 1.5 -0.3\nv 0.3 1.5 -0.3\nv 0.3 1.5 0.3\nv -0.3 1.5 0.3\n\
               f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n";
    let data = raytree::mesh::obj::parse_obj(obj).unwrap();
    let v: Vec<f64> = (0..40)
        .map(|seed| {
            let src = r#"{
  "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov_y": 1, "width": 1, "height": 1},
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}, "lamp": {"emission": [2, 2, 2]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "mesh", "file": "lamp.obj", "material": "lamp"}
  ],
  "settings": {"light_samples": 256, "seed": SEED}
}"#
            .replace("SEED", &seed.to_string());
            let scene = Scene::from_json_with(&src, &mut |_| Ok(data.clone())).unwrap();
            render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {},
            )
            .image
            .get(0, 0)
            .x
        })
        .collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let se = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    let big = [
        DVec3::new(-1.0, 2.0, -1.0),
        DVec3::new(1.0, 2.0, -1.0),
        DVec3::new(1.0, 2.0, 1.0),
        DVec3::new(-1.0, 2.0, 1.0),
    ];
    let small = big.map(|p| DVec3::new(0.3 * p.x, 1.5, 0.3 * p.z));
    let exact = ALBEDO / PI * polygon_irradiance(DVec3::ZERO, DVec3::Y, &big, 2.0);
    let both = exact + ALBEDO / PI * polygon_irradiance(DVec3::ZERO, DVec3::Y, &small, 2.0);
    assert!(se > 0.0 && se < 0.01 * exact, "s.e. {se} vs {exact}");
    assert!(
        (mean - exact).abs() < 4.0 * se && (mean - both).abs() > 8.0 * se,
        "mean {mean} vs exact {exact} (s.e. {se}; hidden counted: {both})"
    );
}

/// The text tree labels an area-light sample's arriving light as what it is, the radiance, its
/// pdf and the estimate L / pdf, not as an irradiance `E` (which a point light's line keeps).
#[test]
fn text_tree_names_area_samples_l_over_pdf() {
    let sphere = r#"{"type": "sphere", "center": [0, 2, 0], "radius": 0.5, "material": "lamp"}"#;
    let text = raytree::text::tree_text(&trace_pixel(&one_point(sphere, 2, 0), 0, 0).unwrap());
    let shadows: Vec<&str> = text.lines().filter(|l| l.contains("shadow #")).collect();
    assert_eq!(shadows.len(), 2, "{text}");
    for l in shadows {
        assert!(
            l.contains("  L 2.0000") && l.contains("  pdf ") && l.contains("  L/pdf "),
            "{l}"
        );
        assert!(!l.contains("  E "), "{l}");
    }
}

/// Emission leaves the outer side only: a quad facing up lights nothing below it.
#[test]
fn a_quad_facing_away_lights_nothing() {
    let up = r#"{"type": "quad", "corner": [-0.5, 1, -0.5], "edge_u": [0, 0, 1], "edge_v": [1, 0, 0], "material": "lamp"}"#;
    let img = render(
        &SceneIntegrator::new(&one_point(up, 16, 0)),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_eq!(img.get(0, 0).x, 0.0);
}

/// A quad light over a floor half covered by an occluding quad at half the height: the floor's
/// radiance rises monotonically across the penumbra, from exactly 0 in the umbra.
#[test]
fn penumbra_is_monotone() {
    let src = r#"{
  "camera": {"position": [0, 0.5, 3], "look_at": [0, 0, 0], "fov_y": 1.9, "width": 9, "height": 1},
  "materials": {"floor": {"diffuse": [0.5, 0.5, 0.5]}, "lamp": {"emission": [2, 2, 2]}, "black": {}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "quad", "corner": [-0.5, 2, -0.5], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "material": "lamp"},
    {"type": "quad", "corner": [-10, 1, -10], "edge_u": [10, 0, 0], "edge_v": [0, 0, 20], "material": "black"}
  ],
  "settings": {"light_samples": 4096}
}"#;
    let scene = Scene::from_json(src).unwrap();
    let img = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let row: Vec<f64> = (0..9).map(|x| img.get(x, 0).x).collect();
    // The floor points span about x in [-0.45, 0.45]: inside the penumbra x in [-0.5, 0.5].
    assert!(row[0] > 0.0, "{row:?}");
    for w in row.windows(2) {
        // Each step adds about 1/9 of the light; the noise at 4096 samples is ~1% of it.
        assert!(w[1] > w[0] * 1.05, "{row:?}");
    }
    let mut umbra = scene.clone();
    umbra.camera.position = DVec3::new(-2.0, 0.5, 3.0);
    let img = render(
        &SceneIntegrator::new(&umbra),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_eq!(img.get(4, 0).x, 0.0);
}

/// The recorded tree equals the rendered pixel bit for bit, at 1 and 4 samples per pixel.
#[test]
fn tree_equals_pixel_with_area_lights() {
    let src = include_str!("../fixtures/soft-shadows.json");
    for spp in [1, 4] {
        let mut scene = Scene::from_json(src).unwrap();
        scene.camera = scene.camera.with_size(32, 20);
        scene.settings.spp = spp;
        scene.settings.whitted.light_samples = Some(3);
        let img = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        let mut area_nodes = 0;
        for y in 0..20 {
            for x in 0..32 {
                let tree = trace_pixel(&scene, x, y).unwrap();
                assert_eq!(tree.radiance, img.get(x, y), "pixel ({x}, {y}) spp {spp}");
                area_nodes += tree
                    .nodes
                    .iter()
                    .filter(|n| n.shadow.as_ref().is_some_and(|s| s.area.is_some()))
                    .count();
            }
        }
        assert!(area_nodes > 0);
    }
}

#[test]
fn bad_quads_and_light_samples_are_rejected_with_their_path() {
    let base = |obj: &str, settings: &str| {
        format!(
            r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4, "height": 3}},
"materials": {{"m": {{"emission": [1,1,1]}}}},
"objects": [{obj}],
"settings": {{{settings}}}}}"#
        )
    };
    let ok = r#"{"type": "quad", "corner": [0,0,0], "edge_u": [1,0,0], "edge_v": [0,1,0], "material": "m"}"#;
    assert!(Scene::from_json(&base(ok, "\"light_samples\": 4")).is_ok());
    for (obj, settings, path) in [
        (ok.replace("[0,1,0]", "[2,0,0]"), "", "objects[0].edge_v"),
        (ok.replace("[1,0,0]", "[0,0,0]"), "", "objects[0].edge_u"),
        (ok.replace("[0,1,0]", "[0,0,0]"), "", "objects[0].edge_v"),
        (
            ok.replace("\"edge_v\": [0,1,0], ", ""),
            "",
            "objects[0].edge_v",
        ),
        (
            ok.to_string(),
            "\"light_samples\": 0",
            "settings.light_samples",
        ),
        (
            ok.to_string(),
            "\"light_samples\": -1",
            "settings.light_samples",
        ),
        // The new spelling: the error is where the file writes the key.
        (
            ok.to_string(),
            "\"integrator\": {\"type\": \"whitted\", \"light_samples\": 0}",
            "settings.integrator.light_samples",
        ),
        (
            ok.to_string(),
            "\"integrator\": {\"type\": \"path\"}, \"other_integrators\": [{\"type\": \"whitted\", \"light_samples\": 70000}]",
            "settings.other_integrators[0].light_samples",
        ),
    ] {
        let text = base(&obj, settings);
        let e = Scene::from_json(&text).unwrap_err();
        assert_eq!(e.path, path, "{e}");
        assert!(e.line.is_some() && e.column.is_some(), "{e}");
        if settings.contains("integrator") {
            let (line, column) = raytree::scene::locate(&text, path).expect(path);
            assert_eq!((e.line, e.column), (Some(line), Some(column)), "{e}");
        }
    }
}
