//! Figures of the acne sweep: per-strategy heat-map sheets and the summary plot.
//!
//! Drawn with tiny-skia (already the project's rasterizer) plus ab_glyph for labels: the plot is
//! a matrix of coloured cells, which needs no charting library, and plotters' bitmap backend is
//! not among the project's dependencies.

use super::canvas::{Canvas, Rgb8};
use anyhow::Result;
use raytree::analysis::acne::{AcneCell, AcneReport, sci};
use raytree::scene::OffsetStrategy;

const INK: Rgb8 = [30, 30, 30];
const ACNE: Rgb8 = [220, 40, 40];
const LEAK: Rgb8 = [40, 110, 230];
const BOTH: Rgb8 = [190, 40, 200];
const CLEAN: Rgb8 = [200, 235, 200];

fn mix(a: Rgb8, b: Rgb8, t: f64) -> Rgb8 {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|i| (f64::from(a[i]) * (1.0 - t) + f64::from(b[i]) * t).round() as u8)
}

/// Colour of one pixel of a heat map: the render dimmed to grey, red where a ray self-hit,
/// blue where one leaked, magenta for both.
fn heat_pixel(cell: &AcneCell, i: usize) -> Rgb8 {
    let (s, l) = (cell.map.self_hits[i], cell.map.leaks[i]);
    match (s > 0, l > 0) {
        (true, true) => BOTH,
        (true, false) => ACNE,
        (false, true) => LEAK,
        (false, false) => {
            let p = cell.image.pixels[i];
            let y = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
            let g = 40 + (f64::from(raytree::math::linear_to_srgb8(y)) * 0.55) as u8;
            [g, g, g]
        }
    }
}

/// One sheet per strategy: rows are epsilons, columns scene scales, each cell the render with
/// its self-hit (red) and leak (blue) pixels.
pub fn heat_map(report: &AcneReport, strategy: OffsetStrategy) -> Result<Vec<u8>> {
    let c = &report.config;
    let k = (96 / c.width).max(1);
    let (cw, ch) = (c.width * k, c.height * k);
    let (left, top, gap) = (64u32, 52u32, 4u32);
    let cols = c.scales.len() as u32;
    let rows = c.epsilons.len() as u32;
    let mut cv = Canvas::new(
        left + cols * (cw + gap),
        top + rows * (ch + gap) + 24,
        [255, 255, 255],
    )?;
    let title = format!(
        "offset '{}': red = self-hit (acne), blue = leak, magenta = both",
        strategy.name()
    );
    cv.text(4.0, 18.0, 15.0, &title, INK);
    cv.text(left as f32, 38.0, 12.0, "scene scale ->", INK);
    for (j, s) in c.scales.iter().enumerate() {
        let x = left + j as u32 * (cw + gap);
        cv.text(
            x as f32 + 2.0,
            (top - 2) as f32,
            11.0,
            &format!("s={}", sci(*s)),
            INK,
        );
    }
    for (i, &e) in c.epsilons.iter().enumerate() {
        let y = top + i as u32 * (ch + gap);
        cv.text(
            2.0,
            (y + ch / 2 + 4) as f32,
            11.0,
            &format!("eps {}", sci(e)),
            INK,
        );
        for (j, cell) in report.row(strategy, e).enumerate() {
            let x0 = left + j as u32 * (cw + gap);
            for py in 0..ch {
                for px in 0..cw {
                    let idx = ((py / k) * c.width + px / k) as usize;
                    cv.pixel(x0 + px, y + py, heat_pixel(cell, idx));
                }
            }
        }
    }
    cv.png()
}

/// Colour of a summary cell: pale green when clean, else red (acne) and/or blue (leaks) whose
/// strength grows with the fraction of affected pixels.
fn summary_colour(cell: &AcneCell) -> Rgb8 {
    if cell.clean() {
        return CLEAN;
    }
    let n = cell.pixels.max(1) as f64;
    let (a, l) = (cell.self_hit_pixels as f64 / n, cell.leak_pixels as f64 / n);
    let strength = |f: f64| 0.45 + 0.55 * f.sqrt();
    match (a > 0.0, l > 0.0) {
        (true, false) => mix([255, 255, 255], ACNE, strength(a)),
        (false, true) => mix([255, 255, 255], LEAK, strength(l)),
        _ => mix([255, 255, 255], BOTH, strength(a.max(l))),
    }
}

