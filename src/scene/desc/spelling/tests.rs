use super::*;
use crate::scene::desc::PathSettings;

fn read(json: &str) -> Result<Settings, String> {
    serde_json::from_str::<Settings>(json).map_err(|e| e.to_string())
}

/// The caustic fixture's settings, as it was written, and in the new spelling.
#[test]
fn both_spellings_read_the_same_settings() {
    let old =
        read(r#"{"integrator": "path", "spp": 64, "max_depth": 16, "light_samples": 1}"#).unwrap();
    let new = read(
        r#"{"integrator": {"type": "path"}, "other_integrators": [{"type": "whitted", "light_samples": 1}],
            "spp": 64, "max_depth": 16}"#,
    )
    .unwrap();
    assert_eq!(old, new);
    assert_eq!(new.integrator, IntegratorKind::Path);
    assert_eq!(new.whitted.light_samples, Some(1));
    let bdpt = read(r#"{"integrator": {"type": "bdpt", "rr_depth": 3, "mis": "power"}}"#).unwrap();
    let flat = read(r#"{"integrator": "bdpt", "rr_depth": 3, "mis": "power"}"#).unwrap();
    assert_eq!(bdpt, flat);
    assert_eq!(
        (bdpt.path.rr_depth, bdpt.path.mis),
        (3, MisHeuristic::Power)
    );
    let whitted =
        read(r#"{"integrator": {"type": "whitted", "fresnel": "schlick", "min_weight": null}}"#)
            .unwrap();
    assert_eq!(whitted.whitted.fresnel, FresnelModel::Schlick);
    assert_eq!(whitted.whitted.min_weight, None);
    assert_eq!(read("{}").unwrap(), Settings::default());
}

/// Every combination of integrator in force and settings that differ from the defaults writes
/// the new spelling and reads back equal.
#[test]
fn the_new_spelling_reads_back_equal() {
    let whitted = [
        WhittedSettings::default(),
        WhittedSettings {
            fresnel: FresnelModel::None,
            shadows: ShadowMode::Translucent,
            min_weight: Some(0.0),
            tolerance: 0.5,
            light_samples: Some(3),
            glossy_samples: 7,
            dielectric_roulette: Some(2),
            roulette_below: Some(0.25),
        },
    ];
    let path = [
        PathSettings::default(),
        PathSettings {
            rr_depth: 9,
            ..PathSettings::default()
        },
        PathSettings {
            mis: MisHeuristic::Power,
            ..PathSettings::default()
        },
        PathSettings {
            rr_depth: 0,
            mis: MisHeuristic::Power,
        },
    ];
    for kind in IntegratorKind::ALL {
        for w in whitted {
            for p in path {
                let s = Settings {
                    integrator: kind,
                    whitted: w,
                    path: p,
                    spp: 3,
                    ..Settings::default()
                };
                let text = serde_json::to_string(&s).unwrap();
                assert!(text.starts_with(r#"{"integrator":{"type":"#), "{text}");
                assert!(!text.contains(r#""rr_depth":9,"type""#), "{text}");
                assert_eq!(read(&text), Ok(s), "{text}");
                assert!(
                    old_spelling(&format!(r#"{{"settings": {text}}}"#)).is_empty(),
                    "{text}"
                );
            }
        }
    }
}

#[test]
fn keys_of_another_integrator_and_keys_given_twice_are_refused() {
    let refused = |json: &str, want: &str| {
        let e = read(json).expect_err(json);
        assert!(e.contains(want), "{json}: {e}");
    };
    refused(
        r#"{"integrator": {"type": "path", "fresnel": "schlick"}}"#,
        "unknown field `fresnel`, expected `rr_depth`",
    );
    refused(
        r#"{"integrator": {"type": "whitted", "rr_depth": 3}}"#,
        "unknown field `rr_depth`",
    );
    refused(
        r#"{"integrator": {"type": "light", "mis": "power"}}"#,
        "unknown field `mis`",
    );
    refused(
        r#"{"integrator": {"type": "metropolis"}}"#,
        r#"unknown integrator "metropolis""#,
    );
    refused(
        r#"{"integrator": {"type": "path", "rr_depth": -1}}"#,
        "rr_depth: invalid value: integer `-1`",
    );
    refused(
        r#"{"integrator": {"type": "bdpt", "mis": "max"}}"#,
        "mis: unknown MIS heuristic",
    );
    refused(
        r#"{"integrator": {"fresnel": "exact"}}"#,
        "missing field `type`",
    );
    refused(r#"{"integrator": 3}"#, "expected an integrator");
    refused(
        r#"{"integrator": {"type": "whitted", "fresnel": "schlick"}, "fresnel": "exact"}"#,
        "fresnel is given twice: in settings (the old spelling) and in settings.integrator",
    );
    refused(
        r#"{"integrator": {"type": "path", "rr_depth": 2}, "other_integrators": [{"type": "bdpt", "rr_depth": 4}]}"#,
        "rr_depth is given twice: in settings.integrator and in settings.other_integrators[0]",
    );
    refused(
        r#"{"integrator": {"type": "path"}, "other_integrators": [{"type": "path", "rr_depth": 4}]}"#,
        r#"other_integrators[0]: "path" is the integrator in force"#,
    );
    refused(
        r#"{"other_integrators": [{"type": "path"}, {"type": "path"}]}"#,
        r#"other_integrators[1]: "path" is given twice (also other_integrators[0])"#,
    );
    assert!(read(r#"{"fresnel": null}"#).is_err());
    refused(
        r#"{"integrator": {"type": "path", "rr_depth": null}}"#,
        "invalid type: null",
    );
}

#[test]
fn the_old_spelling_is_named_key_by_key() {
    let scene = r#"{"camera": {}, "settings": {"spp": 2, "integrator": "path", "rr_depth": 3, "light_samples": 1}}"#;
    assert_eq!(
        old_spelling(scene),
        ["integrator", "light_samples", "rr_depth"]
    );
    assert!(old_spelling(r#"{"settings": {"integrator": {"type": "path"}, "spp": 2}}"#).is_empty());
    assert!(old_spelling(r#"{"camera": {}}"#).is_empty());
    assert!(old_spelling("not json").is_empty());
    let s = read(r#"{"integrator": "path", "rr_depth": 3, "light_samples": 1}"#).unwrap();
    assert_eq!(
        new_spelling(&s),
        r#""integrator": {"type":"path","rr_depth":3}, "other_integrators": [{"type":"whitted","light_samples":1}]"#
    );
}

/// A tree records its settings flat, in the layout of schema `raytree.tree/2`.
#[test]
fn the_flat_record_keeps_the_tree_layout() {
    let mut s = Settings {
        integrator: IntegratorKind::Path,
        ..Settings::default()
    };
    s.path.rr_depth = 2;
    s.whitted.light_samples = Some(1);
    let text = serde_json::to_string(&crate::scene::desc::SettingsRecord::from(&s)).unwrap();
    assert_eq!(
        text,
        r#"{"integrator":"path","seed":0,"max_depth":16,"spp":1,"offset":{"strategy":"normal","epsilon":0.0001},"fresnel":"exact","shadows":"opaque","tolerance":0.00196078431372549,"max_rays":1048576,"light_samples":1,"rr_depth":2}"#
    );
    let back: crate::scene::desc::SettingsRecord = serde_json::from_str(&text).unwrap();
    assert_eq!(Settings::from(back), s);
}
