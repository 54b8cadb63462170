//! `raytree cost`: the accuracy/time sweep, written as Markdown, CSV, JSON and a plot.

use super::args::CostArgs;
use super::load::load;
use super::output::{Inputs, Origin, OutDir, OutputSet, encode_rgb8_png};
use super::plot::error_vs_time;
use super::say::{out, sayln};
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use raytree::analysis::cost::{self, CostReport, Sweep};
use raytree::scene::IntegratorKind;
use std::fmt::Write;

/// Run the sweep and write `cost.md`, `cost.csv`, `cost.json` and `cost.png` into the output
/// directory (created if missing; in an existing one only these four files are replaced, each
/// atomically). Nothing is written unless every render succeeded. A non-finite error is
/// written as `not finite` (Markdown), an empty field (CSV) or `null` (JSON), and not plotted.
pub fn run(a: &CostArgs) -> Result<()> {
    let mut overrides = a.overrides.clone();
    if overrides.size.is_none() {
        overrides.size = Some(if a.quick { "160x90" } else { "320x180" }.to_string());
    }
    let loaded = load(a.scene.as_deref(), &overrides)?;
    // A sweep holds a reference and a render (and their errors) at once.
    super::budget::check_image_with(
        &loaded.scene,
        super::budget::mib(a.overrides.max_memory),
        3 * super::budget::PIXEL_BYTES,
    )?;
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let dir = OutDir::create(&a.output)?;
    let names = ["cost.md", "cost.csv", "cost.json", "cost.png"];
    let mut set = OutputSet::new(&inputs, false);
    let slots = names
        .iter()
        .map(|n| dir.reserve(&mut set, n, Origin::Named))
        .collect::<Result<Vec<_>>>()?;
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
        raytree::text::guard_nonfinite(&md)
            .into_owned()
            .into_bytes(),
        csv(&report).into_bytes(),
        serde_json::to_vec_pretty(&report)?,
        plot,
    ];
    for (slot, b) in slots.into_iter().zip(bytes) {
        set.stage(slot, &b)?;
    }
    set.commit()?;
    dir.keep();
    out(&md)?;
    sayln!("wrote {}/{{{}}}", a.output.display(), names.join(","))?;
    Ok(())
}

fn markdown(r: &CostReport, label: &str) -> String {
    let mut s = if r.reference.integrator == IntegratorKind::Path {
        path_header(r, label)
    } else {
        whitted_header(r, label)
    };
    s.push_str("| axis | value | median ms | rays | camera | reflected | refracted | shadow | diffuse | RMSE | max err | pixels off >1/255 | Pareto |\n");
    s.push_str(
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | :---: |\n",
    );
    for row in &r.rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            row.axis,
            row.value,
            row.median_ms,
            row.rays.total,
            row.rays.camera,
            row.rays.reflected,
            row.rays.refracted,
            row.rays.shadow,
            row.rays.diffuse,
            fin(row.error.rmse, |v| format!("{v:.2e}")),
            fin(row.error.max, |v| {
                if v < 1e6 {
                    format!("{v:.3}")
                } else {
                    format!("{v:.3e}")
                }
            }),
            fin(row.error.off_8bit, |v| format!("{:.2}%", v * 100.0)),
            if row.pareto { "*" } else { "" }
        );
    }
    s
}

