//! A fixed-budget fuzzer for the input readers (issue 13): mutates the fixtures' scene JSON and
//! an OBJ mesh with a seeded generator and runs the OBJ reader on its own (an error must name a
//! line of the file) and the scene loader (meshes from the mutated OBJ) on every case. It reports cases per second, how cases ended, the slowest
//! case, and every panic or rejection without a position (with the input, to reproduce).
//!
//! ```sh
//! cargo run --release --example fuzz_loader -- --seconds 60 [--seed 1] [--show-slowest]
//! ```
//!
//! Exit status 1 if anything was found. Results are recorded in docs/robustness.md.

use raytree::Scene;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

const SCENES: [&str; 10] = [
    include_str!("../fixtures/absorption.json"),
    include_str!("../fixtures/classic.json"),
    include_str!("../fixtures/diffuse.json"),
    include_str!("../fixtures/mirrors.json"),
    include_str!("../fixtures/nested.json"),
    include_str!("../fixtures/slab.json"),
    include_str!("../fixtures/tir-block.json"),
    include_str!("../fixtures/translucent-shadow.json"),
    include_str!("../fixtures/water-grazing.json"),
    include_str!("../fixtures/mesh/bunny.json"),
];

/// A cube with normals, texture coordinates, comments, groups, quads and negative indices.
const OBJ: &str = "# cube\no cube\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\n\
v 1 1 1\nv -1 1 1\nvn 0 0 -1\nvn 0 0 1\nvt 0 0\nvt 1 0\ng sides\ns 1\nusemtl m\n\
f 1/1/1 2/2/1 3/1/1 4/2/1\nf 5//2 6//2 7//2 8//2\nf 1 2 6 5\nf -5 -6 -2 -1\nf 2 3 7\nf 2 7 6\n\
f 1 5 8 4 # a comment\n";

/// Tokens that matter to JSON and OBJ readers.
const TOKENS: [&str; 28] = [
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "\"",
    "\\",
    "\\u",
    "\\ud800",
    "\u{feff}",
    "\n",
    "\r\n",
    "1e999",
    "-0",
    "1e-400",
    "null",
    "true",
    "[3, 7]",
    "\"type\": \"mesh\"",
    "\"file\": \"m.obj\"",
    "\"radius\": 1,",
    "\"materials\": {}",
    "f 1 2 3\n",
    "v 1e308 1e308 1e308\n",
    "f 0 0 0\n",
    "f -99 1 2\n",
    "vn 0 0 0\n",
];

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// One to eight stacked mutations of `data`; `other` is spliced from.
fn mutate(rng: &mut Rng, data: &mut Vec<u8>, other: &[u8]) {
    for _ in 0..=rng.below(8) {
        let n = data.len();
        let at = rng.below(n + 1);
        match rng.below(8) {
            0 if n > 0 => data[at.min(n - 1)] ^= 1 << rng.below(8),
            1 => data.insert(at, rng.next() as u8),
            2 => {
                let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
                data.splice(at..at, t.iter().copied());
            }
            3 => {
                let end = (at + 1 + rng.below(64)).min(n);
                data.drain(at.min(end)..end);
            }
            4 => {
                let end = (at + 1 + rng.below(256)).min(n);
                let span = data[at.min(end)..end].to_vec();
                data.splice(at..at, span);
            }
            5 if !other.is_empty() => {
                let a = rng.below(other.len());
                let b = (a + 1 + rng.below(512)).min(other.len());
                data.splice(at..at, other[a..b].iter().copied());
            }
            6 => {
                // Replace a digit run with an extreme number.
                let extremes = [
                    "1e308",
                    "-1e308",
                    "5e-324",
                    "0",
                    "-1",
                    "4294967296",
                    "1e999",
                ];
                if let Some(d) = (at..n).find(|&i| data[i].is_ascii_digit()) {
                    let end = (d..n).find(|&i| !data[i].is_ascii_digit()).unwrap_or(n);
                    let e = extremes[rng.below(extremes.len())].as_bytes();
                    data.splice(d..end, e.iter().copied());
                }
            }
            _ => {
                let end = (at + rng.below(16)).min(n);
                data.truncate(end.max(at.min(n)));
            }
        }
    }
}

/// What the readers did with one case.
enum Outcome {
    Accepted,
    Rejected,
    /// A scene error with no line or column.
    Unplaced(String),
}

/// What the OBJ reader did with the case's mesh on its own.
enum ObjOutcome {
    Accepted,
    /// An error on a line of the file (or the whole-file "no faces").
    Rejected,
    /// Not UTF-8 (refused by `input::decode` with its position, before the reader).
    NotText,
    /// An error on no line, or on a line past the end of the file.
    Unplaced(String),
}

