//! The per-pixel samples of the path tracer: the sample list and histogram against the
//! recorded tree, the firefly explanation of the caustic pixel, and every sample in one diagram
//! (issue 16).

mod common;

use raytree::analysis::{firefly, samples};
use raytree::diagram::all_samples::{MIN_FADE, sample_fades};
use raytree::diagram::{Diagram, DiagramOptions};
use raytree::{RayTree, Scene, trace_pixel};
use std::path::PathBuf;

fn scene(name: &str) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The caustic fixture's pixel under the glass ball (spp 64, path integrator).
fn caustic() -> (Scene, RayTree) {
    let s = scene("caustic.json");
    let t = trace_pixel(&s, 98, 112).unwrap();
    (s, t)
}

fn lum(c: raytree::math::Rgb) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

#[test]
fn rows_and_histogram_agree_with_the_tree() {
    let (_, t) = caustic();
    let rows = samples::sample_rows(&t);
    assert_eq!(rows.len(), t.samples.len());
    // Every sample once, sorted by value, with the tree's radiance.
    let mut seen: Vec<usize> = rows.iter().map(|r| r.index).collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..t.samples.len()).collect::<Vec<_>>());
    for w in rows.windows(2) {
        assert!(w[0].value >= w[1].value);
    }
    for r in &rows {
        assert_eq!(r.radiance, t.samples[r.index].radiance);
        // A sample's radiance is the sum of its nodes' contributions, its complete paths
        // among them.
        let sum: f64 = r.paths.iter().map(|p| lum(p.contribution)).sum();
        assert!(
            (sum - r.value).abs() <= 1e-9 * r.value.max(1.0),
            "{sum} {}",
            r.value
        );
    }
    let h = samples::histogram(&t);
    let binned: usize = h.bins.iter().map(|b| b.samples.len()).sum();
    assert_eq!(binned + h.zero.len() + h.non_finite.len(), t.samples.len());
    for (k, b) in h.bins.iter().enumerate() {
        for &i in &b.samples {
            let v = lum(t.samples[i].radiance).log10();
            assert!(b.lo <= v && v < b.hi, "sample {i} ({v}) in bar {k}");
        }
    }
    assert!(!h.zero.is_empty(), "most caustic samples are black");
}

#[test]
fn the_caustic_firefly_is_blamed_on_the_floor_bounce() {
    let (_, t) = caustic();
    let top = &samples::sample_rows(&t)[0];
    let f = firefly::explain(&t, top.index).expect("the brightest caustic sample is a firefly");
    assert!(
        matches!(f.cause, firefly::Cause::Caustic { .. }),
        "{:?}",
        f.cause
    );
    assert!(
        f.lpe.starts_with("C<RD>") && f.lpe.ends_with("<TS>L"),
        "{}",
        f.lpe
    );
    let bounce = t.node(f.node);
    assert_eq!(bounce.kind, raytree::RayKind::Diffuse);
    assert!(f.ratio() > firefly::FIREFLY_RATIO);
    // Issue 32: the rare thing is the event, counted over the pixel's samples, not the pdf.
    let firefly::Cause::Caustic { events, .. } = f.cause else {
        unreachable!()
    };
    assert!(events >= 1 && events < t.samples.len(), "{events}");
    let text = f.sentence();
    let count = format!("{events} of the pixel's {} samples", t.samples.len());
    assert!(text.contains(&count), "{text}");
    assert!(!text.contains("rare sample"), "{text}");
    // A black sample is no firefly.
    assert!(firefly::explain(&t, samples::histogram(&t).zero[0]).is_none());
}

