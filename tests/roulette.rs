//! Russian-roulette splitting at dielectrics (`settings.dielectric_roulette`, issue 18): exact
//! in expectation against the exhaustive tree, at linear cost.

mod common;
use raytree::SceneIntegrator;
use raytree::render::RenderOptions;
use raytree::{Scene, render, trace_pixel};

fn glass(depth: u32) -> Scene {
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let mut scene = Scene::from_json(src).unwrap();
    scene.camera = scene.camera.with_size(32, 18);
    scene.settings.max_depth = depth;
    scene.settings.whitted.min_weight = Some(0.0);
    scene
}

/// The mean over 300 seeds of the roulette render (one sample at each pixel centre, so only the
/// roulette varies) against the exhaustive tree of the same depth: per pixel within 6 standard
/// errors or 1e-3 (a branch of probability 1e-3 may never be taken in 300 seeds: a grazing hit
/// whose R is near 1 then looks exact and noiseless, off by its tiny share), and the image sum
/// within 5 standard errors of the per-seed sums, which the rare branches cannot hide from. A
/// roulette that forgot to divide by its probability is off by many standard errors. It traces
/// far fewer rays.
#[test]
fn the_roulette_is_exact_in_expectation() {
    exact_in_expectation(|s| s.settings.whitted.dielectric_roulette = Some(0), 0.5);
}

/// The same for the roulette below a weight (`settings.roulette_below`, here 0.3 so that most
/// hits below the camera ray's play it): weak branches follow one ray, exact in expectation,
/// and the strong ones still split (0.53 of the split's rays here, against 0.5 and less when
/// every hit plays).
#[test]
fn the_roulette_below_a_weight_is_exact_in_expectation() {
    exact_in_expectation(|s| s.settings.whitted.roulette_below = Some(0.3), 0.6);
}

