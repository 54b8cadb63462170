//! How [`Settings`] are written in the scene JSON, and read back.
//!
//! The integrator's own settings are a tagged value:
//!
//! ```json
//! "settings": {
//!   "integrator": {"type": "whitted", "fresnel": "schlick", "light_samples": 4},
//!   "other_integrators": [{"type": "path", "rr_depth": 8}],
//!   "spp": 4
//! }
//! ```
//!
//! Each type takes only the keys its integrator reads (`{"type": "path", "fresnel": ...}` is
//! refused). `other_integrators` holds the settings of integrators other than the chosen one,
//! for a command that switches to one of them (`--integrator`, `raytree versus`, the
//! inspector's menu). The old spelling, `"integrator": "path"` with the integrators' keys
//! beside the others (`"rr_depth": 8`), is still read ([`old_spelling`] names its keys); a key
//! given in both spellings, or twice, is refused. `path`, `light` and `bdpt` share `rr_depth`
//! (and `mis`, which `bdpt` alone reads).

use super::antialias::{AdaptiveDesc, Antialiasing};
use super::integrator::{
    DEFAULT_RR_DEPTH, IntegratorKind, MisHeuristic, ShadowMode, WhittedSettings,
};
use super::settings::{FilterDesc, OffsetDesc, SamplerKind, Settings};
use crate::math::FresnelModel;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// One integrator's settings as written: `{"type": ..., keys}`. Absent keys are `None`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum IntegratorDesc {
    /// The Whitted integrator's keys.
    Whitted(WhittedDesc),
    /// The path tracer's keys.
    Path(RouletteDesc),
    /// Light tracing's keys.
    Light(RouletteDesc),
    /// Bidirectional path tracing's keys.
    Bdpt(BdptDesc),
}

/// [`WhittedSettings`] as written (every key optional).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)] // the fields of WhittedSettings, documented there
pub struct WhittedDesc {
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub fresnel: Option<FresnelModel>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub shadows: Option<ShadowMode>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub min_weight: Option<Option<f64>>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub tolerance: Option<f64>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub light_samples: Option<Option<u32>>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub glossy_samples: Option<u32>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub dielectric_roulette: Option<Option<u32>>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub roulette_below: Option<Option<f64>>,
}

/// The path tracer's and light tracing's keys as written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RouletteDesc {
    /// [`crate::scene::PathSettings::rr_depth`].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub rr_depth: Option<u32>,
}

/// Bidirectional path tracing's keys as written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BdptDesc {
    /// [`crate::scene::PathSettings::rr_depth`].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub rr_depth: Option<u32>,
    /// [`crate::scene::PathSettings::mis`].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some"
    )]
    pub mis: Option<MisHeuristic>,
}

/// A present key: its value (so that `null` is refused where the setting is not optional, and
/// is `Some(None)`, the setting's "absent", where it is).
fn some<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

impl IntegratorDesc {
    /// The integrator these keys are for.
    #[must_use]
    pub fn kind(&self) -> IntegratorKind {
        match self {
            IntegratorDesc::Whitted(_) => IntegratorKind::Whitted,
            IntegratorDesc::Path(_) => IntegratorKind::Path,
            IntegratorDesc::Light(_) => IntegratorKind::Light,
            IntegratorDesc::Bdpt(_) => IntegratorKind::Bdpt,
        }
    }

    /// Its keys as a [`WhittedDesc`] and a [`BdptDesc`] (the Monte Carlo integrators' keys
    /// are a subset of bdpt's).
    fn parts(&self) -> (WhittedDesc, BdptDesc) {
        match *self {
            IntegratorDesc::Whitted(w) => (w, BdptDesc::default()),
            IntegratorDesc::Path(r) | IntegratorDesc::Light(r) => (
                WhittedDesc::default(),
                BdptDesc {
                    rr_depth: r.rr_depth,
                    mis: None,
                },
            ),
            IntegratorDesc::Bdpt(b) => (WhittedDesc::default(), b),
        }
    }

