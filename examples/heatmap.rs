//! Write a traversal heat map (BVH nodes + primitive tests per camera ray) of a scene as a
//! PNG, next to its render: `cargo run --release --example heatmap -- SCENE.json OUT.png`.
//! Mesh files are resolved against the scene's directory.

use raytree::Scene;
use raytree::scene::traversal_cost_image;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, scene_path, out] = &args[..] else {
        return Err("usage: heatmap SCENE.json OUT.png".into());
    };
    let dir = Path::new(scene_path).parent().unwrap_or(Path::new(""));
    let src = std::fs::read_to_string(scene_path)?;
    let scene = Scene::from_json_with(&src, &mut |file| {
        let text = std::fs::read_to_string(dir.join(file)).map_err(|e| e.to_string())?;
        raytree::mesh::parse_obj(&text).map_err(|e| format!("{file}: {e}"))
    })?;
    let costs = traversal_cost_image(&scene);
    let max = costs.iter().map(|c| c.total()).max().unwrap_or(1).max(1);
    // Black -> red -> yellow -> white by cost relative to the maximum.
    let pixels: Vec<u8> = costs
        .iter()
        .flat_map(|c| {
            let x = f64::from(c.total()) / f64::from(max) * 3.0;
            [x, x - 1.0, x - 2.0].map(|v| (v.clamp(0.0, 1.0) * 255.0) as u8)
        })
        .collect();
    image::save_buffer(
        out,
        &pixels,
        scene.camera.width,
        scene.camera.height,
        image::ColorType::Rgb8,
    )?;
    let mean = costs.iter().map(|c| f64::from(c.total())).sum::<f64>() / costs.len() as f64;
    println!("wrote {out}: cost per camera ray mean {mean:.1}, max {max}");
    Ok(())
}
