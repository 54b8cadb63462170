//! Adaptive antialiasing through the pixel loop's other sinks: the AOV render, the debug views
//! and the denoiser's gather take exactly the adaptive render's samples (`settings.adaptive`,
//! `--adaptive T --max-spp N`), and the CLI combinations that were refused now run; those that
//! still make no sense exit 2 and write nothing.

mod common;
use common::{fails_with, raytree};

use raytree::aov::{CLASSES, McView, render_aovs, standard_classes};
use raytree::denoise::{DenoiseParams, denoise, gather};
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::scene::AdaptiveDesc;
use raytree::{Scene, SceneIntegrator, render};

const CAUSTIC: &str = include_str!("../fixtures/caustic.json");

/// The caustic fixture (path integrator) at 64x48, 2 spp, refined to 8 spp where the first
/// pass differs by more than 0.1.
fn adaptive_caustic() -> Scene {
    let mut s = Scene::from_json(CAUSTIC).unwrap();
    s.camera = s.camera.with_size(64, 48);
    s.settings.spp = 2;
    s.settings.adaptive = Some(AdaptiveDesc {
        threshold: 0.1,
        max_spp: Some(8),
    });
    s
}

/// The AOV render of an adaptive scene: its beauty is `render`'s bit for bit (and not the
/// uniform render's), the six light transport classes sum to it within 1e-12, and its
/// `spp` debug view is `--spp-map`'s per-pixel sample counts.
#[test]
fn aovs_and_the_spp_view_follow_the_adaptive_render() {
    let scene = adaptive_caustic();
    let (image, stats, map) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let total = (scene.camera.width * scene.camera.height) as u64;
    assert!(
        stats.refined_pixels > 0 && stats.refined_pixels < total,
        "{} of {total} refined: not a test of the two passes",
        stats.refined_pixels
    );
    let r = render_aovs(&SceneIntegrator::new(&scene), &standard_classes(), &|_| {}).unwrap();
    assert_eq!(r.beauty, image);
    assert_eq!(r.stats, stats);
    let mut uniform = scene.clone();
    uniform.settings.adaptive = None;
    assert_ne!(
        r.beauty,
        render(
            &SceneIntegrator::new(&uniform),
            &RenderOptions::new(),
            &|_| {}
        )
        .image
    );
    let mut lit = [false; CLASSES.len()];
    for (i, p) in r.beauty.pixels.iter().enumerate() {
        let sum = r.aovs.iter().fold(Rgb::ZERO, |s, a| s + a.pixels[i]);
        let err = (sum - *p).abs().max_element();
        assert!(
            err <= 1e-12 * p.max_element().max(1.0),
            "pixel {i}: {sum} vs {p}"
        );
        for (k, a) in r.aovs.iter().enumerate() {
            lit[k] |= a.pixels[i] != Rgb::ZERO;
        }
    }
    assert!(lit[2] && lit[4], "direct light and caustics: {lit:?}");
    let spp: Vec<f64> = map.samples.iter().map(|&n| f64::from(n)).collect();
    assert_eq!(McView::Spp.values(&r), spp);
    assert!(spp.contains(&2.0) && spp.contains(&8.0));
    // Every pixel's statistics are over all its samples: a refined pixel's noise estimate
    // comes from 8 samples.
    assert!(r.mc.iter().zip(&map.samples).all(|(p, &n)| p.samples == n));
}

/// The denoiser's gather of an adaptive scene renders the adaptive image bit for bit, with
/// finite features, and the denoised image is finite.
#[test]
fn the_gather_of_an_adaptive_scene_is_the_adaptive_render() {
    let scene = adaptive_caustic();
    let (image, stats, _) = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let (raw, gstats, features) = gather(&SceneIntegrator::new(&scene), &|_| {});
    assert_eq!(raw, image);
    assert_eq!(gstats, stats);
    assert!(stats.refined_pixels > 0);
    assert_eq!(features.spp, 2);
    assert!(features.variance.iter().all(|v| v.is_finite() && *v >= 0.0));
    let out = denoise(&raw, &features, &DenoiseParams::default());
    assert!(out.pixels.iter().all(|p| p.is_finite()));
    assert_ne!(out, raw);
}

