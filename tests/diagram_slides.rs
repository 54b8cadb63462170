//! Slide-ready defaults (issue 17): the contribution threshold, framing on the kept rays,
//! labels that never overlap, and planes that follow a ray.

use raytree::diagram::model::{LabelRole, RaySegment, SliceShape};
use raytree::diagram::share::{keep, shares};
use raytree::diagram::{Diagram, DiagramOptions, PlaneSpec, label_box};
use raytree::{NodeId, RayKind, RayTree, Scene, trace_pixel};

fn scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `nested.json` at the refracting pixel with the exhaustive tree (`--min-weight 0`).
fn nested() -> (Scene, RayTree) {
    let mut s = scene("nested.json");
    s.settings.whitted.min_weight = Some(0.0);
    let tree = trace_pixel(&s, 320, 150).unwrap();
    (s, tree)
}

fn build(s: &Scene, t: &RayTree, opts: DiagramOptions) -> Diagram {
    Diagram::build(s, t, &opts).unwrap()
}

/// The interesting pixels of the fixtures (refracting, TIR, translucent shadow, nested media).
const PIXELS: [(&str, u32, u32); 7] = [
    ("nested.json", 320, 150),
    ("tir-block.json", 320, 230),
    ("translucent-shadow.json", 268, 215),
    ("translucent-shadow.json", 268, 197),
    ("slab.json", 304, 166),
    ("classic.json", 400, 200),
    ("water-grazing.json", 320, 180),
];

#[test]
fn the_default_leaves_out_rays_without_a_visible_share_and_says_so() {
    let (s, tree) = nested();
    assert_eq!(tree.nodes.len(), 472, "the issue's tree");
    let d = build(&s, &tree, DiagramOptions::default());
    let share = shares(&tree);
    // Drawn: the rays with at least 1 % of the pixel and their ancestors, nothing else.
    let kept = keep(&tree, 0, 0.01, &[]);
    let drawn: Vec<u32> = d.rays.iter().map(|r| r.node.0).collect();
    let want: Vec<u32> = tree
        .depth_first(tree.samples[0].root)
        .into_iter()
        .filter(|id| kept.kept[id.index()])
        .map(|id| id.0)
        .collect();
    assert_eq!(drawn, want);
    assert!(d.rays.len() <= 20, "{} rays drawn", d.rays.len());
    for r in &d.rays {
        let n = tree.node(r.node);
        let big_below = tree
            .depth_first(n.id)
            .iter()
            .any(|c| share[c.index()] >= 0.01);
        assert!(
            big_below,
            "#{} carries {} and nothing under it is visible",
            n.id.0,
            share[n.id.index()]
        );
    }
    assert_eq!(d.dropped_rays, 472 - d.rays.len());
    assert!(
        d.dropped_share > 0.0 && d.dropped_share < 0.1,
        "{}",
        d.dropped_share
    );
    let legend = d
        .labels
        .iter()
        .find(|l| l.role == LabelRole::Legend && l.text.contains("left out"))
        .expect("the legend says what was left out");
    assert!(
        legend
            .text
            .starts_with(&format!("{} rays under 1% of the pixel", d.dropped_rays)),
        "{}",
        legend.text
    );
    // 0 draws every ray, and the legend has no such line.
    let all = build(
        &s,
        &tree,
        DiagramOptions {
            min_share: 0.0,
            ..DiagramOptions::default()
        },
    );
    assert_eq!(all.rays.len(), 472);
    assert_eq!(all.dropped_rays, 0);
    assert!(!all.labels.iter().any(|l| l.text.contains("left out")));
}

