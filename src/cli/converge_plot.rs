//! The log-log plot of `raytree converge`: rel-RMSE against spp (left) and seconds (right), one
//! line per series, with the N^-1/2 line through the first series' first point (plotters, the
//! same embedded font as `raytree cost`).

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use raytree::analysis::converge::Curve;

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// The marker of a series: each of the first six series has its own shape, alternating filled
/// and hollow and growing in size, so two series with the same points both stay visible (a
/// hollow square around a filled circle).
#[derive(Clone, Copy)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Cross,
    Ring,
    Diamond,
}

impl Marker {
    fn of(k: usize) -> Self {
        [
            Self::Circle,
            Self::Square,
            Self::Triangle,
            Self::Cross,
            Self::Ring,
            Self::Diamond,
        ][k % 6]
    }

    /// The marker centred `at` (pixels from its anchor).
    fn element<DB: DrawingBackend>(
        self,
        (x, y): (i32, i32),
        color: RGBColor,
    ) -> DynElement<'static, DB, (i32, i32)> {
        let hollow = color.stroke_width(2);
        match self {
            Self::Circle => Circle::new((x, y), 4, color.filled()).into_dyn(),
            Self::Square => Rectangle::new([(x - 7, y - 7), (x + 7, y + 7)], hollow).into_dyn(),
            Self::Triangle => Polygon::new(
                vec![(x, y - 8), (x - 7, y + 5), (x + 7, y + 5)],
                color.filled(),
            )
            .into_dyn(),
            Self::Cross => Cross::new((x, y), 7, hollow).into_dyn(),
            Self::Ring => Circle::new((x, y), 10, hollow).into_dyn(),
            Self::Diamond => PathElement::new(
                vec![(x, y - 9), (x + 9, y), (x, y + 9), (x - 9, y), (x, y - 9)],
                hollow,
            )
            .into_dyn(),
        }
    }
}

/// A positive, finite range around `values` (log axes), padded by `pad` either side.
fn range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() && hi > 0.0 {
        (lo / pad, hi * pad)
    } else {
        (0.1, 10.0)
    }
}

/// A log-log chart of the plot, on its drawing area.
type Chart<'a, 'b> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

fn err(e: &dyn std::fmt::Display) -> anyhow::Error {
    anyhow!("plot: {e}")
}

/// RGB bytes of `w x h`.
pub fn plot(curves: &[Curve], (iw, ih): (u32, u32), w: u32, h: u32) -> Result<Vec<u8>> {
    super::plot::register_font();
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let root = root
            .titled(
                &format!("raytree converge: rel-RMSE vs reference ({iw}x{ih})"),
                ("sans-serif", 26),
            )
            .map_err(|e| err(&e))?;
        // A caption under the plots when two series coincide (one line would hide the other).
        let caption = raytree::analysis::converge::identical_text(curves);
        let root = match &caption {
            Some(text) => {
                let (plots, bottom) = root.split_vertically(root.dim_in_pixel().1 - 30);
                bottom
                    .draw_text(text, &("sans-serif", 16).into_text_style(&bottom), (15, 5))
                    .map_err(|e| err(&e))?;
                plots
            }
            None => root,
        };
        let (left, right) = root.split_horizontally(w / 2);
        let points = || curves.iter().flat_map(|c| c.points.iter());
        // Headroom above for the legend.
        let ys = range(points().map(|p| p.rel_rmse), 1.5);
        let ys = (ys.0, ys.1 * 6.0);
        for (area, by_time) in [(left, false), (right, true)] {
            let axis = XAxis { by_time };
            let xs = range(points().map(|p| axis.x_of(p)), 1.3);
            let mut chart = ChartBuilder::on(&area)
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d((xs.0..xs.1).log_scale(), (ys.0..ys.1).log_scale())
                .map_err(|e| err(&e))?;
            draw_mesh(&mut chart, axis)?;
            draw_reference_line(&mut chart, curves, axis, xs, ys)?;
            for (k, c) in curves.iter().enumerate() {
                draw_curve(&mut chart, c, k, axis)?;
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .label_font(("sans-serif", 15))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(buf)
}

/// Which of the two panels: rel-RMSE against samples per pixel, or against seconds.
#[derive(Clone, Copy)]
struct XAxis {
    by_time: bool,
}

impl XAxis {
    /// A point's position on this axis.
    fn x_of(self, p: &raytree::analysis::converge::Point) -> f64 {
        if self.by_time {
            p.seconds
        } else {
            f64::from(p.spp)
        }
    }
}

/// The grid, the tick labels and the axis names.
fn draw_mesh(chart: &mut Chart, axis: XAxis) -> Result<()> {
    chart
        .configure_mesh()
        .x_desc(if axis.by_time {
            "seconds"
        } else {
            "samples per pixel"
        })
        .y_desc("rel-RMSE")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .x_labels(6)
        .x_label_formatter(&|v| {
            if *v >= 10.0 {
                format!("{v:.0}")
            } else if *v >= 0.1 {
                format!("{v:.1}")
            } else {
                format!("{v:.0e}")
            }
        })
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(&e))
}

/// N^-1/2 through the first series' first plottable point, across the x range `xs` and
/// clamped to the y range `ys`.
fn draw_reference_line(
    chart: &mut Chart,
    curves: &[Curve],
    axis: XAxis,
    xs: (f64, f64),
    ys: (f64, f64),
) -> Result<()> {
    if let Some(p0) = curves.first().and_then(|c| {
        c.points
            .iter()
            .find(|p| axis.x_of(p) > 0.0 && p.rel_rmse > 0.0 && p.rel_rmse.is_finite())
    }) {
        let (x0, y0) = (axis.x_of(p0), p0.rel_rmse);
        let line = (0..=40).map(|i| {
            let x = xs.0 * (xs.1 / xs.0).powf(f64::from(i) / 40.0);
            (x, (y0 * (x / x0).powf(-0.5)).clamp(ys.0, ys.1))
        });
        chart
            .draw_series(DashedLineSeries::new(
                line,
                8,
                5,
                BLACK.mix(0.6).stroke_width(2),
            ))
            .map_err(|e| err(&e))?
            .label("N^-1/2")
            .legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.6).stroke_width(2))
            });
    }
    Ok(())
}

/// Series `k`: its line, its markers and its legend entry with the fitted slope.
fn draw_curve<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    c: &Curve,
    k: usize,
    axis: XAxis,
) -> Result<()> {
    let color = COLORS[k % COLORS.len()];
    let pts: Vec<(f64, f64)> = c
        .points
        .iter()
        .map(|p| (axis.x_of(p), p.rel_rmse))
        .filter(|(x, y)| x.is_finite() && *x > 0.0 && y.is_finite() && *y > 0.0)
        .collect();
    let slope = if axis.by_time {
        c.slope_seconds
    } else {
        c.slope_spp
    };
    let label = match slope {
        Some(s) => format!("{} (slope {s:.2})", c.name),
        None => c.name.clone(),
    };
    let marker = Marker::of(k);
    chart
        .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
        .map_err(|e| err(&e))?
        .label(label)
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (20, 0)], color.stroke_width(2))
                + marker.element((10, 0), color)
        });
    chart
        .draw_series(
            pts.iter()
                .map(|p| EmptyElement::at(*p) + marker.element((0, 0), color)),
        )
        .map_err(|e| err(&e))?;
    Ok(())
}
