//! Tests of `growth`.

use super::*;
use crate::math::FresnelModel;

fn fixture(name: &str) -> Scene {
    let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn nested_dielectrics_grow_exponentially() {
    let g = tree_growth(&fixture("nested.json"));
    assert_eq!(g.growth, Growth::Exponential, "{g:?}");
    assert!(
        g.reasons
            .iter()
            .any(|r| r == "nested: glass ball (dielectric) is inside water tank (dielectric)"),
        "{g:?}"
    );
    assert!(
        g.reasons[0].starts_with("a ray at glass ball splits"),
        "{g:?}"
    );
    // Without Fresnel reflection every hit has one child: a chain, linear in depth.
    let mut s = fixture("nested.json");
    s.settings.whitted.fresnel = FresnelModel::None;
    assert_eq!(tree_growth(&s).growth, Growth::Polynomial(1));
    s.settings.max_depth = 0;
    assert_eq!(tree_growth(&s).growth, Growth::Bounded);
}

#[test]
fn a_diffuse_scene_is_bounded_and_facing_mirrors_are_linear() {
    let g = tree_growth(&fixture("diffuse.json"));
    assert_eq!(g.growth, Growth::Bounded, "{g:?}");
    let g = tree_growth(&fixture("mirrors.json"));
    assert_eq!(g.growth, Growth::Polynomial(1), "{g:?}");
    assert_eq!(
        g.reasons,
        ["facing mirrors: front mirror and back mirror can see each other"]
    );
    // One mirror alone sees nothing specular: bounded.
    let mut s = fixture("mirrors.json");
    s.objects.remove(1);
    s.rebuild_accel();
    assert_eq!(tree_growth(&s).growth, Growth::Bounded);
}

#[test]
fn one_convex_dielectric_is_linear_and_its_exits_do_not_return() {
    for f in ["slab.json", "tir-block.json", "translucent-shadow.json"] {
        let g = tree_growth(&fixture(f));
        assert_eq!(g.growth, Growth::Polynomial(1), "{f}: {g:?}");
        assert!(g.reasons[0].contains("internal reflection"), "{f}: {g:?}");
    }
}

#[test]
fn grid_pixels_are_cell_centres() {
    let p = grid_pixels(320, 180, 16, 9);
    assert_eq!(p.len(), 144);
    assert_eq!(p[0], (10, 10));
    assert_eq!(p[143], (310, 170));
    assert_eq!(grid_pixels(4, 2, 16, 9).len(), 144); // repeats pixels, stays inside
    assert!(
        grid_pixels(4, 2, 16, 9)
            .iter()
            .all(|&(x, y)| x < 4 && y < 2)
    );
    assert!(grid_pixels(0, 2, 16, 9).is_empty());
}

#[test]
fn the_cut_saves_rays_in_nested_glass_and_nothing_without_recursion() {
    let mut s = fixture("nested.json");
    s.camera = s.camera.with_size(160, 90);
    s.settings.max_depth = 16;
    let c = cut_savings(&s, 16, 9, &|| false).unwrap();
    assert!(c.min_weight > 0.0);
    assert_eq!(c.budget_samples, 0);
    // Known from the full render (docs/cost.md): 12.8x the rays at depth 16.
    assert!(c.ratio() > 4.0, "{c:?}");
    // The exhaustive count is the sum of the sampled pixels' trees with min_weight 0.
    let mut full = s.clone();
    full.settings.whitted.min_weight = Some(0.0);
    let nodes: usize = grid_pixels(160, 90, 16, 9)
        .iter()
        .map(|&(x, y)| crate::render::trace_pixel(&full, x, y).unwrap().nodes.len())
        .sum();
    assert_eq!(nodes as u64, c.exhaustive_rays);
    // The default plays no roulette (opt-in since issue 32): the cut alone.
    assert_eq!(c.roulette_below, 0.0, "{c:?}");
    assert!(c.sentence().contains(&format!(
        "traces {} rays where the exhaustive tree would trace {}",
        c.cut_rays, c.exhaustive_rays
    )));
    let d = cut_savings(&fixture("diffuse.json"), 16, 9, &|| false).unwrap();
    assert_eq!(d.cut_rays, d.exhaustive_rays);
    assert!(d.sentence().contains("no saving"));
    assert!(cut_savings(&s, 16, 9, &|| true).is_none());
}