fn run_obj(obj: &[u8]) -> (Option<String>, ObjOutcome) {
    let text = match raytree::input::decode(obj.to_vec()) {
        Ok(t) => t,
        Err(_) => return (None, ObjOutcome::NotText),
    };
    let lines = text.lines().count();
    let outcome = match raytree::mesh::parse_obj(&text) {
        Ok(_) => ObjOutcome::Accepted,
        Err(e) if (1..=lines).contains(&e.line) => ObjOutcome::Rejected,
        Err(e) if e.line == 0 && e.message.starts_with("no faces") => ObjOutcome::Rejected,
        Err(e) => ObjOutcome::Unplaced(format!("line {} of {lines}: {}", e.line, e.message)),
    };
    (Some(text), outcome)
}

fn run_case(scene: &[u8], obj_text: Option<&str>) -> Outcome {
    let text = match raytree::input::decode(scene.to_vec()) {
        Ok(t) => t,
        Err(_) => return Outcome::Rejected,
    };
    let result = Scene::from_json_with(&text, &mut |_file| match obj_text {
        Some(t) => raytree::mesh::parse_obj(t).map_err(|e| e.to_string()),
        None => Err("not UTF-8".into()),
    });
    match result {
        Ok(_) => Outcome::Accepted,
        Err(e) if e.line.is_some() && e.column.is_some() => Outcome::Rejected,
        Err(e) => Outcome::Unplaced(e.to_string()),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let flag = |name: &str, default: u64| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let budget = Duration::from_secs(flag("--seconds", 60));
    let seed = flag("--seed", 1);
    let mut rng = Rng(seed);
    // Panics are caught and reported below; the default hook would print each one.
    std::panic::set_hook(Box::new(|_| {}));
    let (mut cases, mut accepted, mut rejected) = (0u64, 0u64, 0u64);
    // The OBJ reader on its own: accepted, rejected with a line, not UTF-8.
    let mut obj_counts = [0u64; 3];
    // Scenes with a mesh object (the loader read the case's OBJ).
    let mut with_mesh = 0u64;
    let mut findings: Vec<String> = Vec::new();
    let mut slowest = (Duration::ZERO, String::new());
    let start = Instant::now();
    while start.elapsed() < budget {
        let i = rng.below(SCENES.len());
        let mut scene = SCENES[i].as_bytes().to_vec();
        let other = SCENES[rng.below(SCENES.len())].as_bytes();
        mutate(&mut rng, &mut scene, other);
        with_mesh += u64::from(scene.windows(6).any(|w| w == b"\"mesh\""));
        let mut obj = OBJ.as_bytes().to_vec();
        if rng.below(2) == 0 {
            mutate(&mut rng, &mut obj, OBJ.as_bytes());
        }
        let t0 = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let (obj_text, obj_outcome) = run_obj(&obj);
            (obj_outcome, run_case(&scene, obj_text.as_deref()))
        }));
        let took = t0.elapsed();
        cases += 1;
        let show = || {
            format!(
                "scene {:?}\nobj {:?}",
                String::from_utf8_lossy(&scene),
                String::from_utf8_lossy(&obj)
            )
        };
        if took > slowest.0 {
            slowest = (took, show());
        }
        if let Ok((o, _)) = &outcome {
            match o {
                ObjOutcome::Accepted => obj_counts[0] += 1,
                ObjOutcome::Rejected => obj_counts[1] += 1,
                ObjOutcome::NotText => obj_counts[2] += 1,
                ObjOutcome::Unplaced(e) => {
                    findings.push(format!("OBJ error without a line: {e}\n{}", show()));
                }
            }
        }
        match outcome.map(|(_, o)| o) {
            Ok(Outcome::Accepted) => accepted += 1,
            Ok(Outcome::Rejected) => rejected += 1,
            Ok(Outcome::Unplaced(e)) => findings.push(format!("no position: {e}\n{}", show())),
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| (*s).to_string()))
                    .unwrap_or_default();
                findings.push(format!("PANIC: {msg}\n{}", show()));
            }
        }
    }
    let secs = start.elapsed().as_secs_f64();
    println!(
        "fuzz_loader: seed {seed}, {cases} cases in {secs:.1} s ({:.0} cases/s): {accepted} accepted, {rejected} rejected with a position, {} findings",
        cases as f64 / secs,
        findings.len()
    );
    println!(
        "OBJ reader: {} accepted, {} rejected with a line, {} not UTF-8 (refused with a position); {with_mesh} scenes named a mesh",
        obj_counts[0], obj_counts[1], obj_counts[2]
    );
    println!(
        "slowest case: {:.2} ms ({} bytes of input)",
        slowest.0.as_secs_f64() * 1e3,
        slowest.1.len()
    );
    if std::env::args().any(|a| a == "--show-slowest") {
        println!("{}", slowest.1);
    }
    for f in findings.iter().take(10) {
        println!("---\n{f}");
    }
    if !findings.is_empty() {
        std::process::exit(1);
    }
}
