//! The pixel filter and the thin lens through the render path: the film positions and camera-ray
//! origins that [`render_pixel`] records follow the filter's and the lens disk's pdfs
//! (chi-square, `sampling::chi2`), with the default sampler at fixed seeds.

use super::*;
use crate::sampling::chi2::{SAMPLES, test_plane};
use crate::sampling::warp::concentric_disk_pdf;
use crate::scene::FilterDesc;

/// An empty scene (every camera ray misses) with a thin lens and `filter`, at 40,000 samples
/// per pixel: ten pixels give the chi-square's 400,000 samples.
fn scene(filter: FilterDesc, seed: u64) -> Scene {
    let mut s = Scene::from_json(
        r#"{"camera": {"position": [1, 2, 3], "look_at": [1, 2, -7], "fov_y": 50,
            "width": 10, "height": 4, "aperture_radius": 0.5, "focus_distance": 4}}"#,
    )
    .unwrap();
    s.settings.filter = filter;
    s.settings.spp = 40_000;
    s.settings.seed = seed;
    s
}

/// Film offsets from the pixel centre and lens points (on the unit disk) of every sample of
/// pixels (0..10, 2), as recorded.
fn recorded(scene: &Scene) -> (Vec<DVec2>, Vec<DVec2>) {
    let integrator = SceneIntegrator::new(scene);
    let c = &scene.camera;
    let (mut offsets, mut lens) = (Vec::new(), Vec::new());
    let mut sampler = StratifiedJitter::for_settings(&scene.settings);
    for x in 0..10 {
        let mut rec = TreeRecorder::default();
        let mut samples = Vec::new();
        let mut counts = RayCounts::default();
        render_pixel(
            &integrator,
            &mut sampler,
            (x, 2),
            &mut rec,
            &mut counts,
            |s| {
                samples.push(s);
            },
        );
        for s in samples {
            offsets.push(DVec2::new(s.film[0] - f64::from(x) - 0.5, s.film[1] - 2.5));
            let o = rec.nodes[s.root.0 as usize].origin - c.position;
            lens.push(DVec2::new(o.dot(c.right), o.dot(c.up)) / c.aperture_radius);
        }
    }
    assert_eq!(offsets.len(), SAMPLES);
    (offsets, lens)
}

#[test]
fn recorded_film_offsets_and_lens_points_follow_the_filter_and_the_disk() {
    let filters = [
        FilterDesc::Tent { radius: 1.5 },
        FilterDesc::Gaussian {
            sigma: 0.5,
            radius: None,
        },
    ];
    for (i, f) in filters.into_iter().enumerate() {
        let scene = scene(f, 7 + i as u64);
        let (offsets, lens) = recorded(&scene);
        let filter = f.filter();
        let r = filter.radius();
        let mut it = offsets.into_iter();
        test_plane(
            (DVec2::splat(-r), DVec2::splat(r)),
            0,
            |_| it.next(),
            |p| filter.pdf(p),
        )
        .assert_passes(&format!("film offsets of {f:?}"));
        let mut it = lens.into_iter();
        test_plane(
            (DVec2::splat(-1.0), DVec2::splat(1.0)),
            0,
            |_| it.next(),
            concentric_disk_pdf,
        )
        .assert_passes(&format!("lens points with {f:?}"));
    }
}

/// The test rejects film offsets that do not follow the filter: the box's positions tested
/// against the tent's pdf.
#[test]
fn the_render_path_chi_square_rejects_the_wrong_filter() {
    let scene = scene(FilterDesc::Box {}, 3);
    let (offsets, _) = recorded(&scene);
    let tent = crate::sampling::PixelFilter::Tent { radius: 1.0 };
    let mut it = offsets.into_iter();
    let chi2 = test_plane(
        (DVec2::splat(-1.0), DVec2::splat(1.0)),
        0,
        |_| it.next(),
        |p| tent.pdf(p),
    );
    assert!(!chi2.passes(), "{chi2:?}");
}