/// Sizes of the summary plot's panels, in pixels.
struct PanelLayout {
    cell_w: u32,
    cell_h: u32,
    /// Room for the epsilon labels left of the cells.
    left: u32,
    /// Room for the title and scale labels above the cells.
    top: u32,
    panel_w: u32,
    panel_h: u32,
}

/// The summary plot: one panel per strategy, epsilon (rows, small at the top) against scene
/// scale (columns).
pub fn plot(report: &AcneReport, scene: &str) -> Result<Vec<u8>> {
    let c = &report.config;
    let (cell_w, cell_h) = (44u32, 22u32);
    let (left, top) = (62u32, 44u32);
    let layout = PanelLayout {
        cell_w,
        cell_h,
        left,
        top,
        panel_w: left + c.scales.len() as u32 * cell_w + 24,
        panel_h: top + c.epsilons.len() as u32 * cell_h + 34,
    };
    let (panel_w, panel_h) = (layout.panel_w, layout.panel_h);
    let per_row = 2u32;
    let n = c.strategies.len() as u32;
    let grid_rows = n.div_ceil(per_row);
    let (head, foot) = (36u32, 30u32);
    let mut cv = Canvas::new(
        per_row.min(n) * panel_w + 10,
        head + grid_rows * panel_h + foot,
        [255, 255, 255],
    )?;
    cv.text(
        8.0,
        22.0,
        16.0,
        &format!(
            "Self-intersection sweep: {scene} (scene moved {}x its size from the origin)",
            sci(c.shift)
        ),
        INK,
    );
    for (k, &st) in c.strategies.iter().enumerate() {
        let corner = (
            (k as u32 % per_row) * panel_w + 8,
            head + (k as u32 / per_row) * panel_h,
        );
        draw_panel(&mut cv, report, &layout, st, corner);
    }
    let fy = (head + grid_rows * panel_h + 16) as f32;
    draw_legend(&mut cv, fy);
    cv.png()
}

/// One strategy's panel with its top-left corner at `(px, py)`: its verdict, the scale labels,
/// and a row of cells per epsilon.
fn draw_panel(
    cv: &mut Canvas,
    report: &AcneReport,
    layout: &PanelLayout,
    st: OffsetStrategy,
    (px, py): (u32, u32),
) {
    let c = &report.config;
    let PanelLayout {
        cell_w,
        cell_h,
        left,
        top,
        ..
    } = *layout;
    let ok = report.clean_everywhere(st);
    let verdict = if ok.len() == c.epsilons.len() {
        "clean everywhere".to_string()
    } else if ok.is_empty() {
        "no epsilon is clean at every scale".to_string()
    } else {
        format!("clean at every scale for {} eps", ok.len())
    };
    cv.text(
        px as f32,
        (py + 18) as f32,
        14.0,
        &format!("{}: {verdict}", st.name()),
        INK,
    );
    for (j, s) in c.scales.iter().enumerate() {
        let label = sci(*s);
        let x = (px + left + j as u32 * cell_w) as f32
            + (cell_w as f32 - cv.text_width(&label, 10.0)) / 2.0;
        cv.text(x, (py + top - 4) as f32, 10.0, &label, INK);
    }
    for (i, &e) in c.epsilons.iter().enumerate() {
        let y = py + top + i as u32 * cell_h;
        let label = if st.uses_epsilon() {
            sci(e)
        } else {
            "(none)".to_string()
        };
        cv.text(px as f32, (y + cell_h / 2 + 4) as f32, 10.0, &label, INK);
        for (j, cell) in report.row(st, e).enumerate() {
            let x = px + left + j as u32 * cell_w;
            cv.rect(
                x as f32,
                y as f32,
                (cell_w - 2) as f32,
                (cell_h - 2) as f32,
                summary_colour(cell),
            );
        }
    }
    let by = py + top + c.epsilons.len() as u32 * cell_h + 14;
    cv.text(
        (px + left) as f32,
        by as f32,
        11.0,
        "scene scale ->   (rows: epsilon, small at top)",
        INK,
    );
}

/// The colour legend along the bottom, its baseline at `fy`.
fn draw_legend(cv: &mut Canvas, fy: f32) {
    let mut x = 10.0;
    for (colour, label) in [
        (CLEAN, "clean"),
        (ACNE, "self-hits (acne): eps too small"),
        (LEAK, "leaks: eps too large"),
        (BOTH, "both"),
    ] {
        cv.rect(x, fy - 10.0, 14.0, 12.0, colour);
        cv.text(x + 18.0, fy, 12.0, label, INK);
        x += 30.0 + cv.text_width(label, 12.0);
    }
}
