use super::*;
use crate::Scene;
use crate::integrator::SceneIntegrator;
use crate::lpe::filter_tree;
use crate::render::render;

fn caustic(spp: u32) -> Scene {
    let mut s = Scene::from_json(include_str!("../../fixtures/caustic.json")).unwrap();
    s.settings.spp = spp;
    s
}

fn aovs(scene: &Scene, specs: &[&str]) -> AovRender {
    let specs: Vec<String> = specs.iter().map(|s| (*s).to_owned()).collect();
    let lpes: Vec<Lpe> = parse_aovs(&specs)
        .unwrap()
        .into_iter()
        .map(|a| a.lpe)
        .collect();
    render_aovs(&SceneIntegrator::new(scene), &lpes, &|_| {}).unwrap()
}

#[test]
fn the_beauty_image_is_the_renders_bit_for_bit() {
    let scene = caustic(2);
    let r = aovs(&scene, &["c=C<RD>S+L"]);
    let (image, stats, _) = render(
        &crate::integrator::SceneIntegrator::new(&scene),
        &crate::render::RenderOptions::new(),
        &|_| {},
    )
    .into_parts();
    assert_eq!(r.beauty, image);
    assert_eq!(r.stats.rays, stats.rays);
    // Whitted (no expressions) too.
    let mut w = Scene::default_scene();
    w.camera.width = 64;
    w.camera.height = 48;
    let r = render_aovs(&SceneIntegrator::new(&w), &[], &|_| {}).unwrap();
    assert_eq!(
        r.beauty,
        render(
            &crate::integrator::SceneIntegrator::new(&w),
            &crate::render::RenderOptions::new(),
            &|_| {}
        )
        .image
    );
}

#[test]
fn the_standard_classes_partition_every_path_string() {
    let lpes = standard_classes();
    let events = ["<RD>", "<RS>", "<TS>", "<RG>", "<TG>"];
    // Every string C e1..en X with n <= 4 events and X in {L, B} matches exactly one class.
    let mut strings = vec![String::from("C")];
    for _ in 0..4 {
        let longer: Vec<String> = strings
            .iter()
            .flat_map(|s| events.iter().map(move |e| format!("{s}{e}")))
            .collect();
        strings.extend(longer);
    }
    strings.dedup();
    let mut checked = 0;
    for s in &strings {
        for end in ['L', 'B'] {
            let path = format!("{s}{end}");
            let hits: Vec<&str> = CLASSES
                .iter()
                .zip(&lpes)
                .filter(|(_, l)| l.matches(&path))
                .map(|(c, _)| c.name)
                .collect();
            assert_eq!(hits.len(), 1, "{path}: {hits:?}");
            checked += 1;
        }
    }
    assert!(checked > 1000);
    // classify, the inspector's regex-free rule, agrees with the expressions.
    for s in &strings {
        for end in ['L', 'B'] {
            let path = format!("{s}{end}");
            let k = lpes.iter().position(|l| l.matches(&path));
            assert_eq!(classify(&path), k, "{path}");
        }
        assert_eq!(classify(s), None, "{s}");
    }
    assert!(lpes[4].matches("C<RD><TS><TS>L") && lpes[5].matches("C<RS><RD><TS><RG>B"));
}

