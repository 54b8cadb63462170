//! `raytree effects`, `raytree cost` and `raytree compare` through the binary: what the
//! effects report says of three fixtures, the cost study's CSV, JSON and plot, and image
//! comparison (zero error against itself, a size mismatch exits 2 without a map).

mod common;
use common::{fails, fixture, raytree, stderr};

#[test]
fn effects_cost_and_compare() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = raytree(&["effects", &fixture("mirrors.json")], d);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("[off] refraction (Snell)") && text.contains("[on ] reflection"),
        "{text}"
    );
    assert!(
        text.contains("ray tree: linear")
            && text.contains("facing mirrors: front mirror and back mirror can see each other"),
        "{text}"
    );
    let o = raytree(
        &["effects", &fixture("nested.json"), "--max-depth", "16"],
        d,
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("ray tree: exponential")
            && text.contains("nested: glass ball (dielectric) is inside water tank (dielectric)")
            && text.contains("x fewer) on a 16x9 sample of pixel centres"),
        "{text}"
    );
    // Whitted scenes have no per-sample note; a path-traced one says its samples are paths,
    // and labels the tree and the cut as Whitted's.
    assert!(!text.contains("rays per sample"), "{text}");
    let o = raytree(&["effects", &fixture("caustic.json")], d);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("rays per sample: path integrator: each sample is one path")
            && text.contains("ray tree (whitted): linear")
            && text.contains("what the cut saves (whitted): "),
        "{text}"
    );
    // A quick cost sweep at 16x9, one repeat, of `scene` (the built-in one: none) into `out`.
    let quick_cost = |scene: Option<&str>, out: &str| {
        let mut args = vec!["cost"];
        args.extend(scene);
        args.extend(["--quick", "--size", "16x9", "--repeats", "1", "-o", out]);
        let o = raytree(&args, d);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    // `cost` on a path-traced scene: its own header and axes, not Whitted's.
    quick_cost(Some(&fixture("caustic.json")), "path-rep");
    let md = std::fs::read_to_string(d.join("path-rep/cost.md")).unwrap();
    assert!(
        md.contains(", path integrator. Reference:")
            && md.contains("| rr_depth | from bounce 5 |")
            && !md.contains("| fresnel |")
            && !md.contains("| min_weight |"),
        "{md}"
    );
    let o = raytree(&["effects", &fixture("diffuse.json")], d);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("ray tree: bounded") && !text.contains("what the cut saves"),
        "{text}"
    );
    quick_cost(None, "rep");
    let csv = std::fs::read_to_string(d.join("rep/cost.csv")).unwrap();
    // Header, depth, Fresnel, spp, automatic antialiasing (at 4 spp; at 1 it is uniform),
    // offset, min weight, dielectric roulette, roulette below (suggested), adaptive, filter (no area
    // light, no rough material).
    assert_eq!(
        csv.lines().count(),
        1 + 4 + 3 + 2 + 1 + 4 + 3 + 1 + 1 + 1 + 2,
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("roulette_below,suggested (")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("antialiasing,auto 4 spp,")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("adaptive,0.1 to 16 spp,")),
        "{csv}"
    );
    assert!(
        csv.lines().any(|l| l.starts_with("min_weight,auto (")),
        "the automatic cut has a row: {csv}"
    );
    assert!(
        csv.lines().any(|l| l.ends_with(",true")),
        "a Pareto front exists"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("rep/cost.json")).unwrap()).unwrap();
    assert_eq!(json["reference"]["max_depth"], 32);
    assert!(image::open(d.join("rep/cost.png")).is_ok());
    // An image compared with itself has zero error; different images do not.
    for args in [
        ["render", "-o", "a.png", "--size", "32x18"],
        ["render", "-o", "b.png", "--size", "32x18"],
    ] {
        assert!(raytree(&args, d).status.success());
    }
    assert!(
        raytree(
            &[
                "render",
                "-o",
                "c.png",
                "--size",
                "32x18",
                "--max-depth",
                "0"
            ],
            d
        )
        .status
        .success()
    );
    let o = raytree(&["compare", "a.png", "b.png", "-o", "map.png"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("RMSE 0.000000e0  max error 0.000000"));
    let o = raytree(&["compare", "a.png", "c.png"], d);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("RMSE 0.000000e0"));
    assert!(
        raytree(&["render", "-o", "small.png", "--size", "8x8"], d)
            .status
            .success()
    );
    let err = fails(&raytree(
        &["compare", "a.png", "small.png", "-o", "map2.png"],
        d,
    ));
    assert!(err.contains("sizes differ"), "{err}");
    assert!(!d.join("map2.png").exists());
}