    /// `kind`'s keys: every one that differs from its default, or with `all`, what the
    /// Whitted integrator's and bdpt's scene files have always written (`fresnel`, `shadows`,
    /// `tolerance`; the rest when set). The Whitted keys of another kind are dropped.
    fn of(kind: IntegratorKind, s: &Settings, all: bool) -> Self {
        let (w, p) = (&s.whitted, &s.path);
        let d = WhittedSettings::default();
        let keep = |differs: bool| all || differs;
        let rr_depth = (p.rr_depth != DEFAULT_RR_DEPTH).then_some(p.rr_depth);
        match kind {
            IntegratorKind::Whitted => IntegratorDesc::Whitted(WhittedDesc {
                fresnel: keep(w.fresnel != d.fresnel).then_some(w.fresnel),
                shadows: keep(w.shadows != d.shadows).then_some(w.shadows),
                min_weight: w.min_weight.map(Some),
                tolerance: keep(w.tolerance != d.tolerance).then_some(w.tolerance),
                light_samples: w.light_samples.map(Some),
                glossy_samples: (w.glossy_samples != 1).then_some(w.glossy_samples),
                dielectric_roulette: w.dielectric_roulette.map(Some),
                roulette_below: w.roulette_below.map(Some),
            }),
            IntegratorKind::Path => IntegratorDesc::Path(RouletteDesc { rr_depth }),
            IntegratorKind::Light => IntegratorDesc::Light(RouletteDesc { rr_depth }),
            IntegratorKind::Bdpt => IntegratorDesc::Bdpt(BdptDesc {
                rr_depth,
                mis: (p.mis != MisHeuristic::Balance).then_some(p.mis),
            }),
        }
    }

    /// Whether no key is given.
    fn is_empty(&self) -> bool {
        let (w, b) = self.parts();
        w == WhittedDesc::default() && b == BdptDesc::default()
    }
}

/// `settings.integrator`: a name (the old spelling) or the tagged value.
#[derive(Clone, Copy, Debug, PartialEq)]
enum IntegratorSpelling {
    Name(IntegratorKind),
    Tagged(IntegratorDesc),
}

