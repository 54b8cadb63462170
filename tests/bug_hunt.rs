//! The numbers a bug hunt needs (issue 32, items 14-17), through the binary: `compare`'s mean
//! signed difference with its interval, signed map and `--region`.

mod common;
use common::{fails, raytree};
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
