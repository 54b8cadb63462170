//! The error-versus-time plot of `raytree cost` (plotters, bitmap back-end, embedded font).

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use plotters::style::FontStyle;
use raytree::analysis::cost::{CostReport, CostRow};
use std::sync::Once;

/// Register egui's embedded Ubuntu Light as "sans-serif", so no system fonts are needed.
pub(super) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

const AXES: [(&str, RGBColor); 9] = [
    ("max_depth", RGBColor(31, 119, 180)),
    ("fresnel", RGBColor(255, 127, 14)),
    ("spp", RGBColor(44, 160, 44)),
    ("offset", RGBColor(214, 39, 40)),
    ("min_weight", RGBColor(148, 103, 189)),
    ("light_samples", RGBColor(140, 86, 75)),
    ("glossy_samples", RGBColor(227, 119, 194)),
    ("filter", RGBColor(23, 190, 207)),
    ("roulette_below", RGBColor(188, 189, 34)),
];

/// Draw RMSE (log) against median time (log) as RGB bytes of `w x h`; Pareto points ringed
/// and joined. Rows whose error or time is not finite cannot sit on a log axis (an infinite
/// range never ends its tick loop): they are left out and the caption counts them.
pub fn error_vs_time(report: &CostReport, w: u32, h: u32) -> Result<Vec<u8>> {
    register_font();
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("plot: {e}"))?;
        let plottable =
            |r: &&CostRow| r.error.rmse.is_finite() && r.median_ms.is_finite() && r.median_ms > 0.0;
        let rows: Vec<_> = report.rows.iter().filter(plottable).collect();
        let left_out = report.rows.len() - rows.len();
        let Ranges {
            floor,
            emax,
            tmin,
            tmax,
        } = Ranges::of(&rows);
        let note = if left_out > 0 {
            format!("; {left_out} settings with non-finite error not plotted")
        } else {
            String::new()
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "raytree cost: error vs time ({}x{}){note}",
                    report.size[0], report.size[1]
                ),
                ("sans-serif", 28),
            )
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((tmin..tmax).log_scale(), (floor..emax).log_scale())
            .map_err(|e| anyhow!("plot: {e}"))?;
        chart
            .configure_mesh()
            .x_desc("median render time (ms)")
            .y_desc("RMSE vs reference (linear)")
            .label_style(("sans-serif", 16))
            .x_label_formatter(&|v| format!("{v:.1}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(|e| anyhow!("plot: {e}"))?;
        draw_rows(&mut chart, &rows, floor)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| anyhow!("plot: {e}"))?;
        root.present().map_err(|e| anyhow!("plot: {e}"))?;
    }
    Ok(buf)
}

/// The log axes' ranges around the plottable rows.
struct Ranges {
    /// The lowest error shown: zero errors are drawn here.
    floor: f64,
    emax: f64,
    /// Median time in ms.
    tmin: f64,
    tmax: f64,
}

impl Ranges {
    fn of(rows: &[&CostRow]) -> Self {
        // Zero error cannot sit on a log axis: floor it at a tenth of the smallest non-zero error.
        let nonzero = rows.iter().map(|r| r.error.rmse).filter(|e| *e > 0.0);
        let floor = nonzero.clone().fold(f64::INFINITY, f64::min).min(1e-3) / 10.0;
        let emax = nonzero.fold(floor * 10.0, f64::max) * 30.0; // room for the legend
        let fastest = rows
            .iter()
            .map(|r| r.median_ms)
            .fold(f64::INFINITY, f64::min);
        let tmin = if fastest.is_finite() { fastest } else { 1.0 } / 1.5;
        let tmax = rows.iter().map(|r| r.median_ms).fold(tmin * 1.5, f64::max) * 1.5;
        Self {
            floor,
            emax,
            tmin,
            tmax,
        }
    }
}

/// The Pareto front's line, one labelled point per row coloured by its axis, and rings on the
/// front; errors below `floor` are drawn at it.
fn draw_rows(
    chart: &mut ChartContext<BitMapBackend, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    rows: &[&CostRow],
    floor: f64,
) -> Result<()> {
    let clamp = |e: f64| e.max(floor);
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.pareto)
        .map(|r| (r.median_ms, clamp(r.error.rmse)))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), BLACK.stroke_width(2)))
        .map_err(|e| anyhow!("plot: {e}"))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    for (k, (axis, color)) in AXES.into_iter().enumerate() {
        // Stagger labels by axis so settings that land on the same point stay legible.
        let dy = -10 + 16 * k as i32 - 32;
        let pts: Vec<_> = rows.iter().filter(|r| r.axis == axis).collect();
        chart
            .draw_series(pts.iter().map(|r| {
                let p = (r.median_ms, clamp(r.error.rmse));
                EmptyElement::at(p)
                    + Circle::new((0, 0), 6, color.filled())
                    + Text::new(
                        r.value.clone(),
                        (10, dy),
                        ("sans-serif", 16).into_font().color(&color),
                    )
            }))
            .map_err(|e| anyhow!("plot: {e}"))?
            .label(axis)
            .legend(move |(x, y)| Circle::new((x + 10, y), 6, color.filled()));
    }
    chart
        .draw_series(
            front
                .iter()
                .map(|p| Circle::new(*p, 10, BLACK.stroke_width(2))),
        )
        .map_err(|e| anyhow!("plot: {e}"))?;
    Ok(())
}
