//! `raytree cost`: the accuracy/time sweep, written as Markdown, CSV, JSON and a plot.

use super::args::CostArgs;
use super::load::load;
use super::output::{Pending, encode_rgb8_png};
use super::plot::error_vs_time;
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use raytree::analysis::cost::{self, CostReport, Sweep};
use std::fmt::Write;

/// Run the sweep and write `cost.md`, `cost.csv`, `cost.json` and `cost.png` into the output
/// directory. Nothing is written unless every render succeeded.
pub fn run(a: &CostArgs) -> Result<()> {
    let mut overrides = a.overrides.clone();
    if overrides.size.is_none() {
        overrides.size = Some(if a.quick { "160x90" } else { "320x180" }.to_string());
    }
    let loaded = load(a.scene.as_deref(), &overrides)?;
    std::fs::create_dir_all(&a.output)
        .with_context(|| format!("cannot create {}", a.output.display()))?;
    let names = ["cost.md", "cost.csv", "cost.json", "cost.png"];
    let pending: Vec<Pending> = names
        .iter()
        .map(|n| Pending::create(&a.output.join(n)))
        .collect::<Result<_>>()?;
    let mut sweep = if a.quick {
        Sweep::quick()
    } else {
        Sweep::full()
    };
    if let Some(r) = a.repeats {
        sweep.repeats = r.max(1);
    }
    let bar = ProgressBar::new(0).with_style(
        ProgressStyle::with_template("cost sweep [{bar:40}] {pos}/{len} renders {elapsed_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let report = cost::run(&loaded.scene, &sweep, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let md = markdown(&report, &loaded.label);
    let plot = encode_rgb8_png(&error_vs_time(&report, 1200, 800)?, 1200, 800)?;
    let bytes: [Vec<u8>; 4] = [
        md.clone().into_bytes(),
        csv(&report).into_bytes(),
        serde_json::to_vec_pretty(&report)?,
        plot,
    ];
    for (p, b) in pending.into_iter().zip(bytes) {
        p.commit(&b)?;
    }
    print!("{md}");
    println!("wrote {}/{{{}}}", a.output.display(), names.join(","));
    Ok(())
}

fn markdown(r: &CostReport, label: &str) -> String {
    let mut s = format!(
        "Cost sweep of {label} at {}x{}. Reference: max depth {}, exact Fresnel, offset {}, no min weight; 1 spp (pixel centres) for every axis but spp, {} spp for the spp axis. Each row changes one setting of the base (depth 16, exact Fresnel, 1 spp, min weight 0, robust offset); the offset rows use the scene's epsilon {:e}.\n\n",
        r.size[0],
        r.size[1],
        r.reference.max_depth,
        r.reference.offset.strategy.name(),
        r.reference_spp,
        r.rows
            .first()
            .map_or(0.0, |row| row.settings.offset.epsilon),
    );
    s.push_str("| axis | value | median ms | rays | camera | reflected | refracted | shadow | RMSE | max err | pixels off >1/255 | Pareto |\n");
    s.push_str(
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | :---: |\n",
    );
    for row in &r.rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {:.2e} | {:.3} | {:.2}% | {} |",
            row.axis,
            row.value,
            row.median_ms,
            row.rays.total,
            row.rays.camera,
            row.rays.reflected,
            row.rays.refracted,
            row.rays.shadow,
            row.error.rmse,
            row.error.max,
            row.error.off_8bit * 100.0,
            if row.pareto { "*" } else { "" }
        );
    }
    s
}

fn csv(r: &CostReport) -> String {
    let mut s = String::from(
        "axis,value,median_ms,rays,camera,reflected,refracted,shadow,rmse,max_error,off_8bit,pareto\n",
    );
    for row in &r.rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            row.axis,
            row.value,
            row.median_ms,
            row.rays.total,
            row.rays.camera,
            row.rays.reflected,
            row.rays.refracted,
            row.rays.shadow,
            row.error.rmse,
            row.error.max,
            row.error.off_8bit,
            row.pareto
        );
    }
    s
}
