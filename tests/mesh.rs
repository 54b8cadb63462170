//! Meshes in whole scenes: BVH against a linear scan, trees on glass meshes with bad shading
//! normals, OBJ errors through the CLI, and the shared reference meshes.

mod common;
use common::{Rng, raytree};

use glam::DVec3;
use raytree::SceneIntegrator;
use raytree::analysis::invariants::tree_violations;
use raytree::math::Ray;
use raytree::mesh::generate::icosphere;
use raytree::mesh::{MeshData, parse_obj};
use raytree::render::RenderOptions;
use raytree::scene::Hit;
use raytree::tree::RayKind;
use raytree::{Scene, render, trace_pixel};
use std::fmt::Write;
use std::path::PathBuf;

impl Rng {
    /// A point in the cube `[-1, 1)^3`.
    fn v(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
    }
}

/// An icosphere as OBJ text, with per-vertex normals: outward, perturbed by `noise`, and every
/// `flip_every`-th one reversed (0 = none).
fn ico_obj(level: u32, noise: f64, flip_every: usize) -> String {
    let d = icosphere(level);
    let mut rng = Rng(5);
    let mut s = String::new();
    for p in &d.positions {
        writeln!(s, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for (i, p) in d.positions.iter().enumerate() {
        let mut n = *p + noise * rng.v();
        if flip_every > 0 && i % flip_every == 0 {
            n = -n;
        }
        writeln!(s, "vn {} {} {}", n.x, n.y, n.z).unwrap();
    }
    for f in &d.faces {
        let [a, b, c] = f.vertices.map(|v| v + 1);
        writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}").unwrap();
    }
    s
}

fn scene_json(objects: &str, w: u32, h: u32) -> String {
    format!(
        r#"{{"camera": {{"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 45, "width": {w}, "height": {h}}},
  "background": [0.3, 0.5, 0.8], "ambient": [0.05, 0.05, 0.05],
  "materials": {{
    "glass": {{"transmissivity": [0.9, 0.9, 0.9], "ior": 1.5, "specular": [0.5, 0.5, 0.5], "shininess": 50, "absorption": [0.2, 0.1, 0.0]}},
    "mirror": {{"reflectivity": [0.8, 0.8, 0.8], "diffuse": [0.1, 0.1, 0.1]}},
    "matte": {{"diffuse": {{"checker": {{"even": [0.9, 0.9, 0.9], "odd": [0.2, 0.2, 0.2], "size": 0.5}}}}}}
  }},
  "objects": [
    {{"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "matte"}},
    {objects}
  ],
  "lights": [{{"type": "point", "position": [3, 5, 4], "intensity": [60, 60, 60]}}],
  "settings": {{"max_depth": 8}}}}"#
    )
}

fn with_obj(json: &str, obj: &str) -> Scene {
    let data = parse_obj(obj).unwrap();
    Scene::from_json_with(json, &mut |_| Ok::<MeshData, String>(data.clone())).unwrap()
}

/// The pre-BVH `Scene::intersect`: a linear scan in object order.
fn linear(scene: &Scene, ray: &Ray, mut t_max: f64) -> Option<(f64, DVec3, usize)> {
    let mut best = None;
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(h) = o.shape.intersect(ray, t_max) {
            t_max = h.t;
            best = Some((h.t, h.normal, i));
        }
    }
    best
}

