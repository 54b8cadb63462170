//! Adaptive antialiasing (`settings.adaptive`, issue 18): more samples only where a pixel's
//! first pass (or its neighbours') disagrees, decided from the same bits when one pixel is
//! re-traced, so that its tree records exactly the samples the render used. The automatic
//! default (`settings.antialiasing`) is in `tests/auto_antialiasing.rs`.

mod common;
use common::{fails_with, raytree};

use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::scene::{AdaptiveDesc, icosphere_scene};
use raytree::{Scene, render, trace_pixel};

fn adaptive(threshold: f64, max_spp: u32) -> Option<AdaptiveDesc> {
    Some(AdaptiveDesc {
        threshold,
        max_spp: Some(max_spp),
    })
}

/// An emissive sphere in front of a constant background, and a glass ball that shows part of
/// it: flat regions, edges at the silhouettes and a refracted edge.
fn disc(spp: u32) -> Scene {
    let src = r#"{
      "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 40, "width": 32, "height": 24},
      "background": [0.1, 0.2, 0.3],
      "materials": {"lamp": {"emission": [1.0, 0.8, 0.5]}, "glass": {"transmissivity": [1, 1, 1], "ior": 1.5}},
      "objects": [
        {"type": "sphere", "center": [0.1, 0.05, -5], "radius": 1.1, "material": "lamp"},
        {"type": "sphere", "center": [-1.1, -0.5, -3.5], "radius": 0.5, "material": "glass"}
      ],
      "settings": {"spp": SPP, "antialiasing": "uniform"}
    }"#;
    Scene::from_json(&src.replace("SPP", &spp.to_string())).unwrap()
}

fn glass_emitters(w: u32, h: u32) -> Scene {
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let mut scene = Scene::from_json(src).unwrap();
    scene.camera = scene.camera.with_size(w, h);
    scene.settings.max_depth = 16;
    scene
}

/// Threshold 0: a pixel is refined exactly when its first-pass samples (traced without the
/// adaptive setting) and its 8 neighbours' first-pass means (the uniform render's pixels) are
/// not all equal; flat pixels keep `spp`, the silhouette and the pixels beside it take
/// `max_spp`.
#[test]
fn flat_pixels_keep_spp_and_edges_take_more() {
    let uniform = disc(4);
    let mut scene = uniform.clone();
    scene.settings.adaptive = adaptive(0.0, 36);
    let (image, stats, map) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let means = render(
        &SceneIntegrator::new(&uniform),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let (w, h) = (scene.camera.width, scene.camera.height);
    assert_eq!(map.samples.len(), (w * h) as usize);
    let mut refined = 0;
    for y in 0..h {
        for x in 0..w {
            let first = trace_pixel(&uniform, x, y).unwrap();
            let l0 = first.samples[0].radiance;
            let mut values: Vec<_> = first.samples.iter().map(|s| s.radiance).collect();
            for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                if (0..w as i32).contains(&nx) && (0..h as i32).contains(&ny) {
                    values.push(means.get(nx as u32, ny as u32));
                }
            }
            let edge = values.iter().any(|&v| v != l0);
            let n = map.samples[(y * w + x) as usize];
            assert_eq!(n, if edge { 36 } else { 4 }, "pixel {x},{y}");
            refined += u32::from(edge);
            if !edge {
                assert_eq!(image.get(x, y), first.radiance, "flat pixel {x},{y}");
            }
        }
    }
    assert_eq!(stats.refined_pixels, u64::from(refined));
    assert_eq!(stats.samples, u64::from(w * h * 4 + refined * 32));
    // The centre and the corners are flat; the silhouettes (rings of about 2 pi r pixels, 3
    // pixels wide) are refined and are a small part of the image.
    assert_eq!(map.samples[(12 * w + 16) as usize], 4);
    assert_eq!(map.samples[0], 4);
    assert!((20..300).contains(&refined), "{refined} refined pixels");
}

/// A threshold above every contrast refines nothing: the image is the uniform render's.
#[test]
fn a_high_threshold_is_the_uniform_render() {
    let uniform = disc(4);
    let mut scene = uniform.clone();
    scene.settings.adaptive = adaptive(1.0, 64);
    let (image, stats, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert_eq!(stats.refined_pixels, 0);
    assert_eq!(
        image,
        render(
            &SceneIntegrator::new(&uniform),
            &RenderOptions::new(),
            &|_| {}
        )
        .image
    );
}

/// Every pixel's tree is the rendered pixel bit for bit with adaptive antialiasing on, with as
/// many samples as the render took, numbered in order; for the glass scene and for a mesh scene
/// (whose uniform render traces camera packets).
#[test]
fn trees_equal_pixels_with_adaptive_on() {
    let mut glass = glass_emitters(40, 24);
    glass.settings.spp = 4;
    glass.settings.adaptive = adaptive(0.05, 32);
    let mut mesh = icosphere_scene(2, 20, 3.0);
    mesh.camera = mesh.camera.with_size(20, 20);
    mesh.settings.spp = 2;
    mesh.settings.adaptive = adaptive(0.02, 10);
    for scene in [glass, mesh] {
        let (image, stats, map) = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        assert!(stats.refined_pixels > 0);
        let w = scene.camera.width;
        for y in 0..scene.camera.height {
            for x in 0..w {
                let tree = trace_pixel(&scene, x, y).unwrap();
                assert_eq!(tree.radiance, image.get(x, y), "pixel {x},{y}");
                let n = map.samples[(y * w + x) as usize];
                assert_eq!(tree.samples.len(), n as usize, "pixel {x},{y}");
                assert!(tree.samples.iter().zip(0..).all(|(s, i)| s.index == i));
            }
        }
        assert_eq!(
            image,
            render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {}
            )
            .image
        );
    }
}

