//! Diagram framing: a deep bounce's far-away hit does not shrink the figure's first bounces.

use glam::DVec3;
use raytree::diagram::{Diagram, DiagramOptions};
use raytree::{Scene, trace_pixel};

/// A mirror ball in front of the camera and a wall 100 units behind the camera: the camera
/// ray's reflection (depth 1) comes back and hits the wall far away.
const SCENE: &str = r#"{
  "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30, "width": 64, "height": 48},
  "materials": {
    "mirror": {"reflectivity": [0.9, 0.9, 0.9], "diffuse": [0.1, 0.1, 0.1]},
    "wall": {"diffuse": [0.7, 0.7, 0.7]}
  },
  "objects": [
    {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "mirror"},
    {"type": "plane", "point": [0, 0, 105], "normal": [0, 0, -1], "material": "wall"}
  ],
  "lights": [{"type": "point", "position": [3, 4, 6], "intensity": [50, 50, 50]}]
}"#;

#[test]
fn far_hits_beyond_the_labelled_depths_leave_through_the_frame() {
    let scene = Scene::from_json(SCENE).unwrap();
    let tree = trace_pixel(&scene, 36, 26).unwrap();
    let far = tree
        .nodes
        .iter()
        .filter(|n| n.depth == 1)
        .find_map(|n| n.hit.as_ref().filter(|h| h.object == 1))
        .expect("the reflected ray hits the wall")
        .point;
    assert!(far.z > 100.0, "{far}");
    let build = |label_depth| {
        let opts = DiagramOptions {
            label_depth,
            min_share: 0.0,
            ..DiagramOptions::default()
        };
        Diagram::build(&scene, &tree, &opts).unwrap()
    };
    let inside = |d: &Diagram, p: DVec3| {
        let q = d.frame.to_canvas(p);
        q.x >= 0.0 && q.y >= 0.0 && q.x <= d.width && q.y <= d.height
    };
    // Whatever the labelled depths, the figure frames the ball (radius 1: at least 150 px
    // across at 1280x720) and the wall hit a hundred units away is off canvas.
    for label_depth in [0, 1, 2] {
        let d = build(label_depth);
        assert!(d.frame.scale > 75.0, "{}", d.frame.scale);
        assert!(!inside(&d, far));
        // Every ray is still drawn, the far one clipped at the frame.
        assert_eq!(d.rays.len(), tree.nodes.len());
    }
}