impl<'de> Deserialize<'de> for IntegratorSpelling {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = IntegratorSpelling;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "an integrator: {\"type\": \"whitted\" | \"path\" | \"light\" | \"bdpt\", ...its settings} (or its name alone)",
                )
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
                IntegratorKind::from_name(v)
                    .map(IntegratorSpelling::Name)
                    .map_err(E::custom)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                m: A,
            ) -> Result<Self::Value, A::Error> {
                use serde::de::Error;
                let value = serde_json::Map::<String, serde_json::Value>::deserialize(
                    serde::de::value::MapAccessDeserializer::new(m),
                )?;
                tagged(value)
                    .map(IntegratorSpelling::Tagged)
                    .map_err(A::Error::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// The tagged value `{"type": ..., keys}`: read by hand rather than as serde's internally
/// tagged enum, which buffers the keys and loses their path, so that an error names its key
/// (`glossy_samples: invalid value: integer -2, expected u32`).
fn tagged(mut keys: serde_json::Map<String, serde_json::Value>) -> Result<IntegratorDesc, String> {
    let kind = match keys.remove("type") {
        Some(serde_json::Value::String(name)) => IntegratorKind::from_name(&name)?,
        Some(other) => return Err(format!("type: expected an integrator's name, got {other}")),
        None => return Err(
            "missing field `type` (the integrator: \"whitted\", \"path\", \"light\" or \"bdpt\")"
                .into(),
        ),
    };
    fn part<T: serde::de::DeserializeOwned>(
        keys: serde_json::Map<String, serde_json::Value>,
    ) -> Result<T, String> {
        serde_path_to_error::deserialize(serde_json::Value::Object(keys)).map_err(|e| {
            let path = e.path().to_string();
            let message = e.into_inner().to_string();
            // An unknown key names itself; any other error is prefixed with its key.
            if path == "." || message.starts_with("unknown field") {
                message
            } else {
                format!("{path}: {message}")
            }
        })
    }
    Ok(match kind {
        IntegratorKind::Whitted => IntegratorDesc::Whitted(part(keys)?),
        IntegratorKind::Path => IntegratorDesc::Path(part(keys)?),
        IntegratorKind::Light => IntegratorDesc::Light(part(keys)?),
        IntegratorKind::Bdpt => IntegratorDesc::Bdpt(part(keys)?),
    })
}

/// The settings block as written, in either spelling.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SettingsIn {
    #[serde(default, deserialize_with = "some")]
    integrator: Option<IntegratorSpelling>,
    #[serde(default, deserialize_with = "some")]
    other_integrators: Option<Vec<IntegratorDesc>>,
    #[serde(default, deserialize_with = "some")]
    seed: Option<u64>,
    #[serde(default, deserialize_with = "some")]
    max_depth: Option<u32>,
    #[serde(default, deserialize_with = "some")]
    spp: Option<u32>,
    #[serde(default, deserialize_with = "some")]
    filter: Option<FilterDesc>,
    #[serde(default, deserialize_with = "some")]
    offset: Option<OffsetDesc>,
    #[serde(default, deserialize_with = "some")]
    max_rays: Option<u64>,
    #[serde(default)]
    sampler: Option<SamplerKind>,
    #[serde(default, deserialize_with = "some")]
    antialiasing: Option<Antialiasing>,
    #[serde(default)]
    adaptive: Option<AdaptiveDesc>,
    // The integrators' keys in the old spelling, beside the others.
    #[serde(default, deserialize_with = "some")]
    fresnel: Option<FresnelModel>,
    #[serde(default, deserialize_with = "some")]
    shadows: Option<ShadowMode>,
    #[serde(default, deserialize_with = "some")]
    min_weight: Option<Option<f64>>,
    #[serde(default, deserialize_with = "some")]
    tolerance: Option<f64>,
    #[serde(default, deserialize_with = "some")]
    light_samples: Option<Option<u32>>,
    #[serde(default, deserialize_with = "some")]
    glossy_samples: Option<u32>,
    #[serde(default, deserialize_with = "some")]
    dielectric_roulette: Option<Option<u32>>,
    #[serde(default, deserialize_with = "some")]
    roulette_below: Option<Option<f64>>,
    #[serde(default, deserialize_with = "some")]
    rr_depth: Option<u32>,
    #[serde(default, deserialize_with = "some")]
    mis: Option<MisHeuristic>,
}

impl<'de> Deserialize<'de> for Settings {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        SettingsIn::deserialize(d)?
            .into_settings()
            .map_err(serde::de::Error::custom)
    }
}

/// The integrators' keys given in one place (`settings` in the old spelling,
/// `settings.integrator`, or an element of `settings.other_integrators`).
struct KeySource {
    place: String,
    whitted: WhittedDesc,
    path: BdptDesc,
}

/// Takes `field` from `$from` into `$into`, refusing a key given twice.
macro_rules! take {
    ($into:expr, $from:expr, $place:expr, $places:expr, $($field:ident),+) => {$(
        if $from.$field.is_some() {
            if let Some(first) = $places.iter().find(|(k, _)| *k == stringify!($field)) {
                return Err(format!(
                    "{} is given twice: in {} and in {} (keep one)",
                    stringify!($field), first.1, $place
                ));
            }
            $places.push((stringify!($field), $place.clone()));
            $into.$field = $from.$field;
        }
    )+};
}

