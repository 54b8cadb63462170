//! Cross-section diagrams: the model against the scene and tree, and both back-ends (the CLI is
//! in `tests/diagram_cli.rs`).

use glam::DVec3;
use raytree::diagram::model::{Fill, SliceShape};
use raytree::diagram::{Diagram, DiagramOptions, PlaneSpec, Style, Theme, to_png, to_svg};
use raytree::{RayKind, RayTree, Scene, trace_pixel};
use std::path::PathBuf;

fn fixture_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

fn scene(name: &str) -> Scene {
    Scene::from_json(&std::fs::read_to_string(fixture_path(name)).unwrap()).unwrap()
}

/// Every ray (no contribution threshold).
fn build(scene: &Scene, tree: &RayTree, plane: PlaneSpec) -> Diagram {
    let opts = DiagramOptions {
        plane,
        min_share: 0.0,
        ..DiagramOptions::default()
    };
    Diagram::build(scene, tree, &opts).unwrap()
}

#[test]
fn every_ray_node_appears_exactly_once() {
    for (name, x, y) in [
        ("classic.json", 400, 200),
        ("tir-block.json", 320, 230),
        ("absorption.json", 180, 200),
    ] {
        let s = scene(name);
        let tree = trace_pixel(&s, x, y).unwrap();
        let d = build(&s, &tree, PlaneSpec::Incidence);
        let mut drawn: Vec<u32> = d.rays.iter().map(|r| r.node.0).collect();
        drawn.sort_unstable();
        let all: Vec<u32> = (0..tree.nodes.len() as u32).collect();
        assert_eq!(drawn, all, "{name}");
        assert!(
            tree.nodes.len() > 5,
            "{name}: pick a pixel with a real tree"
        );
    }
}

#[test]
fn kinds_and_depth_filters_drop_rays() {
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let opts = DiagramOptions {
        kinds: vec![RayKind::Camera, RayKind::Refracted],
        max_depth: Some(2),
        ..DiagramOptions::default()
    };
    let d = Diagram::build(&s, &tree, &opts).unwrap();
    let want = tree
        .nodes
        .iter()
        .filter(|n| matches!(n.kind, RayKind::Camera | RayKind::Refracted) && n.depth <= 2)
        .count();
    assert_eq!(d.rays.len(), want);
    assert!(
        d.rays
            .iter()
            .all(|r| r.kind != RayKind::Shadow && r.depth <= 2)
    );
}

#[test]
fn projected_distances_are_the_coordinate_offsets() {
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let d = build(
        &s,
        &tree,
        PlaneSpec::Axis {
            axis: 2,
            value: 0.3,
        },
    );
    assert!(d.frame.normal.abs().abs_diff_eq(DVec3::Z, 1e-12));
    let mut checked = 0;
    for r in &d.rays {
        let n = tree.node(r.node);
        let start = if n.kind == RayKind::Camera {
            n.origin
        } else {
            n.spawn_point
        };
        assert!((r.plane_distance[0].abs() - (start.z - 0.3).abs()).abs() < 1e-9);
        if let Some(h) = &n.hit {
            assert!((r.plane_distance[1].abs() - (h.point.z - 0.3).abs()).abs() < 1e-9);
            // The drawn end is the orthogonal projection of the hit (when in the view; rays
            // to hits outside it leave through the frame).
            let inside = r.to.x > d.view.min.x + 1e-6
                && r.to.x < d.view.max.x - 1e-6
                && r.to.y > d.view.min.y + 1e-6
                && r.to.y < d.view.max.y - 1e-6;
            if !inside {
                continue;
            }
            let q = d.frame.canvas_to_plane(r.to);
            assert!(
                (d.frame.origin + q.x * d.frame.u + q.y * d.frame.v
                    - DVec3::new(h.point.x, h.point.y, 0.3))
                .length()
                    < 1e-9
            );
            checked += 1;
        }
        if r.off_plane {
            assert!(r.fade < 1.0 && r.plane_distance.iter().any(|x| x.abs() > 1e-6));
        }
    }
    assert!(checked >= 3, "{checked}");
    // In the plane of incidence the camera ray and its first reflection lie in the plane.
    let d = build(&s, &tree, PlaneSpec::Incidence);
    for r in d
        .rays
        .iter()
        .filter(|r| r.kind == RayKind::Camera || r.kind == RayKind::Reflected && r.depth == 1)
    {
        assert!(r.plane_distance.iter().all(|x| x.abs() < 1e-9), "{r:?}");
        assert!(!r.off_plane);
    }
}