/// Mean over 300 seeds against the exhaustive split (see above); the roulette traces less than
/// `max_ratio` of the split's rays.
fn exact_in_expectation(roulette: impl Fn(&mut Scene), max_ratio: f64) {
    let exhaustive = glass(8);
    let (exact, split, _) = render(
        &SceneIntegrator::new(&exhaustive),
        &RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    let n = 300;
    let pixels = exact.pixels.len();
    let (mut sum, mut sum2) = (vec![0.0; pixels], vec![0.0; pixels]);
    let (mut total, mut total2) = (0.0, 0.0);
    let mut rays = 0;
    for seed in 1..=n {
        let mut s = exhaustive.clone();
        roulette(&mut s);
        s.settings.seed = seed;
        let (img, stats, _) =
            render(&SceneIntegrator::new(&s), &RenderOptions::new(), &|_| {}).into_parts();
        rays += stats.rays.total();
        let mut image = 0.0;
        for (i, p) in img.pixels.iter().enumerate() {
            let v = p.x + p.y + p.z;
            sum[i] += v;
            sum2[i] += v * v;
            image += v;
        }
        total += image;
        total2 += image * image;
    }
    let n = n as f64;
    let stats = |s: f64, s2: f64| {
        let mean = s / n;
        let var = (s2 / n - mean * mean).max(0.0) * n / (n - 1.0);
        (mean, (var / n).sqrt())
    };
    let sum3 = |p: &raytree::math::Rgb| p.x + p.y + p.z;
    let mut noisy = 0;
    for i in 0..pixels {
        let (mean, se) = stats(sum[i], sum2[i]);
        let want = sum3(&exact.pixels[i]);
        assert!(
            (mean - want).abs() < (6.0 * se).max(1e-3),
            "pixel {i}: mean {mean} against {want}, standard error {se}"
        );
        noisy += usize::from(se > 1e-6);
    }
    assert!(noisy > 50, "{noisy} pixels with roulette noise");
    let (mean, se) = stats(total, total2);
    let want: f64 = exact.pixels.iter().map(sum3).sum();
    let t = (mean - want) / se;
    assert!(t.abs() < 5.0, "image sum {mean} against {want}, t = {t}");
    let ratio = rays as f64 / n / split.rays.total() as f64;
    assert!(ratio < max_ratio, "{ratio} of the split's rays");
}

/// A recorded pixel makes the same choices as the render: its tree equals the pixel, and it
/// has one child per dielectric hit where the split has two.
#[test]
fn trees_equal_pixels_with_the_roulette() {
    let mut scene = glass(8);
    scene.settings.whitted.dielectric_roulette = Some(0);
    scene.settings.seed = 7;
    scene.settings.spp = 2;
    let image = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    for y in 0..18 {
        for x in 0..32 {
            assert_eq!(trace_pixel(&scene, x, y).unwrap().radiance, image.get(x, y));
        }
    }
}

/// The suggested weight (opt-in since issue 32; the default splits every hit): that of
/// glass-emitters (brightest emitter 1: 0.01) leaves the split where it is visible and plays
/// roulette below; trees equal pixels, some record a roulette choice, and an explicit
/// `min_weight` (the exhaustive tree of `min_weight 0`) gets no suggestion.
#[test]
fn the_suggested_weight_plays_roulette_only_below_it() {
    use raytree::integrator::bound::carried::{auto_roulette_below, carried_bound};
    let src = include_str!("../benches/mitsuba-scenes/glass-emitters.json");
    let mut scene = Scene::from_json(src).unwrap();
    scene.camera = scene.camera.with_size(32, 18);
    let bound = carried_bound(
        &scene,
        scene.settings.max_depth,
        scene.settings.whitted.shadows,
    );
    assert_eq!(bound, 1.0);
    assert_eq!(auto_roulette_below(&scene, &scene.settings), 0.01);
    // The default plays no roulette at all.
    let plain = trace_pixel(&scene, 16, 9).unwrap();
    assert!(
        plain
            .nodes
            .iter()
            .all(|n| n.interface.as_ref().is_none_or(|i| i.roulette.is_none()))
    );
    scene.settings.whitted.roulette_below = Some(0.01);
    let image = render(
        &SceneIntegrator::new(&scene),
        &RenderOptions::new(),
        &|_| {},
    )
    .image;
    let mut choices = 0;
    for y in 0..18 {
        for x in 0..32 {
            let tree = trace_pixel(&scene, x, y).unwrap();
            assert_eq!(tree.radiance, image.get(x, y));
            for n in &tree.nodes {
                if let Some(c) = n.interface.as_ref().and_then(|i| i.roulette) {
                    choices += 1;
                    assert!(n.throughput.max_element() < 0.01, "{n:?}");
                    assert!(c.probability > 0.0 && c.probability < 1.0);
                    // The followed ray's weight is its split weight over its probability.
                    let kids: Vec<_> = tree
                        .nodes
                        .iter()
                        .filter(|k| k.parent == Some(n.id))
                        .collect();
                    let followed = kids
                        .iter()
                        .filter(|k| k.kind != raytree::tree::RayKind::Shadow);
                    assert!(followed.count() <= 1, "one ray followed");
                }
            }
        }
    }
    assert!(choices > 0);
    scene.settings.whitted.roulette_below = None;
    scene.settings.whitted.min_weight = Some(0.0);
    assert_eq!(auto_roulette_below(&scene, &scene.settings), 0.0);
}

/// `raytree render --roulette-below W` says how many glass hits played the roulette and below
/// which weight; the default and `--roulette-below 0` split every hit (and say nothing); a
/// negative weight is refused with its setting's path.
#[test]
fn render_reports_the_roulette_and_it_can_be_turned_off() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/benches/mitsuba-scenes/mirror-corridor.json"
    );
    let run = |extra: &[&str]| {
        let mut args = vec!["render", scene, "--size", "64x36", "-o", "a.png"];
        args.extend_from_slice(extra);
        common::raytree(&args, dir.path())
    };
    let o = run(&[]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("roulette:"));
    let o = run(&["--roulette-below", "2.5e-3"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(
            "glass hits where the throughput was below 2.50e-3 followed one of their two rays"
        ),
        "{text}"
    );
    let o = run(&["--roulette-below", "0"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("roulette:"));
    let empty = tempfile::tempdir().unwrap();
    common::fails_with(
        empty.path(),
        &["render", scene, "--roulette-below=-1", "-o", "b.png"],
        "--roulette-below: must be a finite number >= 0, got -1",
    );
    // In a scene file: the setting's JSON path and its line:column.
    let text = std::fs::read_to_string(scene).unwrap().replace(
        r#""max_depth": 32"#,
        r#""max_depth": 32, "roulette_below": -0.5"#,
    );
    std::fs::write(empty.path().join("s.json"), text).unwrap();
    common::fails_with(
        empty.path(),
        &["render", "s.json", "-o", "b.png"],
        "settings.roulette_below",
    );
    let o = common::raytree(&["render", "s.json", "-o", "b.png"], empty.path());
    let err = common::stderr(&o);
    assert!(
        err.contains("s.json:") && err.contains("must be a finite number >= 0"),
        "{err}"
    );
}
