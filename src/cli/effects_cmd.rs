//! `raytree effects`: the effect plan with a reason for each line, how the ray tree grows with
//! max depth, and what the automatic cut saves on a 16x9 sample of pixels.

use super::args::EffectsArgs;
use super::load::load;
use super::say::sayln;
use anyhow::Result;
use raytree::analysis::growth::{Growth, cut_savings, path_note, tree_growth};
use raytree::effects::EffectPlan;

/// Print which effects the tracer will run for the scene and why, then the tree's growth.
pub fn run(a: &EffectsArgs) -> Result<()> {
    let loaded = load(a.scene.as_deref(), &a.overrides)?;
    let plan = EffectPlan::for_scene(&loaded.scene);
    sayln!("effects for {}:", loaded.label)?;
    for l in plan.explain(&loaded.scene) {
        sayln!(
            "  [{}] {:<26} {}",
            if l.on { "on " } else { "off" },
            l.effect,
            l.reason
        )?;
    }
    if !loaded.notes.is_empty() {
        sayln!("converted from another format; approximated:")?;
        for n in &loaded.notes {
            sayln!("  - {}", raytree::input::escape_controls(&n.to_string()))?;
        }
    }
    if let Some(old) = &loaded.old_spelling {
        sayln!("settings written in the old spelling (still read): {old}")?;
    }
    let growth = tree_growth(&loaded.scene);
    // Under the path integrator the tree and the cut are Whitted's: said first, then labelled.
    let whitted = match path_note(&loaded.scene) {
        Some(note) => {
            sayln!("rays per sample: {note}")?;
            " (whitted)"
        }
        None => "",
    };
    sayln!("ray tree{whitted}: {}", growth.summary())?;
    for r in &growth.reasons {
        sayln!("  - {r}")?;
    }
    if growth.growth != Growth::Bounded
        && let Some(s) = cut_savings(&loaded.scene, 16, 9, &|| false)
    {
        sayln!("what the cut saves{whitted}: {}", s.sentence())?;
    }
    Ok(())
}
