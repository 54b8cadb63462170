//! Issue 14's seams: the integrator chosen by `settings.integrator`, the per-pixel sampler and
//! `settings.seed`, through the library and through every tracing command.

mod common;
use common::raytree;

use raytree::render::RenderOptions;
use raytree::render::render_pixel;
use raytree::sampling::{PixelSampler, StratifiedJitter};
use raytree::scene::{IntegratorKind, icosphere_scene};
use raytree::{
    Integrator, NoopRecorder, RayCounts, Scene, SceneIntegrator, TreeRecorder, render, trace_pixel,
};
use std::process::Output;

/// A sampler whose film offsets are a fixed function of (pixel, sample): lets a test know where
/// every camera ray must start.
#[derive(Clone, Copy, Default)]
struct Fixed {
    pixel: (u32, u32),
    index: u32,
    dim: u32,
}

impl Fixed {
    fn offset((x, y): (u32, u32), s: u32) -> (f64, f64) {
        let u = f64::from((x * 7 + y * 3 + s * 5) % 16) / 16.0 + 1.0 / 64.0;
        let v = f64::from((x * 5 + y * 11 + s * 3) % 16) / 16.0 + 1.0 / 64.0;
        (u, v)
    }
}

impl PixelSampler for Fixed {
    fn start_sample(&mut self, pixel: (u32, u32), index: u32) {
        (self.pixel, self.index, self.dim) = (pixel, index, 0);
    }
    fn next_1d(&mut self) -> f64 {
        self.dim += 1;
        0.5
    }
    fn next_2d(&mut self) -> (f64, f64) {
        self.dim += 2;
        if self.dim == 2 {
            Self::offset(self.pixel, self.index)
        } else {
            (0.5, 0.5)
        }
    }
}

/// Uniform antialiasing: these tests are about the sampler seam, which automatic
/// antialiasing (its own film positions) does not use.
fn small(mut scene: Scene, w: u32, h: u32, spp: u32) -> Scene {
    scene.camera = scene.camera.with_size(w, h);
    scene.settings.spp = spp;
    scene.settings.antialiasing = raytree::scene::Antialiasing::Uniform;
    scene
}

/// The render takes its film positions from the sampler: a recorded pixel's samples sit where
/// the sampler put them, and a whole render with that sampler (rows, and 8x8 packets for a mesh
/// scene) equals the pixels traced one by one, bit for bit.
#[test]
fn film_positions_come_from_the_sampler() {
    let classic = small(Scene::default_scene(), 48, 27, 3);
    let mesh = small(icosphere_scene(2, 20, 3.0), 20, 20, 2);
    for scene in [classic, mesh] {
        let integrator = SceneIntegrator::new(&scene);
        let (image, _, _) = render(
            &integrator,
            &RenderOptions::new().with_sampler(Fixed::default()),
            &|_| {},
        )
        .into_parts();
        let default = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .image;
        assert_ne!(image, default, "the sampler changed nothing");
        let mut sampler = Fixed::default();
        for y in 0..scene.camera.height {
            for x in 0..scene.camera.width {
                let mut rec = TreeRecorder::default();
                let mut samples = Vec::new();
                let mut counts = RayCounts::default();
                let l = render_pixel(
                    &integrator,
                    &mut sampler,
                    (x, y),
                    &mut rec,
                    &mut counts,
                    |s| samples.push(s),
                )
                .0;
                assert_eq!(l, image.get(x, y), "pixel ({x}, {y})");
                for s in &samples {
                    let (u, v) = Fixed::offset((x, y), s.index);
                    assert_eq!(s.film, [f64::from(x) + u, f64::from(y) + v]);
                }
                assert_eq!(samples.len() as u32, scene.settings.spp);
            }
        }
    }
}

/// `settings.seed` moves the jittered positions; the re-traced pixel still equals the render at
/// any seed, and seed 0 is the default render.
#[test]
fn the_seed_moves_samples_and_trees_still_equal_pixels() {
    let base = small(Scene::default_scene(), 40, 24, 4);
    let mut seeded = base.clone();
    seeded.settings.seed = 12_345;
    let (a, b) = (
        render(&SceneIntegrator::new(&base), &RenderOptions::new(), &|_| {}).image,
        render(
            &SceneIntegrator::new(&seeded),
            &RenderOptions::new(),
            &|_| {},
        )
        .image,
    );
    assert_ne!(a, b);
    let tree = trace_pixel(&seeded, 20, 12).unwrap();
    assert_eq!(tree.radiance, b.get(20, 12));
    let tree0 = trace_pixel(&base, 20, 12).unwrap();
    assert_ne!(tree.samples[1].film, tree0.samples[1].film);
    for y in 0..24 {
        for x in 0..40 {
            assert_eq!(trace_pixel(&seeded, x, y).unwrap().radiance, b.get(x, y));
        }
    }
    // The default sampler built by hand at seed 0 gives the default render.
    let integrator = SceneIntegrator::new(&base);
    let by_hand = render(
        &integrator,
        &RenderOptions::new().with_sampler(StratifiedJitter::new(4, 0)),
        &|_| {},
    )
    .image;
    assert_eq!(by_hand, a);
}

