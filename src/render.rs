//! Pixels: stratified samples, the parallel render, and re-tracing one pixel into a tree.
//!
//! One code path: [`render_pixel`] is generic over the recorder; the image uses
//! [`NoopRecorder`], the tree [`TreeRecorder`], so a recorded pixel equals the rendered one bit
//! for bit.

use crate::bvh::TraversalCost;
use crate::bvh::wide::PACKET;
use crate::geometry::Shape;
use crate::math::Rgb;
use crate::scene::Scene;
use crate::trace::{DiagnosticRecorder, NoopRecorder, RayCounts, Recorder, Tracer, TreeRecorder};
use crate::tree::{RayTree, SampleRecord, TREE_SCHEMA};
use rayon::prelude::*;

/// A linear-radiance image, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<Rgb>,
}

impl Image {
    /// The pixel at (x, y).
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[(y * self.width + x) as usize]
    }

    /// 8-bit sRGB bytes, RGB order, clamped.
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.to_array().map(crate::math::linear_to_srgb8))
            .collect()
    }
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced by kind.
    pub rays: RayCounts,
    /// Pixels whose value was not finite (replaced by black).
    pub nonfinite_pixels: u64,
    /// The first such pixel, in scan order.
    pub first_nonfinite: Option<(u32, u32)>,
    /// Pixels with at least one self-hit ray (diagnosed renders only; see `trace::diagnose`).
    pub self_hit_pixels: u64,
    /// Pixels with at least one leaking ray (diagnosed renders only).
    pub leak_pixels: u64,
}

/// Per-pixel diagnostic counts of a diagnosed render, row-major like [`Image`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DiagnosticMap {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Self-hit rays per pixel.
    pub self_hits: Vec<u32>,
    /// Leaking rays per pixel.
    pub leaks: Vec<u32>,
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, well-mixed hash for per-pixel seeds.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn unit(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Film position of sample `s` of pixel (x, y): the centre for one sample, otherwise jittered
/// stratified on a `cols x rows` grid, seeded by the pixel and sample so it is reproducible.
#[must_use]
pub fn sample_position(x: u32, y: u32, s: u32, spp: u32) -> (f64, f64) {
    if spp <= 1 {
        return (f64::from(x) + 0.5, f64::from(y) + 0.5);
    }
    jittered(x, y, s, spp)
}

/// The stratified position of [`sample_position`] for `spp > 1`. Out of line, so its square
/// root and `ceil` are not hoisted into one-sample renders.
#[inline(never)]
fn jittered(x: u32, y: u32, s: u32, spp: u32) -> (f64, f64) {
    let cols = f64::from(spp).sqrt().ceil() as u32;
    let rows = spp.div_ceil(cols);
    let seed =
        splitmix64((u64::from(y) << 32 | u64::from(x)) ^ (u64::from(s) << 48).rotate_left(7));
    let jx = unit(seed);
    let jy = unit(splitmix64(seed));
    let sx = (f64::from(s % cols) + jx) / f64::from(cols);
    let sy = (f64::from(s / cols) + jy) / f64::from(rows);
    (f64::from(x) + sx, f64::from(y) + sy)
}

/// Trace every sample of pixel (x, y) into `rec`; returns the pixel radiance (box filter).
pub fn render_pixel<R: Recorder>(
    scene: &Scene,
    x: u32,
    y: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    on_sample: impl FnMut(SampleRecord),
) -> Rgb {
    render_pixel_with(&Tracer::new(scene), x, y, rec, counts, on_sample)
}

/// [`render_pixel`] with a prepared tracer (and so a chosen effect plan).
pub fn render_pixel_with<R: Recorder>(
    tracer: &Tracer,
    x: u32,
    y: u32,
    rec: &mut R,
    counts: &mut RayCounts,
    mut on_sample: impl FnMut(SampleRecord),
) -> Rgb {
    let scene = tracer.scene();
    let spp = scene.settings.spp.max(1);
    let mut sum = Rgb::ZERO;
    for s in 0..spp {
        let (fx, fy) = sample_position(x, y, s, spp);
        let (l, root) = tracer.trace_camera(tracer.film().ray(fx, fy), rec, counts);
        sum += l;
        if let Some(root) = root {
            on_sample(SampleRecord {
                index: s,
                film: [fx, fy],
                root,
                radiance: l,
            });
        }
    }
    sum / f64::from(spp)
}

/// Re-trace pixel (x, y) and record its full tree. `None` if the pixel is outside the image.
#[must_use]
pub fn trace_pixel(scene: &Scene, x: u32, y: u32) -> Option<RayTree> {
    if x >= scene.camera.width || y >= scene.camera.height {
        return None;
    }
    let mut rec = TreeRecorder::default();
    let mut samples = Vec::new();
    let mut counts = RayCounts::default();
    let radiance = render_pixel(scene, x, y, &mut rec, &mut counts, |s| samples.push(s));
    // The settings as traced: the automatic cut is recorded as the value it took.
    let settings = crate::scene::Settings {
        min_weight: Some(crate::trace::bound::effective_min_weight(scene)),
        ..scene.settings
    };
    Some(RayTree {
        schema: TREE_SCHEMA.to_string(),
        pixel: [x, y],
        settings,
        radiance,
        samples,
        nodes: rec.nodes,
    })
}

/// Render the whole image in parallel (rows over rayon's pool; for scenes with meshes, bands of
/// 8 rows whose camera rays are traced as 8x8 packets, the same pixels bit for bit). `progress`
/// is called with the number of rows finished so far, from worker threads. Non-finite pixels
/// are written black and counted; [`RenderStats::first_nonfinite`] names the first so its tree
/// can be inspected.
pub fn render(scene: &Scene, progress: &(dyn Fn(u32) + Sync)) -> (Image, RenderStats) {
    render_with(&Tracer::new(scene), progress)
}

/// [`render`] with a prepared tracer (and so a chosen effect plan).
pub fn render_with(tracer: &Tracer, progress: &(dyn Fn(u32) + Sync)) -> (Image, RenderStats) {
    let (image, stats, _) = render_recorded::<NoopRecorder>(tracer, progress);
    (image, stats)
}

/// [`render`] with the self-hit and leak diagnostics on: the same image, plus the counts in
/// [`RenderStats`] and per pixel. Costs extra intersections per spawned ray.
pub fn render_diagnosed(
    scene: &Scene,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, DiagnosticMap) {
    render_recorded::<DiagnosticRecorder>(&Tracer::new(scene), progress)
}

/// Rows `rows` of the image without recording, in parallel over rayon's pool: linear radiance
/// (row-major, non-finite values as traced) and the rays traced. The same code path and so the
/// same pixels as [`render_with`] (for scenes with meshes, bands of 8 rows from `rows.start`
/// traced as 8x8 packets); the inspector shows its image with it before it gathers statistics.
pub fn render_rows(tracer: &Tracer, rows: std::ops::Range<u32>) -> (Vec<Rgb>, RayCounts) {
    let scene = tracer.scene();
    let w = scene.camera.width;
    let parts: Vec<(Vec<Rgb>, RayCounts)> = if uses_packets::<NoopRecorder>(scene) {
        packet_bands::<NoopRecorder>(tracer, rows, &|_| {})
    } else {
        rows.into_par_iter()
            .map(|y| {
                let mut counts = RayCounts::default();
                let row = (0..w)
                    .map(|x| {
                        render_pixel_with(tracer, x, y, &mut NoopRecorder, &mut counts, |_| {})
                    })
                    .collect();
                (row, counts)
            })
            .collect()
    };
    let mut pixels = Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum());
    let mut counts = RayCounts::default();
    for (p, c) in parts {
        pixels.extend(p);
        counts += c;
    }
    (pixels, counts)
}

