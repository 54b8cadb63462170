//! `raytree explain` and `raytree diff` (issue 17) through the binary: text, JSON, exit codes.

mod common;
use common::raytree;

use std::path::PathBuf;
use std::process::Output;

fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
        .display()
        .to_string()
}

fn run(args: &[&str]) -> Output {
    raytree(args, &std::env::temp_dir())
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn fails(o: &Output) -> String {
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(o.stdout.is_empty(), "{o:?}");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn explain_the_glass_pixel() {
    let text = ok(&run(&["explain", "--pixel", "400,200"]));
    let sees = text.lines().nth(2).unwrap();
    assert!(
        sees.starts_with("- floor seen through the glass ball: ") && sees.contains("(#"),
        "{text}"
    );
    assert!(text.contains("suspicious: nothing"), "{text}");
}

#[test]
fn explain_json_shares_add_up() {
    for (scene, pixel) in [
        (fixture("classic.json"), "400,200"),
        (fixture("tir-block.json"), "320,230"),
        (fixture("nested.json"), "320,150"),
    ] {
        let out = ok(&run(&["explain", &scene, "--pixel", pixel, "--json"]));
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let pixel_value: Vec<f64> = serde_json::from_value(v["radiance"].clone()).unwrap();
        let mut sum = [0.0; 3];
        for s in v["shares"].as_array().unwrap() {
            let c: Vec<f64> = serde_json::from_value(s["value"].clone()).unwrap();
            for i in 0..3 {
                sum[i] += c[i];
            }
        }
        for i in 0..3 {
            assert!((sum[i] - pixel_value[i]).abs() < 1e-12, "{scene}: {sum:?}");
        }
        for s in v["sentences"].as_array().unwrap() {
            assert!(!s["nodes"].as_array().unwrap().is_empty(), "{s}");
            assert!(s["kind"].is_string() && s["text"].is_string());
        }
    }
}

#[test]
fn explain_tir_and_max_depth() {
    // With the suggested roulette weight (opt-in since issue 32) a weak branch plays roulette:
    // one of its TIR rays' parents followed one ray.
    let tir =
        ::raytree::Scene::from_json(&std::fs::read_to_string(fixture("tir-block.json")).unwrap())
            .unwrap();
    let w = ::raytree::integrator::bound::carried::auto_roulette_below(&tir, &tir.settings);
    let text = ok(&run(&[
        "explain",
        &fixture("tir-block.json"),
        "--pixel",
        "320,230",
        "--roulette-below",
        &format!("{w:e}"),
    ]));
    assert!(
        text.contains("total internal reflection at 2 rays inside the glass block"),
        "{text}"
    );
    assert!(text.contains("- Russian roulette at "), "{text}");
    assert!(text.contains("where the throughput was below "), "{text}");
    let text = ok(&run(&[
        "explain",
        &fixture("tir-block.json"),
        "--pixel",
        "320,230",
    ]));
    assert!(
        text.contains("total internal reflection at 3 rays inside the glass block"),
        "{text}"
    );
    assert!(!text.contains("Russian roulette"), "{text}");
    let text = ok(&run(&[
        "explain",
        &fixture("nested.json"),
        "--pixel",
        "320,150",
        "--max-depth",
        "1",
    ]));
    assert!(text.contains("- cut by max depth 1: "), "{text}");
}

#[test]
fn explain_reports_acne_at_epsilon_zero() {
    let args = ["explain", "--pixel", "250,200", "--offset", "normal"];
    let clean = ok(&run(&args));
    assert!(!clean.contains("self-intersection"), "{clean}");
    let acne = ok(&run(&[&args[..], &["--epsilon", "0"]].concat()));
    assert!(acne.contains("(self-intersection: acne)"), "{acne}");
}

#[test]
fn explain_bad_input_exits_2() {
    let e = fails(&run(&["explain", "--pixel", "640,0"]));
    assert!(e.contains("outside the 640x360 image"), "{e}");
    let e = fails(&run(&["explain", "--pixel", "1;2"]));
    assert!(e.contains("--pixel"), "{e}");
    let e = fails(&run(&["explain", "--pixel", "1,2", "--fresnel", "fast"]));
    assert!(e.contains("--fresnel"), "{e}");
}

#[test]
fn diff_identical_settings() {
    let o = run(&[
        "diff",
        "--pixel",
        "400,200",
        "--a",
        "--fresnel exact",
        "--b",
        "",
    ]);
    let text = ok(&o);
    assert!(
        text.contains("no difference: the trees are identical (17 rays matched)"),
        "{text}"
    );
}

#[test]
fn diff_fresnel_models_diverge_at_the_camera_ray() {
    let text = ok(&run(&[
        "diff",
        "--pixel",
        "400,200",
        "--a",
        "--fresnel exact",
        "--b",
        "--fresnel schlick",
    ]));
    assert!(
        text.contains("first divergence: camera #0 (level 0): interface.fresnel.model exact -> schlick; interface.fresnel.r "),
        "{text}"
    );
    let out = ok(&run(&[
        "diff",
        "--pixel",
        "400,200",
        "--a=--fresnel exact",
        "--b=--fresnel schlick",
        "--json",
    ]));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["first_divergence"]["a"], 0);
    assert_eq!(
        v["first_divergence"]["fields"][1]["field"],
        "interface.fresnel.r"
    );
    assert_eq!(v["settings"][0]["field"], "settings.fresnel");
}

#[test]
fn diff_offsets_where_epsilon_zero_gives_acne() {
    let text = ok(&run(&[
        "diff",
        "--pixel",
        "250,200",
        "--a",
        "--offset normal --epsilon 0",
        "--b",
        "--offset robust",
        "--full",
    ]));
    assert!(text.contains("first divergence: "), "{text}");
    assert!(text.contains("self_hit: true -> false"), "{text}");
    assert!(text.contains("only in a: "), "{text}");
}

#[test]
fn diff_two_scene_files() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(fixture("classic.json")).unwrap();
    let b = dir.path().join("b.json");
    std::fs::write(&b, src.replace("\"ior\": 1.5", "\"ior\": 1.33")).unwrap();
    assert!(std::fs::read_to_string(&b).unwrap().contains("1.33"));
    let text = ok(&raytree(
        &[
            "diff",
            &fixture("classic.json"),
            "b.json",
            "--pixel",
            "400,200",
            "--full",
        ],
        dir.path(),
    ));
    assert!(text.contains("first divergence: camera #0"), "{text}");
    assert!(text.contains("interface.n2: 1.5 -> 1.33"), "{text}");
}

#[test]
fn diff_bad_override_strings_exit_2() {
    for (a, expect) in [
        ("--bogus", "unexpected argument '--bogus'"),
        ("--offset sideways", "--offset: unknown value"),
        ("--spp", "a value is required"),
        ("--max-depth 'three", "unclosed quote"),
    ] {
        let e = fails(&run(&["diff", "--pixel", "400,200", "--a", a]));
        assert!(e.contains(expect), "{a}: {e}");
        assert!(e.starts_with("error: --a"), "{e}");
    }
    let e = fails(&run(&["diff", "--pixel", "400,200", "--b", "--size 0x3"]));
    assert!(e.contains("--b") && e.contains("--size"), "{e}");
}
