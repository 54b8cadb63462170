//! The whole-command property of issue 13: for any scene the loader accepts, every command ends
//! with exit 0 or 2 within bounded memory, writes only finite numbers, and leaves no temp file.
//!
//! Scenes are the fixtures with extreme but accepted values stacked on them (huge and tiny radii,
//! lights of 1e30..1.7e308, epsilons up to 1e308, absorption, ior near 1 and huge, depth up to
//! 1024, a few samples, a far camera, a mesh scaled to 1e-150 or 1e150, ...), shrunk to 12x8,
//! kept only when `Scene::from_json` accepts them. Each is run through `render` (EXR and PNG),
//! `trace` (JSON and text), `diagram` (SVG) and `effects` under the harness's memory cap and a
//! timeout, and every number each writes (EXR pixels, JSON numbers, SVG attributes and text,
//! standard output and error) is checked to be finite.
//!
//! The per-sample ray budget is set to at most 4096 so that a case costs milliseconds: the
//! default budget's time is the business of `bounds.rs`, not of this property.

use super::finite::{exr_problem, nonfinite_tokens, svg_problem, tree_json_problem};
use super::harness::{MEM_MIB, Run, run_with, temp_files};
use super::scenes::{FIXTURES, HEIGHT, Mutation, TET, WIDTH, accepted, mutation, scene_text};
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::path::Path;
use std::time::Duration;

/// A check of a successful run's output (its streams, its output file).
type Check = dyn Fn(&Run, Option<&Path>) -> Option<String>;

/// What one command did wrong, if anything: its exit, a panic, a timeout, a temp file, an
/// output left by a refused run, a non-finite number in its streams or its output file.
fn command_problem(
    dir: &Path,
    args: &[&str],
    output: Option<&str>,
    check: &Check,
) -> Option<String> {
    let r = run_with(args, dir, MEM_MIB, Duration::from_secs(30));
    let out = output.map(|o| dir.join(o));
    let problem = if r.timed_out {
        Some("timed out".to_string())
    } else if !matches!(r.code, Some(0 | 2)) {
        Some(format!("exit {:?}", r.code))
    } else if r.stderr.contains("panicked") {
        Some("panicked".into())
    } else if !temp_files(dir).is_empty() {
        Some(format!("temp files left: {:?}", temp_files(dir)))
    } else if r.code == Some(2) && !r.stderr.contains("error:") {
        Some("exit 2 without an error message".into())
    } else if r.code == Some(2) && out.as_ref().is_some_and(|o| o.exists()) {
        Some("a refused run left its output".into())
    } else if r.code == Some(0) && out.as_ref().is_some_and(|o| !o.exists()) {
        Some("exit 0 but no output file".into())
    } else if let Some(t) = Some(nonfinite_tokens(&r.stdout)).filter(|t| !t.is_empty()) {
        Some(format!("stdout holds {t:?}"))
    } else if let Some(t) = Some(nonfinite_tokens(&r.stderr)).filter(|t| !t.is_empty()) {
        Some(format!("stderr holds {t:?}"))
    } else if r.code == Some(0) {
        check(&r, out.as_deref())
    } else {
        None
    };
    if let Some(o) = &out {
        let _ = std::fs::remove_file(o);
    }
    problem.map(|p| {
        format!(
            "raytree {}: {p}\nexit {:?}\nstdout {}\nstderr {}",
            args.join(" "),
            r.code,
            cut(&r.stdout),
            cut(&r.stderr)
        )
    })
}

fn cut(s: &str) -> String {
    if s.len() > 2000 {
        format!(
            "{}... ({} bytes)",
            &s[..s.floor_char_boundary(2000)],
            s.len()
        )
    } else {
        s.to_string()
    }
}

