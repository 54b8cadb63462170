//! The settings in force as one flat record: how a ray tree (`raytree.tree/2`) and a report
//! write them, every integrator's settings beside the others, so that a tree says everything
//! that was traced with and `raytree diff` compares settings key by key. A scene file spells
//! them by integrator instead (`spelling.rs`).

use super::antialias::{AdaptiveDesc, Antialiasing};
use super::integrator::{
    DEFAULT_RR_DEPTH, IntegratorKind, MisHeuristic, PathSettings, ShadowMode, WhittedSettings,
};
use super::settings::{FilterDesc, OffsetDesc, SamplerKind, Settings};
use crate::math::FresnelModel;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// [`Settings`] flat: the layout of a tree's `settings` since schema `raytree.tree/2`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(missing_docs)] // the fields of Settings, WhittedSettings and PathSettings, documented there
pub struct SettingsRecord {
    pub integrator: IntegratorKind,
    pub seed: u64,
    pub max_depth: u32,
    pub spp: u32,
    #[serde(skip_serializing_if = "FilterDesc::is_box")]
    pub filter: FilterDesc,
    pub offset: OffsetDesc,
    pub fresnel: FresnelModel,
    pub shadows: ShadowMode,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_weight: Option<f64>,
    pub tolerance: f64,
    pub max_rays: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_samples: Option<u32>,
    #[serde(skip_serializing_if = "is_default_rr_depth")]
    pub rr_depth: u32,
    #[serde(skip_serializing_if = "is_one")]
    pub glossy_samples: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampler: Option<SamplerKind>,
    #[serde(skip_serializing_if = "Antialiasing::is_auto")]
    pub antialiasing: Antialiasing,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<AdaptiveDesc>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dielectric_roulette: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roulette_below: Option<f64>,
    #[serde(skip_serializing_if = "is_balance")]
    pub mis: MisHeuristic,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_default_rr_depth(v: &u32) -> bool {
    *v == DEFAULT_RR_DEPTH
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_one(v: &u32) -> bool {
    *v == 1
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_balance(v: &MisHeuristic) -> bool {
    *v == MisHeuristic::Balance
}

impl Default for SettingsRecord {
    fn default() -> Self {
        Self::from(&Settings::default())
    }
}

impl From<&Settings> for SettingsRecord {
    fn from(s: &Settings) -> Self {
        let (w, p) = (&s.whitted, &s.path);
        Self {
            integrator: s.integrator,
            seed: s.seed,
            max_depth: s.max_depth,
            spp: s.spp,
            filter: s.filter,
            offset: s.offset,
            fresnel: w.fresnel,
            shadows: w.shadows,
            min_weight: w.min_weight,
            tolerance: w.tolerance,
            max_rays: s.max_rays,
            light_samples: w.light_samples,
            rr_depth: p.rr_depth,
            glossy_samples: w.glossy_samples,
            sampler: s.sampler,
            antialiasing: s.antialiasing,
            adaptive: s.adaptive,
            dielectric_roulette: w.dielectric_roulette,
            roulette_below: w.roulette_below,
            mis: p.mis,
        }
    }
}

impl From<SettingsRecord> for Settings {
    fn from(r: SettingsRecord) -> Self {
        Self {
            integrator: r.integrator,
            whitted: WhittedSettings {
                fresnel: r.fresnel,
                shadows: r.shadows,
                min_weight: r.min_weight,
                tolerance: r.tolerance,
                light_samples: r.light_samples,
                glossy_samples: r.glossy_samples,
                dielectric_roulette: r.dielectric_roulette,
                roulette_below: r.roulette_below,
            },
            path: PathSettings {
                rr_depth: r.rr_depth,
                mis: r.mis,
            },
            seed: r.seed,
            max_depth: r.max_depth,
            spp: r.spp,
            filter: r.filter,
            offset: r.offset,
            max_rays: r.max_rays,
            sampler: r.sampler,
            antialiasing: r.antialiasing,
            adaptive: r.adaptive,
        }
    }
}

/// `#[serde(with = "crate::scene::desc::flat_settings")]` on a [`Settings`] field: written
/// and read as a [`SettingsRecord`].
pub mod flat_settings {
    use super::{Deserialize, Deserializer, Serialize, Serializer, Settings, SettingsRecord};

    /// Write `s` flat.
    ///
    /// # Errors
    /// The serializer's.
    pub fn serialize<S: Serializer>(s: &Settings, ser: S) -> Result<S::Ok, S::Error> {
        SettingsRecord::from(s).serialize(ser)
    }

    /// Read flat settings.
    ///
    /// # Errors
    /// The deserializer's.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Settings, D::Error> {
        SettingsRecord::deserialize(d).map(Settings::from)
    }
}
