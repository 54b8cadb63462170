//! The sweep of `raytree cost`: which values each axis takes, the settings of every row and the
//! reference each row is compared with.

use super::with_settings;
use crate::effects::EffectPlan;
use crate::integrator::SceneIntegrator;
use crate::integrator::bound::auto_min_weight;
use crate::math::FresnelModel;
use crate::render::adaptive_plan;
use crate::scene::{
    AdaptiveDesc, Antialiasing, FilterDesc, IntegratorKind, OffsetStrategy, SamplerKind, Scene,
    Settings, WhittedSettings,
};

/// The sweep: which values each axis takes.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// Max depths.
    pub depths: Vec<u32>,
    /// Fresnel models.
    pub fresnels: Vec<FresnelModel>,
    /// Samples per pixel.
    pub spps: Vec<u32>,
    /// Offset strategies.
    pub offsets: Vec<OffsetStrategy>,
    /// Min weights; `None` is the automatic cut (the default, `crate::integrator::bound`).
    pub min_weights: Vec<Option<f64>>,
    /// Shadow rays per area light (rows only when the scene has an emissive sphere, quad or
    /// triangle to sample and something it lights).
    pub light_samples: Vec<u32>,
    /// Rays per rough lobe (rows only when the scene has a rough material).
    pub glossy_samples: Vec<u32>,
    /// Pixel filters as `--filter` writes them (`box`, `tent:R`, `gaussian:SIGMA`), rendered at
    /// [`Sweep::filter_spp`] samples per pixel.
    pub filters: Vec<String>,
    /// Samples per pixel of the filter rows (one sample sits at the pixel centre whatever the
    /// filter).
    pub filter_spp: u32,
    /// Adaptive antialiasing as `(threshold, max_spp)`, with a first pass of
    /// [`Sweep::adaptive_spp`] samples, against the spp axis's reference: beside the spp rows
    /// (the camera ray count is the samples taken).
    pub adaptive: Vec<(f64, u32)>,
    /// First-pass samples of the adaptive rows.
    pub adaptive_spp: u32,
    /// Depths from which dielectric hits play Russian roulette instead of splitting (rows only
    /// when the scene has a transmissive material), against the exhaustive reference like the
    /// min-weight rows: the roulette's noise beside the automatic cut's bounded error.
    pub dielectric_roulette: Vec<u32>,
    /// Weights below which dielectric hits play Russian roulette (`None`: the automatic weight,
    /// the default), with the automatic cut, against the exhaustive reference (rows only when
    /// the scene has a transmissive material); the min-weight rows are the cut alone.
    pub roulette_below: Vec<Option<f64>>,
    /// Depths from which the path integrator plays Russian roulette (`settings.rr_depth`;
    /// rows only for a path-traced scene, at [`Sweep::filter_spp`] samples against the spp
    /// reference: the roulette saves rays and adds noise, not bias).
    pub rr_depths: Vec<u32>,
    /// Light samples of the light-samples axis's reference.
    pub reference_light_samples: u32,
    /// Glossy samples of the glossy-samples axis's reference.
    pub reference_glossy_samples: u32,
    /// Reference max depth.
    pub reference_depth: u32,
    /// Reference samples per pixel (for the spp axis).
    pub reference_spp: u32,
    /// Timed repeats per setting (median reported).
    pub repeats: u32,
}

/// One row of a sweep, and whether it changes the Whitted integrator's own settings.
struct SweepRow {
    axis: String,
    label: String,
    settings: Settings,
    whitted: bool,
}

/// The rows of a sweep, in the order they are measured.
struct RowList(Vec<SweepRow>);

impl RowList {
    fn push(&mut self, axis: &str, label: String, settings: Settings, whitted: bool) {
        self.0.push(SweepRow {
            axis: axis.to_string(),
            label,
            settings,
            whitted,
        });
    }
}

impl Sweep {
    /// The full sweep of the issue: depth 0..16, every Fresnel model, 1/4/16 spp, every offset
    /// strategy, and min_weight from off to coarse with the automatic cut beside them.
    #[must_use]
    pub fn full() -> Self {
        Self {
            depths: vec![0, 1, 2, 4, 8, 16],
            fresnels: vec![
                FresnelModel::None,
                FresnelModel::Schlick,
                FresnelModel::Exact,
            ],
            spps: vec![1, 4, 16],
            offsets: OffsetStrategy::ALL.to_vec(),
            // 1 / (255 * 12.92): the smallest linear step visible in 8-bit sRGB near black.
            min_weights: vec![
                Some(0.0),
                None,
                Some(3.0e-4),
                Some(1.0e-3),
                Some(1.0e-2),
                Some(5.0e-2),
            ],
            light_samples: vec![1, 4, 16],
            glossy_samples: vec![1, 4, 16],
            filters: vec!["box".into(), "tent:1".into(), "gaussian:0.5".into()],
            filter_spp: 4,
            adaptive: vec![(0.1, 16), (0.05, 32), (0.02, 64)],
            adaptive_spp: 2,
            dielectric_roulette: vec![0, 2, 4],
            roulette_below: vec![None, Some(1.0e-3), Some(1.0e-2), Some(1.0e-1)],
            rr_depths: vec![1, 2, 5, 10, 16],
            reference_depth: 32,
            reference_spp: 64,
            reference_light_samples: 1024,
            reference_glossy_samples: 256,
            repeats: 5,
        }
    }