#[test]
fn sphere_slice_is_the_exact_circle() {
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    // glass ball: centre (1, 0.9, 1.2), radius 0.9; the plane z = 1.5 is 0.3 from the centre.
    let d = build(
        &s,
        &tree,
        PlaneSpec::Axis {
            axis: 2,
            value: 1.5,
        },
    );
    let ball = d
        .objects
        .iter()
        .find(|o| o.name == "glass ball")
        .expect("sliced");
    let SliceShape::Circle { center, radius } = ball.shape else {
        panic!("{:?}", ball.shape)
    };
    assert!((radius / d.frame.scale - (0.81f64 - 0.09).sqrt()).abs() < 1e-9);
    assert!((center - d.frame.to_canvas(DVec3::new(1.0, 0.9, 1.5))).length() < 1e-9);
    assert!(matches!(ball.fill, Fill::Glass { ior, .. } if ior == 1.5));
    // The mirror ball (z = -0.6, r = 1) is not cut by z = 1.5.
    assert!(d.objects.iter().all(|o| o.name != "mirror ball"));
    assert!(d.labels.iter().any(|l| l.text.starts_with("glass ball")));
}

#[test]
fn box_slice_is_the_exact_polygon() {
    let s = scene("tir-block.json");
    let tree = trace_pixel(&s, 320, 230).unwrap();
    // glass block: [-1, 0.002, -1] .. [1, 1.2, 1]; y = 0.6 cuts the 2 x 2 square.
    let d = build(
        &s,
        &tree,
        PlaneSpec::Axis {
            axis: 1,
            value: 0.6,
        },
    );
    let block = d
        .objects
        .iter()
        .find(|o| o.name == "glass block")
        .expect("sliced");
    let SliceShape::Polygon(p) = &block.shape else {
        panic!()
    };
    assert_eq!(p.len(), 4);
    let mut world: Vec<(i64, i64)> = p
        .iter()
        .map(|c| {
            let q = d.frame.canvas_to_plane(*c);
            let w = d.frame.origin + q.x * d.frame.u + q.y * d.frame.v;
            assert!((w.y - 0.6).abs() < 1e-9);
            ((w.x * 1e6).round() as i64, (w.z * 1e6).round() as i64)
        })
        .collect();
    world.sort_unstable();
    assert_eq!(
        world,
        vec![
            (-1_000_000, -1_000_000),
            (-1_000_000, 1_000_000),
            (1_000_000, -1_000_000),
            (1_000_000, 1_000_000)
        ]
    );
    // A plane through the block's side shows the floor as a line with its inside below.
    let d = build(
        &s,
        &tree,
        PlaneSpec::Axis {
            axis: 0,
            value: 0.0,
        },
    );
    let floor = d.objects.iter().find(|o| o.name == "floor").unwrap();
    let (a, b) = floor.edge.unwrap();
    assert!((d.frame.canvas_to_plane(a).y - d.frame.canvas_to_plane(b).y).abs() < 1e-9);
}