fn rmse(a: &raytree::Image, b: &raytree::Image) -> f64 {
    let n = a.pixels.len() as f64;
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).length_squared())
        .sum();
    (sum / n).sqrt()
}

/// At equal (or more) total samples, uniform stratified sampling's error against an
/// independent 1024-spp reference (another seed) is well above adaptive antialiasing's, on the
/// emissive sphere with a glass ball before it (silhouettes and a refracted edge).
#[test]
fn adaptive_beats_uniform_at_equal_samples() {
    let mut base = disc(4);
    base.camera = base.camera.with_size(64, 48);
    let mut reference = base.clone();
    (reference.settings.spp, reference.settings.seed) = (1024, 99);
    let reference = render(
        &SceneIntegrator::new(&reference),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let mut ad = base.clone();
    ad.settings.adaptive = adaptive(0.05, 64);
    let (image, stats, _) =
        render(&SceneIntegrator::new(&ad), &RenderOptions::new(), &|_| {}).into_parts();
    let pixels = u64::from(64 * 48u32);
    assert!(
        stats.refined_pixels * 4 < pixels,
        "{} refined",
        stats.refined_pixels
    );
    let spp = stats.samples.div_ceil(pixels) as u32;
    let mut uniform = base.clone();
    uniform.settings.spp = spp;
    let (e_ad, e_un) = (
        rmse(&image, &reference),
        rmse(
            &render(
                &SceneIntegrator::new(&uniform),
                &RenderOptions::new(),
                &|_| {},
            )
            .image,
            &reference,
        ),
    );
    eprintln!(
        "adaptive {e_ad:.5} ({} samples), uniform {e_un:.5} ({spp} spp)",
        stats.samples
    );
    assert!(
        e_ad < 0.5 * e_un,
        "adaptive {e_ad:.5} ({} samples) against uniform {e_un:.5} at {spp} spp",
        stats.samples
    );
}

/// The flags: `--adaptive T --max-spp N` through `render` and `trace`; bad values exit 2 and
/// write nothing.
#[test]
fn flags_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    std::fs::write(d.join("s.json"), src).unwrap();
    let fails = |args: &[&str], text: &str| fails_with(d, args, text);
    fails(
        &["render", "s.json", "--antialiasing", "edges", "-o", "a.png"],
        "--antialiasing: unknown mode \"edges\", expected auto or uniform",
    );
    fails(
        &[
            "render",
            "s.json",
            "--spp",
            "4",
            "--adaptive",
            "-1",
            "-o",
            "a.png",
        ],
        "--adaptive: must be a finite number >= 0",
    );
    fails(
        &[
            "render",
            "s.json",
            "--spp",
            "4",
            "--max-spp",
            "8",
            "-o",
            "a.png",
        ],
        "--max-spp: needs adaptive",
    );
    fails(
        &[
            "render",
            "s.json",
            "--spp",
            "4",
            "--adaptive",
            "0.1",
            "--max-spp",
            "3",
            "-o",
            "a.png",
        ],
        "--max-spp: must be in spp..=65536",
    );
    fails(
        &[
            "render",
            "s.json",
            "--spp",
            "4",
            "--adaptive",
            "0.1",
            "--spp-map",
            "m.exr",
            "-o",
            "a.png",
        ],
        "--spp-map",
    );
    // The map would overwrite the image it describes.
    fails(
        &[
            "render",
            "s.json",
            "--spp",
            "2",
            "--spp-map",
            "a.png",
            "-o",
            "a.png",
        ],
        "--spp-map a.png is the output image",
    );
    let bad = src.replace(
        r#""max_depth": 32"#,
        r#""max_depth": 32, "spp": 4, "adaptive": {"threshold": 0.1, "max_spp": 2}"#,
    );
    std::fs::write(d.join("s.json"), bad).unwrap();
    fails(
        &["render", "s.json", "-o", "a.png"],
        "settings.adaptive.max_spp",
    );
    std::fs::write(d.join("s.json"), src).unwrap();
    let flags = [
        "--size",
        "40x24",
        "--spp",
        "4",
        "--adaptive",
        "0.05",
        "--max-spp",
        "20",
    ];
    let o = raytree(
        &[
            &["render", "s.json", "-o", "a.exr", "--spp-map", "m.png"],
            &flags[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("pixels refined to 20 spp"), "{out}");
    let map = image::open(d.join("m.png")).unwrap().into_rgb8();
    assert_eq!(map.dimensions(), (40, 24));
    let white = map.pixels().filter(|p| p.0 == [255; 3]).count();
    let black = map.pixels().filter(|p| p.0 == [0; 3]).count();
    assert!(
        white > 0 && black > 0 && white + black == 40 * 24,
        "{white} {black}"
    );
    // The tree of a white (refined) pixel has 20 samples.
    let i = map.pixels().position(|p| p.0 == [255; 3]).unwrap() as u32;
    let pixel = format!("{},{}", i % 40, i / 40);
    let o = raytree(
        &[
            &["trace", "s.json", "--json", "--pixel", &pixel],
            &flags[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tree: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(tree["samples"].as_array().unwrap().len(), 20);
    assert_eq!(tree["settings"]["adaptive"]["max_spp"], 20);
}