    /// A small sweep for a quick look.
    #[must_use]
    pub fn quick() -> Self {
        Self {
            depths: vec![0, 1, 4, 16],
            spps: vec![1, 4],
            min_weights: vec![Some(0.0), None, Some(1.0e-2)],
            light_samples: vec![1, 4],
            glossy_samples: vec![1, 4],
            filters: vec!["box".into(), "gaussian:0.5".into()],
            adaptive: vec![(0.1, 16)],
            dielectric_roulette: vec![2],
            roulette_below: vec![None],
            rr_depths: vec![2, 5, 16],
            reference_spp: 16,
            reference_light_samples: 256,
            reference_glossy_samples: 64,
            repeats: 3,
            ..Self::full()
        }
    }

    /// The settings of every row, as `(axis, value label, settings)`, from `base`. The
    /// automatic min_weight row is labelled `auto (w)` with the cut it takes on `scene`.
    ///
    /// Under the path integrator the axes of the Whitted integrator's own settings
    /// ([`crate::scene::WhittedSettings`]) are left out (their rows would all equal the base), and the Russian-roulette depth and the
    /// sampler are swept (at [`Sweep::filter_spp`] samples, against the spp reference).
    #[must_use]
    pub fn settings(&self, scene: &Scene, base: &Settings) -> Vec<(String, String, Settings)> {
        let path = base.integrator == IntegratorKind::Path;
        let mut rows: Vec<(String, String, Settings)> = self
            .rows(scene, base)
            .into_iter()
            .filter(|r| !(path && r.whitted))
            .map(|r| (r.axis, r.label, r.settings))
            .collect();
        if path {
            for &d in &self.rr_depths {
                let mut s = Settings {
                    spp: self.filter_spp,
                    ..*base
                };
                s.path.rr_depth = d;
                let label = if d >= base.max_depth {
                    format!("off ({d} >= max depth)")
                } else {
                    format!("from bounce {d}")
                };
                rows.push(("rr_depth".to_string(), label, s));
            }
            // The sampler: stratified jitter against Owen-scrambled Sobol (the default).
            for kind in SamplerKind::ALL {
                let s = Settings {
                    sampler: Some(kind),
                    spp: self.filter_spp,
                    ..*base
                };
                rows.push(("sampler".to_string(), kind.name().to_string(), s));
            }
        }
        rows
    }

    /// Every row of the Whitted sweep.
    fn rows(&self, scene: &Scene, base: &Settings) -> Vec<SweepRow> {
        let mut out = RowList(Vec::new());
        self.image_rows(scene, base, &mut out);
        self.light_rows(scene, base, &mut out);
        self.roulette_rows(scene, base, &mut out);
        self.sampling_rows(base, &mut out);
        out.0
    }

    /// The rows of depth, Fresnel, samples per pixel, automatic antialiasing, offset strategy
    /// and minimum weight.
    fn image_rows(&self, scene: &Scene, base: &Settings, out: &mut RowList) {
        for &d in &self.depths {
            out.push(
                "max_depth",
                d.to_string(),
                Settings {
                    max_depth: d,
                    ..*base
                },
                false,
            );
        }
        for &f in &self.fresnels {
            out.push(
                "fresnel",
                format!("{f:?}").to_lowercase(),
                Settings {
                    whitted: WhittedSettings {
                        fresnel: f,
                        ..base.whitted
                    },
                    ..*base
                },
                true,
            );
        }
        for &n in &self.spps {
            out.push("spp", n.to_string(), Settings { spp: n, ..*base }, false);
        }
        // Automatic antialiasing beside each uniform spp row, where the scene allows it.
        for &n in &self.spps {
            let s = Settings {
                spp: n,
                antialiasing: Antialiasing::Auto,
                ..*base
            };
            let scene = with_settings(scene, s);
            if adaptive_plan(&SceneIntegrator::new(&scene)).is_some_and(|p| p.auto) {
                out.push("antialiasing", format!("auto {n} spp"), s, false);
            }
        }
        for &o in &self.offsets {
            let mut s = *base;
            s.offset.strategy = o;
            out.push("offset", o.name().to_string(), s, false);
        }
        for &w in &self.min_weights {
            // The cut alone: no roulette below a weight (an explicit min_weight has none).
            let s = Settings {
                whitted: WhittedSettings {
                    min_weight: w,
                    roulette_below: Some(0.0),
                    ..base.whitted
                },
                ..*base
            };
            let label = match w {
                Some(w) => format!("{w:e}"),
                None => format!("auto ({:.1e})", auto_min_weight(scene, &s)),
            };
            out.push("min_weight", label, s, true);
        }
    }

