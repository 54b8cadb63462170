//! The numbers a bug hunt needs (issue 32, items 14-17), through the binary: `compare`'s mean
//! signed difference with its interval, signed map and `--region`; `outliers` on an image with
//! a known hot pixel and on a scene; `converge` naming identical series; `diff` between
//! stochastic settings naming the first differing decision with a standard error.

mod common;
use common::{fails, fixture, raytree};
use std::path::Path;

/// A `w x h` EXR at `dir/name` with `f(x, y)` in every channel.
fn exr(dir: &Path, name: &str, (w, h): (u32, u32), f: impl Fn(u32, u32) -> f32) {
    let img = image::Rgb32FImage::from_fn(w, h, |x, y| {
        let v = f(x, y);
        image::Rgb([v, v, v])
    });
    img.save(dir.join(name)).unwrap();
}

fn stdout(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Noise in [-0.05, 0.05) from a hash of the pixel.
fn noise(x: u32, y: u32) -> f32 {
    let mut r = common::Rng(u64::from(y * 1000 + x));
    (r.next() as f32 - 0.5) * 0.1
}

#[test]
fn compare_gives_the_signed_mean_with_an_interval_over_a_region() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // B is A plus 0.1 inside 8..24 x 8..24 only; A is a noisy grey.
    exr(d, "a.exr", (32, 32), |x, y| 0.5 + noise(x, y));
    exr(d, "b.exr", (32, 32), |x, y| {
        let inside = (8..24).contains(&x) && (8..24).contains(&y);
        0.5 + noise(x, y) + if inside { 0.1 } else { 0.0 }
    });
    let text = stdout(&raytree(&["compare", "a.exr", "b.exr", "-o", "map.png"], d));
    assert!(
        text.contains(
            "mean signed difference A - B, 95% interval from 16 block means of 8x8 pixels"
        ),
        "{text}"
    );
    // The whole image: -0.1 x 256/1024 = -0.025, its blocks either 0 or -0.1.
    let r_line = text
        .lines()
        .find(|l| l.trim_start().starts_with("R "))
        .unwrap();
    assert!(r_line.contains("-2.500e-2"), "{r_line}");
    // Inside the region the difference is the constant -0.1: beyond the noise.
    let text = stdout(&raytree(
        &["compare", "a.exr", "b.exr", "--region", "8,8,24,24"],
        d,
    ));
    assert!(text.contains("region 8,8 to 24,24"), "{text}");
    assert!(
        text.contains("from 256 single pixels"),
        "a 16x16 region has 4 blocks: pixels are the blocks: {text}"
    );
    let r_line = text
        .lines()
        .find(|l| l.trim_start().starts_with("R "))
        .unwrap();
    assert!(
        r_line.contains("-1.000e-1") && r_line.contains("beyond the noise"),
        "{r_line}"
    );
    // Outside it nothing differs.
    let text = stdout(&raytree(
        &["compare", "a.exr", "b.exr", "--region", "0,0,32,8"],
        d,
    ));
    assert!(text.contains("RMSE 0.000000e0"), "{text}");
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
    // The map is signed, with a legend strip under the (magnified) image.
    let map = image::open(d.join("map.png")).unwrap().into_rgb8();
    let k = 420u32.div_ceil(32);
    assert_eq!((map.width(), map.height()), (32 * k, 32 * k + 52));
    let at = |x: u32, y: u32| map.get_pixel(x * k + k / 2, y * k + k / 2).0;
    let (inside, outside) = (at(16, 16), at(2, 2));
    assert!(
        inside[2] > inside[0] + 50,
        "A darker than B: blue, {inside:?}"
    );
    assert_eq!(outside, [221, 221, 221], "equal: grey");
}

#[test]
fn compare_refuses_bad_regions_and_scales_with_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    exr(d, "a.exr", (16, 8), |_, _| 0.5);
    for (flag, value, why) in [
        ("--region", "0,0,17,8", "leaves the 16x8 image"),
        ("--region", "4,0,4,8", "is empty"),
        ("--region", "0,0,8", "four integers"),
        ("--region", "-1,0,8,8", "X0 must be a pixel coordinate"),
        ("--scale", "inf", "--scale"),
        ("--scale", "0", "--scale"),
    ] {
        let o = raytree(
            &["compare", "a.exr", "a.exr", flag, value, "-o", "m.png"],
            d,
        );
        let e = fails(&o);
        assert!(e.contains(why), "{value}: {e}");
        assert!(o.stdout.is_empty(), "{value}: printed {:?}", o.stdout);
        assert!(!d.join("m.png").exists(), "{value}");
    }
}