/// Rows `rows` in bands of [`TILE`] rows from `rows.start`, in parallel, each traced by
/// [`render_band`]; `on_band` is called with each band's row count as it finishes.
fn packet_bands<R: Recorder + Default>(
    tracer: &Tracer,
    rows: std::ops::Range<u32>,
    on_band: &(dyn Fn(u32) + Sync),
) -> Vec<(Vec<Rgb>, RayCounts)> {
    let starts: Vec<u32> = rows.clone().step_by(TILE as usize).collect();
    starts
        .into_par_iter()
        .map(|y0| {
            let n = TILE.min(rows.end - y0);
            let band = render_band::<R>(tracer, y0, n);
            on_band(n);
            band
        })
        .collect()
}

/// Whether a render with recorder `R` traces camera rays as packets: nothing is recorded and
/// the scene has a mesh.
fn uses_packets<R: Recorder>(scene: &Scene) -> bool {
    !R::RECORDS
        && !R::DIAGNOSE
        && scene.camera.width > 0
        && scene
            .objects
            .iter()
            .any(|o| matches!(o.shape, Shape::Mesh(_)))
}

type Row = (Vec<Rgb>, Vec<(u32, u32)>, RayCounts);

fn render_recorded<R: Recorder + Default>(
    tracer: &Tracer,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, DiagnosticMap) {
    let scene = tracer.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let done = std::sync::atomic::AtomicU32::new(0);
    let rows: Vec<Row> = if uses_packets::<R>(scene) {
        let on_band = |n| progress(done.fetch_add(n, std::sync::atomic::Ordering::Relaxed) + n);
        packet_bands::<R>(tracer, 0..h, &on_band)
            .into_iter()
            .flat_map(|(band, counts)| {
                let rows: Vec<Row> = band
                    .chunks(w as usize)
                    .enumerate()
                    .map(|(i, row)| {
                        let counts = if i == 0 { counts } else { RayCounts::default() };
                        (row.to_vec(), Vec::new(), counts)
                    })
                    .collect();
                rows
            })
            .collect()
    } else {
        (0..h)
            .into_par_iter()
            .map(|y| {
                let mut counts = RayCounts::default();
                let mut diag = Vec::new();
                let mut rec = R::default();
                let row = (0..w)
                    .map(|x| {
                        let before = counts;
                        let l = render_pixel_with(tracer, x, y, &mut rec, &mut counts, |_| {});
                        if R::DIAGNOSE {
                            let self_hits = counts.self_hits - before.self_hits;
                            let leaks = counts.leaks - before.leaks;
                            diag.push((self_hits as u32, leaks as u32));
                        }
                        l
                    })
                    .collect();
                progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
                (row, diag, counts)
            })
            .collect()
    };
    let mut stats = RenderStats::default();
    let mut pixels = Vec::with_capacity((w * h) as usize);
    let mut map = DiagnosticMap {
        width: w,
        height: h,
        ..DiagnosticMap::default()
    };
    for (y, (row, diag, counts)) in rows.into_iter().enumerate() {
        stats.rays += counts;
        for (x, p) in row.into_iter().enumerate() {
            if p.is_finite() {
                pixels.push(p);
            } else {
                stats.nonfinite_pixels += 1;
                stats.first_nonfinite.get_or_insert((x as u32, y as u32));
                pixels.push(Rgb::ZERO);
            }
        }
        for (s, l) in diag {
            stats.self_hit_pixels += u64::from(s > 0);
            stats.leak_pixels += u64::from(l > 0);
            map.self_hits.push(s);
            map.leaks.push(l);
        }
    }
    let image = Image {
        width: w,
        height: h,
        pixels,
    };
    (image, stats, map)
}