#[test]
fn aovs_that_partition_the_paths_sum_to_the_beauty_image() {
    let mut cornell = Scene::from_json(include_str!("../../fixtures/cornell-box.json")).unwrap();
    cornell.camera.width = 48;
    cornell.camera.height = 48;
    cornell.settings.spp = 4;
    for scene in [caustic(4), cornell] {
        let specs: Vec<String> = CLASSES
            .iter()
            .map(|c| format!("{}={}", c.name, c.lpe))
            .collect();
        let specs: Vec<&str> = specs.iter().map(String::as_str).collect();
        let r = aovs(&scene, &specs);
        let mut nonzero = [false; 6];
        for (i, p) in r.beauty.pixels.iter().enumerate() {
            let sum = r.aovs.iter().fold(Rgb::ZERO, |s, a| s + a.pixels[i]);
            let err = (sum - *p).abs().max_element();
            assert!(
                err <= 1e-12 * p.max_element().max(1.0),
                "pixel {i}: {sum} vs {p}"
            );
            for (k, a) in r.aovs.iter().enumerate() {
                nonzero[k] |= a.pixels[i] != Rgb::ZERO;
            }
        }
        // Not a vacuous partition: direct and indirect light are both there.
        assert!(nonzero[2] && nonzero[5], "{nonzero:?}");
    }
    // The issue's example names: direct, indirect, with emission and the paths that start
    // on the glass they partition this black-background scene's paths.
    let scene = caustic(2);
    let r = aovs(
        &scene,
        &[
            "emit=CL",
            "direct=C<RD>L",
            "indirect=C<RD>.+L",
            "glass=CS.*L",
        ],
    );
    for (i, p) in r.beauty.pixels.iter().enumerate() {
        let sum = r.aovs.iter().fold(Rgb::ZERO, |s, a| s + a.pixels[i]);
        assert!((sum - *p).abs().max_element() <= 1e-12 * p.max_element().max(1.0));
    }
}

#[test]
fn an_aov_pixel_is_the_filtered_trees_radiance() {
    let scene = caustic(16);
    let lpe = Lpe::parse("C<RD>S+L").unwrap();
    let r = render_aovs(
        &SceneIntegrator::new(&scene),
        std::slice::from_ref(&lpe),
        &|_| {},
    )
    .unwrap();
    for (x, y) in [(98, 112), (120, 120), (30, 150)] {
        let tree = crate::trace_pixel(&scene, x, y).unwrap();
        let f = filter_tree(&tree, std::slice::from_ref(&lpe)).unwrap();
        let a = r.aovs[0].get(x, y);
        assert!(
            (a - f.radiance).abs().max_element() <= 1e-12,
            "{a} vs {}",
            f.radiance
        );
    }
}

#[test]
fn the_caustic_aov_lights_the_floor_under_the_ball_and_nothing_far_from_it() {
    let scene = caustic(8);
    let r = aovs(&scene, &["caustics=C<RD>S+L", "refracted=C<RD><TS>+L"]);
    let sum = |img: &Image, [x0, y0, x1, y1]: [u32; 4]| {
        let mut s = 0.0;
        for y in y0..y1 {
            for x in x0..x1 {
                s += crate::bsdf::luminance(img.get(x, y));
            }
        }
        s
    };
    let under = [84, 100, 120, 124];
    let all = [0, 0, 240, 180];
    // C<RD>S+L: bright under the ball, where most of it is; the rest is the ball's mirror
    // reflection of the lamp onto the floor (C<RD><RS>L), a few sparse samples.
    let (c, refr) = (&r.aovs[0], &r.aovs[1]);
    assert!(
        sum(c, under) > 0.6 * sum(c, all),
        "{} of {}",
        sum(c, under),
        sum(c, all)
    );
    // Through the glass only: all of it under the ball, nothing on the rest of the floor.
    assert!(sum(refr, under) > 1.0);
    assert_eq!(sum(refr, under), sum(refr, all));
    for far in [[0, 120, 60, 180], [180, 120, 240, 180], [0, 0, 240, 40]] {
        assert_eq!(sum(refr, far), 0.0);
    }
}

#[test]
fn the_noise_view_matches_a_hand_computation_on_the_recorded_samples() {
    let scene = caustic(16);
    let r = aovs(&scene, &[]);
    let w = scene.camera.width;
    for (x, y) in [(98, 112), (60, 140), (150, 100)] {
        let tree = crate::trace_pixel(&scene, x, y).unwrap();
        let l: Vec<f64> = tree
            .samples
            .iter()
            .map(|s| crate::bsdf::luminance(s.radiance))
            .collect();
        let n = l.len() as f64;
        let mean = l.iter().sum::<f64>() / n;
        let var = l.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        let want = (var / n).sqrt() / mean;
        let px = &r.mc[(y * w + x) as usize];
        assert!(
            (px.rel_err - want).abs() <= 1e-12 * want,
            "{} vs {want}",
            px.rel_err
        );
        assert!(px.rel_err > 0.0);
        assert_eq!(px.samples, 16);
        // Path length: the recorded tree's path rays (shadow rays not counted) per sample.
        let rays = tree
            .nodes
            .iter()
            .filter(|n| n.kind != crate::RayKind::Shadow)
            .count();
        assert!((px.path_length - rays as f64 / n).abs() < 1e-12);
        let rr = tree
            .nodes
            .iter()
            .filter(|n| n.end == crate::tree::EndReason::RussianRoulette)
            .count();
        assert_eq!(px.roulette as usize, rr);
    }
}

