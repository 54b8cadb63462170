//! Inspector latency: click -> tree + diagram display list, and a full re-render through the
//! render worker (classic scene, 640x360, depth 16).

use criterion::{Criterion, criterion_group, criterion_main};
use raytree::SceneIntegrator;
use raytree::diagram::{Diagram, DiagramOptions, Style, Theme, display_list};
use raytree::gui::{Command, Files, InspectorApp, Session};
use raytree::render::RenderOptions;
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
        st.whitted.min_weight = Some(if flip { 1e-12 } else { 0.0 });
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
    view.debug = raytree::gui::model::stats::DebugView::Depth;
    s.apply(Command::SetView(view));
    g.bench_function("rerender_640x360_depth16_worker_debug_view", |b| {
        b.iter(|| {
            change(&mut s);
            s.wait_render();
        })
    });
    g.bench_function("render_640x360_depth16_noop_recorder", |b| {
        b.iter(|| {
            black_box(raytree::render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {},
            ))
        })
    });
    g.finish();
}

/// The scene files of `fixtures/`.
struct FixtureFiles;

impl Files for FixtureFiles {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
    }
    fn modified(&self, _: &Path) -> Option<SystemTime> {
        None
    }
    fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
        Ok(())
    }
}

/// One whole inspector frame (`ctx.run_ui` of the full UI, then tessellation) at 1560x940 with
/// a deep tree selected: `nested.json` at depth 16, the refracting pixel 320,150.
fn frames(c: &mut Criterion) {
    let mut g = c.benchmark_group("gui_frame");
    g.measurement_time(Duration::from_secs(4)).sample_size(20);
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.settings.max_depth = 16;
        Ok(())
    });
    let mut session = Session::new(
        Some("fixtures/nested.json".into()),
        Box::new(FixtureFiles),
        adjust,
        Arc::new(|| {}),
    );
    session.wait_render();
    let (x, y) = (320, 150);
    session.apply(Command::SelectPixel([x, y]));
    eprintln!(
        "nested {x},{y}: {} rays",
        session.doc.tree.as_ref().map_or(0, |t| t.nodes.len())
    );
    // The parts of a selection's cost.
    {
        let doc = &session.doc;
        let tree = doc.tree.as_ref().unwrap();
        g.bench_function("nested_trace_pixel", |b| {
            b.iter(|| black_box(raytree::trace_pixel(&doc.scene, x, y)))
        });
        let opts = raytree::gui::model::diagram::diagram_options(doc, [1030, 300]);
        g.bench_function("nested_diagram_build_display_list", |b| {
            b.iter(|| {
                let d = Diagram::build(&doc.scene, tree, &opts).unwrap();
                black_box(display_list(&d, &Style::new(Theme::Dark)))
            })
        });
        let d = Diagram::build(&doc.scene, tree, &opts).unwrap();
        g.bench_function("nested_diagram_raster", |b| {
            b.iter(|| black_box(raytree::diagram::to_pixmap(&d, &Style::new(Theme::Dark))))
        });
    }
    let mut app = InspectorApp::new(session);
    let ctx = egui::Context::default();
    let screen = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1560.0, 940.0));
    let mut t = 0.0;
    let mut frame = |app: &mut InspectorApp, events: Vec<egui::Event>| {
        t += 1.0 / 60.0;
        let input = egui::RawInput {
            screen_rect: Some(screen),
            time: Some(t),
            events,
            ..Default::default()
        };
        let out = ctx.run_ui(input, |ui| app.show(ui));
        black_box(ctx.tessellate(out.shapes, out.pixels_per_point))
    };
    for _ in 0..3 {
        frame(&mut app, Vec::new());
    }
    expand_all(&mut app);
    frame(&mut app, Vec::new());
    // The pointer moving over the image (the hover readout changes every frame).
    let mut k = 0;
    g.bench_function("frame_nested_depth16_hover", |b| {
        b.iter(|| {
            k = (k + 1) % 50;
            let pos = egui::pos2(500.0 + k as f32, 300.0);
            frame(&mut app, vec![egui::Event::PointerMoved(pos)])
        })
    });
    // A click's frame: the selection alternates between two refracting pixels.
    let mut flip = false;
    g.bench_function("frame_nested_depth16_after_select", |b| {
        b.iter(|| {
            flip = !flip;
            let p = if flip { [321, 150] } else { [x, y] };
            app.session.apply(Command::SelectPixel(p));
            frame(&mut app, Vec::new())
        })
    });
    // A path-traced pixel with its Samples section: the Cornell box at spp 16 (a firefly pixel,
    // 16 rows, a 5-bar histogram), every level open.
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.settings.spp = 16;
        Ok(())
    });
    let mut session = Session::new(
        Some("fixtures/cornell-box.json".into()),
        Box::new(FixtureFiles),
        adjust,
        Arc::new(|| {}),
    );
    session.wait_render();
    session.apply(Command::SelectPixel([159, 46]));
    eprintln!(
        "cornell-box 159,46 spp 16: {} rays",
        session.doc.tree.as_ref().map_or(0, |t| t.nodes.len())
    );
    let mut app = InspectorApp::new(session);
    for _ in 0..3 {
        frame(&mut app, Vec::new());
    }
    expand_all(&mut app);
    frame(&mut app, Vec::new());
    g.bench_function("frame_cornell_spp16_hover", |b| {
        b.iter(|| {
            k = (k + 1) % 50;
            let pos = egui::pos2(500.0 + k as f32, 300.0);
            frame(&mut app, vec![egui::Event::PointerMoved(pos)])
        })
    });
    g.bench_function("frame_cornell_spp16_after_select", |b| {
        b.iter(|| {
            flip = !flip;
            let p = if flip { [160, 46] } else { [159, 46] };
            app.session.apply(Command::SelectPixel(p));
            frame(&mut app, Vec::new())
        })
    });
    g.finish();
}

/// Open every level of the selected tree (2144 rows).
fn expand_all(app: &mut InspectorApp) {
    app.expand_all();
}

criterion_group!(gui, benches, frames);
criterion_main!(gui);
