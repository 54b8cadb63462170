//! The denoiser's measured table (docs/denoise.md): for each path-traced fixture, rel-RMSE
//! against a high-spp reference before and after denoising at 1, 4, 16 and 64 spp, with the
//! render's and the filter's seconds.
//!
//! `cargo run --release --example denoise_table -- [REF_SPP] [WIDTH] [OUT_DIR]` (defaults 1024,
//! 128; OUT_DIR, when given, receives each raw and denoised PNG).

use raytree::analysis::converge::rel_rmse;
use raytree::denoise::{DenoiseParams, denoise, gather};
use raytree::render::RenderOptions;
use raytree::render::render;
use raytree::scene::IntegratorKind;
use raytree::{Scene, SceneIntegrator};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ref_spp: u32 = args.get(1).map_or(1024, |a| a.parse().expect("REF_SPP"));
    let width: u32 = args.get(2).map_or(128, |a| a.parse().expect("WIDTH"));
    let out = args.get(3);
    println!(
        "| fixture (path, {width} px wide) | spp | render s | denoise s | rel-RMSE raw | rel-RMSE denoised | ratio |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    for name in ["cornell-box", "caustic", "glossy", "depth-of-field"] {
        let path = format!("{}/fixtures/{name}.json", env!("CARGO_MANIFEST_DIR"));
        let mut scene = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        let c = &scene.camera;
        let h = (f64::from(width) * f64::from(c.height) / f64::from(c.width)).round() as u32;
        scene.camera = scene.camera.with_size(width, h.max(1));
        scene.settings.integrator = IntegratorKind::Path;
        scene.settings.spp = ref_spp;
        let (reference, _, _) = render(
            &SceneIntegrator::new(&scene),
            &RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        for spp in [1, 4, 16, 64] {
            scene.settings.spp = spp;
            let t = Instant::now();
            let (raw, _, features) = gather(&SceneIntegrator::new(&scene), &|_| {});
            let render_s = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let den = denoise(&raw, &features, &DenoiseParams::default());
            let denoise_s = t.elapsed().as_secs_f64();
            let (a, b) = (
                rel_rmse(&raw, &reference).unwrap(),
                rel_rmse(&den, &reference).unwrap(),
            );
            println!(
                "| {name} | {spp} | {render_s:.3} | {denoise_s:.3} | {a:.4} | {b:.4} | {:.2} |",
                b / a
            );
            if let Some(dir) = out {
                let write = |tag: &str, img: &raytree::Image| {
                    let bytes = raytree::codec::png(img).unwrap();
                    std::fs::write(format!("{dir}/{name}-{spp}-{tag}.png"), bytes).unwrap();
                };
                write("raw", &raw);
                write("denoised", &den);
                if spp == 1 {
                    write("ref", &reference);
                    write("albedo", &features.albedo_image());
                    write("normal", &features.normal_image());
                }
            }
        }
    }
}