#[test]
fn the_noise_view_is_zero_on_noise_free_renders() {
    // Whitted at one sample per pixel: nothing to estimate a spread from.
    let mut w = Scene::default_scene();
    w.camera.width = 32;
    w.camera.height = 24;
    let r = render_aovs(&SceneIntegrator::new(&w), &[], &|_| {}).unwrap();
    assert!(r.mc.iter().all(|p| p.rel_err == 0.0));
    assert!(McView::Noise.values(&r).iter().any(|_| true));
    // A constant scene under the path tracer at 16 spp: every sample sees the same background.
    let mut c = Scene::from_json(
        r#"{"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40,
            "width": 8, "height": 8}, "background": [0.3, 0.5, 0.7],
            "objects": [], "lights": [], "settings": {"integrator": "path", "spp": 16}}"#,
    )
    .unwrap();
    c.settings.spp = 16;
    let r = render_aovs(&SceneIntegrator::new(&c), &[], &|_| {}).unwrap();
    assert!(r.mc.iter().all(|p| p.rel_err == 0.0 && p.mean > 0.0));
    // And the same pixels' spread is positive once the samples differ (a lit floor).
    let r = aovs(&caustic(4), &[]);
    assert!(r.mc.iter().any(|p| p.rel_err > 0.0));
}

#[test]
fn bad_specs_name_their_column() {
    let e = Aov::parse("caustics").unwrap_err();
    assert_eq!(e.column, 1);
    let e = Aov::parse("a.b=CL").unwrap_err();
    assert_eq!(e.column, 2);
    assert!(e.message.contains("'.'"), "{e}");
    let e = Aov::parse("=CL").unwrap_err();
    assert_eq!(e.column, 1);
    // The expression's own column, counted from the start of NAME=LPE.
    let e = Aov::parse("x=C<RD>Q").unwrap_err();
    assert_eq!(e.column, 8, "{e}");
    let specs = [
        "a=CL".to_owned(),
        "b=C.*B".to_owned(),
        "a=C<RD>L".to_owned(),
    ];
    let e = parse_aovs(&specs).unwrap_err();
    assert_eq!(e.index, 2);
    assert!(e.message.contains("twice"), "{e}");
    // Expressions under Whitted are refused.
    let w = Scene::default_scene();
    let l = [Lpe::parse("CL").unwrap()];
    assert_eq!(
        render_aovs(&SceneIntegrator::new(&w), &l, &|_| {}).unwrap_err(),
        AovError::Whitted
    );
}

#[test]
fn the_views_read_their_fields_and_shares_lie_in_zero_one() {
    let r = aovs(&caustic(4), &["caustics=C<RD>S+L", "all=C.*[LB]"]);
    let names = ["caustics", "all"];
    let all = McView::parse("share:all", &names).unwrap();
    let caustics = McView::parse("share:caustics", &names).unwrap();
    for i in 0..r.mc.len() {
        let a = all.value(&r, i);
        assert!(a == 0.0 || (a - 1.0).abs() < 1e-9, "{a}");
        assert!((0.0..=1.0 + 1e-9).contains(&caustics.value(&r, i)));
    }
    assert!(McView::parse("share:nope", &names).is_err());
    assert!(
        McView::parse("bogus", &names)
            .unwrap_err()
            .contains("noise")
    );
    let spp = McView::Spp.values(&r);
    assert!(spp.iter().all(|v| *v == 4.0));
    assert_eq!(McView::Spp.range(&spp), (0.0, 4.0));
    assert_eq!(
        McView::Dropped.range(&McView::Dropped.values(&r)),
        (0.0, 1.0)
    );
}

