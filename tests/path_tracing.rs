//! The path integrator end to end (issue 15): tree == pixel bit for bit on every fixture, the
//! recorded estimator (contributions, LPEs, MIS weights, roulette), dropped NaN samples, and
//! the command line (`--integrator path`, `--rr-depth`, `settings.rr_depth` errors).

mod common;

use common::raytree;
use raytree::SceneIntegrator;
use raytree::analysis::invariants::tree_violations;
use raytree::bvh::TraversalCost;
use raytree::integrator::PathTracer;
use raytree::math::{Ray, Rgb};
use raytree::render::RenderOptions;
use raytree::sampling::PixelSampler;
use raytree::scene::{Film, Hit, IntegratorKind};
use raytree::tree::{EndReason, Pdf, RayKind};
use raytree::{Integrator, NodeId, RayCounts, Recorder, Scene, render, trace_pixel};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

fn fixture(name: &str) -> Scene {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    Scene::from_json(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn fixtures() -> Vec<(String, Scene)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut out: Vec<(String, Scene)> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "json").then(|| {
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                (name.clone(), fixture(&name))
            })
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(out.len() >= 13, "{}", out.len());
    out
}

/// Every fixture under the path integrator at spp 1, 4 and 16 (its default Sobol sampler) and
/// at spp 4 with the stratified sampler: each pixel's recorded tree
/// gives the rendered value bit for bit and keeps the invariants (the sample's radiance is the
/// sum of its contributions, LPEs extend, the Whitted-shaped sums).
#[test]
fn every_fixture_tree_equals_pixel_under_the_path_integrator() {
    use raytree::scene::SamplerKind;
    for (name, mut scene) in fixtures() {
        scene.settings.integrator = IntegratorKind::Path;
        // The default (Sobol, unless the fixture names one), then the stratified sampler.
        for (spp, w, h, sampler) in [
            (1, 16, 10, scene.settings.sampler),
            (4, 8, 5, scene.settings.sampler),
            (16, 4, 3, scene.settings.sampler),
            (4, 8, 5, Some(SamplerKind::Stratified)),
        ] {
            scene.settings.sampler = sampler;
            scene.camera = scene.camera.with_size(w, h);
            scene.settings.spp = spp;
            let (image, stats, _) = render(
                &SceneIntegrator::new(&scene),
                &RenderOptions::new(),
                &|_| {},
            )
            .into_parts();
            assert_eq!(stats.rays.dropped_samples, 0, "{name}");
            for y in 0..h {
                for x in 0..w {
                    let tree = trace_pixel(&scene, x, y).unwrap();
                    assert_eq!(
                        tree.radiance,
                        image.get(x, y),
                        "{name} spp {spp} pixel {x},{y}: tree != render"
                    );
                    let v = tree_violations(&tree, scene.background);
                    assert!(v.is_empty(), "{name} spp {spp} pixel {x},{y}: {v:#?}");
                    assert!(tree.nodes.iter().all(|n| n.path.is_some()));
                }
            }
        }
    }
}

/// The caustic fixture records the caustic path of the issue, `C<RD><TS><TS>L`, with a
/// positive contribution found by BSDF sampling (MIS weight 1 after the delta lobes), and the
/// diffuse bounces are `diffuse` rays with a solid-angle pdf.
#[test]
fn the_caustic_is_recorded_as_its_light_path_expression() {
    let scene = fixture("caustic.json");
    let mut found = None;
    'scan: for y in (100..150).step_by(3) {
        for x in (80..140).step_by(3) {
            let tree = trace_pixel(&scene, x, y).unwrap();
            for n in &tree.nodes {
                let p = n.path.as_ref().unwrap();
                if p.lpe == "C<RD><TS><TS>L" && p.contribution.max_element() > 0.0 {
                    assert_eq!(n.kind, RayKind::Refracted);
                    assert_eq!(p.mis_weight, Some(1.0));
                    assert!(matches!(p.pdf, Some(Pdf::Delta(_))));
                    let diffuse = tree.node(tree.node(n.parent.unwrap()).parent.unwrap());
                    assert_eq!(diffuse.kind, RayKind::Diffuse);
                    assert!(
                        matches!(diffuse.path.as_ref().unwrap().pdf, Some(Pdf::Density(d)) if d > 0.0)
                    );
                    found = Some((x, y));
                    break 'scan;
                }
            }
        }
    }
    assert!(found.is_some(), "no caustic path under the ball");
    // Whitted sees no caustic: its tree has no diffuse ray at all.
    let mut whitted = scene.clone();
    whitted.settings.integrator = IntegratorKind::Whitted;
    let (x, y) = found.unwrap();
    let tree = trace_pixel(&whitted, x, y).unwrap();
    assert_eq!(tree.count_by_kind()[4], 0);
}

