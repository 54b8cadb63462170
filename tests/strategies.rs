//! `raytree strategies` (issue 30): the bidirectional render split by strategy (Veach 1997,
//! figure 10.3). The weighted parts add up to the render; with MIS off, every strategy that can
//! make a path length estimates the same light (per-strategy images agree within their noise,
//! Welch's test at 5 sigma over the whole image); the command writes its figure and refuses bad
//! input without writing. Fixed seeds.

mod common;

use common::raytree;
use raytree::SceneIntegrator;
use raytree::analysis::strategies::{Part, Split, split};
use raytree::math::Rgb;
use raytree::render::RenderOptions;
use raytree::scene::IntegratorKind;
use raytree::{Scene, render};
use std::path::PathBuf;

/// The Cornell box at `size` x `size` pixels, `spp` samples, under BDPT.
fn cornell(size: u32, spp: u32) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/cornell-box.json");
    let text = std::fs::read_to_string(p).unwrap();
    let text = text.replace(
        "\"width\": 256, \"height\": 256",
        &format!("\"width\": {size}, \"height\": {size}"),
    );
    let mut scene = Scene::from_json(&text).unwrap();
    assert_eq!(scene.camera.width, size);
    scene.settings.integrator = IntegratorKind::Bdpt;
    scene.settings.spp = spp;
    scene
}

fn lum(c: Rgb) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// The weighted parts sum to the rendered image (up to the order of the additions), and the
/// shares of the luminance sum to 1.
#[test]
fn the_weighted_strategies_add_up_to_the_render() {
    for bounces in [0, 2] {
        let scene = cornell(24, 4);
        let s = split(&scene, bounces, &|_| {});
        let (image, _, _) = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        let total = s.total();
        let mut worst = 0.0f64;
        for (a, b) in total.iter().zip(&image.pixels) {
            let d = (*a - *b).abs().max_element();
            worst = worst.max(d / b.abs().max_element().max(1e-3));
        }
        assert!(
            worst < 1e-9,
            "bounces {bounces}: relative difference {worst}"
        );
        let shares: f64 = s.shares().iter().map(|(_, x)| x).sum();
        assert!((shares - 1.0).abs() < 1e-9, "{shares}");
        let longer = s.parts.iter().any(|p| p.part == Part::Longer);
        assert!(
            longer,
            "the Cornell box has paths longer than {bounces} bounces"
        );
        for p in &s.parts {
            if let Some(b) = p.part.bounces() {
                assert!(b <= bounces, "{:?}", p.part);
            }
        }
    }
}

/// Mean and variance of the mean of one part's unweighted per-pixel luminance.
fn mean_and_error(s: &Split, part: Part) -> (f64, f64) {
    let img = s.parts.iter().find(|p| p.part == part).unwrap();
    let v: Vec<f64> = img.unweighted.iter().map(|&c| lum(c)).collect();
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var / n)
}

/// MIS off, each strategy alone: for one and two bounces every strategy the Cornell box's quad
/// lamp and diffuse walls allow (`s = 0` hitting the lamp, `s = 1` sampling it, the
/// connections, `t = 1` light tracing) gives the same image mean within 5 sigma, and not zero.
#[test]
fn each_strategy_alone_estimates_the_same_light() {
    let scene = cornell(48, 8);
    let s = split(&scene, 2, &|_| {});
    for bounces in [1u32, 2] {
        let estimates: Vec<(Part, (f64, f64))> = (0..=bounces + 1)
            .map(|sv| Part::Strategy {
                s: sv,
                t: bounces + 2 - sv,
            })
            .map(|p| (p, mean_and_error(&s, p)))
            .collect();
        for (p, (m, _)) in &estimates {
            assert!(*m > 1e-4, "{p:?} carries no light: {m}");
        }
        for (i, (pa, (ma, ea))) in estimates.iter().enumerate() {
            for (pb, (mb, eb)) in &estimates[i + 1..] {
                let z = (ma - mb).abs() / (ea + eb).sqrt();
                assert!(z < 5.0, "{pa:?} {ma} vs {pb:?} {mb}: {z:.2} sigma");
            }
        }
    }
}

/// The command writes the figure, one image per strategy weighted and unweighted, and the
/// report; a wrong integrator or too many bounces exit 2 and write nothing.
#[test]
fn command_line_strategies() {
    let d = tempfile::tempdir().unwrap();
    let scene = common::fixture("cornell-box.json");
    let out = d.path().join("st");
    let args = [
        "strategies",
        &scene,
        "--size",
        "24x24",
        "--spp",
        "2",
        "--bounces",
        "1",
        "-o",
        out.to_str().unwrap(),
    ];
    let o = raytree(&args, d.path());
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("share of the image's luminance: "), "{text}");
    for f in [
        "sheet.png",
        "report.md",
        "report.json",
        "s0-t2.png",
        "s1-t2.png",
        "s1-t2-unweighted.png",
        "s2-t1.png",
        "s0-t3-unweighted.png",
        "longer.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let shares: f64 = json["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["share"].as_f64().unwrap())
        .sum();
    assert!((shares - 1.0).abs() < 1e-9, "{shares}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("| s=1 t=2 | 1 |"), "{md}");
    for bad in [
        vec!["--integrator", "path"],
        vec!["--bounces", "7"],
        vec!["--spp", "0x"],
    ] {
        let fresh = d.path().join("fresh");
        let mut a = vec!["strategies", &scene, "-o", fresh.to_str().unwrap()];
        a.extend(bad.iter().copied());
        let o = raytree(&a, d.path());
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", common::stderr(&o));
        assert!(!fresh.exists(), "{bad:?} created the directory");
    }
}