/// The header of a Whitted scene's sweep: its axes and references.
fn whitted_header(r: &CostReport, label: &str) -> String {
    let mut s = format!(
        "Cost sweep of {label} at {}x{}. Reference: max depth {}, exact Fresnel, offset {}, no min weight (the exhaustive tree); 1 spp (pixel centres) for every axis but spp, {} spp for the spp axis. Each row changes one setting of the base, the default settings at depth 16 (exact Fresnel, 1 spp, the automatic min weight {:.1e} and, with glass, the automatic roulette below a weight, robust offset); the min_weight rows are the cut alone (no roulette); the offset rows use the scene's epsilon {:e}.\n\n",
        r.size[0],
        r.size[1],
        r.reference.max_depth,
        r.reference.offset.strategy.name(),
        r.reference_spp,
        r.base_min_weight,
        r.rows
            .first()
            .map_or(0.0, |row| row.settings.offset.epsilon),
    );
    let _ = write!(
        s,
        "Stochastic axes: light_samples rows (only for scenes with an area light) against {} light samples, glossy_samples rows (only for scenes with a rough material) against {} glossy samples, both at the pixel centres; filter rows at {} spp against the same filter at {} spp; adaptive rows (threshold to max spp, first pass {} spp; camera rays = samples taken) against {} spp; dielectric_roulette rows (only for scenes with glass: reflection or refraction chosen by Russian roulette from that depth on, exact in expectation) against the pixel-centre reference, their error the roulette's noise beside the automatic cut's bounded error; roulette_below rows (glass only: hits of a throughput below that weight play the roulette, with the automatic cut) against the same reference.\n\n",
        r.reference_light_samples,
        r.reference_glossy_samples,
        spp_of(r, "filter"),
        r.reference_spp,
        spp_of(r, "adaptive"),
        r.reference_spp,
    );
    s
}

/// The spp of the first row of `axis` (0 without one).
fn spp_of(r: &CostReport, axis: &str) -> u32 {
    r.rows
        .iter()
        .find(|row| row.axis == axis)
        .map_or(0, |row| row.settings.spp)
}

/// The header of a path-traced scene's sweep: its axes and references, and the Whitted axes
/// it leaves out.
fn path_header(r: &CostReport, label: &str) -> String {
    format!(
        "Cost sweep of {label} at {}x{}, path integrator. Reference: max depth {}, offset {}; 1 spp for the max_depth and offset axes (the same random numbers as each row, so a row's error is what its setting changes), {} spp for the spp axis. Each row changes one setting of the base, the scene's settings at depth 16 (1 spp, robust offset). Not swept: the Fresnel model, min_weight, light_samples, glossy_samples and the glass roulettes, which the path integrator does not read ({}).\n\nStochastic axes: rr_depth rows (Russian roulette from that bounce on; off from the max depth on) and sampler rows (stratified jitter, Owen-scrambled Sobol) at {} spp against {} spp; filter rows at {} spp against the same filter at {} spp; adaptive rows (threshold to max spp, first pass {} spp; camera rays = samples taken) against {} spp.\n\n",
        r.size[0],
        r.size[1],
        r.reference.max_depth,
        r.reference.offset.strategy.name(),
        r.reference_spp,
        raytree::scene::WhittedSettings::WHY_OTHERS_IGNORE,
        spp_of(r, "rr_depth"),
        r.reference_spp,
        spp_of(r, "filter"),
        r.reference_spp,
        spp_of(r, "adaptive"),
        r.reference_spp,
    )
}

fn csv(r: &CostReport) -> String {
    let mut s = String::from(
        "axis,value,median_ms,rays,camera,reflected,refracted,shadow,diffuse,rmse,max_error,off_8bit,pareto\n",
    );
    for row in &r.rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            row.axis,
            row.value,
            row.median_ms,
            row.rays.total,
            row.rays.camera,
            row.rays.reflected,
            row.rays.refracted,
            row.rays.shadow,
            row.rays.diffuse,
            csv_num(row.error.rmse),
            csv_num(row.error.max),
            csv_num(row.error.off_8bit),
            row.pareto
        );
    }
    s
}

/// `f(v)`, or `not finite` for NaN and infinities (never written as a number).
fn fin(v: f64, f: impl Fn(f64) -> String) -> String {
    if v.is_finite() {
        f(v)
    } else {
        "not finite".to_string()
    }
}

/// A CSV field: the number, or empty for NaN and infinities.
fn csv_num(v: f64) -> String {
    if v.is_finite() {
        v.to_string()
    } else {
        String::new()
    }
}
