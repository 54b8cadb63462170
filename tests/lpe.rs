//! Light path expressions (issue 16): `filter_tree` on a recorded caustic, and
//! `raytree trace --lpe` (text, JSON, a bad expression, a Whitted tree).

mod common;

use common::raytree;
use raytree::lpe::{Lpe, filter_tree};
use raytree::{Scene, trace_pixel};
use std::path::PathBuf;

fn caustic() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/caustic.json")
}

/// A pixel of the caustic under the glass ball, with some `C<RD><TS><TS>L` paths.
const PIXEL: (u32, u32) = (98, 112);

#[test]
fn the_filter_keeps_matching_paths_and_their_ancestors() {
    let scene = Scene::from_json(&std::fs::read_to_string(caustic()).unwrap()).unwrap();
    let tree = trace_pixel(&scene, PIXEL.0, PIXEL.1).unwrap();
    let lpe = Lpe::parse("C<RD>S+L").unwrap();
    let f = filter_tree(&tree, std::slice::from_ref(&lpe)).unwrap();
    assert!(
        f.matched > 0 && f.matched < f.paths,
        "{} of {}",
        f.matched,
        f.paths
    );
    assert!(f.tree.samples.len() < tree.samples.len());
    // Every kept leaf is a matching path, every kept node's ids are consistent, and the
    // matching nodes' path strings all satisfy the expression.
    for (i, n) in f.tree.nodes.iter().enumerate() {
        assert_eq!(n.id.index(), i);
        for c in &n.children {
            assert_eq!(f.tree.node(*c).parent, Some(n.id));
        }
        let lpe_str = &n.path.as_ref().unwrap().lpe;
        if n.children.is_empty() {
            assert!(lpe.matches(lpe_str), "{lpe_str}");
        }
    }
    for s in &f.tree.samples {
        assert!(f.tree.node(s.root).parent.is_none());
    }
    let share = f.share.unwrap();
    assert!(share > 0.0 && share <= 1.0 + 1e-12, "{share}");
    // `.*` keeps every complete path (a node whose path ends at a light or the background),
    // and drops only the branches that end elsewhere (absorbed, cut by depth or roulette).
    let all = filter_tree(&tree, &[Lpe::parse(".*").unwrap()]).unwrap();
    let complete = |t: &raytree::RayTree| {
        t.nodes
            .iter()
            .filter(|n| n.path.as_ref().unwrap().lpe.ends_with(['L', 'B']))
            .count()
    };
    assert_eq!(all.matched, all.paths);
    assert_eq!(complete(&all.tree), complete(&tree));
    assert!(all.tree.nodes.len() <= tree.nodes.len());
    assert!((all.share.unwrap() - 1.0).abs() < 1e-9);
    let none = filter_tree(&tree, &[Lpe::parse("CV+L").unwrap()]).unwrap();
    assert!(none.tree.nodes.is_empty() && none.matched == 0);
}

#[test]
fn trace_lpe_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = caustic();
    let scene = scene.to_str().unwrap();
    let pixel = format!("{},{}", PIXEL.0, PIXEL.1);
    let base = ["trace", scene, "--integrator", "path", "--pixel", &pixel];
    let run = |extra: &[&str]| raytree(&[&base[..], extra].concat(), d);

    let o = run(&["--lpe", "C<RD>S+L"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let head = text.lines().next().unwrap();
    assert!(
        head.starts_with("lpe C<RD>S+L: ") && head.contains("paths match"),
        "{head}"
    );
    assert!(text.contains("| C<RD><TS><TS>L"), "{text}");
    assert!(!text.contains("| C<RD>L"), "{text}");

    let o = run(&["--lpe", "C<RD>S+L", "--json"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let lpes: Vec<&str> = v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["path"]["lpe"].as_str().unwrap())
        .collect();
    assert!(lpes.contains(&"C<RD><TS><TS>L"), "{lpes:?}");
    assert!(
        lpes.iter().all(|l| "C<RD><TS><TS>L".starts_with(l)),
        "{lpes:?}"
    );

    // A bad expression: exit 2, the column, nothing on stdout.
    let o = run(&["--lpe", "Cx"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("column 2") && err.contains("'x'"), "{err}");
    assert!(o.stdout.is_empty());
    let o = run(&["--lpe", "C{2,1}", "--json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("column 2"));
    assert!(o.stdout.is_empty());

    // A Whitted tree has no path records.
    let o = raytree(
        &[
            "trace",
            scene,
            "--integrator",
            "whitted",
            "--pixel",
            &pixel,
            "--lpe",
            "CB",
        ],
        d,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("path integrator"), "{err}");
    assert!(o.stdout.is_empty());
}
