//! The packet path of the render: bands of [`TILE`] rows whose camera rays are traced as
//! 8x8 packets, the same pixels bit for bit as the pixel loop.

use super::camera_sample;
use crate::bvh::TraversalCost;
use crate::bvh::wide::PACKET;
use crate::integrator::{Integrator, RayCounts, Recorder};
use crate::math::Rgb;
use crate::sampling::PixelSampler;
use rayon::prelude::*;

/// Rows `rows` in bands of [`TILE`] rows from `rows.start`, in parallel, each traced by
/// [`render_band`]; `on_band` is called with each band's row count as it finishes.
pub(super) fn packet_bands<R: Recorder + Default, I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    rows: std::ops::Range<u32>,
    on_band: &(dyn Fn(u32) + Sync),
) -> Vec<(Vec<Rgb>, RayCounts)> {
    let starts: Vec<u32> = rows.clone().step_by(TILE as usize).collect();
    starts
        .into_par_iter()
        .map(|y0| {
            let n = TILE.min(rows.end - y0);
            let band = render_band::<R, I, S>(integrator, sampler.clone(), y0, n);
            on_band(n);
            band
        })
        .collect()
}

/// Rows per band and columns per tile of the packet path: a packet is the camera rays of one
/// sample of an 8x8 tile.
const TILE: u32 = 8;

/// Rows `y0..y0 + rows` (at most [`TILE`]) without recording, a tile of camera rays at a time
/// through [`Scene::intersect_packet`]: the pixels (row-major) and the ray counts. Each pixel
/// sums its samples in the same order as [`render_pixel`], and each ray's hit is its single
/// ray's, so the pixels are [`render_pixel`]'s bit for bit (the integrator takes
/// packets only when it draws nothing from the sampler past the film offset).
fn render_band<R: Recorder + Default, I: Integrator, S: PixelSampler>(
    integrator: &I,
    mut sampler: S,
    y0: u32,
    rows: u32,
) -> (Vec<Rgb>, RayCounts) {
    let scene = integrator.scene();
    let w = scene.camera.width;
    let spp = scene.settings.spp.max(1);
    let mut counts = RayCounts::default();
    let mut rec = R::default();
    let mut band = vec![crate::math::PixelSum::default(); (w * rows) as usize];
    let film = integrator.film();
    let filter = scene.settings.filter.filter();
    let mut rays = Vec::with_capacity(PACKET);
    let mut hits = [None; PACKET];
    let mut cost = [TraversalCost::default(); PACKET];
    let mut radiance = [Rgb::ZERO; PACKET];
    for x0 in (0..w).step_by(TILE as usize) {
        let cols = TILE.min(w - x0);
        for s in 0..spp {
            rays.clear();
            for dy in 0..rows {
                for dx in 0..cols {
                    let (_, ray) = camera_sample(film, filter, &mut sampler, x0 + dx, y0 + dy, s);
                    rays.push(ray);
                }
            }
            cost.fill(TraversalCost::default());
            scene.intersect_packet(&rays, &mut hits, &mut cost);
            let n = rays.len();
            let found = (&hits[..n], &cost[..n]);
            let out = &mut radiance[..n];
            integrator.camera_packet_radiance(&rays, found, out, &mut rec, &mut counts);
            for (i, &l) in radiance[..n].iter().enumerate() {
                let (dx, dy) = (i as u32 % cols, i as u32 / cols);
                band[(dy * w + x0 + dx) as usize] += l;
            }
        }
    }
    let band = band.into_iter().map(|p| p / f64::from(spp)).collect();
    (band, counts)
}
