//! Diagram cost: build the model and rasterize it at 1280x720 for deep trees.

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::diagram::{Diagram, DiagramOptions, Style, to_pixmap, to_png, to_svg};
use raytree::{Scene, trace_pixel};
use std::hint::black_box;
use std::time::Duration;

fn fixture(name: &str) -> Scene {
    let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("diagram");
    g.measurement_time(Duration::from_secs(3)).sample_size(20);
    let style = Style::default();
    let opts = DiagramOptions::default();
    // tir-block pixel (320, 230): 31 rays, depth 16 (cut by max_depth); nested: 315 rays.
    for (label, name, x, y) in [
        ("tir-block depth 16", "tir-block.json", 320, 230),
        ("nested 315 rays", "nested.json", 380, 170),
    ] {
        let scene = fixture(name);
        let tree = trace_pixel(&scene, x, y).unwrap();
        let depth = tree.nodes.iter().map(|n| n.depth).max().unwrap_or(0);
        eprintln!("{label}: {} nodes, max depth {depth}", tree.nodes.len());
        g.bench_function(format!("{label}: build"), |b| {
            b.iter(|| Diagram::build(black_box(&scene), black_box(&tree), &opts).unwrap())
        });
        g.bench_function(format!("{label}: build + raster 1280x720"), |b| {
            b.iter(|| {
                to_pixmap(
                    &Diagram::build(black_box(&scene), black_box(&tree), &opts).unwrap(),
                    &style,
                )
            })
        });
        let d = Diagram::build(&scene, &tree, &opts).unwrap();
        g.bench_function(format!("{label}: png encode incl. raster"), |b| {
            b.iter(|| to_png(black_box(&d), &style))
        });
        g.bench_function(format!("{label}: svg"), |b| {
            b.iter(|| to_svg(black_box(&d), &style))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