#[test]
fn outliers_finds_the_hot_pixel_of_an_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    exr(d, "hot.exr", (24, 16), |x, y| {
        if (x, y) == (7, 5) {
            20.0
        } else {
            0.5 + noise(x, y)
        }
    });
    let text = stdout(&raytree(&["outliers", "hot.exr", "--top", "3"], d));
    let first = text
        .lines()
        .find(|l| l.trim_start().starts_with("1."))
        .unwrap();
    assert!(first.contains("pixel 7,5"), "{text}");
    assert!(
        first.contains("value [20.0000, 20.0000, 20.0000]"),
        "{first}"
    );
    let median: f64 = first
        .split("neighbourhood median ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((median - 0.5).abs() < 0.05, "{first}");
    assert!(text.contains("raytree trace SCENE --pixel 7,5"), "{text}");
    assert!(text.contains("raytree explain SCENE --pixel 7,5"), "{text}");
    let json = stdout(&raytree(
        &["outliers", "hot.exr", "--json", "--window", "5"],
        d,
    ));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["by_excess"][0]["pixel"], serde_json::json!([7, 5]));
    assert_eq!(v["window"], 5);
    assert!(v["by_std_error"].is_null(), "an image has no samples");
    // Bad input: exit 2.
    for args in [
        &["outliers", "hot.exr", "--window", "4"][..],
        &["outliers", "hot.exr", "--top", "0"],
        &["outliers", "hot.exr", "--spp", "4"],
        &["outliers", "missing.exr"],
    ] {
        fails(&raytree(args, d));
    }
}

#[test]
fn outliers_of_a_scene_rank_by_excess_and_by_standard_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let caustic = fixture("caustic.json");
    let args = [
        "outliers", &caustic, "--spp", "4", "--size", "60x45", "--top", "5", "--json",
    ];
    let v: serde_json::Value = serde_json::from_str(&stdout(&raytree(&args, d))).unwrap();
    let top = &v["by_excess"][0];
    let (lum, median) = (
        top["luminance"].as_f64().unwrap(),
        top["median"].as_f64().unwrap(),
    );
    assert!(lum > 5.0 * median + 1.0, "a firefly: {top}");
    let se = v["by_std_error"].as_array().unwrap();
    assert_eq!(se.len(), 5);
    assert!(
        se.windows(2).all(|w| {
            w[0]["std_error"].as_f64().unwrap() >= w[1]["std_error"].as_f64().unwrap()
        })
    );
    // The command printed for the pixel runs, with the render's settings.
    let explain = top["explain"].as_str().unwrap();
    assert!(explain.ends_with("--spp 4 --size 60x45"), "{explain}");
    let words: Vec<&str> = explain.split_whitespace().skip(1).collect();
    let text = stdout(&raytree(&words, d));
    let [x, y] = [&top["pixel"][0], &top["pixel"][1]];
    assert!(text.contains(&format!("pixel ({x}, {y})")), "{text}");
}

#[test]
fn converge_says_when_two_series_are_identical() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The built-in scene has point lights only: MIS and light sampling give the same image.
    let args = [
        "converge",
        "--integrator",
        "path",
        "--size",
        "16x12",
        "--max-spp",
        "4",
        "--ref-spp",
        "16",
        "--series",
        "default,light-only,bsdf-only",
        "-o",
        "rep",
    ];
    stdout(&raytree(&args, d));
    let md = std::fs::read_to_string(d.join("rep/converge.md")).unwrap();
    assert!(
        md.contains("Identical series (the same rel-RMSE at every spp")
            && md.contains("default = light-only")
            && !md.contains("bsdf-only = "),
        "{md}"
    );
}

#[test]
fn diff_between_roulette_depths_names_the_first_differing_decision() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let caustic = fixture("caustic.json");
    let base = [
        "diff",
        &caustic,
        "--pixel",
        "98,112",
        "--spp",
        "16",
        "--a",
        "--rr-depth 1",
        "--b",
        "--rr-depth 8",
    ];
    let short = stdout(&raytree(&base, d));
    assert!(
        short.contains("first differing decision: sample "),
        "{short}"
    );
    assert!(short.contains("path roulette"), "{short}");
    assert!(short.contains("+/- ["), "a standard error: {short}");
    assert!(
        short.contains("(standard error, paired by sample, 16 samples)"),
        "{short}"
    );
    assert!(
        short.contains("--full lists every changed field"),
        "{short}"
    );
    let mut full_args = base.to_vec();
    full_args.push("--full");
    let full = stdout(&raytree(&full_args, d));
    assert!(full.starts_with(short.lines().next().unwrap()));
    assert!(
        short.lines().count() * 5 < full.lines().count(),
        "short {} lines, full {}",
        short.lines().count(),
        full.lines().count()
    );
    assert!(short.lines().count() <= 12, "{short}");
    let json = stdout(&raytree(&[&base[..], &["--json"]].concat(), d));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["first_decision"]["decision"], "path roulette");
    assert!(v["pixel"]["std_error"][0].as_f64().unwrap() >= 0.0);
}
