//! `raytree effects`: the effect plan with a reason for each line.

use super::args::EffectsArgs;
use super::load::load;
use super::say::sayln;
use anyhow::Result;
use raytree::effects::EffectPlan;

/// Print which effects the tracer will run for the scene and why.
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
    Ok(())
}