#[test]
fn all_samples_draws_every_sample_faded_by_its_value() {
    let (s, t) = caustic();
    let top = samples::sample_rows(&t)[0].index;
    let base = DiagramOptions {
        sample: top,
        min_share: 0.0,
        ..DiagramOptions::default()
    };
    let one = Diagram::build(&s, &t, &base).unwrap();
    let all = Diagram::build(
        &s,
        &t,
        &DiagramOptions {
            all_samples: true,
            ..base.clone()
        },
    )
    .unwrap();
    assert_eq!(one.rays.len(), t.depth_first(t.samples[top].root).len());
    assert_eq!(all.rays.len(), t.nodes.len(), "every ray of every sample");
    // The chosen sample is drawn as alone (same frame, same rays, last so on top).
    assert_eq!(all.frame, one.frame);
    assert_eq!(&all.rays[all.rays.len() - one.rays.len()..], &one.rays[..]);
    // The others are faded by their value: a black sample at MIN_FADE of its plane fade.
    let fades = sample_fades(&t);
    assert_eq!(fades[top], 1.0);
    let black = samples::histogram(&t).zero[0];
    assert!((fades[black] - MIN_FADE).abs() < 1e-12);
    let root = t.samples[black].root;
    let r = all.rays.iter().find(|r| r.node == root).unwrap();
    assert!(r.fade <= MIN_FADE + 1e-12, "{}", r.fade);
}