#[test]
fn the_scene_chooses_the_integrator() {
    let scene = Scene::default_scene();
    assert_eq!(scene.settings.integrator, IntegratorKind::Whitted);
    assert_eq!(SceneIntegrator::new(&scene).kind(), IntegratorKind::Whitted);
    let json = |v: &str| {
        format!(
            r#"{{"camera": {{"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4,
            "height": 3}}, "settings": {{"integrator": {v}, "seed": 7}}}}"#
        )
    };
    let ok = Scene::from_json(&json("\"whitted\"")).unwrap();
    assert_eq!(ok.settings.seed, 7);
    let path = Scene::from_json(&json("\"path\"")).unwrap();
    assert_eq!(path.settings.integrator, IntegratorKind::Path);
    assert_eq!(SceneIntegrator::new(&path).kind(), IntegratorKind::Path);
    let e = Scene::from_json(&json("\"bidir\"")).unwrap_err();
    assert_eq!(e.path, "settings.integrator");
    assert!(e.message.contains("unknown integrator \"bidir\""), "{e}");
    // The tree names its integrator and seed.
    let tree = serde_json::to_value(trace_pixel(&ok, 1, 1).unwrap()).unwrap();
    assert_eq!(tree["settings"]["integrator"], "whitted");
    assert_eq!(tree["settings"]["seed"], 7);
    // NoopRecorder through the seam: the same pixel as the plain render.
    let mut counts = RayCounts::default();
    let mut sampler = StratifiedJitter::for_settings(&ok.settings);
    let integrator = SceneIntegrator::new(&ok);
    let l = render_pixel(
        &integrator,
        &mut sampler,
        (2, 1),
        &mut NoopRecorder,
        &mut counts,
        |_| {},
    )
    .0;
    assert_eq!(
        l,
        render(&SceneIntegrator::new(&ok), &RenderOptions::new(), &|_| {})
            .image
            .get(2, 1)
    );
}

fn fails_with(o: &Output, text: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(text), "{err}");
}

/// Every tracing command takes `--integrator` (whitted or path) and `--seed`; an unknown
/// integrator is refused with exit 2 and nothing written, as is a scene file asking for one.
#[test]
fn every_tracing_command_takes_integrator_and_seed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let size = ["--size", "16x9"];
    let commands: [&[&str]; 6] = [
        &["render", "-o", "out.png"],
        &["trace", "--pixel", "3,3"],
        &["diagram", "--pixel", "3,3", "-o", "out.svg"],
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
        &["effects"],
    ];
    for cmd in commands {
        let with = |extra: &[&str]| {
            let mut args = cmd.to_vec();
            args.extend_from_slice(extra);
            if cmd[0] != "acne" && cmd[0] != "diagram" {
                args.extend_from_slice(&size);
            }
            raytree(&args, d)
        };
        fails_with(
            &with(&["--integrator", "nope"]),
            "unknown integrator \"nope\"",
        );
        fails_with(
            &with(&["--sampler", "halton"]),
            "--sampler: unknown sampler \"halton\"",
        );
        assert!(
            std::fs::read_dir(d).unwrap().next().is_none(),
            "{cmd:?} wrote"
        );
        if cmd[0] != "cost" && cmd[0] != "acne" {
            for integrator in ["whitted", "path"] {
                for sampler in ["stratified", "sobol"] {
                    let o = with(&[
                        "--integrator",
                        integrator,
                        "--seed",
                        "3",
                        "--rr-depth",
                        "2",
                        "--sampler",
                        sampler,
                    ]);
                    assert!(
                        o.status.success(),
                        "{cmd:?}: {}",
                        String::from_utf8_lossy(&o.stderr)
                    );
                }
            }
        }
        for f in ["out.png", "out.svg"] {
            let _ = std::fs::remove_file(d.join(f));
        }
    }
    std::fs::write(
        d.join("p.json"),
        r#"{"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov_y": 40, "width": 4,
        "height": 3}, "settings": {"integrator": "bidir"}}"#,
    )
    .unwrap();
    let o = raytree(&["render", "p.json", "-o", "p.png"], d);
    fails_with(&o, "settings.integrator: unknown integrator \"bidir\"");
    assert!(!d.join("p.png").exists());
    std::fs::write(
        d.join("p.json"),
        "{\"camera\": {\"position\": [0,0,5], \"look_at\": [0,0,0], \"fov_y\": 40, \"width\": 4,\n\
         \"height\": 3},\n\"settings\": {\"sampler\": \"halton\"}}",
    )
    .unwrap();
    let o = raytree(&["render", "p.json", "-o", "p.png"], d);
    fails_with(
        &o,
        "p.json:3:33: settings.sampler: unknown sampler \"halton\", expected \"stratified\" or \"sobol\"",
    );
    assert!(!d.join("p.png").exists());
}

