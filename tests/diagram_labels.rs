//! Issue 32, item 8: a diagram's labels sit at their own ray's vertex and never overlap,
//! checked by geometry on the display list (what the PNG, the SVG and the inspector paint) of
//! the caustic and Cornell-box fixtures, with and without an LPE filter, at the export's size
//! and at sizes like the inspector's panel.

use raytree::diagram::model::{Diagram, LabelRole, Rect};
use raytree::diagram::paint::Prim;
use raytree::diagram::{DiagramOptions, Style, display_list, label_box};
use raytree::lpe::{Lpe, filter_tree_all_samples};
use raytree::{RayTree, Scene, trace_pixel};

use glam::DVec2;

fn scene(name: &str, spp: Option<u32>) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    let mut s = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    if let Some(n) = spp {
        s.settings.spp = n;
    }
    s
}

/// Distance from `p` to rectangle `r` (0 inside).
fn to_rect(r: &Rect, p: DVec2) -> f64 {
    (r.min - p).max(p - r.max).max(DVec2::ZERO).length()
}

/// Distance from segment `a`-`b` to rectangle `r` (sampled finely enough for a test).
fn segment_to_rect(r: &Rect, a: DVec2, b: DVec2) -> f64 {
    (0..=200)
        .map(|i| to_rect(r, a + (b - a) * (f64::from(i) / 200.0)))
        .fold(f64::INFINITY, f64::min)
}

/// How far (in font sizes) a label may lie from its vertex: its box's nearest point.
const NEAR: f64 = 2.5;

/// Every defect of one figure: overlapping labels, labels away from their vertex.
fn defects(what: &str, d: &Diagram) -> Vec<String> {
    let prims = display_list(d, &Style::default());
    let texts: Vec<(Rect, &str)> = prims
        .iter()
        .filter_map(|p| match p {
            Prim::Text {
                pos,
                text,
                size,
                anchor,
                ..
            } => Some((label_box(*pos, *anchor, text, *size), text.as_str())),
            _ => None,
        })
        .collect();
    let mut out = Vec::new();
    assert_eq!(texts.len(), d.labels.len(), "{what}: one text per label");
    for (i, (a, ta)) in texts.iter().enumerate() {
        for (b, tb) in &texts[i + 1..] {
            if a.overlaps(b) {
                out.push(format!("{what}: {ta:?} overlaps {tb:?}"));
            }
        }
    }
    // Every labelled hit keeps its angle (a label with no free spot near its vertex would be
    // dropped, which must not be how the rule is met).
    for h in &d.hits {
        let depth = d
            .rays
            .iter()
            .rev()
            .find(|s| s.node == h.node)
            .map(|s| s.depth);
        let has = d
            .labels
            .iter()
            .any(|l| l.node == Some(h.node) && l.text.starts_with("θi"));
        if depth.is_some_and(|k| k <= DiagramOptions::default().label_depth) && !has {
            out.push(format!("{what}: the hit of #{} has no θi label", h.node.0));
        }
    }
    // Marks at a vertex leave its short rays visible: an arc's radius is at most 0.6 of the
    // shortest ray drawn there (or 0.3 font sizes).
    for h in &d.hits {
        let fs = d
            .labels
            .iter()
            .find(|l| l.role == LabelRole::Angle)
            .map_or(17.0, |l| l.size);
        let shortest = d
            .rays
            .iter()
            .filter(|s| s.node == h.node || s.from == h.point)
            .map(|s| (s.to - s.from).length())
            .filter(|l| *l > 0.0)
            .fold(f64::INFINITY, f64::min);
        for a in &h.arcs {
            if a.radius > (0.6 * shortest).max(0.3 * fs) + 1e-9 {
                out.push(format!(
                    "{what}: an arc of radius {:.0} px at #{} covers a {:.0} px ray",
                    a.radius, h.node.0, shortest
                ));
            }
        }
    }
    for (l, (r, text)) in d.labels.iter().zip(&texts) {
        assert_eq!(l.text, *text, "{what}: the display list paints the labels");
        let Some(node) = l.node else { continue };
        let far = match l.role {
            LabelRole::Angle | LabelRole::Interface => {
                let h = d.hits.iter().find(|h| h.node == node).expect("its hit");
                to_rect(r, h.point)
            }
            LabelRole::Attenuation => {
                let s = d
                    .rays
                    .iter()
                    .rev()
                    .find(|s| s.node == node)
                    .expect("its ray");
                segment_to_rect(r, s.from, s.to)
            }
            _ => continue,
        };
        if far > NEAR * l.size {
            out.push(format!(
                "{what}: {text:?} (#{}) is {:.0} px from its vertex ({:.1} font sizes)",
                node.0,
                far,
                far / l.size
            ));
        }
    }
    out
}

/// The figures of every sample of `tree` that has a ray to draw, at three sizes.
fn figures(what: &str, s: &Scene, tree: &RayTree) -> Vec<String> {
    let mut out = Vec::new();
    for (w, h) in [(1280, 720), (1030, 330), (900, 300)] {
        for k in 0..tree.samples.len().min(16) {
            let opts = DiagramOptions {
                width: w,
                height: h,
                sample: k,
                title: what.to_string(),
                ..DiagramOptions::default()
            };
            let d = Diagram::build(s, tree, &opts).unwrap();
            out.extend(defects(&format!("{what} sample {k} {w}x{h}"), &d));
        }
    }
    out
}

fn check(name: &str, spp: Option<u32>, pixels: &[(u32, u32)], lpe: Option<&str>) {
    let s = scene(name, spp);
    let mut bad = Vec::new();
    for &(x, y) in pixels {
        let tree = trace_pixel(&s, x, y).unwrap();
        let tree = match lpe {
            Some(e) => {
                let f = filter_tree_all_samples(&tree, &[Lpe::parse(e).unwrap()]).unwrap();
                f.tree
            }
            None => tree,
        };
        bad.extend(figures(&format!("{name} {x},{y} lpe {lpe:?}"), &s, &tree));
    }
    assert!(bad.is_empty(), "{} defects:\n{}", bad.len(), bad.join("\n"));
}

const CAUSTIC: [(u32, u32); 3] = [(98, 112), (120, 100), (60, 140)];
const CORNELL: [(u32, u32); 5] = [(128, 128), (128, 200), (159, 46), (100, 150), (170, 170)];

#[test]
fn caustic_labels_sit_at_their_vertex_and_never_overlap() {
    check("caustic.json", Some(16), &CAUSTIC, None);
}

#[test]
fn caustic_labels_under_an_lpe_filter_sit_at_their_vertex_and_never_overlap() {
    // The inspector's caustic filter: the camera ray at the floor, the diffuse bounce up
    // through the ball to the lamp.
    check("caustic.json", Some(16), &CAUSTIC, Some("C<RD>S+L"));
}

#[test]
fn cornell_labels_sit_at_their_vertex_and_never_overlap() {
    check("cornell-box.json", Some(4), &CORNELL, None);
}

#[test]
fn cornell_labels_under_an_lpe_filter_sit_at_their_vertex_and_never_overlap() {
    check("cornell-box.json", Some(4), &CORNELL, Some("C<RD>+L"));
}