#[test]
fn a_blocked_shadow_ray_of_a_visible_surface_is_kept() {
    // classic 400,200: the refracted ray's floor hit is lit by a shadow ray; the shadow rays
    // blocked by the ball carry nothing, but unblocked they would: they stay in the figure.
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let d = build(&s, &tree, DiagramOptions::default());
    let blocked = |r: &&RaySegment| {
        r.kind == RayKind::Shadow && tree.node(r.node).radiance.max_element() == 0.0
    };
    let share = shares(&tree);
    for r in d.rays.iter().filter(blocked) {
        assert!(share[r.node.index()] >= 0.01);
    }
    // The selection is always drawn, however little it carries.
    let tiny = tree
        .nodes
        .iter()
        .find(|n| share[n.id.index()] < 1e-4)
        .expect("a tiny ray")
        .id;
    let d = build(
        &s,
        &tree,
        DiagramOptions {
            highlight: Some(tiny),
            ..DiagramOptions::default()
        },
    );
    assert!(d.rays.iter().any(|r| r.node == tiny && r.highlighted));
}

#[test]
fn labels_never_overlap_in_the_default_figures() {
    for (name, x, y) in PIXELS {
        let s = scene(name);
        let tree = trace_pixel(&s, x, y).unwrap();
        for size in [(1280, 720), (900, 300)] {
            let d = build(
                &s,
                &tree,
                DiagramOptions {
                    width: size.0,
                    height: size.1,
                    ..DiagramOptions::default()
                },
            );
            let boxes: Vec<_> = d
                .labels
                .iter()
                .map(|l| (l, label_box(l.pos, l.anchor, &l.text, l.size)))
                .collect();
            for (i, (la, a)) in boxes.iter().enumerate() {
                for (lb, b) in &boxes[i + 1..] {
                    assert!(
                        !a.overlaps(b),
                        "{name} {x},{y} {size:?}: {:?} overlaps {:?}",
                        la.text,
                        lb.text
                    );
                }
            }
            // Object names are always there.
            assert!(
                d.labels.iter().any(|l| l.role == LabelRole::Object),
                "{name}"
            );
        }
    }
}

/// The radius in pixels of sphere object `name`'s slice.
fn radius(d: &Diagram, name: &str) -> f64 {
    d.objects
        .iter()
        .find(|o| o.name == name)
        .and_then(|o| match o.shape {
            SliceShape::Circle { radius, .. } => Some(radius),
            _ => None,
        })
        .unwrap_or_else(|| panic!("{name} not cut"))
}

#[test]
fn the_glass_is_large_enough_for_a_slide() {
    // Before: the glass ball of nested.json was 60 px across at 1280x720 (20-80 px in the
    // panel), the classic glass ball 110 px (radii 30 and 55).
    let (s, tree) = nested();
    let d = build(&s, &tree, DiagramOptions::default());
    assert!(
        radius(&d, "glass ball") > 75.0,
        "{}",
        radius(&d, "glass ball")
    );
    let s = scene("classic.json");
    let tree = trace_pixel(&s, 400, 200).unwrap();
    let d = build(&s, &tree, DiagramOptions::default());
    assert!(
        radius(&d, "glass ball") > 120.0,
        "{}",
        radius(&d, "glass ball")
    );
    // The camera ray still comes in over a visible stretch.
    let cam = d.rays.iter().find(|r| r.kind == RayKind::Camera).unwrap();
    assert!((cam.to - cam.from).length() > 100.0);
}

#[test]
fn the_translucent_shadow_lies_in_the_automatic_plane() {
    // The floor's plane of incidence missed the tinted ball the shadow ray crosses.
    let s = scene("translucent-shadow.json");
    let tree = trace_pixel(&s, 268, 215).unwrap();
    let inc = build(
        &s,
        &tree,
        DiagramOptions {
            plane: PlaneSpec::Incidence,
            ..DiagramOptions::default()
        },
    );
    let shadow_off = |d: &Diagram| {
        d.rays
            .iter()
            .any(|r| r.kind == RayKind::Shadow && r.off_plane)
    };
    assert!(
        shadow_off(&inc),
        "the shadow ray leaves the plane of incidence"
    );
    let d = build(&s, &tree, DiagramOptions::default());
    assert!(radius(&d, "tinted ball") > 100.0);
    assert!(
        d.rays.iter().all(|r| !r.off_plane),
        "camera and shadow ray in the plane"
    );
    assert!(d.plane_text.contains("shadow ray #1"), "{}", d.plane_text);
    // The spare room is above the floor, not an empty floor below the figure.
    let floor = d.objects.iter().find(|o| o.name == "floor").unwrap();
    let (a, b) = floor.edge.unwrap();
    assert!(
        a.y.max(b.y) > d.view.max.y - 0.2 * (d.view.max.y - d.view.min.y),
        "{a} {b}"
    );
    // Where the plane of incidence holds the rays, auto keeps it.
    let s = scene("tir-block.json");
    let tree = trace_pixel(&s, 320, 230).unwrap();
    let d = build(&s, &tree, DiagramOptions::default());
    assert!(
        d.plane_text.starts_with("plane of incidence"),
        "{}",
        d.plane_text
    );
}

