//! Issue 14's depth of field and pixel filters through the library and the command line:
//! aperture 0 is the pinhole bit for bit, packets trace thin-lens rays correctly, recorded
//! trees equal rendered pixels, and bad values are refused with exit 2.

mod common;
use common::{fails_with, raytree};

use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::render::render_pixel;
use raytree::sampling::SceneSampler;
use raytree::scene::{FilterDesc, icosphere_scene};
use raytree::{RayCounts, Scene, TreeRecorder, render, trace_pixel};

const DOF: &str = include_str!("../fixtures/depth-of-field.json");

fn small(mut scene: Scene, w: u32, h: u32, spp: u32) -> Scene {
    scene.camera = scene.camera.with_size(w, h);
    scene.settings.spp = spp;
    scene
}

fn dof() -> Scene {
    Scene::from_json(DOF).unwrap()
}

/// `aperture_radius: 0` (with any focus distance) renders the pinhole image bit for bit, at 1
/// and 4 samples per pixel, for spheres (rows) and a mesh (8x8 packets).
#[test]
fn aperture_zero_is_the_pinhole_bit_for_bit() {
    let mut pinhole = dof();
    pinhole.settings.filter = FilterDesc::Box {};
    pinhole.camera.aperture_radius = 0.0;
    let written = DOF.replace(
        "\"aperture_radius\": 0.15",
        "\"aperture_radius\": 0, \"focus_distance\": 2.5",
    );
    let mut zero = Scene::from_json(&written).unwrap();
    zero.settings.filter = FilterDesc::Box {};
    assert_eq!(zero.camera.aperture_radius, 0.0);
    assert_eq!(zero.camera.focus_distance, 2.5);
    let no_lens = DOF
        .replace(", \"aperture_radius\": 0.15", "")
        .replace("\"aperture_radius\": 0.15", "");
    let no_lens =
        Scene::from_json(&no_lens.replace("\"height\": 270,\n", "\"height\": 270\n")).unwrap();
    for spp in [1, 4] {
        let a = render(
            &SceneIntegrator::new(&small(pinhole.clone(), 64, 36, spp)),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        let b = render(
            &SceneIntegrator::new(&small(zero.clone(), 64, 36, spp)),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        let mut c_scene = small(no_lens.clone(), 64, 36, spp);
        c_scene.settings.filter = FilterDesc::Box {};
        let c = render(
            &SceneIntegrator::new(&c_scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        assert_eq!(a, b, "spp {spp}");
        assert_eq!(a, c, "spp {spp}");
    }
    let mesh = small(icosphere_scene(2, 20, 3.0), 24, 24, 4);
    let mut focused = mesh.clone();
    focused.camera.focus_distance = 1.7;
    assert_eq!(
        render(&SceneIntegrator::new(&mesh), &RenderOptions::new(), &|_| {}).image,
        render(
            &SceneIntegrator::new(&focused),
            &RenderOptions::new(),
            &|_| {}
        )
        .image
    );
}

/// With a thin lens and a tent or Gaussian filter, every recorded tree equals its rendered
/// pixel bit for bit at 1 and 4 samples per pixel; and a mesh scene's packet render (camera rays
/// of 64 pixels, each from its own lens point) equals its pixels traced one by one.
#[test]
fn trees_equal_pixels_with_a_lens_and_filters() {
    let filters = [
        FilterDesc::Tent { radius: 1.5 },
        FilterDesc::Gaussian {
            sigma: 0.6,
            radius: Some(2.0),
        },
    ];
    for filter in filters {
        for spp in [1, 4] {
            let mut s = small(dof(), 32, 18, spp);
            s.settings.filter = filter;
            let image = render(&SceneIntegrator::new(&s), &RenderOptions::new(), &|_| {}).image;
            for y in 0..18 {
                for x in 0..32 {
                    let tree = trace_pixel(&s, x, y).unwrap();
                    assert_eq!(
                        tree.radiance,
                        image.get(x, y),
                        "{filter:?} spp {spp} ({x}, {y})"
                    );
                    assert_eq!(tree.samples.len() as u32, spp);
                }
            }
            let mut mesh = small(icosphere_scene(2, 20, 3.0), 20, 20, spp);
            mesh.camera.aperture_radius = 0.2;
            mesh.camera.focus_distance = 2.5;
            mesh.settings.filter = filter;
            let image = render(&SceneIntegrator::new(&mesh), &RenderOptions::new(), &|_| {}).image;
            for y in 0..20 {
                for x in 0..20 {
                    let mut counts = RayCounts::default();
                    let l = render_pixel(
                        &SceneIntegrator::new(&mesh),
                        &mut SceneSampler::for_settings(&mesh.settings),
                        (x, y),
                        &mut TreeRecorder::default(),
                        &mut counts,
                        |_| {},
                    )
                    .0;
                    assert_eq!(l, image.get(x, y), "mesh {filter:?} spp {spp} ({x}, {y})");
                }
            }
        }
    }
}

/// The lens is used: an aperture changes the image, and camera rays leave from the lens.
#[test]
fn an_aperture_blurs_and_camera_rays_leave_from_the_lens() {
    let s = small(dof(), 48, 27, 4);
    let mut pin = s.clone();
    pin.camera.aperture_radius = 0.0;
    assert_ne!(
        render(&SceneIntegrator::new(&s), &RenderOptions::new(), &|_| {}).image,
        render(&SceneIntegrator::new(&pin), &RenderOptions::new(), &|_| {}).image
    );
    let tree = trace_pixel(&s, 10, 20).unwrap();
    let p = s.camera.position;
    for sample in &tree.samples {
        let o = tree.nodes[sample.root.0 as usize].origin;
        assert!(o != p && (o - p).length() <= 0.15 * (1.0 + 1e-12), "{o}");
    }
}

/// Bad apertures, focus distances and filters are refused with the flag or JSON path (and
/// line:column), exit 2 and nothing written; good flags render.
#[test]
fn bad_lens_and_filter_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let r = ["render", "--size", "16x9", "-o", "out.png"];
    fn with<'a>(r: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [r, extra].concat()
    }
    fails_with(
        d,
        &with(&r, &["--aperture", "-0.1"]),
        "--aperture: must be a finite number >= 0, got -0.1",
    );
    fails_with(
        d,
        &with(&r, &["--focus", "0"]),
        "--focus: must be a finite number > 0, got 0",
    );
    fails_with(
        d,
        &with(&r, &["--focus", "-2"]),
        "--focus: must be a finite number > 0",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "tent:0"]),
        "--filter: radius must be a finite number > 0, got 0",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "tent:-1"]),
        "--filter: radius must be a finite number > 0",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "gaussian:0"]),
        "--filter: sigma must be a finite number > 0",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "gaussian"]),
        "--filter: gaussian needs its sigma",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "mitchell"]),
        "--filter: unknown filter \"mitchell\"",
    );
    fails_with(
        d,
        &with(&r, &["--filter", "tent:wide"]),
        "--filter: radius \"wide\" is not a number",
    );
    for cmd in [
        &["trace", "--pixel", "1,1"][..],
        &["diagram", "--pixel", "1,1", "-o", "d.svg"],
        &["effects"],
        &["cost", "--quick", "--repeats", "1", "-o", "cost"],
        &[
            "acne",
            "--size",
            "8x6",
            "--scales",
            "1",
            "--epsilons",
            "1e-4",
            "-o",
            "acne",
        ],
    ] {
        fails_with(d, &[cmd, &["--aperture", "-1"]].concat(), "--aperture");
        fails_with(d, &[cmd, &["--filter", "tent:0"]].concat(), "--filter");
        fails_with(d, &[cmd, &["--focus", "0"]].concat(), "--focus");
    }
    let scene = |camera: &str, settings: &str| {
        format!(
            "{{\"camera\": {{\"position\": [0,0,5], \"look_at\": [0,0,0], \"fov_y\": 40,\n  \"width\": 4, \"height\": 3{camera}}},\n \"settings\": {{{settings}}}}}"
        )
    };
    let cases = [
        (
            scene(", \"aperture_radius\": -0.5", ""),
            "s.json:2:",
            "camera.aperture_radius: must be a finite number >= 0",
        ),
        (
            scene(", \"focus_distance\": 0", ""),
            "s.json:2:",
            "camera.focus_distance: must be a finite number > 0",
        ),
        (
            scene("", "\"filter\": {\"type\": \"tent\", \"radius\": 0}"),
            "s.json:3:",
            "settings.filter.radius: must be a finite number > 0",
        ),
        (
            scene("", "\"filter\": {\"type\": \"gaussian\", \"sigma\": -1}"),
            "s.json:3:",
            "settings.filter.sigma: must be a finite number > 0",
        ),
        (
            scene(
                "",
                "\"filter\": {\"type\": \"gaussian\", \"sigma\": 1, \"radius\": 0}",
            ),
            "s.json:3:",
            "settings.filter.radius",
        ),
        (
            scene("", "\"filter\": {\"type\": \"mitchell\"}"),
            "s.json:3:",
            "settings.filter",
        ),
    ];
    for (src, at, text) in cases {
        std::fs::write(d.join("s.json"), &src).unwrap();
        fails_with(d, &["render", "s.json", "-o", "out.png"], at);
        fails_with(d, &["render", "s.json", "-o", "out.png"], text);
    }
    let o = raytree(
        &with(
            &r,
            &[
                "--aperture",
                "0.1",
                "--focus",
                "6",
                "--filter",
                "gaussian:0.5",
                "--spp",
                "2",
            ],
        ),
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = raytree(
        &[
            "trace", "--pixel", "3,3", "--size", "16x9", "--json", "--filter", "tent:2",
        ],
        d,
    );
    assert!(o.status.success());
    let json = String::from_utf8_lossy(&o.stdout);
    assert!(json.contains("\"filter\""), "the tree records the filter");
}