/// Russian roulette is recorded: with rr_depth 1 in the Cornell box, some node records a
/// survival probability in (0, 1], kills end the path, and survivors' weights are divided by
/// the probability.
#[test]
fn russian_roulette_is_recorded() {
    let mut scene = fixture("cornell-box.json");
    scene.settings.path.rr_depth = 1;
    scene.settings.spp = 16;
    let tree = trace_pixel(&scene, 128, 200).unwrap();
    let (mut killed, mut survived) = (0, 0);
    for n in &tree.nodes {
        let Some(r) = n.path.as_ref().unwrap().roulette else {
            continue;
        };
        assert!(r.probability > 0.0 && r.probability <= 1.0);
        if r.survived {
            survived += 1;
            let child = n
                .children
                .iter()
                .map(|c| tree.node(*c))
                .find(|c| c.kind != RayKind::Shadow)
                .unwrap();
            let f = child.path.as_ref().unwrap().bsdf_cos_pdf.unwrap();
            assert_eq!(child.weight, f / r.probability);
        } else {
            killed += 1;
            assert_eq!(n.end, EndReason::RussianRoulette);
        }
    }
    assert!(killed > 0 && survived > 0, "{killed} {survived}");
}

/// A path integrator that makes every 5th sample NaN (through the seam, as a buggy BSDF
/// would): the render drops them, counts them, names the first, and writes no NaN.
struct NanEvery<'a> {
    inner: PathTracer<'a>,
    calls: AtomicU64,
}

impl Integrator for NanEvery<'_> {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Path
    }
    fn scene(&self) -> &Scene {
        self.inner.scene()
    }
    fn film(&self) -> &Film<'_> {
        self.inner.film()
    }
    fn camera_radiance<R: Recorder, S: PixelSampler>(
        &self,
        ray: Ray,
        sampler: &mut S,
        rec: &mut R,
        counts: &mut RayCounts,
    ) -> (Rgb, Option<NodeId>) {
        let (l, id) = self.inner.trace_camera(ray, sampler, rec, counts);
        if self.calls.fetch_add(1, Ordering::Relaxed) % 5 == 4 {
            (Rgb::splat(f64::NAN), id)
        } else {
            (l, id)
        }
    }
    fn traces_packets(&self) -> bool {
        false
    }
    fn camera_packet_radiance<R: Recorder>(
        &self,
        _: &[Ray],
        _: (&[Option<Hit>], &[TraversalCost]),
        _: &mut [Rgb],
        _: &mut R,
        _: &mut RayCounts,
    ) {
    }
}

#[test]
fn nan_samples_are_dropped_counted_and_named() {
    let mut scene = fixture("cornell-box.json");
    scene.camera = scene.camera.with_size(8, 6);
    scene.settings.spp = 4;
    let nan = NanEvery {
        inner: PathTracer::new(&scene),
        calls: AtomicU64::new(0),
    };
    let (image, stats, _) = render(&nan, &RenderOptions::new(), &|_| {}).into_parts();
    assert_eq!(stats.rays.dropped_samples, 8 * 6 * 4 / 5);
    assert!(image.pixels.iter().all(|p| p.is_finite()));
    assert_eq!(stats.nonfinite_pixels, 0);
    let (x, y, s) = stats.rays.first_dropped.unwrap();
    assert!(y < 6 && x < 8 && s < 4);
}

fn fails_with(o: &std::process::Output, text: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(text), "{err}");
}

/// `--integrator path` and `--rr-depth` on the command line; bad values exit 2 naming the flag
/// or the JSON path with line:column, and write nothing.
#[test]
fn command_line_integrator_and_rr_depth() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = raytree(
        &[
            "render",
            "--integrator",
            "path",
            "--rr-depth",
            "2",
            "--size",
            "16x9",
            "--spp",
            "2",
            "-o",
            "a.png",
        ],
        d,
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains("samples/s") && out.contains("rr depth 2"),
        "{out}"
    );
    let o = raytree(&["render", "--rr-depth", "5000", "-o", "b.png"], d);
    fails_with(&o, "--rr-depth: must be at most 1024, got 5000");
    assert!(!d.join("b.png").exists());
    std::fs::write(
        d.join("p.json"),
        "{\"camera\": {\"position\": [0,0,5], \"look_at\": [0,0,0], \"fov_y\": 40, \"width\": 4,\n\"height\": 3}, \"settings\": {\"integrator\": \"path\", \"rr_depth\": 4096}}",
    )
    .unwrap();
    let o = raytree(&["render", "p.json", "-o", "p.png"], d);
    fails_with(&o, "settings.rr_depth");
    fails_with(&o, "must be at most 1024, got 4096");
    fails_with(&o, "p.json:2:");
    assert!(!d.join("p.png").exists());
    // The JSON tree is schema 2 with the path fields.
    let o = raytree(
        &[
            "trace",
            "--integrator",
            "path",
            "--pixel",
            "400,300",
            "--json",
        ],
        d,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["schema"], "raytree.tree/2");
    assert_eq!(
        v["nodes"][0]["path"]["lpe"]
            .as_str()
            .unwrap()
            .chars()
            .next(),
        Some('C')
    );
    // The text tree prints the LPE; effects says what the path integrator ignores.
    let o = raytree(&["trace", "--integrator", "path", "--pixel", "400,300"], d);
    assert!(String::from_utf8_lossy(&o.stdout).contains("| C"));
    let o = raytree(&["effects", "--integrator", "path"], d);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("path integrator"), "{out}");
}