/// `explain` on a caustic pixel under BDPT names the strategies that brought its light, the
/// light-tracing one (s = 4, t = 1: emitter, glass, glass, floor) first with its MIS weight;
/// the shares in the sentence add up to 100%.
#[test]
fn explain_names_the_strategy_of_a_caustic() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/caustic.json");
    let mut scene = Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap();
    scene.settings.integrator = IntegratorKind::Bdpt;
    scene.settings.spp = 4;
    let tree = raytree::trace_pixel(&scene, 105, 116).unwrap();
    let e = raytree::analysis::explain::explain(&tree, &scene);
    let s = e
        .sentences
        .iter()
        .find(|s| s.text.starts_with("the light came "))
        .unwrap_or_else(|| panic!("{:#?}", e.sentences));
    assert!(
        s.text.starts_with("the light came ") && s.text.contains("% from s=4 t=1 (light tracing"),
        "{}",
        s.text
    );
    let first = s.text.split(" from ").nth(1).unwrap();
    assert!(first.starts_with("s=4 t=1"), "{}", s.text);
    let percents: f64 = s
        .text
        .split("% from ")
        .filter_map(|part| part.rsplit([' ', ',']).next()?.parse::<f64>().ok())
        .sum();
    assert!((percents - 100.0).abs() < 1.0, "{percents}: {}", s.text);
    assert!(
        !e.sentences
            .iter()
            .any(|s| s.text.contains("by light sampling (shadow rays)"))
    );
    // The shares add up to the pixel: only the splats that landed here count, not the other
    // connections of their light paths.
    let sum = e.shares.iter().fold(Rgb::ZERO, |a, s| a + s.value);
    let d = (sum - tree.radiance).abs().max_element();
    assert!(
        d <= 1e-9 * tree.radiance.max_element(),
        "{sum:?} vs {:?}",
        tree.radiance
    );
}

/// `diff` understands strategies: a BDPT pixel under the balance and the power heuristic is
/// split by strategy in both trees, each side's parts add up to its pixel, the weights differ
/// while the strategies made are the same, and the command prints the table.
#[test]
fn diff_splits_a_bidirectional_pixel_by_strategy() {
    let mut a = cornell(24, 4);
    let mut b = a.clone();
    a.settings.path.mis = raytree::scene::MisHeuristic::Balance;
    b.settings.path.mis = raytree::scene::MisHeuristic::Power;
    let (ta, tb) = (
        raytree::trace_pixel(&a, 12, 14).unwrap(),
        raytree::trace_pixel(&b, 12, 14).unwrap(),
    );
    let d = raytree::analysis::diff::diff(&ta, &tb);
    assert!(d.strategies.len() >= 3, "{:?}", d.strategies);
    for (side, tree) in [(0, &ta), (1, &tb)] {
        let sum: Rgb = d
            .strategies
            .iter()
            .map(|c| if side == 0 { c.a } else { c.b })
            .sum();
        let r = tree.radiance;
        assert!(
            (sum - r).abs().max_element() <= 1e-12 * r.max_element().max(1e-300),
            "side {side}: parts {sum} != pixel {r}"
        );
    }
    assert!(
        d.strategies
            .iter()
            .any(|c| matches!(c.mis_weight, [Some(x), Some(y)] if (x - y).abs() > 1e-6)),
        "{:?}",
        d.strategies
    );
    assert!(d.first_decision.is_none(), "{:?}", d.first_decision);
    let text = raytree::analysis::diff::diff_text(&d, &ta, &tb);
    assert!(text.contains("by strategy ("), "{text}");
    assert!(text.contains("    s=1 t=2: "), "{text}");

    let dir = tempfile::tempdir().unwrap();
    let cornell = common::fixture("cornell-box.json");
    let args = [
        "diff",
        &cornell,
        "--pixel",
        "128,140",
        "--spp",
        "2",
        "--integrator",
        "bdpt",
        "--a",
        "--mis balance",
        "--b",
        "--mis power",
    ];
    let out = raytree(&args, dir.path());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{out:?}");
    assert!(text.contains("by strategy ("), "{text}");
}

/// The sample list and the firefly sentence understand strategies: under BDPT each sample's
/// paths carry their `(s, t)`, the rows' labels name it, and a firefly's sentence names its
/// strategy and MIS weight (a caustic under BDPT is not "at full MIS weight": the strategies
/// from the light's side share it).
#[test]
fn sample_rows_and_fireflies_name_their_strategy() {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/caustic.json");
    let mut scene = Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap();
    scene.camera = scene.camera.with_size(48, 36);
    scene.settings.integrator = IntegratorKind::Bdpt;
    scene.settings.spp = 16;
    let mut fireflies = Vec::new();
    let mut labelled = 0;
    for y in (14..30).step_by(2) {
        for x in (8..40).step_by(2) {
            let tree = raytree::trace_pixel(&scene, x, y).unwrap();
            for row in raytree::analysis::samples::sample_rows(&tree) {
                for path in &row.paths {
                    match path.strategy {
                        Some([s, t]) => {
                            assert_eq!(path.label(), format!("{} s={s} t={t}", path.lpe));
                            labelled += 1;
                        }
                        // The background a camera ray escaped to is no strategy's.
                        None => assert_eq!(path.label(), path.lpe),
                    }
                }
                if let Some(f) = raytree::analysis::firefly::explain(&tree, row.index) {
                    fireflies.push(f.sentence());
                }
            }
        }
    }
    assert!(labelled > 100, "{labelled} paths");
    assert!(
        !fireflies.is_empty(),
        "some BDPT firefly in the caustic's middle"
    );
    for f in &fireflies {
        assert!(f.contains("strategy s="), "{f}");
        assert!(f.contains("MIS weigh"), "{f}");
        assert!(!f.contains("at full MIS weight"), "{f}");
    }
}