#[test]
fn bvh_scene_intersect_equals_the_linear_scan() {
    let mut rng = Rng(42);
    let mut objects = Vec::new();
    for i in 0..60 {
        let c = rng.v() * 3.0;
        let o = match i % 3 {
            0 => format!(
                r#"{{"type": "sphere", "center": [{}, {}, {}], "radius": {}, "material": "matte"}}"#,
                c.x,
                c.y,
                c.z,
                0.1 + 0.4 * rng.next()
            ),
            1 => format!(
                r#"{{"type": "box", "min": [{}, {}, {}], "max": [{}, {}, {}], "material": "matte"}}"#,
                c.x,
                c.y,
                c.z,
                c.x + 0.5,
                c.y + 0.3,
                c.z + 0.4
            ),
            _ => {
                let (b, d) = (c + rng.v(), c + rng.v());
                format!(
                    r#"{{"type": "triangle", "vertices": [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]], "material": "matte"}}"#,
                    c.x, c.y, c.z, b.x, b.y, b.z, d.x, d.y, d.z
                )
            }
        };
        objects.push(o);
    }
    // Two objects at the same place: the tie must go to the lower index, as in the scan.
    objects.push(
        r#"{"type": "sphere", "center": [0, 0, 0], "radius": 0.7, "material": "glass"}"#.into(),
    );
    objects.push(
        r#"{"type": "sphere", "center": [0, 0, 0], "radius": 0.7, "material": "mirror"}"#.into(),
    );
    objects.push(r#"{"type": "mesh", "file": "ico", "scale": 1.2, "translate": [1, 0.5, 0], "material": "glass"}"#.into());
    let scene = with_obj(&scene_json(&objects.join(",\n"), 8, 8), &ico_obj(3, 0.0, 0));
    let mut hits = 0;
    for k in 0..20_000 {
        let origin = rng.v() * 6.0;
        let ray = Ray::new(
            origin,
            rng.v().normalize(),
            if k % 2 == 0 { 0.0 } else { 1e-4 },
        );
        let t_max = if k % 3 == 0 { 2.0 } else { f64::INFINITY };
        let got = scene
            .intersect(&ray, t_max)
            .map(|h: Hit| (h.t, h.normal, h.object));
        assert_eq!(got, linear(&scene, &ray, t_max), "ray {ray:?}");
        assert_eq!(
            scene.occluded(&ray, t_max, &mut Default::default()),
            got.is_some()
        );
        hits += usize::from(got.is_some());
    }
    assert!(hits > 5000, "{hits}");
    let centre = Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z, 0.0);
    assert_eq!(scene.intersect(&centre, f64::INFINITY).unwrap().object, 61);
}

/// Reflected rays leave on the incident side of the geometric normal, refracted rays cross it.
fn sides_are_consistent(tree: &raytree::RayTree) -> Vec<String> {
    let mut bad = Vec::new();
    for n in &tree.nodes {
        let Some(h) = &n.hit else { continue };
        let incident = if h.entering { h.normal } else { -h.normal };
        for c in &n.children {
            let c = tree.node(*c);
            let side = c.direction.dot(incident);
            let ok = match c.kind {
                RayKind::Reflected => side > 0.0,
                RayKind::Refracted => side < 0.0,
                _ => true,
            };
            if !ok {
                bad.push(format!(
                    "node {} ({:?}) goes to the wrong side: {side}",
                    c.id.0, c.kind
                ));
            }
        }
    }
    bad
}