impl SettingsIn {
    /// The settings these keys spell, or why they spell none.
    fn into_settings(self) -> Result<Settings, String> {
        let d = Settings::default();
        let mut s = Settings {
            seed: self.seed.unwrap_or(d.seed),
            max_depth: self.max_depth.unwrap_or(d.max_depth),
            spp: self.spp.unwrap_or(d.spp),
            filter: self.filter.unwrap_or(d.filter),
            offset: self.offset.unwrap_or(d.offset),
            max_rays: self.max_rays.unwrap_or(d.max_rays),
            sampler: self.sampler,
            antialiasing: self.antialiasing.unwrap_or(d.antialiasing),
            adaptive: self.adaptive,
            ..d
        };
        let sources = self.key_sources(&mut s.integrator)?;
        let (mut w, mut p) = (WhittedDesc::default(), BdptDesc::default());
        let mut places: Vec<(&str, String)> = Vec::new();
        for src in &sources {
            let (from_w, from_p, place) = (&src.whitted, &src.path, &src.place);
            take!(
                w, from_w, place, places, fresnel, shadows, min_weight, tolerance
            );
            take!(w, from_w, place, places, light_samples, glossy_samples);
            take!(
                w,
                from_w,
                place,
                places,
                dielectric_roulette,
                roulette_below
            );
            take!(p, from_p, place, places, rr_depth, mis);
        }
        s.whitted = w.over(s.whitted);
        s.path.rr_depth = p.rr_depth.unwrap_or(s.path.rr_depth);
        s.path.mis = p.mis.unwrap_or(s.path.mis);
        Ok(s)
    }

    /// Where the integrators' keys are given, in the order they are read; sets `integrator`
    /// to the one in force.
    fn key_sources(&self, integrator: &mut IntegratorKind) -> Result<Vec<KeySource>, String> {
        let mut out = vec![KeySource {
            place: "settings (the old spelling)".into(),
            whitted: WhittedDesc {
                fresnel: self.fresnel,
                shadows: self.shadows,
                min_weight: self.min_weight,
                tolerance: self.tolerance,
                light_samples: self.light_samples,
                glossy_samples: self.glossy_samples,
                dielectric_roulette: self.dielectric_roulette,
                roulette_below: self.roulette_below,
            },
            path: BdptDesc {
                rr_depth: self.rr_depth,
                mis: self.mis,
            },
        }];
        match self.integrator {
            Some(IntegratorSpelling::Name(k)) => *integrator = k,
            Some(IntegratorSpelling::Tagged(desc)) => {
                *integrator = desc.kind();
                let (whitted, path) = desc.parts();
                out.push(KeySource {
                    place: "settings.integrator".into(),
                    whitted,
                    path,
                });
            }
            None => {}
        }
        for (i, desc) in self.other_integrators.iter().flatten().enumerate() {
            let name = desc.kind().name();
            if desc.kind() == *integrator {
                return Err(format!(
                    "other_integrators[{i}]: \"{name}\" is the integrator in force: its settings go in settings.integrator"
                ));
            }
            if let Some(j) = self
                .other_integrators
                .iter()
                .flatten()
                .take(i)
                .position(|o| o.kind() == desc.kind())
            {
                return Err(format!(
                    "other_integrators[{i}]: \"{name}\" is given twice (also other_integrators[{j}])"
                ));
            }
            let (whitted, path) = desc.parts();
            out.push(KeySource {
                place: format!("settings.other_integrators[{i}]"),
                whitted,
                path,
            });
        }
        Ok(out)
    }
}

impl WhittedDesc {
    /// `base` with the keys given here.
    fn over(self, base: WhittedSettings) -> WhittedSettings {
        WhittedSettings {
            fresnel: self.fresnel.unwrap_or(base.fresnel),
            shadows: self.shadows.unwrap_or(base.shadows),
            min_weight: self.min_weight.unwrap_or(base.min_weight),
            tolerance: self.tolerance.unwrap_or(base.tolerance),
            light_samples: self.light_samples.unwrap_or(base.light_samples),
            glossy_samples: self.glossy_samples.unwrap_or(base.glossy_samples),
            dielectric_roulette: self.dielectric_roulette.unwrap_or(base.dielectric_roulette),
            roulette_below: self.roulette_below.unwrap_or(base.roulette_below),
        }
    }
}

/// The settings block as written (the new spelling).
#[derive(Serialize)]
struct SettingsOut {
    integrator: IntegratorDesc,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    other_integrators: Vec<IntegratorDesc>,
    seed: u64,
    max_depth: u32,
    spp: u32,
    #[serde(skip_serializing_if = "FilterDesc::is_box")]
    filter: FilterDesc,
    offset: OffsetDesc,
    max_rays: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    sampler: Option<SamplerKind>,
    #[serde(skip_serializing_if = "Antialiasing::is_auto")]
    antialiasing: Antialiasing,
    #[serde(skip_serializing_if = "Option::is_none")]
    adaptive: Option<AdaptiveDesc>,
}

