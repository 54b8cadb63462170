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
    // The match count and share travel with the JSON, as the text header says them.
    let f = &v["lpe_filter"];
    assert_eq!(f["expressions"][0], "C<RD>S+L", "{f}");
    let (matched, paths) = (f["matched"].as_u64().unwrap(), f["paths"].as_u64().unwrap());
    assert!(matched >= 1 && matched < paths, "{f}");
    assert!(
        head.contains(&format!("{matched} of {paths} paths match")),
        "{head}"
    );
    assert!(f["share"].as_f64().unwrap() > 0.0, "{f}");
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

/// `raytree diagram --lpe` draws only the matching paths: the caustic's chain (camera, the
/// diffuse bounce off the floor, two refractions through the ball), and a pixel with no match
/// is an error with no file written.
#[test]
fn diagram_lpe_draws_only_the_matching_paths() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = caustic();
    let scene = scene.to_str().unwrap();
    let pixel = format!("{},{}", PIXEL.0, PIXEL.1);
    let svg = d.join("c.svg");
    let args = [
        "diagram",
        scene,
        "--integrator",
        "path",
        "--pixel",
        &pixel,
        "--lpe",
        "C<RD><TS><TS>L",
        "--min-share",
        "0",
        "-o",
        svg.to_str().unwrap(),
    ];
    let o = raytree(&args, d);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("paths match"), "the title says what was kept");
    // Unfiltered, the same figure draws more rays ("wrote ... (1280x720, N rays drawn, ...").
    let drawn = |o: &std::process::Output| -> usize {
        let s = String::from_utf8_lossy(&o.stdout).into_owned();
        let at = s.find(" rays drawn").expect("the wrote line counts rays");
        s[..at].rsplit(' ').next().unwrap().parse().unwrap()
    };
    let kept = drawn(&o);
    let all = d.join("all.svg");
    let mut a2: Vec<&str> = args[..6].to_vec();
    a2.extend(["--min-share", "0", "-o", all.to_str().unwrap()]);
    let o2 = raytree(&a2, d);
    assert!(o2.status.success());
    // The caustic's chain is four rays (camera, diffuse, two refractions; the last meets the
    // lamp), and no shadow ray; unfiltered, the pixel's first sample has shadow rays (NEE).
    assert_eq!(kept, 4);
    assert!(!text.contains("shadow (to light)"));
    assert!(
        std::fs::read_to_string(&all)
            .unwrap()
            .contains("shadow (to light)")
    );
    assert!(drawn(&o2) > 0);
    let none = d.join("none.svg");
    let o = raytree(
        &[
            "diagram",
            scene,
            "--integrator",
            "path",
            "--pixel",
            &pixel,
            "--lpe",
            "CV+L",
            "-o",
            none.to_str().unwrap(),
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no path"));
    assert!(!none.exists());
}

/// `diagram --lpe X --sample K` draws the pixel's sample K (numbered as `raytree trace` numbers
/// them, not its position among the matching ones); a sample with no matching path is an
/// error that names the samples that have one, with no file written.
#[test]
fn diagram_lpe_sample_is_the_pixels_sample() {
    let path = caustic();
    let scene = Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let tree = trace_pixel(&scene, PIXEL.0, PIXEL.1).unwrap();
    let lpe = Lpe::parse("C<RD><TS><TS>L").unwrap();
    let kept = filter_tree(&tree, std::slice::from_ref(&lpe)).unwrap().tree;
    let matching: Vec<u32> = kept.samples.iter().map(|s| s.index).collect();
    // A matching sample that is not the first matching one (its position differs from its
    // index), and a sample without a match.
    let k = *matching.last().unwrap();
    assert!(k as usize != matching.len() - 1, "{matching:?}");
    let missing = (0..tree.samples.len() as u32)
        .find(|i| !matching.contains(i))
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pixel = format!("{},{}", PIXEL.0, PIXEL.1);
    let run = |sample: u32, out: &std::path::Path| {
        let sample = sample.to_string();
        raytree(
            &[
                "diagram",
                path.to_str().unwrap(),
                "--pixel",
                &pixel,
                "--lpe",
                "C<RD><TS><TS>L",
                "--sample",
                &sample,
                "-o",
                out.to_str().unwrap(),
            ],
            d,
        )
    };
    let svg = d.join("k.svg");
    let o = run(k, &svg);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains(&format!("sample {k},")),
        "the title names sample {k}"
    );
    let none = d.join("none.svg");
    let o = run(missing, &none);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    let list: Vec<String> = matching.iter().map(u32::to_string).collect();
    assert!(err.contains(&list.join(", ")), "{err}");
    assert!(!none.exists());
}

/// Fuzz the parser (issue 27): any string, and valid expressions with characters inserted,
/// deleted or repeated, parse to `Ok` (whose matcher then runs on path strings) or to an error
/// whose column lies in the expression; never a panic, and in bounded time (the regex
/// compiler's size limit refuses blow-ups).
mod fuzz {
    use ::raytree::lpe::Lpe;
    use proptest::prelude::*;

    const SEEDS: [&str; 6] = [
        "C<RD>S+L",
        "C(<R.>|<T.>)*L",
        "CD+L",
        "C[^D]*<RG>L",
        "C.*L",
        "C<TS>{2,3}<RD>L",
    ];
    const ALPHABET: &str = "CLDSGRT<>()[]|*+?.^{},0123'x \u{1b}\u{0}é";

    fn check(expr: &str) -> Result<(), TestCaseError> {
        match Lpe::parse(expr) {
            Ok(l) => {
                for path in ["CL", "C<RD>L", "C<TS><TS><RD>L", "C<RG><RD><RD>L"] {
                    let _ = l.matches(path);
                }
            }
            Err(e) => prop_assert!(
                e.column >= 1 && e.column <= expr.chars().count() + 1,
                "column {} of {expr:?}",
                e.column
            ),
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        #[test]
        fn any_string_parses_or_is_refused_at_a_column(s in "\\PC{0,40}") {
            check(&s)?;
        }

        #[test]
        fn mutated_expressions_parse_or_are_refused_at_a_column(
            seed in 0..SEEDS.len(),
            edits in prop::collection::vec((0usize..64, 0usize..ALPHABET.chars().count(), 0u8..3), 1..6),
        ) {
            let mut chars: Vec<char> = SEEDS[seed].chars().collect();
            let alphabet: Vec<char> = ALPHABET.chars().collect();
            for (at, c, op) in edits {
                let at = at % (chars.len() + 1);
                match op {
                    0 => chars.insert(at, alphabet[c]),
                    1 if at < chars.len() => { chars.remove(at); }
                    _ => {
                        let tail: Vec<char> = chars[at..].to_vec();
                        chars.extend(tail);
                    }
                }
            }
            check(&chars.into_iter().collect::<String>())?;
        }
    }
}