/// The path integrator draws from the Sobol sampler unless the scene or `--sampler` asks for
/// the stratified one; Whitted from the stratified one. Every choice gives trees equal to
/// their pixels, and the samplers built by hand give the renders.
#[test]
fn the_sampler_follows_the_integrator_and_the_setting() {
    use raytree::sampling::SobolSampler;
    use raytree::scene::SamplerKind;
    let mut path = small(Scene::default_scene(), 12, 8, 4);
    path.settings.integrator = IntegratorKind::Path;
    path.settings.seed = 5;
    assert_eq!(path.settings.sampler_kind(), SamplerKind::Sobol);
    let sobol = render(&SceneIntegrator::new(&path), &RenderOptions::new(), &|_| {}).image;
    let integrator = SceneIntegrator::new(&path);
    let by_hand = render(
        &integrator,
        &RenderOptions::new().with_sampler(SobolSampler::new(5, (0, 0), 0)),
        &|_| {},
    )
    .image;
    assert_eq!(by_hand, sobol);
    let mut strat = path.clone();
    strat.settings.sampler = Some(SamplerKind::Stratified);
    let stratified = render(
        &SceneIntegrator::new(&strat),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let by_hand = render(
        &integrator,
        &RenderOptions::new().with_sampler(StratifiedJitter::new(4, 5)),
        &|_| {},
    )
    .image;
    assert_eq!(by_hand, stratified);
    assert_ne!(sobol, stratified);
    for (scene, image) in [(&path, &sobol), (&strat, &stratified)] {
        for y in 0..8 {
            for x in 0..12 {
                assert_eq!(trace_pixel(scene, x, y).unwrap().radiance, image.get(x, y));
            }
        }
    }
    // Whitted asked for Sobol renders with it; its default stays stratified.
    let mut whitted = small(Scene::default_scene(), 12, 8, 4);
    assert_eq!(whitted.settings.sampler_kind(), SamplerKind::Stratified);
    let plain = render(
        &SceneIntegrator::new(&whitted),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    whitted.settings.sampler = Some(SamplerKind::Sobol);
    let w_sobol = render(
        &SceneIntegrator::new(&whitted),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    assert_ne!(plain, w_sobol);
    assert_eq!(
        trace_pixel(&whitted, 3, 2).unwrap().radiance,
        w_sobol.get(3, 2)
    );
    // The tree records the choice when the scene made one.
    let tree = serde_json::to_value(trace_pixel(&strat, 1, 1).unwrap()).unwrap();
    assert_eq!(tree["settings"]["sampler"], "stratified");
}

/// `--seed` reaches the samples: the trace JSON records it, and its jittered positions differ
/// from seed 0's; `--seed 0 --integrator whitted` renders the default image byte for byte.
#[test]
fn seed_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let trace = |seed: &str| {
        let args = [
            "trace", "--pixel", "5,5", "--spp", "4", "--size", "16x9", "--json", "--seed", seed,
        ];
        let o = raytree(&args, d);
        assert!(o.status.success());
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let (t0, t9) = (trace("0"), trace("9"));
    assert_eq!(t9["settings"]["seed"], 9);
    assert_ne!(t0["samples"][1]["film"], t9["samples"][1]["film"]);
    let render = |extra: &[&str], out: &str| {
        let mut args = vec!["render", "--size", "16x9", "--spp", "4", "-o", out];
        args.extend_from_slice(extra);
        assert!(raytree(&args, d).status.success());
        std::fs::read(d.join(out)).unwrap()
    };
    let plain = render(&[], "a.exr");
    assert_eq!(
        plain,
        render(&["--seed", "0", "--integrator", "whitted"], "b.exr")
    );
    assert_ne!(plain, render(&["--seed", "1"], "c.exr"));
}
