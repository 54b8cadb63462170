//! `raytree acne`: the self-intersection sweep, written as a report directory.

use super::acne_figures::{heat_map, plot};
use super::args::{AcneArgs, Overrides};
use super::load::{load, pair};
use anyhow::{Context, Result, anyhow, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raytree::analysis::acne::{AcneConfig, sweep};
use raytree::scene::OffsetStrategy;
use std::path::{Path, PathBuf};

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

/// A directory that appears whole: files go into a hidden sibling, which replaces the target
/// on [`StagedDir::commit`] and is removed if dropped before.
struct StagedDir {
    target: PathBuf,
    temp: PathBuf,
}

impl StagedDir {
    fn create(target: &Path) -> Result<Self> {
        if target.exists() && !(target.is_dir() && is_replaceable(target)) {
            bail!(
                "cannot write {}: it exists and is not an earlier acne report (no report.json)",
                target.display()
            );
        }
        let name = target
            .file_name()
            .with_context(|| format!("cannot write {}: not a directory name", target.display()))?;
        let parent = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let temp = parent.join(format!(
            ".{}.{}.tmp",
            name.to_string_lossy(),
            std::process::id()
        ));
        std::fs::create_dir_all(&temp)
            .with_context(|| format!("cannot write {}", target.display()))?;
        Ok(Self {
            target: target.to_path_buf(),
            temp,
        })
    }

    fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        std::fs::write(self.temp.join(name), bytes)
            .with_context(|| format!("cannot write {}", self.target.join(name).display()))
    }

    fn commit(mut self) -> Result<()> {
        let old = self.temp.with_extension("old");
        if self.target.exists() {
            std::fs::rename(&self.target, &old)
                .with_context(|| format!("cannot replace {}", self.target.display()))?;
        }
        std::fs::rename(&self.temp, &self.target)
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        let _ = std::fs::remove_dir_all(&old);
        self.temp = PathBuf::new();
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.temp.as_os_str().is_empty() {
            let _ = std::fs::remove_dir_all(&self.temp);
        }
    }
}

fn is_replaceable(dir: &Path) -> bool {
    dir.join("report.json").is_file()
        || std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_none())
}

/// Run the sweep and write report.md, report.json, heatmap-<strategy>.png and plot.png.
pub fn run(a: &AcneArgs) -> Result<()> {
    let cfg = config(a)?;
    let overrides = Overrides {
        integrator: a.integrator.clone(),
        seed: a.seed,
        ..Overrides::default()
    };
    let loaded = load(a.scene.as_deref(), &overrides)?;
    let out = StagedDir::create(&a.output)?;
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
    out.write("report.md", report.markdown(&name).as_bytes())?;
    out.write(
        "report.json",
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    for &st in &cfg.strategies {
        out.write(
            &format!("heatmap-{}.png", st.name()),
            &heat_map(&report, st)?,
        )?;
    }
    out.write("plot.png", &plot(&report, &name)?)?;
    out.commit()?;
    println!(
        "wrote {} ({total} renders of {}x{}): report.md, report.json, plot.png, heatmap-*.png",
        a.output.display(),
        cfg.width,
        cfg.height
    );
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
        println!("{:>7}: {verdict}", st.name());
    }
    Ok(())
}