#[test]
fn the_plane_follows_a_chosen_ray() {
    let mut s = scene("tir-block.json");
    // Every split of the tree, deep weak ones included (no roulette below a weight).
    s.settings.whitted.roulette_below = Some(0.0);
    let tree = trace_pixel(&s, 320, 230).unwrap();
    // A ray deep in the tree, off the plane of incidence.
    let inc = build(
        &s,
        &tree,
        DiagramOptions {
            plane: PlaneSpec::Incidence,
            min_share: 0.0,
            ..DiagramOptions::default()
        },
    );
    let off = inc
        .rays
        .iter()
        .find(|r| r.off_plane && r.kind != RayKind::Shadow && r.depth > 0)
        .expect("an off-plane ray")
        .node;
    let d = build(
        &s,
        &tree,
        DiagramOptions {
            plane: PlaneSpec::Ray(off),
            ..DiagramOptions::default()
        },
    );
    let parent = tree.node(off).parent.unwrap();
    for id in [off, parent] {
        let r = d
            .rays
            .iter()
            .find(|r| r.node == id)
            .expect("drawn, even below the threshold");
        assert!(
            !r.off_plane && r.plane_distance.iter().all(|x| x.abs() < 1e-6),
            "#{}: {:?}",
            id.0,
            r.plane_distance
        );
    }
    assert!(
        d.plane_text.contains(&format!("ray #{}", off.0)),
        "{}",
        d.plane_text
    );
    // The camera ray's plane is the plane of incidence.
    let root = build(
        &s,
        &tree,
        DiagramOptions {
            plane: PlaneSpec::Ray(NodeId(0)),
            ..DiagramOptions::default()
        },
    );
    assert_eq!(root.frame.normal, inc.frame.normal);
    // A ray the tree does not have is an error, not a panic.
    let bad = Diagram::build(
        &s,
        &tree,
        &DiagramOptions {
            plane: PlaneSpec::Ray(NodeId(999)),
            ..DiagramOptions::default()
        },
    );
    assert!(bad.unwrap_err().to_string().contains("#999 does not exist"));
    assert_eq!(PlaneSpec::parse("ray=7"), Ok(PlaneSpec::Ray(NodeId(7))));
    assert!(PlaneSpec::parse("ray=x").is_err());
}

/// The legend says how many drawn glass hits followed one ray by Russian roulette (with the
/// suggested weight, opt-in), and says nothing when every hit splits (the default).
#[test]
fn the_legend_counts_roulette_choices() {
    let line = |s: &raytree::Scene| {
        let tree = trace_pixel(s, 320, 230).unwrap();
        let d = build(
            s,
            &tree,
            DiagramOptions {
                min_share: 0.0,
                ..DiagramOptions::default()
            },
        );
        d.legend
            .iter()
            .find(|e| e.text.contains("followed one ray"))
            .map(|e| e.text.clone())
    };
    let mut s = scene("tir-block.json");
    assert_eq!(line(&s), None, "the default splits every hit");
    s.settings.whitted.roulette_below = Some(
        raytree::integrator::bound::carried::auto_roulette_below(&s, &s.settings),
    );
    assert_eq!(
        line(&s).as_deref(),
        Some("1 weak glass hit followed one ray (Russian roulette, weight / probability).")
    );
    s.settings.whitted.roulette_below = Some(0.0);
    assert_eq!(line(&s), None);
}
