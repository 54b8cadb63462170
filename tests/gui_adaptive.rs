//! The inspector's "denoised image" toggle on an adaptive scene (`settings.adaptive`) through
//! egui_kittest: the guide pass goes through the render's pixel loop, so the toggle works
//! (it said "not with adaptive antialiasing" before) and the image it filters is the adaptive
//! render's.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use raytree::gui::denoise_view::DenoiseState;
use raytree::gui::{Files, InspectorApp, Session};
use raytree::scene::AdaptiveDesc;
use std::path::Path;
use std::sync::Arc;
use std::time::SystemTime;

const CAUSTIC: &str = include_str!("../fixtures/caustic.json");

/// The caustic scene, read-only.
struct OneScene;

impl Files for OneScene {
    fn read(&self, _: &Path) -> std::io::Result<String> {
        Ok(CAUSTIC.to_owned())
    }
    fn modified(&self, _: &Path) -> Option<SystemTime> {
        Some(SystemTime::UNIX_EPOCH)
    }
    fn write(&self, _: &Path, _: &[u8]) -> std::io::Result<()> {
        Err(std::io::Error::other("read-only"))
    }
}

#[test]
fn the_denoise_toggle_works_on_an_adaptive_scene() {
    let adjust = Box::new(|s: &mut raytree::Scene| {
        s.settings.spp = 2;
        s.settings.adaptive = Some(AdaptiveDesc {
            threshold: 0.1,
            max_spp: Some(8),
        });
        s.camera = s.camera.with_size(64, 48);
        Ok(())
    });
    let session = Session::new(
        Some("caustic.json".into()),
        Box::new(OneScene),
        adjust,
        Arc::new(|| {}),
    );
    let mut h = Harness::builder()
        .with_size([1500.0, 950.0])
        .with_max_steps(16)
        .build_ui_state(
            |ui, app: &mut InspectorApp| app.show(ui),
            InspectorApp::new(session),
        );
    h.run();
    h.state_mut().session.wait_render();
    h.run();
    h.get_by_label("denoised image").click();
    let mut frames = 0;
    while !h.state().shows_denoised() && frames < 600 {
        h.run();
        std::thread::sleep(std::time::Duration::from_millis(10));
        frames += 1;
    }
    assert!(
        h.state().shows_denoised(),
        "no denoised image after {frames} frames: {:?}",
        h.state().denoise_state()
    );
    assert!(matches!(
        h.state().denoise_state(),
        Some(DenoiseState::Ready(_))
    ));
    let _ = h.get_by_label_contains("denoised in");
    // The document's image is the adaptive render's, some pixels refined.
    let scene = h.state().session.doc.scene.clone();
    let (raw, stats) = raytree::render::render(&scene, &|_| {});
    assert!(stats.refined_pixels > 0);
    assert!(h.state().session.doc.image.pixels == raw.pixels);
}
