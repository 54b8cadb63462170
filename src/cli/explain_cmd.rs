//! `raytree explain`: a pixel's tree in a few sentences (`raytree::analysis::explain`).

use super::args::ExplainArgs;
use super::load::{load, pair};
use super::say::{out, sayln};
use anyhow::{Result, bail};
use raytree::analysis::explain::{explain, explanation_text};

/// Trace the pixel and print its explanation.
pub fn run(a: &ExplainArgs) -> Result<()> {
    let (x, y) = pair("pixel", &a.pixel, ',')?;
    let mut loaded = load(a.scene.as_deref(), &a.overrides)?;
    let mib = super::budget::mib(a.overrides.max_memory);
    super::budget::fit_tree(&mut loaded.scene, mib)?;
    let cam = &loaded.scene.camera;
    let Some(tree) = super::budget::trace(&loaded.scene, (x, y), mib)? else {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            cam.width,
            cam.height
        );
    };
    let e = explain(&tree, &loaded.scene);
    if a.json {
        let finite = e.radiance.is_finite() && e.shares.iter().all(|s| s.value.is_finite());
        if !finite {
            bail!(
                "pixel {x},{y}: the explanation holds a non-finite value; JSON cannot carry it, so none was written (the text form shows it: drop --json)"
            );
        }
        sayln!("{}", serde_json::to_string_pretty(&e)?)?;
    } else {
        out(&explanation_text(&e))?;
    }
    Ok(())
}
