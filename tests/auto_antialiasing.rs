//! Automatic antialiasing (`settings.antialiasing: "auto"`, the default; issue 18): where the
//! image is a function of the film position alone, every pixel takes a first pass of
//! `max(2, spp / 16)` Sobol points and only the pixels on an edge go on to `spp`.

mod common;
use common::raytree;

use raytree::integrator::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::render::adaptive_plan;
use raytree::scene::{AdaptiveDesc, Antialiasing, IntegratorKind, SamplerKind};
use raytree::{Scene, render, trace_pixel};

fn fixture(name: &str) -> Scene {
    let path = format!("{}/fixtures/{name}.json", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn glass_emitters(w: u32, h: u32, spp: u32) -> Scene {
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let mut scene = Scene::from_json(src).unwrap();
    scene.camera = scene.camera.with_size(w, h);
    scene.settings.max_depth = 16;
    scene.settings.spp = spp;
    scene
}

fn plan(scene: &Scene) -> Option<raytree::render::AdaptivePlan> {
    adaptive_plan(&SceneIntegrator::new(scene))
}

/// Auto applies to the deterministic Whitted image at 2 spp or more, and nowhere else: not at
/// 1 spp, not under `uniform`, not with a chosen sampler, not under the path integrator, and
/// not where a sample draws more than its film position (area lights, rough lobes, a lens, the
/// dielectric roulette). An explicit `settings.adaptive` is its own plan.
#[test]
fn auto_only_where_the_image_depends_on_the_film_position_alone() {
    let with = |mut s: Scene, f: &dyn Fn(&mut Scene)| {
        f(&mut s);
        s
    };
    for name in ["classic", "nested", "mirrors", "tir-block"] {
        let scene = with(fixture(name), &|s| s.settings.spp = 8);
        let p = plan(&scene).unwrap_or_else(|| panic!("{name}"));
        assert!(p.auto && (p.first, p.total) == (2, 8), "{name}: {p:?}");
    }
    let classic = fixture("classic");
    let not_auto = [
        ("1 spp", with(classic.clone(), &|s| s.settings.spp = 1)),
        (
            "uniform",
            with(classic.clone(), &|s| {
                s.settings.spp = 8;
                s.settings.antialiasing = Antialiasing::Uniform;
            }),
        ),
        (
            "sampler",
            with(classic.clone(), &|s| {
                s.settings.spp = 8;
                s.settings.sampler = Some(SamplerKind::Stratified);
            }),
        ),
        (
            "path",
            with(classic.clone(), &|s| {
                s.settings.spp = 8;
                s.settings.integrator = IntegratorKind::Path;
            }),
        ),
        (
            "roulette",
            with(classic.clone(), &|s| {
                s.settings.spp = 8;
                s.settings.whitted.dielectric_roulette = Some(2);
            }),
        ),
        (
            "soft shadows",
            with(fixture("soft-shadows"), &|s| s.settings.spp = 8),
        ),
        ("glossy", with(fixture("glossy"), &|s| s.settings.spp = 8)),
        ("lens", fixture("depth-of-field")),
    ];
    for (why, scene) in &not_auto {
        assert_eq!(plan(scene), None, "{why}");
    }
    let explicit = with(classic, &|s| {
        s.settings.spp = 4;
        s.settings.adaptive = Some(AdaptiveDesc {
            threshold: 0.2,
            max_spp: Some(12),
        });
    });
    let p = plan(&explicit).unwrap();
    assert!(!p.auto && (p.first, p.total, p.threshold) == (4, 12, 0.2));
}

/// The auto image recomputed from uniform renders, independently of the adaptive code: a
/// pixel whose first-pass samples (the uniform render at `first` spp under the Sobol sampler,
/// traced) and its 8 neighbours' first-pass means differ by a contrast above
/// [`raytree::scene::AUTO_THRESHOLD`] is the uniform Sobol render at `spp`; any other pixel
/// is its first-pass mean. Returns the image and which pixels are edges.
fn composed(auto: &Scene) -> (raytree::Image, Vec<bool>) {
    let (w, h) = (auto.camera.width, auto.camera.height);
    let first = plan(auto).unwrap().first;
    let mut sobol = auto.clone();
    sobol.settings.sampler = Some(SamplerKind::Sobol);
    let full = render(
        &SceneIntegrator::new(&sobol),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    sobol.settings.spp = first;
    let firsts = render(
        &SceneIntegrator::new(&sobol),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let mut image = firsts.clone();
    let mut edges = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let tree = trace_pixel(&sobol, x, y).unwrap();
            let mut values: Vec<_> = tree.samples.iter().map(|s| s.radiance).collect();
            for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                if (dx, dy) != (0, 0) && (0..w as i32).contains(&nx) && (0..h as i32).contains(&ny)
                {
                    values.push(firsts.get(nx as u32, ny as u32));
                }
            }
            let edge = raytree::sampling::contrast(&values) > raytree::scene::AUTO_THRESHOLD;
            if edge {
                image.pixels[(y * w + x) as usize] = full.get(x, y);
            }
            edges.push(edge);
        }
    }
    (image, edges)
}

/// Auto at 16 spp, bit for bit, is the image [`composed`] from uniform renders: a first pass of
/// 2 Sobol points, 16 on the edges. At 1 spp auto is the uniform render.
#[test]
fn auto_is_the_first_pass_or_the_sobol_render_at_edges() {
    let (w, h) = (48, 27);
    let auto = glass_emitters(w, h, 16);
    let (a, stats, map) =
        render(&SceneIntegrator::new(&auto), &RenderOptions::new(), &|_| {}).into_parts();
    let (want, edges) = composed(&auto);
    assert_eq!(a, want);
    for (i, &edge) in edges.iter().enumerate() {
        assert_eq!(map.samples[i], if edge { 16 } else { 2 }, "pixel {i}");
    }
    let refined = edges.iter().filter(|&&e| e).count() as u64;
    let pixels = u64::from(w * h);
    assert_eq!(stats.refined_pixels, refined);
    assert!(refined > 0 && refined < pixels, "{refined}");
    assert_eq!(stats.samples, 2 * pixels + 14 * refined);

    let one = glass_emitters(48, 27, 1);
    let mut uniform = one.clone();
    uniform.settings.antialiasing = Antialiasing::Uniform;
    assert_eq!(
        render(&SceneIntegrator::new(&one), &RenderOptions::new(), &|_| {}).image,
        render(
            &SceneIntegrator::new(&uniform),
            &RenderOptions::new(),
            &|_| {}
        )
        .image
    );
}

/// Above 16 spp auto's first pass is `spp / 16` Sobol points, refined by continuing the Sobol
/// sequence: bit for bit `settings.adaptive` with that first pass under the Sobol sampler. Its
/// error keeps falling with spp (a fixed first pass misses, at any spp, features thinner than
/// its sample spacing: one probe per pixel centre, tried first, sat at about 0.006 here).
#[test]
fn above_16_spp_the_first_pass_grows_and_the_error_keeps_falling() {
    let auto = glass_emitters(48, 27, 64);
    assert_eq!(plan(&auto).map(|p| (p.first, p.total)), Some((4, 64)));
    let mut explicit = auto.clone();
    explicit.settings.spp = 4;
    explicit.settings.sampler = Some(SamplerKind::Sobol);
    explicit.settings.adaptive = Some(AdaptiveDesc {
        threshold: raytree::scene::AUTO_THRESHOLD,
        max_spp: Some(64),
    });
    let (a, sa, ma) =
        render(&SceneIntegrator::new(&auto), &RenderOptions::new(), &|_| {}).into_parts();
    let (e, se, me) = render(
        &SceneIntegrator::new(&explicit),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert_eq!(a, e);
    assert_eq!(ma.samples, me.samples);
    assert_eq!(sa.samples, se.samples);
    assert!(ma.samples.iter().all(|&n| n == 4 || n == 64));
    let tree = trace_pixel(&auto, 20, 13).unwrap();
    assert_eq!(tree.radiance, a.get(20, 13));
    assert_eq!(tree.edge, Some(tree.samples.len() == 64));

    let mut reference = auto.clone();
    reference.settings.antialiasing = Antialiasing::Uniform;
    (reference.settings.spp, reference.settings.seed) = (1024, 5);
    let reference = render(
        &SceneIntegrator::new(&reference),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let err = |spp: u32| {
        let mut s = auto.clone();
        s.settings.spp = spp;
        rel_rmse(
            &render(&SceneIntegrator::new(&s), &RenderOptions::new(), &|_| {}).image,
            &reference,
        )
    };
    let (e16, e64, e256) = (err(16), err(64), err(256));
    eprintln!("auto rel-RMSE: 16 spp {e16:.5}, 64 spp {e64:.5}, 256 spp {e256:.5}");
    assert!(e64 < 0.7 * e16 && e256 < 0.7 * e64, "{e16} {e64} {e256}");
}

/// Every pixel's tree is the rendered pixel bit for bit under auto, with the samples the render
/// took (1 or spp), numbered in order.
#[test]
fn trees_equal_pixels_under_auto() {
    let scene = glass_emitters(32, 18, 8);
    let (image, stats, map) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert!(stats.refined_pixels > 0);
    for y in 0..18 {
        for x in 0..32 {
            let tree = trace_pixel(&scene, x, y).unwrap();
            assert_eq!(tree.radiance, image.get(x, y), "pixel {x},{y}");
            let n = map.samples[(y * 32 + x) as usize];
            assert_eq!(tree.samples.len(), n as usize, "pixel {x},{y}");
            assert!(tree.samples.iter().zip(0..).all(|(s, i)| s.index == i));
        }
    }
}

fn rel_rmse(a: &raytree::Image, b: &raytree::Image) -> f64 {
    let n = 3.0 * a.pixels.len() as f64;
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| {
            let (p, q) = (p.to_array(), q.to_array());
            (0..3).map(move |i| ((p[i] - q[i]) / (q[i] + 0.01)).powi(2))
        })
        .sum();
    (sum / n).sqrt()
}

/// On glass, water and mirrors before emitters, auto at 16 spp has about the error of the
/// uniform 16-spp render against a 1024-spp uniform reference (another seed), with under half
/// of its samples (0.0175 against 0.0172 with 0.48 of the samples when written), and a quarter
/// of the 1-spp render's error: a rule that missed edges would sit near the latter.
#[test]
fn auto_beats_uniform_with_fewer_samples() {
    let auto = glass_emitters(80, 45, 16);
    let mut uniform = auto.clone();
    uniform.settings.antialiasing = Antialiasing::Uniform;
    let mut reference = uniform.clone();
    (reference.settings.spp, reference.settings.seed) = (1024, 99);
    let reference = render(
        &SceneIntegrator::new(&reference),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let mut one = uniform.clone();
    one.settings.spp = 1;
    let (image, stats, _) =
        render(&SceneIntegrator::new(&auto), &RenderOptions::new(), &|_| {}).into_parts();
    let e_auto = rel_rmse(&image, &reference);
    let e_uniform = rel_rmse(
        &render(
            &SceneIntegrator::new(&uniform),
            &RenderOptions::new(),
            &|_| {},
        )
        .image,
        &reference,
    );
    let e_one = rel_rmse(
        &render(&SceneIntegrator::new(&one), &RenderOptions::new(), &|_| {}).image,
        &reference,
    );
    let pixels = 80 * 45;
    eprintln!(
        "auto {e_auto:.5} ({} samples), uniform 16 spp {e_uniform:.5}, 1 spp {e_one:.5}",
        stats.samples
    );
    assert!(stats.samples * 2 < 16 * pixels, "{}", stats.samples);
    assert!(
        e_auto < 1.1 * e_uniform,
        "auto {e_auto} uniform {e_uniform}"
    );
    assert!(e_auto < 0.25 * e_one, "auto {e_auto} 1 spp {e_one}");
}

/// `raytree render` says what auto did and `--antialiasing uniform` turns it off; the tree of a
/// refined pixel has `spp` samples.
#[test]
fn render_reports_auto_and_uniform_turns_it_off() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    std::fs::write(d.join("s.json"), src).unwrap();
    let size = ["--size", "40x24", "--spp", "8"];
    let run = |extra: &[&str]| {
        let args = [&["render", "s.json", "-o", "a.png"], &size[..], extra].concat();
        let o = raytree(&args, d);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let out = run(&["--spp-map", "m.png"]);
    assert!(
        out.contains("antialiasing auto: ") && out.contains("pixels on an edge took 8 spp"),
        "{out}"
    );
    let map = image::open(d.join("m.png")).unwrap().into_rgb8();
    let i = map.pixels().position(|p| p.0 == [255; 3]).unwrap() as u32;
    assert!(map.pixels().any(|p| p.0 == [0; 3]));
    let pixel = format!("{},{}", i % 40, i / 40);
    let args = [
        &["trace", "s.json", "--json", "--pixel", &pixel][..],
        &size[..],
    ]
    .concat();
    let o = raytree(&args, d);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tree: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(tree["samples"].as_array().unwrap().len(), 8);
    assert_eq!(tree["edge"], true);
    // The text tree says so too, and a pixel without an edge has its first pass.
    let args = [&["trace", "s.json", "--pixel", &pixel][..], &size[..]].concat();
    let text = String::from_utf8_lossy(&raytree(&args, d).stdout).into_owned();
    assert!(
        text.contains("spp 8 (automatic antialiasing: an edge)") && text.contains("sampler sobol"),
        "{text}"
    );
    let j = map.pixels().position(|p| p.0 == [0; 3]).unwrap() as u32;
    let flat = format!("{},{}", j % 40, j / 40);
    let args = [&["trace", "s.json", "--pixel", &flat][..], &size[..]].concat();
    let text = String::from_utf8_lossy(&raytree(&args, d).stdout).into_owned();
    assert!(
        text.contains("spp 8 (automatic antialiasing: no edge, 2 taken)"),
        "{text}"
    );
    let out = run(&["--antialiasing", "uniform"]);
    assert!(!out.contains("antialiasing auto"), "{out}");
}

/// The inspector's image path, bands of rows (`render_rows`), gives the render's pixels under
/// auto and under an explicit `settings.adaptive` (stratified passes): each band takes the
/// first passes of the rows beside it for the decisions at its edges.
#[test]
fn bands_of_rows_equal_the_render_under_auto() {
    let auto = glass_emitters(40, 23, 8);
    assert!(plan(&auto).is_some_and(|p| p.auto));
    let mut explicit = glass_emitters(40, 23, 2);
    explicit.settings.adaptive = Some(AdaptiveDesc {
        threshold: 0.05,
        max_spp: Some(12),
    });
    for scene in [auto, explicit] {
        let integrator = SceneIntegrator::new(&scene);
        let mut pixels = Vec::new();
        for y0 in (0..23).step_by(7) {
            let (band, _) = raytree::render::render_rows(&integrator, y0..(y0 + 7).min(23));
            assert_eq!(band.len(), 40 * ((y0 + 7).min(23) - y0) as usize);
            pixels.extend(band);
        }
        assert_eq!(
            pixels,
            render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {}
            )
            .image
            .pixels
        );
    }
}

mod random_scenes {
    use super::*;
    use proptest::prelude::*;

    /// A sphere: centre, radius and material (0 glass, 1 mirror, 2 lamp, 3 water).
    fn sphere() -> impl Strategy<Value = ([f64; 3], f64, u8)> {
        (
            [-1.5f64..1.5, -1.0f64..1.0, -5.0f64..-2.0],
            0.2f64..0.9,
            0u8..4,
        )
    }

    fn scene(spheres: &[([f64; 3], f64, u8)], spp: u32, seed: u64) -> Scene {
        let objects: Vec<String> = spheres
            .iter()
            .map(|(c, r, m)| {
                let m = ["glass", "mirror", "lamp", "water"][*m as usize];
                format!(
                    r#"{{"type": "sphere", "center": [{}, {}, {}], "radius": {r}, "material": "{m}"}}"#,
                    c[0], c[1], c[2]
                )
            })
            .collect();
        let src = format!(
            r#"{{
              "camera": {{"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 50, "width": 16, "height": 12}},
              "background": [0.2, 0.3, 0.5],
              "materials": {{
                "glass": {{"transmissivity": [1, 1, 1], "ior": 1.5}},
                "water": {{"transmissivity": [0.9, 1, 1], "ior": 1.33}},
                "mirror": {{"reflectivity": [0.9, 0.9, 0.9]}},
                "lamp": {{"emission": [3, 2, 1]}}
              }},
              "objects": [{}],
              "settings": {{"spp": {spp}, "seed": {seed}, "max_depth": 8}}
            }}"#,
            objects.join(", ")
        );
        Scene::from_json(&src).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

        /// On random glass, water, mirror and lamp spheres: the auto image is the one
        /// [`composed`] from uniform renders, bit for bit, every pixel finite; a pixel's tree
        /// equals its pixel with the samples the render took.
        #[test]
        fn auto_composes_first_pass_and_sobol_renders(
            spheres in prop::collection::vec(sphere(), 1..5),
            spp in 2u32..9,
            seed in 0u64..1000,
            pixel in (0u32..16, 0u32..12),
        ) {
            let auto = scene(&spheres, spp, seed);
            prop_assert!(plan(&auto).is_some_and(|p| p.auto));
            let (a, _, map) = render(&SceneIntegrator::new(&auto), &RenderOptions::new(), &|_| {}).into_parts();
            prop_assert_eq!(&a, &composed(&auto).0);
            prop_assert!(a.pixels.iter().all(|p| p.is_finite()));
            let (x, y) = pixel;
            let tree = trace_pixel(&auto, x, y).unwrap();
            prop_assert_eq!(tree.radiance, a.get(x, y));
            prop_assert_eq!(tree.samples.len() as u32, map.samples[(y * 16 + x) as usize]);
        }
    }
}