/// Run every command on `scene.json` in `dir`; the first problem found, if any.
fn commands_problem(dir: &Path, pixel: (u32, u32)) -> Option<String> {
    let size = format!("{WIDTH}x{HEIGHT}");
    let px = format!("{},{}", pixel.0, pixel.1);
    let none = |_: &Run, _: Option<&Path>| None;
    let exr = |_: &Run, o: Option<&Path>| o.and_then(exr_problem);
    let png = |_: &Run, o: Option<&Path>| {
        o.and_then(|o| image::open(o).err().map(|e| format!("unreadable PNG: {e}")))
    };
    let json = |r: &Run, _: Option<&Path>| tree_json_problem(&r.stdout);
    let svg = |_: &Run, o: Option<&Path>| {
        o.and_then(|o| svg_problem(&std::fs::read_to_string(o).unwrap_or_default()))
    };
    let s = size.as_str();
    let p = px.as_str();
    let runs: [(Vec<&str>, Option<&str>, &Check); 6] = [
        (
            vec!["render", "scene.json", "--size", s, "-o", "x.exr"],
            Some("x.exr"),
            &exr,
        ),
        (
            vec!["render", "scene.json", "--size", s, "-o", "x.png"],
            Some("x.png"),
            &png,
        ),
        (
            vec!["trace", "scene.json", "--size", s, "--pixel", p, "--json"],
            None,
            &json,
        ),
        (
            vec!["trace", "scene.json", "--size", s, "--pixel", p],
            None,
            &none,
        ),
        (
            vec!["diagram", "scene.json", "--pixel", p, "-o", "x.svg"],
            Some("x.svg"),
            &svg,
        ),
        (vec!["effects", "scene.json"], None, &none),
    ];
    runs.iter()
        .find_map(|(args, out, check)| command_problem(dir, args, *out, *check))
}

fn case() -> impl Strategy<Value = (usize, Vec<Mutation>, u64, (u32, u32))> {
    (
        0..FIXTURES.len(),
        prop::collection::vec(mutation(), 1..=5),
        prop::sample::select(vec![1u64, 16, 256, 4096]),
        (0..WIDTH, 0..HEIGHT),
    )
}

proptest! {
    #![proptest_config(Config {
        cases: 128,
        max_shrink_iters: 200,
        ..Config::default()
    })]

    #[test]
    fn every_command_on_an_accepted_scene_ends_cleanly_with_finite_output(
        (fixture, mutations, max_rays, pixel) in case()
    ) {
        let text = scene_text(fixture, &mutations, max_rays);
        prop_assume!(accepted(&text));
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("scene.json"), &text).unwrap();
        std::fs::write(dir.path().join("tet.obj"), TET).unwrap();
        if let Some(p) = commands_problem(dir.path(), pixel) {
            return Err(TestCaseError::fail(format!(
                "{}\nfixture {} with {mutations:?}, max_rays {max_rays}\n{text}",
                p, FIXTURES[fixture].0
            )));
        }
    }
}

/// The checks above catch what they are for: each is fed a known-bad output.
#[test]
fn the_checks_reject_non_finite_output() {
    assert_eq!(
        nonfinite_tokens("L [NaN, 0.5, inf]  t=-inf x=1e999"),
        ["NaN", "inf", "-inf", "1e999"]
    );
    assert!(nonfinite_tokens("infinite information, not finite: nan-free 1e308").is_empty());
    assert!(tree_json_problem("{\"radiance\": [NaN, 0, 0]}").is_some());
    assert!(
        tree_json_problem("{\"radiance\": [null, 0, 0]}")
            .unwrap()
            .contains("radiance[0]")
    );
    assert!(svg_problem("<svg><circle cx=\"1\" cy=\"NaN\" r=\"2\"/></svg>").is_some());
    assert!(svg_problem("<svg><circle cx=\"1\" cy=\"2\" r=\"inf\"/></svg>").is_some());
    assert!(svg_problem("<svg><polyline points=\"1,2 NaN,3\"/></svg>").is_some());
    assert!(svg_problem("<svg><text x=\"1\" y=\"2\">R=NaN</text></svg>").is_some());
    assert_eq!(
        svg_problem("<svg><circle cx=\"1\" cy=\"2\" r=\"3\"/></svg>"),
        None
    );
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::Rgb32FImage::from_pixel(2, 2, image::Rgb([0.5, 0.5, 0.5]));
    img.put_pixel(1, 1, image::Rgb([f32::INFINITY, 0.0, 0.0]));
    let p = dir.path().join("inf.exr");
    img.save(&p).unwrap();
    assert!(exr_problem(&p).is_some());
    // And the real outputs of the built-in scene pass them.
    let tree = raytree::trace_pixel(&raytree::Scene::default_scene(), 400, 200).unwrap();
    assert_eq!(
        tree_json_problem(&serde_json::to_string(&tree).unwrap()),
        None
    );
}