#[test]
fn glass_mesh_with_bad_shading_normals_keeps_tree_invariants_and_sides() {
    // Heavily perturbed normals, every 7th reversed: the shading-normal rule must fall back.
    let obj = ico_obj(3, 0.8, 7);
    let objects = r#"{"type": "mesh", "file": "ico", "translate": [0, 0.4, 0], "material": "glass", "name": "ico"},
        {"type": "mesh", "file": "ico", "translate": [-1.6, 0.2, -1], "scale": [0.6, 1, 0.6], "normals": "smooth", "material": "mirror"}"#;
    let scene = with_obj(&scene_json(objects, 40, 30), &obj);
    let (image, _, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let mut triangles = 0;
    let mut shading = 0;
    for y in 0..30 {
        for x in 0..40 {
            let tree = trace_pixel(&scene, x, y).unwrap();
            assert_eq!(tree.radiance, image.get(x, y), "pixel {x},{y}");
            let v = tree_violations(&tree, scene.background);
            assert!(v.is_empty(), "pixel {x},{y}: {v:?}");
            let s = sides_are_consistent(&tree);
            assert!(s.is_empty(), "pixel {x},{y}: {s:?}");
            for n in &tree.nodes {
                if let Some(h) = &n.hit {
                    triangles += usize::from(h.triangle.is_some());
                    shading += usize::from(h.shading_normal.is_some_and(|s| s != h.normal));
                    assert!(n.traversal.nodes > 0);
                    if h.object_name == "ico" {
                        assert!(h.triangle.is_some_and(|t| t < 1280));
                    }
                }
            }
        }
    }
    assert!(triangles > 300 && shading > 100, "{triangles} {shading}");
}

#[test]
fn obj_errors_name_file_and_line_and_exit_2_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let objects = r#"{"type": "mesh", "file": "sub/m.obj", "material": "glass"}"#;
    std::fs::write(dir.path().join("s.json"), scene_json(objects, 8, 6)).unwrap();
    let run = || raytree(&["render", "s.json", "-o", "out.png"], dir.path());
    // Missing file.
    let o = run();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("s.json:") && err.contains("objects[1].file"),
        "{err}"
    );
    // Named as the scene writes it; with the scene given by an absolute path, also where it
    // was looked for.
    assert!(err.contains("cannot read sub/m.obj: "), "{err}");
    let scene = dir.path().join("s.json");
    let o = raytree(
        &["render", &scene.to_string_lossy(), "-o", "out.png"],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let looked = dir.path().join("sub").join("m.obj");
    let expect = format!("cannot read sub/m.obj (looked for {}): ", looked.display());
    assert!(err.contains(&expect), "{err}");
    // Bad index on line 4, then a parse error on line 2.
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    for (text, line) in [
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 4),
        ("v 0 0 0\nv 1 x 0\n", 2),
    ] {
        std::fs::write(dir.path().join("sub/m.obj"), text).unwrap();
        let o = run();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(&format!(": sub/m.obj:{line}: ")), "{err}");
    }
    assert!(!dir.path().join("out.png").exists());
    // A good file, found relative to the scene file, renders.
    std::fs::write(dir.path().join("sub/m.obj"), ico_obj(1, 0.0, 0)).unwrap();
    let o = raytree(&["render", "s.json", "-o", "out.png"], dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("out.png").exists());
    let o = raytree(&["trace", "s.json", "--pixel", "4,3"], dir.path());
    assert!(String::from_utf8_lossy(&o.stdout).contains("triangle "));
}

#[test]
fn shared_meshes_load_when_present() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    if !dir.exists() {
        // Not vacuous without the meshes: the same read-and-parse path on generated OBJ files
        // of known face counts (what the shared meshes check below, minus the bunny's scene).
        eprintln!(
            "{} not found: checking generated meshes instead",
            dir.display()
        );
        let tmp = tempfile::tempdir().unwrap();
        for (level, faces) in [(2, 320), (3, 1_280), (4, 5_120)] {
            let file = tmp.path().join(format!("ico{level}.obj"));
            std::fs::write(&file, ico_obj(level, 0.0, 0)).unwrap();
            let text = std::fs::read_to_string(&file).unwrap();
            let data = parse_obj(&text).unwrap_or_else(|e| panic!("level {level}: {e}"));
            assert_eq!(data.faces.len(), faces, "level {level}");
        }
        return;
    }
    for (file, faces) in [
        ("stanford-bunny.obj", 69_451),
        ("teapot.obj", 6_320),
        ("spot.obj", 5_856),
    ] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let data = parse_obj(&text).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(data.faces.len(), faces, "{file}");
    }
    let json = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/bunny.json"),
    )
    .unwrap();
    let text = std::fs::read_to_string(dir.join("stanford-bunny.obj")).unwrap();
    let mut scene = with_obj(&json, &text);
    scene.camera = scene.camera.with_size(64, 36);
    for (x, y) in [(44, 20), (40, 18), (46, 24)] {
        let tree = trace_pixel(&scene, x, y).unwrap();
        assert!(tree_violations(&tree, scene.background).is_empty());
        let root = tree.node(tree.samples[0].root);
        assert_eq!(
            root.hit.as_ref().map(|h| h.object_name.as_str()),
            Some("glass bunny"),
            "{x},{y}"
        );
    }
}

