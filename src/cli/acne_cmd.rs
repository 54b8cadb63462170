//! `raytree acne`: the self-intersection sweep, written as a report directory.

use super::acne_figures::{heat_map, plot};
use super::args::{AcneArgs, Overrides};
use super::load::{load, pair};
use super::output::{Inputs, Origin, OutDir, OutputSet};
use super::say::sayln;
use anyhow::{Result, anyhow, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raytree::analysis::acne::{AcneConfig, AcneReport, sweep};
use raytree::scene::OffsetStrategy;
use std::path::Path;

fn list<T>(flag: &str, v: &str, parse: impl Fn(&str) -> Option<T>) -> Result<Vec<T>> {
    let out: Vec<T> = v
        .split(',')
        .map(|s| parse(s.trim()).ok_or_else(|| anyhow!("--{flag}: cannot read {:?}", s.trim())))
        .collect::<Result<_>>()?;
    if out.is_empty() {
        bail!("--{flag}: empty list");
    }
    Ok(out)
}

fn positive(s: &str) -> Option<f64> {
    s.parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0)
}

fn config(a: &AcneArgs) -> Result<AcneConfig> {
    let strategies = list("strategies", &a.strategies, |s| {
        serde_json::from_value::<OffsetStrategy>(serde_json::Value::String(s.into())).ok()
    })?;
    let epsilons = list("epsilons", &a.epsilons, |s| {
        s.parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0)
    })?;
    let scales = list("scales", &a.scales, positive)?;
    if !(a.shift.is_finite() && a.shift >= 0.0) {
        bail!("--shift: must be a finite number >= 0, got {}", a.shift);
    }
    let (width, height) = pair("size", &a.size, 'x')?;
    if width == 0 || height == 0 || width > 4096 || height > 4096 {
        bail!(
            "--size: width and height must be in 1..=4096, got {}",
            a.size
        );
    }
    Ok(AcneConfig {
        strategies,
        epsilons,
        scales,
        shift: a.shift,
        width,
        height,
    })
}

/// Run the sweep and write report.md, report.json, heatmap-<strategy>.png and plot.png into
/// the output directory (created if missing; in an existing one only these files are replaced,
/// each atomically, and nothing is written unless the whole sweep succeeded).
pub fn run(a: &AcneArgs) -> Result<()> {
    let cfg = config(a)?;
    let loaded = load(a.scene.as_deref(), &overrides(a))?;
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let dir = OutDir::create(&a.output)?;
    let names = file_names(&cfg);
    let mut set = OutputSet::new(&inputs, false);
    let slots = names
        .iter()
        .map(|n| dir.reserve(&mut set, n, Origin::Named))
        .collect::<Result<Vec<_>>>()?;
    let total = cfg.strategies.len() * cfg.epsilons.len() * cfg.scales.len();
    let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr())
        .with_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} renders {elapsed_precise}")
                .expect("valid template")
                .progress_chars("=> "),
        );
    bar.set_message(format!("acne sweep of {}", loaded.label));
    let report = sweep(&loaded.scene, &cfg, &|n| bar.set_position(n as u64));
    bar.finish_and_clear();
    let name = a
        .scene
        .as_deref()
        .and_then(Path::file_stem)
        .map_or("classic (built-in)".to_string(), |s| {
            s.to_string_lossy().into_owned()
        });
    let mut bytes = vec![
        raytree::text::guard_nonfinite(&report.markdown(&name))
            .into_owned()
            .into_bytes(),
        serde_json::to_string_pretty(&report)?.into_bytes(),
    ];
    for &st in &cfg.strategies {
        bytes.push(heat_map(&report, st)?);
    }
    bytes.push(plot(&report, &name)?);
    for (slot, b) in slots.into_iter().zip(bytes) {
        set.stage(slot, &b)?;
    }
    set.commit()?;
    dir.keep();
    sayln!(
        "wrote {} ({total} renders of {}x{}): report.md, report.json, plot.png, heatmap-*.png",
        a.output.display(),
        cfg.width,
        cfg.height
    )?;
    say_verdicts(&report, &cfg)
}

/// The sweep's render settings from the command line (the scale and offset come from the sweep).
fn overrides(a: &AcneArgs) -> Overrides {
    Overrides {
        integrator: a.integrator.clone(),
        rr_depth: a.rr_depth,
        sampler: a.sampler.clone(),
        seed: a.seed,
        light_samples: a.light_samples,
        glossy_samples: a.glossy_samples,
        aperture: a.aperture,
        focus: a.focus,
        filter: a.filter.clone(),
        ..Overrides::default()
    }
}

/// The report directory's files, in the order they are staged.
fn file_names(cfg: &AcneConfig) -> Vec<String> {
    let mut names = vec!["report.md".to_string(), "report.json".to_string()];
    names.extend(
        cfg.strategies
            .iter()
            .map(|st| format!("heatmap-{}.png", st.name())),
    );
    names.push("plot.png".to_string());
    names
}

/// One line per strategy: the epsilons clean at every scale.
fn say_verdicts(report: &AcneReport, cfg: &AcneConfig) -> Result<()> {
    for &st in &cfg.strategies {
        let ok = report.clean_everywhere(st);
        let list: Vec<String> = ok
            .iter()
            .map(|e| raytree::analysis::acne::sci(*e))
            .collect();
        let verdict = if !st.uses_epsilon() && ok.len() == cfg.epsilons.len() {
            "clean at every scale (uses no epsilon)".to_string()
        } else if list.is_empty() {
            "no epsilon is clean at every scale".to_string()
        } else {
            format!("clean at every scale with epsilon {}", list.join(", "))
        };
        sayln!("{:>7}: {verdict}", st.name())?;
    }
    Ok(())
}