/// Rows per band and columns per tile of the packet path: a packet is the camera rays of one
/// sample of an 8x8 tile.
const TILE: u32 = 8;

/// Rows `y0..y0 + rows` (at most [`TILE`]) without recording, a tile of camera rays at a time
/// through [`Scene::intersect_packet`]: the pixels (row-major) and the ray counts. Each pixel
/// sums its samples in the same order as [`render_pixel_with`], and each ray's hit is its single
/// ray's, so the pixels are [`render_pixel_with`]'s bit for bit.
fn render_band<R: Recorder + Default>(
    tracer: &Tracer,
    y0: u32,
    rows: u32,
) -> (Vec<Rgb>, RayCounts) {
    let scene = tracer.scene();
    let w = scene.camera.width;
    let spp = scene.settings.spp.max(1);
    let mut counts = RayCounts::default();
    let mut rec = R::default();
    let mut band = vec![Rgb::ZERO; (w * rows) as usize];
    let film = tracer.film();
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
                    let (fx, fy) = sample_position(x0 + dx, y0 + dy, s, spp);
                    rays.push(film.ray(fx, fy));
                }
            }
            cost.fill(TraversalCost::default());
            scene.intersect_packet(&rays, &mut hits, &mut cost);
            let n = rays.len();
            let found = (&hits[..n], &cost[..n]);
            tracer.trace_camera_packet(&rays, found, &mut radiance[..n], &mut rec, &mut counts);
            for (i, &l) in radiance[..n].iter().enumerate() {
                let (dx, dy) = (i as u32 % cols, i as u32 / cols);
                band[(dy * w + x0 + dx) as usize] += l;
            }
        }
    }
    for p in &mut band {
        *p /= f64::from(spp);
    }
    (band, counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_stratified_and_inside_the_pixel() {
        for spp in [2, 4, 5, 16] {
            let cols = f64::from(spp).sqrt().ceil() as u32;
            for s in 0..spp {
                let (fx, fy) = sample_position(3, 7, s, spp);
                assert!((3.0..4.0).contains(&fx) && (7.0..8.0).contains(&fy));
                let cx = ((fx - 3.0) * f64::from(cols)).floor() as u32;
                assert_eq!(cx, s % cols);
            }
        }
        assert_eq!(sample_position(3, 7, 0, 1), (3.5, 7.5));
        assert_eq!(sample_position(3, 7, 2, 4), sample_position(3, 7, 2, 4));
        assert_ne!(sample_position(3, 7, 2, 4), sample_position(4, 7, 2, 4));
    }
}
