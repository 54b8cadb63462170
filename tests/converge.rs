//! `raytree converge` (issue 16): the report's files and CSV columns, the error falling with
//! spp on a path-traced fixture, the cached reference, and bad input (exit 2, nothing written).

mod common;

use common::{fails_with, raytree};

fn dir_with_cornell() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/cornell-box.json");
    std::fs::copy(src, dir.path().join("s.json")).unwrap();
    dir
}

#[test]
fn converge_writes_the_report_and_the_error_falls_with_spp() {
    let dir = dir_with_cornell();
    let args = [
        "converge",
        "s.json",
        "-o",
        "rep",
        "--size",
        "24x24",
        "--max-spp",
        "16",
        "--ref-spp",
        "256",
        "--series",
        "default,sobol,denoise",
    ];
    let o = raytree(&args, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rep = dir.path().join("rep");
    for f in [
        "converge.md",
        "converge.csv",
        "converge.json",
        "converge.png",
        "reference.exr",
        "reference.json",
    ] {
        assert!(rep.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(rep.join("converge.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("series,spp,seconds,rel_rmse,slope_spp,slope_seconds")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3 * 5, "{csv}");
    let curve = |name: &str| -> Vec<(u32, f64)> {
        rows.iter()
            .filter(|r| r[0] == name)
            .map(|r| (r[1].parse().unwrap(), r[3].parse().unwrap()))
            .collect()
    };
    for name in ["default", "sobol", "denoise"] {
        let c = curve(name);
        assert_eq!(c.iter().map(|p| p.0).collect::<Vec<_>>(), [1, 2, 4, 8, 16]);
        assert!(c[4].1 < c[0].1 * 0.6, "{name}: {c:?}");
    }
    // Independent samples: the fitted slope against spp is near -1/2.
    let slope: f64 = rows.iter().find(|r| r[0] == "default").unwrap()[4]
        .parse()
        .unwrap();
    assert!((-0.75..-0.3).contains(&slope), "{slope}");
    // The denoised curve starts below the raw one.
    assert!(curve("denoise")[0].1 < curve("default")[0].1);
    // A second run reuses the reference.
    let o = raytree(&args, dir.path());
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("using the cached reference"));
    assert_eq!(
        std::fs::read_to_string(rep.join("converge.csv"))
            .unwrap()
            .lines()
            .count(),
        16
    );
}

#[test]
fn converge_refuses_bad_input_and_writes_nothing() {
    let dir = dir_with_cornell();
    let p = dir.path();
    fails_with(
        p,
        &["converge", "s.json", "-o", "rep", "--series", "mis-off"],
        "unknown series \"mis-off\"",
    );
    fails_with(
        p,
        &[
            "converge",
            "s.json",
            "-o",
            "rep",
            "--max-spp",
            "64",
            "--ref-spp",
            "64",
        ],
        "must be above --max-spp",
    );
    fails_with(
        p,
        &["converge", "s.json", "-o", "rep", "--max-spp", "0"],
        "--max-spp 0: must be 1 to 65536",
    );
    fails_with(
        p,
        &[
            "converge",
            "s.json",
            "-o",
            "rep",
            "--integrator",
            "whitted",
            "--series",
            "bsdf-only",
        ],
        "needs the path integrator",
    );
    fails_with(
        p,
        &[
            "converge",
            "s.json",
            "-o",
            "rep",
            "--reference",
            "missing.exr",
        ],
        "missing.exr",
    );
    // A reference of another size than the render.
    let o = raytree(
        &[
            "render", "s.json", "--size", "8x8", "--spp", "1", "-o", "ref.exr",
        ],
        p,
    );
    assert!(o.status.success());
    let o = raytree(
        &[
            "converge",
            "s.json",
            "-o",
            "rep",
            "--size",
            "9x9",
            "--reference",
            "ref.exr",
        ],
        p,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is 8x8, the render 9x9"));
    assert!(!p.join("rep").exists());
}