    /// The rows of light samples (where the scene has area lights) and glossy samples (where
    /// it has rough lobes).
    fn light_rows(&self, scene: &Scene, base: &Settings, out: &mut RowList) {
        let plan = |s: Settings| EffectPlan::for_scene(&with_settings(scene, s));
        let area = plan(Settings {
            whitted: WhittedSettings {
                light_samples: Some(1),
                ..base.whitted
            },
            ..*base
        })
        .area_lights;
        for &n in self.light_samples.iter().filter(|_| area) {
            let s = Settings {
                whitted: WhittedSettings {
                    light_samples: Some(n),
                    ..base.whitted
                },
                ..*base
            };
            out.push("light_samples", n.to_string(), s, true);
        }
        let glossy = plan(*base).glossy;
        for &n in self.glossy_samples.iter().filter(|_| glossy) {
            let s = Settings {
                whitted: WhittedSettings {
                    glossy_samples: n,
                    ..base.whitted
                },
                ..*base
            };
            out.push("glossy_samples", n.to_string(), s, true);
        }
    }

    /// The rows of glass roulette by depth and by weight, where the scene has glass.
    fn roulette_rows(&self, scene: &Scene, base: &Settings, out: &mut RowList) {
        let glass = scene.materials.iter().any(|m| m.is_transmissive());
        for &d in self.dielectric_roulette.iter().filter(|_| glass) {
            let s = Settings {
                whitted: WhittedSettings {
                    dielectric_roulette: Some(d),
                    ..base.whitted
                },
                ..*base
            };
            out.push("dielectric_roulette", format!("from depth {d}"), s, true);
        }
        for &w in self.roulette_below.iter().filter(|_| glass) {
            // `None` is the weight suggested for the scene (opt-in: the default is off, which
            // the min_weight axis's automatic row measures).
            let mut s = Settings {
                whitted: WhittedSettings {
                    min_weight: None,
                    roulette_below: w,
                    ..base.whitted
                },
                ..*base
            };
            let label = match w {
                Some(w) => format!("{w:e}"),
                None => {
                    let auto = crate::integrator::bound::carried::auto_roulette_below(scene, &s);
                    s.whitted.roulette_below = Some(auto);
                    format!("suggested ({auto:.1e})")
                }
            };
            out.push("roulette_below", label, s, true);
        }
    }

    /// The rows of adaptive sampling and of the pixel filters.
    fn sampling_rows(&self, base: &Settings, out: &mut RowList) {
        for &(threshold, max_spp) in &self.adaptive {
            let s = Settings {
                spp: self.adaptive_spp.max(2),
                adaptive: Some(AdaptiveDesc {
                    threshold,
                    max_spp: Some(max_spp.max(self.adaptive_spp)),
                }),
                ..*base
            };
            out.push(
                "adaptive",
                format!("{threshold} to {max_spp} spp"),
                s,
                false,
            );
        }
        for f in &self.filters {
            // The sweep's own strings; a bad one is a programming error, skipped.
            if let Ok(filter) = FilterDesc::parse(f) {
                let s = Settings {
                    filter,
                    spp: self.filter_spp,
                    ..*base
                };
                out.push("filter", f.clone(), s, false);
            }
        }
    }

    /// The reference a row of `axis` with `settings` is compared with: `reference_settings`
    /// (one sample at each pixel centre), except for the stochastic axes: `spp` against
    /// `reference_spp` samples, `light_samples` against `reference_light_samples` light
    /// samples, `glossy_samples` against `reference_glossy_samples` glossy samples, and
    /// `filter` against the same filter at `reference_spp` samples; `adaptive` and
    /// `antialiasing` (automatic), and the path integrator's `rr_depth` and `sampler`, like `spp`.
    /// The base, and so every reference, is uniform.
    #[must_use]
    pub fn reference_for(&self, axis: &str, settings: &Settings, reference: &Settings) -> Settings {
        let r = *reference;
        match axis {
            "spp" | "adaptive" | "antialiasing" | "rr_depth" | "sampler" => Settings {
                spp: self.reference_spp,
                ..r
            },
            "light_samples" => Settings {
                whitted: WhittedSettings {
                    light_samples: Some(self.reference_light_samples),
                    ..r.whitted
                },
                ..r
            },
            "glossy_samples" => Settings {
                whitted: WhittedSettings {
                    glossy_samples: self.reference_glossy_samples,
                    ..r.whitted
                },
                ..r
            },
            "filter" => Settings {
                spp: self.reference_spp,
                filter: settings.filter,
                ..r
            },
            _ => r,
        }
    }
}