/// What the merge with main's numerics, effects and diagram work must keep for meshes: the
/// watertight test on shared vertices, robust offsets and self-hit diagnostics per triangle,
/// translucent shadows through mesh chords (tree = render), moved scenes, and diagram slices.
#[test]
fn meshes_get_watertight_hits_robust_offsets_diagnostics_and_diagram_slices() {
    use raytree::diagram::model::SliceShape;
    use raytree::diagram::{Diagram, DiagramOptions};
    use raytree::scene::{OffsetStrategy, ShadowMode, transformed};

    // Watertight: a ray from the centre through every vertex (shared by 5-6 triangles) hits.
    let obj = ico_obj(2, 0.0, 0);
    let objects = r#"{"type": "mesh", "file": "ico", "translate": [0, 0.4, 0], "material": "glass", "name": "ico"}"#;
    let mut scene = with_obj(&scene_json(objects, 32, 24), &obj);
    let centre = DVec3::new(0.0, 0.4, 0.0);
    for p in &icosphere(2).positions {
        let ray = Ray::new(centre, p.normalize(), 0.0);
        let hit = scene.intersect(&ray, f64::INFINITY);
        assert!(
            hit.is_some_and(|h| h.object == 1),
            "ray through vertex {p} escaped"
        );
    }

    // Offsets: no offset at all re-hits the triangle left; the robust offset never does.
    scene.settings.offset.strategy = OffsetStrategy::Normal;
    scene.settings.offset.epsilon = 0.0;
    let (_, stats, _) = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::diagnosed(),
        &|_| {},
    )
    .into_parts();
    assert!(stats.self_hit_pixels > 0, "{stats:?}");
    scene.settings.offset.strategy = OffsetStrategy::Robust;
    // Every split (roulette choices hash the hit points, which the move below changes).
    scene.settings.whitted.roulette_below = Some(0.0);
    let (image, stats, _) = raytree::render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::diagnosed(),
        &|_| {},
    )
    .into_parts();
    assert_eq!(stats.self_hit_pixels, 0, "{stats:?}");
    assert!(stats.rays.refracted > 100, "{stats:?}");

    // Translucent shadows through the mesh: every tree equals the render, with mesh blockers.
    scene.settings.whitted.shadows = ShadowMode::Translucent;
    let (translucent, _, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert_ne!(translucent.pixels, image.pixels);
    let mut mesh_blockers = 0;
    for y in 0..24 {
        for x in 0..32 {
            let tree = trace_pixel(&scene, x, y).unwrap();
            assert_eq!(tree.radiance, translucent.get(x, y), "pixel {x},{y}");
            assert!(tree_violations(&tree, scene.background).is_empty());
            mesh_blockers += tree
                .nodes
                .iter()
                .filter_map(|n| n.shadow.as_ref())
                .flat_map(|s| &s.blockers)
                .filter(|b| b.object == 1 && b.chord > 0.0)
                .count();
        }
    }
    assert!(mesh_blockers > 0);

    // A moved scene moves its mesh (and rebuilds its BVH): the same image.
    let moved = transformed(&scene, 4.0, DVec3::new(8.0, 0.0, -16.0));
    let (b, _, _) = render(
        &SceneIntegrator::new(&moved),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let worst = raytree::analysis::cost::compare(&translucent, &b)
        .expect("same size")
        .max;
    assert!(worst < 1e-6, "worst pixel difference {worst}");

    // The diagram cuts the mesh into segments (a closed polygon's worth around the sphere).
    let tree = trace_pixel(&scene, 16, 12).unwrap();
    let d = Diagram::build(&scene, &tree, &DiagramOptions::default()).unwrap();
    let ico = d
        .objects
        .iter()
        .find(|o| o.name == "ico")
        .expect("ico sliced");
    let SliceShape::Segments(s) = &ico.shape else {
        panic!("mesh slice is {:?}", ico.shape);
    };
    assert!(s.len() >= 12, "{}", s.len());
    let svg = raytree::diagram::to_svg(&d, &raytree::diagram::Style::default());
    assert!(svg.contains("<svg"));
}
