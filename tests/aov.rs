//! `raytree render --aov NAME=LPE --debug-view VIEW` and `raytree versus` (issue 16): files
//! written, AOVs that partition the paths sum to the beauty image (read back from EXR), bad
//! specifications exit 2 and write nothing.

mod common;

use common::{fails_with, raytree};
use std::path::{Path, PathBuf};

fn caustic() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/caustic.json")
}

/// A temporary directory holding the caustic scene as `s.json`.
fn dir_with_scene() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::copy(caustic(), d.path().join("s.json")).unwrap();
    d
}

fn read_exr(p: &Path) -> Vec<[f32; 3]> {
    let img = image::open(p).unwrap().into_rgb32f();
    img.pixels().map(|p| p.0).collect()
}

#[test]
fn partitioning_aovs_sum_to_the_beauty_image_and_the_views_are_written() {
    let d = dir_with_scene();
    let args = [
        "render",
        "s.json",
        "--spp",
        "4",
        "-o",
        "out.exr",
        "--aov",
        "emit=CL",
        "--aov",
        "direct=C<RD>L",
        "--aov",
        "indirect=C<RD>.+L",
        "--aov",
        "glass=CS.*L",
        "--debug-view",
        "noise",
        "--debug-view",
        "share:indirect",
    ];
    let o = raytree(&args, d.path());
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("aov indirect: out.indirect.exr"), "{out}");
    // Four samples a pixel: every spread is estimable, no note.
    assert!(!String::from_utf8_lossy(&o.stderr).contains("cannot be estimated"));
    // One sample a pixel: the noise view's black is not a measured zero, and the note says so.
    let o = raytree(
        &[
            "render",
            "s.json",
            "--spp",
            "1",
            "-o",
            "one.png",
            "--debug-view",
            "noise",
        ],
        d.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("note: --debug-view noise:") && err.contains("took one sample"),
        "{err}"
    );
    let beauty = read_exr(&d.path().join("out.exr"));
    let parts: Vec<Vec<[f32; 3]>> = ["emit", "direct", "indirect", "glass"]
        .iter()
        .map(|n| read_exr(&d.path().join(format!("out.{n}.exr"))))
        .collect();
    let mut lit = 0;
    for (i, b) in beauty.iter().enumerate() {
        for c in 0..3 {
            let sum: f32 = parts.iter().map(|p| p[i][c]).sum();
            assert!(
                (sum - b[c]).abs() <= 1e-5 * b[c].max(1.0),
                "pixel {i}: {sum} vs {}",
                b[c]
            );
        }
        lit += usize::from(parts[2][i][0] > 0.0);
    }
    assert!(lit > 100, "{lit} pixels with indirect light");
    // The plain render writes the same beauty image.
    let o = raytree(
        &["render", "s.json", "--spp", "4", "-o", "plain.exr"],
        d.path(),
    );
    assert!(o.status.success());
    assert_eq!(
        std::fs::read(d.path().join("plain.exr")).unwrap(),
        std::fs::read(d.path().join("out.exr")).unwrap()
    );
    for v in ["out.view-noise.png", "out.view-share-indirect.png"] {
        let img = image::open(d.path().join(v)).unwrap();
        // The image and a legend strip under it.
        assert_eq!((img.width(), img.height()), (240, 180 + 40), "{v}");
    }
}

#[test]
fn bad_aovs_exit_2_with_the_column_and_write_nothing() {
    let d = dir_with_scene();
    let run = |extra: &[&str], text: &str| {
        let mut args = vec!["render", "s.json", "--spp", "1", "-o", "out.png"];
        args.extend_from_slice(extra);
        fails_with(d.path(), &args, text);
    };
    run(&["--aov", "c=C<RD>Q"], "column 8");
    run(&["--aov", "c=C<RD>Q"], "         ^");
    run(&["--aov", "caustics"], "expected NAME=LPE");
    run(&["--aov", "a/b=CL"], "column 2");
    run(&["--aov", "a=CL", "--aov", "a=CB"], "given twice");
    run(
        &["--aov", "a=CL", "--integrator", "whitted"],
        "need the path integrator",
    );
    run(
        &["--debug-view", "roulette", "--integrator", "whitted"],
        "path integrator",
    );
    run(&["--debug-view", "share:x"], "no AOV named \"x\"");
    run(&["--debug-view", "fireflies"], "unknown debug view");
    run(
        &["--aov", "a=CL", "--size", "4000x4000", "--max-memory", "64"],
        "with 1 AOVs needs about",
    );
}

#[test]
fn versus_finds_the_caustic_whitted_misses_under_the_ball() {
    let d = dir_with_scene();
    let o = raytree(
        &[
            "versus",
            "s.json",
            "--spp",
            "8",
            "-o",
            "vs",
            "--region",
            "84,100,120,124",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let share = j["difference"]["caustics"]["share"].as_f64().unwrap();
    assert!(share > 0.5, "{j}");
    for f in [
        "whitted.png",
        "path.png",
        "side-by-side.png",
        "difference.png",
        "breakdown.json",
    ] {
        assert!(d.path().join("vs").join(f).is_file(), "{f}");
    }
    let e = dir_with_scene();
    fails_with(
        e.path(),
        &["versus", "s.json", "-o", "x", "--region", "5,5,5,9"],
        "empty",
    );
}

#[test]
fn versus_pairs_any_two_integrators_and_tests_their_difference_against_the_noise() {
    let d = dir_with_scene();
    let run = |pair: &str, region: &str, out: &str| {
        let o = raytree(
            &[
                "versus", "s.json", "--pair", pair, "--spp", "4", "--region", region, "-o", out,
                "--json",
            ],
            d.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        j
    };
    // Whitted has no caustic: under the ball it is darker than path tracing beyond the noise.
    let j = run("path,whitted", "84,100,120,124", "pw");
    assert_eq!(j["pair"], serde_json::json!(["path", "whitted"]), "{j}");
    assert_eq!(j["within_noise"], false, "{j}");
    let m = j["difference"]["mean"].as_array().unwrap();
    assert!(m.iter().all(|x| x.as_f64().unwrap() < 0.0), "{j}");
    for f in [
        "path.png",
        "whitted.png",
        "side-by-side.png",
        "difference.png",
        "breakdown.json",
    ] {
        assert!(d.path().join("pw").join(f).is_file(), "{f}");
    }
    // Path tracing and BDPT estimate the same image: their difference is within a few
    // half-widths of the 95 % interval (fixed seeds).
    let j = run("path,bdpt", "0,0,240,180", "pb");
    let (m, hw) = (&j["difference"]["mean"], &j["difference"]["half_width"]);
    for c in 0..3 {
        let (m, hw) = (m[c].as_f64().unwrap(), hw[c].as_f64().unwrap());
        assert!(hw > 0.0 && m.abs() < 2.0 * hw, "{j}");
    }
    assert!(j["b"]["rays"].as_u64().unwrap() > 0 && j["a"]["seconds"].as_f64().is_some());
    assert!(d.path().join("pb").join("bdpt.png").is_file());
    let e = dir_with_scene();
    for (pair, words) in [
        ("path,path", "must differ"),
        ("path", "expected two"),
        ("path,photon", "photon"),
    ] {
        fails_with(
            e.path(),
            &["versus", "s.json", "--pair", pair, "-o", "bad"],
            words,
        );
    }
}