#[test]
fn whitted_misses_the_caustic_under_the_ball() {
    let v = versus(&caustic(8), Some([84, 100, 114, 124]), &|_| {}).unwrap();
    let b = v.breakdown();
    let share = |n: &str| b.iter().find(|t| t.0 == n).unwrap().2;
    assert!(share("caustics") > 0.5, "{b:?}");
    assert!(v.path_luminance > v.whitted_luminance);
    // The classes sum to the path-traced image.
    let sum: f64 = v.classes.iter().map(|c| c.luminance).sum();
    assert!((sum - v.path_luminance).abs() <= 1e-9 * v.path_luminance);
}

#[test]
fn the_inspectors_node_statistics_are_the_light_recorders() {
    let scene = caustic(16);
    let lpes = standard_classes();
    let r = render_aovs(&SceneIntegrator::new(&scene), &lpes, &|_| {}).unwrap();
    let w = scene.camera.width;
    for (x, y) in [(98, 112), (60, 140), (150, 100), (5, 5)] {
        let tree = crate::trace_pixel(&scene, x, y).unwrap();
        let (px, shares) = pixel_from_nodes(&tree.nodes);
        let i = (y * w + x) as usize;
        let want = r.mc[i];
        assert_eq!(
            (px.samples, px.dropped, px.roulette),
            (want.samples, want.dropped, want.roulette)
        );
        assert!((px.rel_err - want.rel_err).abs() <= 1e-12 * want.rel_err.max(1.0));
        assert!((px.path_length - want.path_length).abs() <= 1e-12);
        for (k, s) in shares.iter().enumerate() {
            let v = McView::Share(k).value(&r, i);
            assert!((s - v).abs() <= 1e-9, "class {k}: {s} vs {v}");
        }
    }
    // Under the ball the caustic class dominates.
    let (_, shares) = pixel_from_nodes(&crate::trace_pixel(&scene, 98, 112).unwrap().nodes);
    assert!(shares[4] > 0.5, "{shares:?}");
}

/// The bits of an image's pixels.
fn bits(image: &Image) -> Vec<[u64; 3]> {
    image
        .pixels
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

fn small_caustic(spp: u32) -> Scene {
    let mut s = caustic(spp);
    s.camera = s.camera.with_size(14, 10);
    s
}

#[test]
fn the_stepped_comparisons_are_the_comparisons_bit_for_bit() {
    let scene = small_caustic(3);
    let region = Some([2, 1, 11, 8]);
    let whole = versus(&scene, region, &|_| {}).unwrap();
    for answer in [false, true] {
        let mut steps = VersusSteps::new(&scene, region);
        let mut n = 1;
        while steps.step(&|| answer) {
            n += 1;
        }
        let v = steps.finish();
        assert_eq!(v.summary(), whole.summary());
        assert_eq!(bits(&v.whitted), bits(&whole.whitted));
        assert_eq!(bits(&v.path.beauty), bits(&whole.path.beauty));
        for (a, b) in v.path.aovs.iter().zip(&whole.path.aovs) {
            assert_eq!(bits(a), bits(b));
        }
        assert_eq!(format!("{:?}", v.path.mc), format!("{:?}", whole.path.mc));
        assert_eq!(
            format!("{:?}", v.whitted_stats),
            format!("{:?}", whole.whitted_stats)
        );
        assert_eq!(v.classes, whole.classes);
        assert_eq!(n, if answer { 1 } else { 2 * 14 * 10 }, "a pixel a step");
    }
    let kinds = [IntegratorKind::Path, IntegratorKind::Bdpt];
    let render_it = &mut |s: &Scene| {
        render(
            &SceneIntegrator::new(s),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
    };
    let whole = pair(&scene, kinds, None, render_it);
    for answer in [false, true] {
        let mut steps = PairSteps::new(&scene, kinds, None);
        while steps.step(&|| answer) {}
        let p = steps.finish();
        assert_eq!(p.summary(), whole.summary());
        assert_eq!(bits(&p.a.image), bits(&whole.a.image));
        assert_eq!(bits(&p.b.image), bits(&whole.b.image));
        assert_eq!(format!("{:?}", p.b.stats), format!("{:?}", whole.b.stats));
    }
}