#[test]
fn svg_parses_and_has_text() {
    let s = scene("tir-block.json");
    let tree = trace_pixel(&s, 320, 230).unwrap();
    let opts = DiagramOptions {
        zoom_offsets: true,
        title: "a <b> & \"c\"".into(),
        ..DiagramOptions::default()
    };
    let d = Diagram::build(&s, &tree, &opts).unwrap();
    assert!(!d.insets.is_empty());
    for theme in [Theme::Light, Theme::Dark] {
        let svg = to_svg(&d, &Style::new(theme));
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let texts: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(str::to_string))
            .collect();
        assert!(texts.iter().any(|t| t == "a <b> & \"c\""), "{texts:?}");
        assert!(texts.iter().any(|t| t.starts_with("θi = ")));
        assert!(texts.iter().any(|t| t.starts_with("TIR")));
        assert_eq!(doc.root_element().attribute("width"), Some("1280"));
    }
}

#[test]
fn png_is_deterministic_and_decodes() {
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let d = build(&s, &tree, PlaneSpec::Incidence);
    let a = to_png(&d, &Style::default());
    let b = to_png(
        &Diagram::build(
            &s,
            &tree,
            &DiagramOptions {
                plane: PlaneSpec::Incidence,
                min_share: 0.0,
                ..DiagramOptions::default()
            },
        )
        .unwrap(),
        &Style::default(),
    );
    assert_eq!(a, b);
    let img = image::load_from_memory(&a).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (1280, 720));
    // Not blank: the camera ray's colour and the background are both present.
    let dark = img
        .pixels()
        .filter(|p| p[0] < 80 && p[1] < 80 && p[2] < 80)
        .count();
    assert!(dark > 500, "{dark}");
    assert!(to_png(&d, &Style::new(Theme::Dark)) != a);
}

#[test]
fn highlight_and_bad_options() {
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let id = tree.nodes[3].id;
    let d = Diagram::build(
        &s,
        &tree,
        &DiagramOptions {
            highlight: Some(id),
            ..DiagramOptions::default()
        },
    )
    .unwrap();
    assert_eq!(
        d.rays
            .iter()
            .filter(|r| r.highlighted)
            .map(|r| r.node)
            .collect::<Vec<_>>(),
        vec![id]
    );
    assert!(
        Diagram::build(
            &s,
            &tree,
            &DiagramOptions {
                sample: 1,
                ..DiagramOptions::default()
            }
        )
        .is_err()
    );
    assert!(
        Diagram::build(
            &s,
            &tree,
            &DiagramOptions {
                width: 10,
                ..DiagramOptions::default()
            }
        )
        .is_err()
    );
    // Labels stay on the canvas.
    for l in &d.labels {
        assert!(
            l.pos.x >= 0.0 && l.pos.x <= 1280.0 && l.pos.y >= 0.0 && l.pos.y <= 720.0,
            "{l:?}"
        );
        assert!(l.size >= 14.0, "{l:?}");
    }
}

/// Issue 32: lamps are drawn. The Cornell box's ceiling lamp is marked where the shadow rays of
/// next-event estimation meet it, the caustic scene's lamp where its light samples land, and an
/// emissive object cut by the plane is filled as an emitter.
#[test]
fn lamps_are_drawn_where_rays_meet_them() {
    let mut s = scene("cornell-box.json");
    s.settings.spp = 4;
    let tree = trace_pixel(&s, 128, 200).unwrap();
    let d = build(&s, &tree, PlaneSpec::Auto);
    let lamp = s.objects.iter().position(|o| o.name == "lamp").unwrap();
    let marks: Vec<_> = d.lights.iter().map(|m| (m.light, m.area)).collect();
    assert!(
        marks.contains(&(s.lights.len() + lamp, true)),
        "the ceiling lamp is marked: {marks:?}"
    );
    let svg = to_svg(&d, &Style::new(Theme::Light));
    assert!(svg.contains(">lamp"), "its name is written");
    // A plane through the lamp cuts it: its slice is an emitter.
    let cut = build(
        &s,
        &tree,
        PlaneSpec::Axis {
            axis: 2,
            value: 0.0,
        },
    );
    assert!(
        cut.objects.iter().any(|o| o.fill == Fill::Emitter),
        "the lamp's slice is filled as an emitter: {:?}",
        cut.objects.iter().map(|o| o.fill).collect::<Vec<_>>()
    );
}
