//! Inspector latency: click -> tree + diagram display list, and a full re-render through the
//! render worker (classic scene, 640x360, depth 16).

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::diagram::{Diagram, DiagramOptions, Style, Theme, display_list};
use raytree::gui::{Command, Files, Session};
use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, SystemTime};

struct NoFiles;

impl Files for NoFiles {
    fn read(&self, _: &Path) -> std::io::Result<String> {
        Err(std::io::ErrorKind::NotFound.into())
    }
    fn modified(&self, _: &Path) -> Option<SystemTime> {
        None
    }
    fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
        Ok(())
    }
}

fn session() -> Session {
    Session::new(
        None,
        Box::new(NoFiles),
        Box::new(|_| Ok(())),
        Arc::new(|| {}),
    )
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("gui");
    g.measurement_time(Duration::from_secs(3)).sample_size(20);

    let scene = raytree::Scene::default_scene();
    // A pixel on the glass ball: a deep tree (59 rays at depth 16).
    let (x, y) = (390, 230);
    let tree = raytree::trace_pixel(&scene, x, y).unwrap();
    eprintln!("tree at {x},{y}: {} nodes", tree.nodes.len());
    let opts = DiagramOptions {
        width: 900,
        height: 300,
        highlight: Some(raytree::NodeId(0)),
        ..DiagramOptions::default()
    };
    let style = Style::new(Theme::Dark);
    g.bench_function("click_trace_pixel", |b| {
        b.iter(|| black_box(raytree::trace_pixel(&scene, x, y)))
    });
    g.bench_function("click_tree_and_diagram", |b| {
        b.iter(|| {
            let t = raytree::trace_pixel(&scene, x, y).unwrap();
            let d = Diagram::build(&scene, &t, &opts).unwrap();
            black_box(display_list(&d, &style))
        })
    });
    let mut s = session();
    s.wait_render();
    g.bench_function("session_select_pixel", |b| {
        b.iter(|| s.apply(Command::SelectPixel([x, y])))
    });

    // Toggle min weight between two values that cut nothing, so every iteration is a real
    // settings change and a full re-render at depth 16.
    let mut flip = false;
    let mut change = |s: &mut Session| {
        let mut st = s.doc.scene.settings;
        st.max_depth = 16;
        st.min_weight = Some(if flip { 1e-12 } else { 0.0 });
        flip = !flip;
        s.apply(Command::SetSettings(st));
    };
    g.bench_function("rerender_640x360_depth16_worker", |b| {
        b.iter(|| {
            change(&mut s);
            s.wait_render();
        })
    });
    g.bench_function("rerender_640x360_depth16_worker_image_only", |b| {
        b.iter(|| {
            // The same change, waiting only for the image (the statistics follow it).
            change(&mut s);
            s.wait_image();
        })
    });
    s.wait_render();
    // With a debug view on screen: one recorded pass gives image and statistics.
    let mut view = s.doc.view;
    view.debug = raytree::gui::stats::DebugView::Depth;
    s.apply(Command::SetView(view));
    g.bench_function("rerender_640x360_depth16_worker_debug_view", |b| {
        b.iter(|| {
            change(&mut s);
            s.wait_render();
        })
    });
    g.bench_function("render_640x360_depth16_noop_recorder", |b| {
        b.iter(|| black_box(raytree::render(&scene, &|_| {})))
    });
    g.finish();
}

criterion_group!(gui, benches);
criterion_main!(gui);