/// A temporary directory holding the caustic scene as `s.json`.
fn dir_with_scene() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("s.json"), CAUSTIC).unwrap();
    d
}

const ADAPTIVE: [&str; 9] = [
    "render",
    "s.json",
    "--size",
    "48x36",
    "--spp",
    "2",
    "--adaptive",
    "0.1",
    "--max-spp=8",
];

fn run_ok(d: &std::path::Path, extra: &[&str]) -> String {
    let mut args = ADAPTIVE.to_vec();
    args.extend_from_slice(extra);
    let o = raytree(&args, d);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `--denoise`, `--features`, `--aov` and `--debug-view` with `--adaptive`, and `--spp-map`
/// with them (refused with exit 2 before the pixel loop): exit 0, every file written; the AOV run's beauty EXR is the plain
/// adaptive render's byte for byte, and `--features` leaves the image the plain render's.
#[test]
fn formerly_refused_adaptive_combinations_run() {
    let d = dir_with_scene();
    let p = d.path();
    run_ok(p, &["-o", "plain.exr"]);
    run_ok(p, &["-o", "plain.png", "--spp-map", "plain.map.png"]);
    run_ok(
        p,
        &["-o", "den.png", "--denoise", "--spp-map", "den.map.png"],
    );
    run_ok(p, &["-o", "feat.png", "--features"]);
    let out = run_ok(
        p,
        &[
            "-o",
            "aov.exr",
            "--aov",
            "direct=C<RD>L",
            "--aov",
            "rest=C<RD>.+L",
            "--debug-view",
            "spp",
            "--debug-view",
            "noise",
            "--spp-map",
            "aov.map.png",
        ],
    );
    assert!(out.contains("adaptive: "), "{out}");
    for f in [
        "den.png",
        "feat.png",
        "feat.albedo.png",
        "feat.normal.png",
        "aov.direct.exr",
        "aov.rest.exr",
        "aov.view-spp.png",
        "aov.view-noise.png",
    ] {
        assert!(p.join(f).is_file(), "{f} not written");
    }
    let read = |f: &str| std::fs::read(p.join(f)).unwrap();
    assert_eq!(read("aov.exr"), read("plain.exr"));
    assert_eq!(read("feat.png"), read("plain.png"));
    assert_ne!(read("den.png"), read("plain.png"));
    // `--spp-map` beside them (refused with them before): the plain render's map.
    assert_eq!(read("den.map.png"), read("plain.map.png"));
    assert_eq!(read("aov.map.png"), read("plain.map.png"));
    // The spp view: black-to-red ramp of 2 and 8 samples, both present.
    let view = image::open(p.join("aov.view-spp.png")).unwrap().into_rgb8();
    let colours: std::collections::HashSet<[u8; 3]> = (0..36)
        .flat_map(|y| (0..48).map(move |x| (x, y)))
        .map(|(x, y)| view.get_pixel(x, y).0)
        .collect();
    assert_eq!(colours.len(), 2, "{colours:?}");
}

/// What still makes no sense together exits 2 with the reason and writes nothing.
#[test]
fn still_refused_combinations_exit_2_and_write_nothing() {
    let d = dir_with_scene();
    let fails = |extra: &[&str], text: &str| {
        let mut args = ADAPTIVE.to_vec();
        args.extend_from_slice(extra);
        fails_with(d.path(), &args, text);
    };
    fails(
        &["-o", "a.png", "--aov", "d=C<RD>L", "--denoise"],
        "--denoise and --features do not combine with --aov or --debug-view",
    );
    fails(
        &["-o", "a.png", "--debug-view", "spp", "--diagnose"],
        "--diagnose",
    );
    fails(
        &[
            "-o",
            "a.png",
            "--integrator",
            "whitted",
            "--debug-view",
            "roulette",
        ],
        "needs the path integrator",
    );
}
