//! Tests of the cost sweep.
use super::*;

fn img(p: &[Rgb]) -> Image {
    Image {
        width: p.len() as u32,
        height: 1,
        pixels: p.to_vec(),
    }
}

#[test]
fn metrics_closed_form() {
    let a = img(&[Rgb::ZERO, Rgb::splat(0.5)]);
    assert_eq!(compare(&a, &a).unwrap(), ErrorMetrics::default());
    let b = img(&[Rgb::new(0.3, 0.0, 0.0), Rgb::splat(0.5)]);
    let m = compare(&a, &b).unwrap();
    assert!((m.rmse - (0.09f64 / 6.0).sqrt()).abs() < 1e-15);
    assert_eq!(m.max, 0.3);
    assert_eq!(m.off_8bit, 0.5);
    assert!(compare(&a, &img(&[Rgb::ZERO])).is_none());
}

#[test]
fn the_sweep_has_an_auto_min_weight_row_and_an_exhaustive_reference() {
    let mut scene = Scene::default_scene();
    scene.camera = scene.camera.with_size(32, 18);
    let sweep = Sweep {
        depths: vec![],
        fresnels: vec![],
        spps: vec![],
        offsets: vec![],
        filters: vec![],
        adaptive: vec![],
        dielectric_roulette: vec![],
        roulette_below: vec![],
        repeats: 1,
        reference_spp: 1,
        ..Sweep::quick()
    };
    let r = run(&scene, &sweep, &|_, _| {});
    assert_eq!(r.reference.whitted.min_weight, Some(0.0));
    assert_eq!(r.base.whitted.min_weight, None);
    let auto = crate::integrator::bound::auto_min_weight(&scene, &r.base);
    assert!(auto > 0.0 && auto == r.base_min_weight);
    let values: Vec<&str> = r.rows.iter().map(|row| row.value.as_str()).collect();
    assert_eq!(values, ["0e0", &format!("auto ({auto:.1e})"), "1e-2"]);
    let [exhaustive, auto_row, coarse] = &r.rows[..] else {
        unreachable!()
    };
    assert_eq!(auto_row.settings.whitted.min_weight, None);
    // The cut traces fewer rays than the exhaustive tree at depth 16, more than 1e-2.
    assert!(auto_row.rays.total < exhaustive.rays.total, "{r:?}");
    assert!(auto_row.rays.total > coarse.rays.total, "{r:?}");
}

#[test]
fn pareto_front() {
    let row = |t: f64, e: f64| CostRow {
        axis: String::new(),
        value: String::new(),
        settings: Settings::default(),
        median_ms: t,
        rays: RaysByKind::default(),
        error: ErrorMetrics {
            rmse: e,
            ..ErrorMetrics::default()
        },
        pareto: false,
    };
    let mut rows = vec![row(1.0, 0.5), row(2.0, 0.1), row(3.0, 0.2), row(4.0, 0.0)];
    mark_pareto(&mut rows);
    let front: Vec<bool> = rows.iter().map(|r| r.pareto).collect();
    assert_eq!(front, [true, true, false, true]);
}

/// The light-samples, glossy-samples and filter axes: rows only where the scene uses the knob,
/// each against its own converged reference, and more samples err less.
#[test]
fn stochastic_axes_are_measured_against_their_references() {
    let sweep = Sweep {
        depths: vec![],
        fresnels: vec![],
        spps: vec![],
        offsets: vec![],
        min_weights: vec![],
        light_samples: vec![1, 16],
        glossy_samples: vec![1, 16],
        filters: vec!["box".into(), "tent:1".into()],
        filter_spp: 4,
        adaptive: vec![],
        dielectric_roulette: vec![],
        roulette_below: vec![],
        reference_spp: 16,
        reference_light_samples: 256,
        reference_glossy_samples: 256,
        repeats: 1,
        ..Sweep::quick()
    };
    let rows = |src: &str| {
        let mut scene = Scene::from_json(src).unwrap();
        scene.camera = scene.camera.with_size(32, 20);
        run(&scene, &sweep, &|_, _| {}).rows
    };
    let labels = |r: &[CostRow]| -> Vec<String> {
        r.iter()
            .map(|row| format!("{} {}", row.axis, row.value))
            .collect()
    };
    let soft = rows(include_str!("../../../fixtures/soft-shadows.json"));
    assert_eq!(
        labels(&soft),
        [
            "light_samples 1",
            "light_samples 16",
            "filter box",
            "filter tent:1"
        ]
    );
    assert!(soft[1].error.rmse < 0.5 * soft[0].error.rmse, "{soft:?}");
    assert!(soft[1].rays.shadow > 10 * soft[0].rays.shadow);
    let glossy = rows(include_str!("../../../fixtures/glossy.json"));
    assert_eq!(
        labels(&glossy),
        [
            "light_samples 1",
            "light_samples 16",
            "glossy_samples 1",
            "glossy_samples 16",
            "filter box",
            "filter tent:1"
        ]
    );
    assert!(
        glossy[3].error.rmse < 0.5 * glossy[2].error.rmse,
        "{glossy:?}"
    );
    assert_eq!(glossy[4].settings.spp, 4);
    let classic = rows(include_str!("../../../fixtures/classic.json"));
    assert_eq!(labels(&classic), ["filter box", "filter tent:1"]);
}