#[test]
fn the_diagram_command_draws_all_samples() {
    let dir = std::env::temp_dir().join(format!("raytree-all-samples-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let caustic = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/caustic.json");
    let c = caustic.to_str().unwrap();
    for (flag, name) in [(None, "one.svg"), (Some("--all-samples"), "all.svg")] {
        let mut args = vec!["diagram", c, "--pixel", "98,112", "--spp", "8", "-o", name];
        args.extend(flag);
        let o = common::raytree(&args, &dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let one = std::fs::read_to_string(dir.join("one.svg")).unwrap();
    let all = std::fs::read_to_string(dir.join("all.svg")).unwrap();
    // The sample drawn in full is the one carrying the most light, not sample 0.
    let mut sc = scene("caustic.json");
    sc.settings.spp = 8;
    let t = trace_pixel(&sc, 98, 112).unwrap();
    let top = raytree::diagram::all_samples::brightest(&t).unwrap();
    assert!(lum(t.samples[top].radiance) > lum(t.samples[0].radiance));
    assert!(
        all.contains(&format!("all 8 samples (sample {top} in full)")),
        "{}",
        all.lines().find(|l| l.contains("samples (")).unwrap_or("")
    );
    assert!(all.matches("<polyline").count() > one.matches("<polyline").count());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_inspector_filter_keeps_every_sample_s_camera_ray() {
    use raytree::lpe::{Lpe, filter_tree, filter_tree_all_samples};
    let (_, t) = caustic();
    let lpe = [Lpe::parse("C<RD><TS><TS>L").unwrap()];
    let cli = filter_tree(&t, &lpe).unwrap();
    let gui = filter_tree_all_samples(&t, &lpe).unwrap();
    assert_eq!(
        (gui.matched, gui.paths, gui.share),
        (cli.matched, cli.paths, cli.share)
    );
    assert_eq!(gui.tree.samples.len(), t.samples.len());
    assert!(cli.tree.samples.len() < t.samples.len());
    // A sample without a match: its camera ray alone; with one: as the command line keeps it.
    for s in &gui.tree.samples {
        let n = gui.tree.depth_first(s.root).len();
        match cli.tree.samples.iter().find(|c| c.index == s.index) {
            None => assert_eq!(n, 1),
            Some(c) => assert_eq!(n, cli.tree.depth_first(c.root).len()),
        }
    }
    // Shares against the whole pixel: the caustic's paths carry it all here.
    let rows = samples::sample_rows(&gui.tree);
    let carried: f64 = rows
        .iter()
        .flat_map(|r| &r.paths)
        .map(|p| lum(p.contribution))
        .sum::<f64>()
        / gui.tree.samples.len() as f64;
    assert!((carried / lum(t.radiance) - gui.share.unwrap()).abs() < 1e-9);
}

/// `--all-samples` is linear in the pixel's rays and one figure draws a bounded number of them
/// (issue 27, item 9): past the bound the dimmest samples are left out and the legend says so.
#[test]
fn all_samples_bounds_what_one_figure_draws() {
    use raytree::diagram::all_samples::{MAX_OTHER_RAYS, brightest};
    let mut s = scene("caustic.json");
    s.settings.spp = 8192;
    let t = trace_pixel(&s, 98, 112).unwrap();
    let top = brightest(&t).unwrap();
    let d = Diagram::build(
        &s,
        &t,
        &DiagramOptions {
            sample: top,
            all_samples: true,
            ..DiagramOptions::default()
        },
    )
    .unwrap();
    let own = t.depth_first(t.samples[top].root);
    let others = d.rays.iter().filter(|r| !own.contains(&r.node)).count();
    assert!(others <= MAX_OTHER_RAYS, "{others}");
    assert!(d.other_samples_left_out > 0);
    let note = d
        .labels
        .iter()
        .find(|l| l.text.contains("dimmest other sample"))
        .expect("the legend says what the bound left out");
    assert!(
        note.text.starts_with(&format!(
            "{} dimmest other samples (",
            d.other_samples_left_out
        )),
        "{}",
        note.text
    );
    // The brightest samples are the ones kept: no drawn sample is dimmer than a left-out one.
    let root_of: std::collections::HashMap<_, usize> = t
        .samples
        .iter()
        .enumerate()
        .map(|(k, s)| (s.root, k))
        .collect();
    let drawn: std::collections::HashSet<usize> = d
        .rays
        .iter()
        .filter_map(|r| root_of.get(&r.node).copied())
        .collect();
    let dimmest_drawn = drawn
        .iter()
        .map(|k| lum(t.samples[*k].radiance))
        .fold(f64::INFINITY, f64::min);
    let brightest_left = (0..t.samples.len())
        .filter(|k| !drawn.contains(k))
        .map(|k| lum(t.samples[k].radiance))
        .fold(0.0, f64::max);
    assert!(
        dimmest_drawn >= brightest_left,
        "{dimmest_drawn} < {brightest_left}"
    );
}

/// The automatic plane's sentence says what it measured: the chosen sample's light, or its
/// rays' throughput when the sample is black (issue 32, item 9: it said "the pixel's light"
/// of a black sample 0).
#[test]
fn the_plane_choice_says_what_it_measured() {
    let (s, t) = caustic();
    let mut lit_switch = 0;
    for k in 0..t.samples.len() {
        let d = Diagram::build(
            &s,
            &t,
            &DiagramOptions {
                sample: k,
                ..DiagramOptions::default()
            },
        )
        .unwrap();
        if !d.plane_text.contains("chosen over the plane of incidence") {
            continue;
        }
        let index = t.samples[k].index;
        if lum(t.samples[k].radiance) > 0.0 {
            lit_switch += 1;
            assert!(
                d.plane_text
                    .contains(&format!("more of sample {index}'s light (summed shares")),
                "{}",
                d.plane_text
            );
        } else {
            assert!(
                d.plane_text.contains(&format!(
                    "more of sample {index}'s throughput (sample {index} is black)"
                )),
                "{}",
                d.plane_text
            );
        }
        assert!(!d.plane_text.contains("pixel's light"), "{}", d.plane_text);
    }
    assert!(
        lit_switch > 0,
        "some lit sample leaves the plane of incidence"
    );
}

/// Counts in the legend are singular for one ray ("1 ray under 1% ...", "1 ray leaves").
#[test]
fn legend_counts_of_one_are_singular() {
    let (s, t) = caustic();
    let mut seen = 0;
    for k in 0..t.samples.len() {
        let d = Diagram::build(
            &s,
            &t,
            &DiagramOptions {
                sample: k,
                ..DiagramOptions::default()
            },
        )
        .unwrap();
        for l in &d.labels {
            assert!(!l.text.starts_with("1 rays"), "{}", l.text);
            if l.text.starts_with("1 ray ") {
                seen += 1;
            }
        }
    }
    assert!(seen > 0, "some sample's legend counts one ray");
}
