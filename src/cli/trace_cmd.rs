//! `raytree trace`.

use super::args::TraceArgs;
use super::load::{load, pair};
use super::say::{out, warnln};
use anyhow::{Result, bail};

/// Print the ray tree of one pixel as text or JSON.
pub fn run(a: &TraceArgs) -> Result<()> {
    let (x, y) = pair("pixel", &a.pixel, ',')?;
    let lpes = parse_lpes(&a.lpe)?;
    let mut loaded = load(a.scene.as_deref(), &a.overrides)?;
    let mib = super::budget::mib(a.overrides.max_memory);
    let lowered = super::budget::fit_tree(&mut loaded.scene, mib)?;
    let cam = &loaded.scene.camera;
    let Some(tree) = super::budget::trace(&loaded.scene, (x, y), mib)? else {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            cam.width,
            cam.height
        );
    };
    let (tree, header, summary) = filter_lpe(tree, &a.lpe, &lpes)?;
    let cut = super::budget::cut_samples(&tree);
    if cut > 0 {
        let why = match lowered {
            Some(_) => " (lowered to fit --max-memory)",
            None => "",
        };
        warnln!(
            "warning: {cut} of {} samples reached the ray budget of {} rays per sample{why}; their trees are cut (end: ray budget, with the weight cut)",
            tree.samples.len(),
            loaded.scene.settings.max_rays
        );
    }
    if a.json {
        // serde_json would write NaN and infinities as null, indistinguishable from "absent".
        if let Some(at) = raytree::finite::first_nonfinite(&tree) {
            bail!(
                "pixel {x},{y}: the tree holds a non-finite number at {at}; JSON cannot carry it, so none was written (the text form shows it: drop --json)"
            );
        }
        /// The tree with, beside its own fields (readers of the schema ignore it), what the
        /// LPE filter matched.
        #[derive(serde::Serialize)]
        struct Filtered<'a> {
            #[serde(flatten)]
            tree: &'a raytree::RayTree,
            #[serde(skip_serializing_if = "Option::is_none")]
            lpe_filter: Option<serde_json::Value>,
        }
        super::say::json(&Filtered {
            tree: &tree,
            lpe_filter: summary,
        })?;
    } else {
        out(&format!("{header}{}", raytree::text::tree_text(&tree)))?;
    }
    Ok(())
}

/// Parse the `--lpe` expressions (before anything is traced or written).
pub(super) fn parse_lpes(exprs: &[String]) -> Result<Vec<raytree::lpe::Lpe>> {
    exprs.iter().map(|e| parse_lpe(e)).collect()
}

/// Keep the paths of `tree` that match any of `lpes` (written as `exprs`), with a one-line
/// header saying how many matched and their share of the pixel, and the same as a JSON object
/// (`expressions`, `matched`, `paths`, `share`, `radiance`); `tree` itself, no header and no
/// object without expressions.
pub(super) fn filter_lpe(
    tree: raytree::RayTree,
    exprs: &[String],
    lpes: &[raytree::lpe::Lpe],
) -> Result<(raytree::RayTree, String, Option<serde_json::Value>)> {
    if lpes.is_empty() {
        return Ok((tree, String::new(), None));
    }
    let Some(f) = raytree::lpe::filter_tree(&tree, lpes) else {
        bail!(
            "--lpe needs the path integrator's records (each node's light path), and this pixel was traced by Whitted: add --integrator path"
        );
    };
    let header = format!(
        "lpe {}: {}
",
        exprs.join(" | "),
        f.summary()
    );
    let summary = serde_json::json!({
        "expressions": exprs,
        "matched": f.matched,
        "paths": f.paths,
        "share": f.share,
        "radiance": f.radiance,
    });
    Ok((f.tree, header, Some(summary)))
}

/// Parse one `--lpe` expression; an error shows the expression with a caret under the column.
fn parse_lpe(expr: &str) -> Result<raytree::lpe::Lpe> {
    raytree::lpe::Lpe::parse(expr).map_err(|e| {
        let (shown, caret) = raytree::input::excerpt(expr, e.column);
        anyhow::anyhow!(
            "--lpe: {}\n  {shown}\n  {}^",
            raytree::input::escape_controls(&e.to_string()),
            " ".repeat(caret)
        )
    })
}
