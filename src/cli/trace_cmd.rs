//! `raytree trace`.

use super::args::TraceArgs;
use super::load::{load, pair};
use super::say::{out, sayln};
use anyhow::{Result, bail};

/// Print the ray tree of one pixel as text or JSON.
pub fn run(a: &TraceArgs) -> Result<()> {
    let (x, y) = pair("pixel", &a.pixel, ',')?;
    let loaded = load(a.scene.as_deref(), &a.overrides)?;
    let cam = &loaded.scene.camera;
    let Some(tree) = raytree::trace_pixel(&loaded.scene, x, y) else {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            cam.width,
            cam.height
        );
    };
    if a.json {
        // serde_json would write NaN and infinities as null, indistinguishable from "absent".
        if let Some(at) = super::finite::first_nonfinite(&tree) {
            bail!(
                "pixel {x},{y}: the tree holds a non-finite number at {at}; JSON cannot carry it, so none was written (the text form shows it: drop --json)"
            );
        }
        sayln!("{}", serde_json::to_string_pretty(&tree)?)?;
    } else {
        out(&raytree::text::tree_text(&tree))?;
    }
    Ok(())
}