impl Serialize for Settings {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        SettingsOut {
            integrator: IntegratorDesc::of(self.integrator, self, true),
            other_integrators: other_integrators(self),
            seed: self.seed,
            max_depth: self.max_depth,
            spp: self.spp,
            filter: self.filter,
            offset: self.offset,
            max_rays: self.max_rays,
            sampler: self.sampler,
            antialiasing: self.antialiasing,
            adaptive: self.adaptive,
        }
        .serialize(ser)
    }
}

/// The settings of the integrators not in force that differ from their defaults, as
/// `settings.other_integrators` (each key once: what the integrator in force writes is left
/// out).
fn other_integrators(s: &Settings) -> Vec<IntegratorDesc> {
    let mut out = Vec::new();
    let whitted = IntegratorDesc::of(IntegratorKind::Whitted, s, false);
    if s.integrator != IntegratorKind::Whitted && !whitted.is_empty() {
        out.push(whitted);
    }
    let bdpt = IntegratorDesc::of(IntegratorKind::Bdpt, s, false);
    let monte_carlo = match (s.integrator, bdpt) {
        (IntegratorKind::Bdpt, _) => None,
        // rr_depth is the chosen one's: bdpt's entry keeps mis alone.
        (IntegratorKind::Path | IntegratorKind::Light, IntegratorDesc::Bdpt(b)) => {
            Some(IntegratorDesc::Bdpt(BdptDesc {
                rr_depth: None,
                ..b
            }))
        }
        (IntegratorKind::Whitted, IntegratorDesc::Bdpt(b)) if b.mis.is_none() => {
            Some(IntegratorDesc::Path(RouletteDesc {
                rr_depth: b.rr_depth,
            }))
        }
        (_, desc) => Some(desc),
    };
    out.extend(monte_carlo.filter(|d| !d.is_empty()));
    out
}

/// The integrators' keys of the old spelling.
const OLD_KEYS: [&str; 10] = [
    "fresnel",
    "shadows",
    "min_weight",
    "tolerance",
    "light_samples",
    "glossy_samples",
    "dielectric_roulette",
    "roulette_below",
    "rr_depth",
    "mis",
];

/// The keys of a scene's JSON `settings` written in the old spelling, sorted: `integrator`
/// when it is a name, and each integrator's key beside the others (`settings.rr_depth`).
/// Empty for the new spelling and for text without a `settings` object. Reads the `settings`
/// value alone, however large the rest of the file.
#[must_use]
pub fn old_spelling(scene_json: &str) -> Vec<String> {
    let Some(at) = crate::scene::locate::position(scene_json, "settings") else {
        return Vec::new();
    };
    let mut values = serde_json::Deserializer::from_str(&scene_json[at..])
        .into_iter::<serde_json::Map<String, serde_json::Value>>();
    let Some(Ok(settings)) = values.next() else {
        return Vec::new();
    };
    settings
        .iter()
        .filter(|(k, v)| {
            (k.as_str() == "integrator" && v.is_string()) || OLD_KEYS.contains(&k.as_str())
        })
        .map(|(k, _)| k.clone())
        .collect()
}

/// The new spelling of the keys [`old_spelling`] names: `"integrator": {"type": ...}` with the
/// keys of the integrator in force, and `"other_integrators"` for the others'.
#[must_use]
pub fn new_spelling(s: &Settings) -> String {
    let chosen = IntegratorDesc::of(s.integrator, s, false);
    let mut out = format!(
        "\"integrator\": {}",
        serde_json::to_string(&chosen).unwrap_or_default()
    );
    let others = other_integrators(s);
    if !others.is_empty() {
        let list = serde_json::to_string(&others).unwrap_or_default();
        out.push_str(&format!(", \"other_integrators\": {list}"));
    }
    out
}

#[cfg(test)]
mod tests;