/// The adaptive rows: a first pass of `adaptive_spp` samples, more where pixels disagree,
/// measured against the spp axis's reference; at threshold 0 the classic scene's edges are
/// refined, so the row takes more samples than the uniform row of the same first pass and has
/// less error.
#[test]
fn adaptive_rows_take_more_samples_at_edges_and_have_less_error() {
    let mut scene = Scene::default_scene();
    scene.camera = scene.camera.with_size(48, 27);
    let sweep = Sweep {
        depths: vec![],
        fresnels: vec![],
        spps: vec![2],
        offsets: vec![],
        min_weights: vec![],
        filters: vec![],
        adaptive: vec![(0.0, 16)],
        adaptive_spp: 2,
        dielectric_roulette: vec![],
        roulette_below: vec![],
        reference_spp: 64,
        repeats: 1,
        ..Sweep::quick()
    };
    let r = run(&scene, &sweep, &|_, _| {});
    let [uniform, auto, adaptive] = &r.rows[..] else {
        panic!("{:?}", r.rows)
    };
    assert_eq!(
        (
            uniform.axis.as_str(),
            auto.axis.as_str(),
            adaptive.axis.as_str()
        ),
        ("spp", "antialiasing", "adaptive")
    );
    assert_eq!(adaptive.value, "0 to 16 spp");
    assert_eq!(auto.value, "auto 2 spp");
    let pixels = 48 * 27;
    assert_eq!(uniform.rays.camera, 2 * pixels);
    // Automatic antialiasing at 2 spp: a first pass of 2 samples, nothing to refine.
    assert!(auto.rays.camera == 2 * pixels, "{}", auto.rays.camera);
    assert!(
        adaptive.rays.camera > 2 * pixels && adaptive.rays.camera < 16 * pixels,
        "{}",
        adaptive.rays.camera
    );
    assert!(
        adaptive.error.rmse < 0.7 * uniform.error.rmse,
        "{} against {}",
        adaptive.error.rmse,
        uniform.error.rmse
    );
}

/// A path-traced scene's sweep leaves out the axes the path integrator does not read (every
/// row would equal the base) and sweeps its Russian-roulette depth instead, against the spp
/// reference; a Whitted scene's sweep has no roulette-depth rows.
#[test]
fn a_path_traced_sweep_has_its_own_axes() {
    let scene = Scene::from_json(include_str!("../../../fixtures/caustic.json")).unwrap();
    assert_eq!(
        scene.settings.integrator,
        crate::scene::IntegratorKind::Path
    );
    let sweep = Sweep::quick();
    let base = Settings {
        max_depth: 16,
        ..scene.settings
    };
    let rows = sweep.settings(&scene, &base);
    let axes: Vec<&str> = rows.iter().map(|(a, _, _)| a.as_str()).collect();
    // No row changes what the path integrator does not read (the Whitted integrator's own
    // settings), and the whole Whitted sweep would have.
    assert!(
        rows.iter().all(|(_, _, s)| s.whitted == base.whitted),
        "{axes:?}"
    );
    let whitted = Settings {
        integrator: crate::scene::IntegratorKind::Whitted,
        ..base
    };
    assert!(
        sweep
            .settings(&scene, &whitted)
            .iter()
            .any(|(_, _, s)| s.whitted != base.whitted),
        "the Whitted sweep changes the Whitted settings"
    );
    assert!(
        axes.contains(&"max_depth") && axes.contains(&"offset"),
        "{axes:?}"
    );
    let rr: Vec<(&str, u32, u32)> = rows
        .iter()
        .filter(|(a, _, _)| a == "rr_depth")
        .map(|(_, v, s)| (v.as_str(), s.path.rr_depth, s.spp))
        .collect();
    assert_eq!(
        rr,
        [
            ("from bounce 2", 2, sweep.filter_spp),
            ("from bounce 5", 5, sweep.filter_spp),
            ("off (16 >= max depth)", 16, sweep.filter_spp),
        ]
    );
    let samplers: Vec<(&str, Option<crate::scene::SamplerKind>, u32)> = rows
        .iter()
        .filter(|(a, _, _)| a == "sampler")
        .map(|(_, v, s)| (v.as_str(), s.sampler, s.spp))
        .collect();
    assert_eq!(
        samplers,
        [
            (
                "stratified",
                Some(crate::scene::SamplerKind::Stratified),
                sweep.filter_spp
            ),
            (
                "sobol",
                Some(crate::scene::SamplerKind::Sobol),
                sweep.filter_spp
            ),
        ]
    );
    let reference = reference_settings(&base, &sweep);
    for axis in ["rr_depth", "sampler"] {
        assert_eq!(
            sweep.reference_for(axis, &rows[0].2, &reference).spp,
            sweep.reference_spp
        );
    }
    // The same scene under Whitted: the Whitted axes, no roulette depth.
    let whitted = Settings {
        integrator: crate::scene::IntegratorKind::Whitted,
        ..base
    };
    let axes: Vec<String> = sweep
        .settings(&scene, &whitted)
        .into_iter()
        .map(|(a, _, _)| a)
        .collect();
    assert!(axes.iter().any(|a| a == "fresnel") && axes.iter().any(|a| a == "min_weight"));
    assert!(
        !axes.iter().any(|a| a == "rr_depth" || a == "sampler"),
        "{axes:?}"
    );
}
