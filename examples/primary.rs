//! Primary-ray throughput on the icosphere of `cargo bench --bench mesh`, for any view, to set
//! beside `benches/embree.py` run on the same view:
//!
//! ```sh
//! cargo run --release --example primary -- LEVEL SIZE [DISTANCE]      # e.g. 8 512 4
//! python3 benches/embree.py LEVEL SIZE --distance DISTANCE
//! ```
//!
//! The camera sits at `(0, 0, DISTANCE)` (3 by default, the benchmark's view) looking at the
//! unit sphere, 40 degrees vertical field of view, one ray through each pixel centre. One thread;
//! 8x8 packets (`Scene::intersect_packet`) and single rays (`Scene::intersect`), the fastest of
//! 15 passes of each, interleaved.

use raytree::Scene;
use raytree::bvh::TraversalCost;
use raytree::scene::icosphere_scene;
use std::hint::black_box;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: primary LEVEL SIZE [DISTANCE]";
    let level: u32 = args.first().ok_or(usage)?.parse()?;
    let size: u32 = args.get(1).ok_or(usage)?.parse()?;
    let distance: f64 = args.get(2).map_or(Ok(3.0), |s| s.parse())?;
    if size == 0 || !(distance > 1.0 && distance.is_finite()) {
        return Err("SIZE must be positive and DISTANCE above 1 (outside the sphere)".into());
    }
    let scene = icosphere_scene(level, size, distance);
    let mut best = [f64::INFINITY; 2];
    let mut hits = [0; 2];
    for _ in 0..15 {
        for (k, packets) in [true, false].into_iter().enumerate() {
            let t = Instant::now();
            hits[k] = black_box(cast(&scene, packets));
            best[k] = best[k].min(t.elapsed().as_secs_f64());
        }
    }
    assert_eq!(
        hits[0], hits[1],
        "packets and single rays hit the same pixels"
    );
    let n = f64::from(size * size);
    println!(
        "raytree {} triangles {size}x{size} distance {distance}: hit {:.3}, 8x8 packets {:.1} ns/ray \
         ({:.2} M rays/s), single rays {:.1} ns/ray (fastest of 15)",
        20 * 4u64.pow(level),
        hits[0] as f64 / n,
        best[0] * 1e9 / n,
        n / best[0] / 1e6,
        best[1] * 1e9 / n,
    );
    Ok(())
}

/// Closest hits of every pixel-centre ray, as 8x8 packets or one by one; the number of hits.
fn cast(scene: &Scene, packets: bool) -> usize {
    let cam = &scene.camera;
    let film = cam.film();
    let ray = |x: u32, y: u32| film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
    let mut hits = 0;
    let mut rays = Vec::with_capacity(64);
    let mut found = [None; 64];
    let mut cost = [TraversalCost::default(); 64];
    for y0 in (0..cam.height).step_by(8) {
        for x0 in (0..cam.width).step_by(8) {
            rays.clear();
            for y in y0..(y0 + 8).min(cam.height) {
                for x in x0..(x0 + 8).min(cam.width) {
                    rays.push(ray(x, y));
                }
            }
            if packets {
                scene.intersect_packet(&rays, &mut found, &mut cost);
                hits += found[..rays.len()].iter().filter(|h| h.is_some()).count();
            } else {
                hits += rays
                    .iter()
                    .filter(|r| scene.intersect(r, f64::INFINITY).is_some())
                    .count();
            }
        }
    }
    hits
}
