//! Two integrators side by side in the inspector (issues 16 and 30): the scene rendered by
//! both on a thread of its own, shown side by side with the signed difference. Whitted and
//! path ([`crate::aov::versus`], as `raytree versus`) break the difference down by light
//! transport class ("what Whitted misses here: 79% caustics, 21% indirect"); any other pair
//! (path and bdpt, light and path...) is tested against the noise ([`crate::aov::pair`], as
//! `raytree versus --pair`).

use crate::Scene;
use crate::aov::{ClassShare, pair, versus};
use crate::aov::{Pair, PairSteps, Versus, VersusSteps};
use crate::gui::jobs::background::{Inbox, Work, deliver};
use crate::gui::model::document::Document;
use crate::scene::IntegratorKind;
use egui::{ColorImage, TextureHandle, TextureOptions};
use std::path::PathBuf;
use std::sync::Arc;

/// What a comparison was made from: the scene file and the scene as set.
#[derive(Clone)]
struct Made {
    path: Option<PathBuf>,
    scene: Arc<Scene>,
}

/// A finished comparison as the panel shows it, made on the job's thread.
struct Outcome {
    summary: String,
    /// The summary's class table as rows (class, expression, luminance, Whitted renders it),
    /// shown in a grid rather than as spaced text (issue 32: it was misaligned); Whitted and
    /// path only.
    classes: Vec<ClassShare>,
    width: u32,
    /// sRGB of side A, side B and the signed difference B - A.
    images: [Vec<u8>; 3],
}

/// The comparison the panel shows.
struct Done {
    made: Made,
    kinds: [IntegratorKind; 2],
    summary: String,
    classes: Vec<ClassShare>,
    textures: [TextureHandle; 3],
    /// The render generation its staleness was last checked at, and whether it was stale then.
    checked: Option<(u64, bool)>,
}

/// A running comparison: what it was made from, its pair, and where its outcome arrives.
type Pending = (Made, [IntegratorKind; 2], Inbox<Result<Outcome, String>>);

/// The "Compare integrators" section: the pair chosen, its running job and its last result.
pub struct VersusPanel {
    kinds: [IntegratorKind; 2],
    pending: Option<Pending>,
    done: Option<Done>,
}

impl Default for VersusPanel {
    fn default() -> Self {
        Self {
            kinds: [IntegratorKind::Whitted, IntegratorKind::Path],
            pending: None,
            done: None,
        }
    }
}

/// An integrator's name in the panel (`Whitted`, as the lecture writes it; the others as the
/// command line does).
fn label(k: IntegratorKind) -> &'static str {
    match k {
        IntegratorKind::Whitted => "Whitted",
        k => k.name(),
    }
}

/// Render `scene` with both `kinds` and compare them: by light transport class for Whitted and
/// path, against the noise for any other pair.
fn compare(scene: &Scene, kinds: [IntegratorKind; 2]) -> Result<Outcome, String> {
    if by_class(kinds) {
        let v = versus(scene, None, &|_| {}).map_err(|e| e.to_string())?;
        return Ok(versus_outcome(&v));
    }
    let p = pair(scene, kinds, None, &mut |s| {
        crate::render::render(
            &crate::integrator::SceneIntegrator::new(s),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
    });
    Ok(pair_outcome(&p))
}

/// Whether the pair is compared by light transport class (Whitted and path).
fn by_class(kinds: [IntegratorKind; 2]) -> bool {
    kinds == [IntegratorKind::Whitted, IntegratorKind::Path]
}

fn flat(px: Vec<[u8; 3]>) -> Vec<u8> {
    px.into_iter().flatten().collect()
}

fn versus_outcome(v: &Versus) -> Outcome {
    Outcome {
        summary: v.summary(),
        classes: v.classes.clone(),
        width: v.whitted.width,
        images: [
            v.whitted.to_srgb8(),
            v.path.beauty.to_srgb8(),
            flat(v.difference_rgb8().0),
        ],
    }
}

fn pair_outcome(p: &Pair) -> Outcome {
    Outcome {
        summary: p.summary(),
        classes: Vec::new(),
        width: p.a.image.width,
        images: [
            p.a.image.to_srgb8(),
            p.b.image.to_srgb8(),
            flat(p.difference_rgb8().0),
        ],
    }
}

/// The comparison as a background job: [`compare`] whole natively; a pixel at a time on
/// wasm32 ([`VersusSteps`], [`PairSteps`]: the same renders).
struct Comparison {
    scene: Arc<Scene>,
    kinds: [IntegratorKind; 2],
    steps: Option<Stepped>,
}

enum Stepped {
    Versus(Box<VersusSteps>),
    Pair(Box<PairSteps>),
}

impl Work for Comparison {
    type Out = Result<Outcome, String>;

    fn whole(self) -> Self::Out {
        compare(&self.scene, self.kinds)
    }

    fn piece(&mut self, more_time: &dyn Fn() -> bool) -> Option<Self::Out> {
        let (scene, kinds) = (&self.scene, self.kinds);
        let steps = self.steps.get_or_insert_with(|| {
            if by_class(kinds) {
                Stepped::Versus(Box::new(VersusSteps::new(scene, None)))
            } else {
                Stepped::Pair(Box::new(PairSteps::new(scene, kinds, None)))
            }
        });
        let more = match steps {
            Stepped::Versus(v) => v.step(more_time),
            Stepped::Pair(p) => p.step(more_time),
        };
        if more {
            return None;
        }
        Some(Ok(match self.steps.take()? {
            Stepped::Versus(v) => versus_outcome(&v.finish()),
            Stepped::Pair(p) => pair_outcome(&p.finish()),
        }))
    }
}

/// Whether a comparison made from `a` still shows `b`: the same scene in every respect but the
/// integrator (the comparison renders both, so switching the integrator leaves it current; a
/// sampler left to the integrator's default is the same too).
fn same_comparison(a: &Scene, b: &Scene) -> bool {
    if std::ptr::eq(a, b) {
        return true;
    }
    let mut settings = a.settings;
    settings.integrator = b.settings.integrator;
    settings == b.settings
        && a.camera == b.camera
        && a.background == b.background
        && a.ambient == b.ambient
        && a.materials == b.materials
        && a.objects == b.objects
        && a.lights == b.lights
}

fn texture(ctx: &egui::Context, name: &str, w: u32, rgb: &[u8]) -> TextureHandle {
    let h = rgb.len() / 3 / (w as usize).max(1);
    let image = ColorImage::from_rgb([w as usize, h], rgb);
    ctx.load_texture(name, image, TextureOptions::NEAREST)
}

impl VersusPanel {
    /// Whether a comparison is running.
    #[must_use]
    pub fn running(&self) -> bool {
        self.pending.is_some()
    }

    /// The last comparison's summary, if any.
    #[must_use]
    pub fn summary(&self) -> Option<&str> {
        self.done.as_ref().map(|d| d.summary.as_str())
    }

    /// Forget a comparison (finished or running) made from another scene file than the one
    /// open now (issue 32: after opening another scene the panel kept the previous scene's
    /// images and numbers).
    fn forget_other_files(&mut self, doc: &Document) {
        let path = &doc.source.path;
        if self.done.as_ref().is_some_and(|d| &d.made.path != path) {
            self.done = None;
        }
        if self.pending.as_ref().is_some_and(|p| &p.0.path != path) {
            self.pending = None;
        }
    }

    /// Whether the comparison shown was made from another scene than the one set now (checked
    /// once per render generation).
    fn stale(&mut self, doc: &Document) -> bool {
        let generation = doc.progress.generation;
        let Some(done) = &mut self.done else {
            return false;
        };
        match done.checked {
            Some((g, stale)) if g == generation => stale,
            _ => {
                let stale = !same_comparison(&done.made.scene, &doc.scene);
                done.checked = Some((generation, stale));
                stale
            }
        }
    }

    /// Take a finished job's outcome, if one has arrived (every frame, the section open or
    /// not).
    pub fn poll(&mut self, ctx: &egui::Context) {
        let Some((made, kinds, rx)) = &self.pending else {
            return;
        };
        let Some(result) = rx.try_recv() else {
            return;
        };
        let (made, kinds) = (made.clone(), *kinds);
        self.pending = None;
        self.done = Some(match result {
            Ok(o) => Done {
                made,
                kinds,
                checked: None,
                summary: o.summary,
                classes: o.classes,
                textures: [0, 1, 2]
                    .map(|i| texture(ctx, &format!("versus-{i}"), o.width, &o.images[i])),
            },
            Err(e) => Done {
                made,
                kinds,
                checked: None,
                summary: format!("the comparison failed: {e}"),
                classes: Vec::new(),
                textures: std::array::from_fn(|_| texture(ctx, "versus-empty", 1, &[0, 0, 0])),
            },
        });
    }

    /// The two integrators to compare, as two menus.
    fn pair_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            for (i, side) in ["A", "B"].into_iter().enumerate() {
                egui::ComboBox::from_label(side)
                    .selected_text(label(self.kinds[i]))
                    .show_ui(ui, |ui| {
                        for k in IntegratorKind::ALL {
                            ui.selectable_value(&mut self.kinds[i], k, label(k));
                        }
                    });
            }
        });
    }

    /// Start the comparison of the pair chosen for the scene as set (as its button does).
    pub fn start(&mut self, ctx: &egui::Context, doc: &Document) {
        let scene = Arc::clone(&doc.scene);
        let kinds = self.kinds;
        let repaint = ctx.clone();
        let work = Comparison {
            scene,
            kinds,
            steps: None,
        };
        let spawned = deliver(
            "raytree-versus",
            Some(crate::integrator::THREAD_STACK_BYTES),
            work,
            move || repaint.request_repaint(),
        );
        if let Ok(rx) = spawned {
            let made = Made {
                path: doc.source.path.clone(),
                scene: Arc::clone(&doc.scene),
            };
            self.pending = Some((made, kinds, rx));
        }
    }

    /// The section: the pair, a button that (re)starts the comparison for the scene as set,
    /// then the three images (A, B, B - A) and the breakdown or the test against the noise.
    pub fn ui(&mut self, ui: &mut egui::Ui, doc: &Document) {
        let ctx = ui.ctx().clone();
        self.forget_other_files(doc);
        let stale = self.stale(doc);
        self.pair_ui(ui);
        let [a, b] = self.kinds;
        ui.horizontal_wrapped(|ui| {
            let again = self
                .done
                .as_ref()
                .is_some_and(|d| !stale && d.kinds == self.kinds);
            let text = if again {
                "compare again".to_string()
            } else {
                format!("compare {} and {}", label(a), label(b))
            };
            let hover = if a == b {
                "choose two different integrators"
            } else {
                "render the scene with both integrators (each at the scene's spp)"
            };
            if ui
                .add_enabled(!self.running() && a != b, egui::Button::new(text))
                .on_hover_text(hover)
                .on_disabled_hover_text(hover)
                .clicked()
            {
                self.start(&ctx, doc);
            }
            if self.running() {
                ui.spinner();
                ui.label("rendering both...");
            }
        });
        let Some(done) = &self.done else {
            return;
        };
        if stale {
            ui.small("(made before the last settings change)");
        }
        let [na, nb] = done.kinds.map(label);
        let width = (ui.available_width() / 3.0 - 6.0).max(40.0);
        let captions = [na.to_string(), nb.to_string(), format!("{nb} - {na}")];
        ui.horizontal(|ui| {
            for (t, caption) in done.textures.iter().zip(&captions) {
                ui.vertical(|ui| {
                    let size = t.size_vec2();
                    let scale = width / size.x.max(1.0);
                    ui.image((t.id(), size * scale));
                    ui.small(caption.as_str());
                });
            }
        });
        ui.small(format!(
            "difference: red where {nb} is brighter, blue where {na} is"
        ));
        // The summary's sentences wrap; its table is a grid, one cell per column.
        let prose = done
            .summary
            .split("\nclass ")
            .next()
            .unwrap_or(&done.summary);
        ui.small(prose);
        classes_ui(ui, &done.classes);
    }
}

/// The class table: class, expression, luminance (right-aligned), whether Whitted renders it.
fn classes_ui(ui: &mut egui::Ui, classes: &[ClassShare]) {
    if classes.is_empty() {
        return;
    }
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
    let mono = |t: String| egui::RichText::new(t).monospace();
    egui::Grid::new("versus-classes")
        .striped(true)
        .num_columns(4)
        .show(ui, |ui| {
            for h in ["class", "expression", "luminance", "Whitted renders it"] {
                ui.label(egui::RichText::new(h).strong());
            }
            ui.end_row();
            for c in classes {
                ui.label(c.name);
                ui.label(mono(c.lpe.to_string()));
                // Monospace and padded: the decimal points line up.
                ui.label(mono(format!("{:>12.4}", c.luminance)));
                ui.label(if c.whitted { "yes" } else { "no" });
                ui.end_row();
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comparison of the caustic at 12x9, 2 spp, whole and a pixel at a time.
    fn both(kinds: [IntegratorKind; 2]) -> [Outcome; 2] {
        let mut scene = Scene::from_json(include_str!("../../../fixtures/caustic.json")).unwrap();
        scene.camera = scene.camera.with_size(12, 9);
        scene.settings.spp = 2;
        let job = || Comparison {
            scene: Arc::new(scene.clone()),
            kinds,
            steps: None,
        };
        let whole = job().whole().unwrap();
        let mut stepped = job();
        let mut n = 1;
        let out = loop {
            match stepped.piece(&|| false) {
                Some(out) => break out.unwrap(),
                None => n += 1,
            }
        };
        // Each side's camera pass, and the light pass of light tracing and BDPT.
        let passes: usize = kinds.iter().map(|k| 1 + usize::from(k.splats())).sum();
        assert_eq!(n, passes * 12 * 9, "a pixel a piece");
        [whole, out]
    }

    #[test]
    fn a_stepped_comparison_is_the_whole_comparison() {
        for kinds in [
            [IntegratorKind::Whitted, IntegratorKind::Path],
            [IntegratorKind::Light, IntegratorKind::Bdpt],
        ] {
            let [a, b] = both(kinds);
            assert_eq!(a.summary, b.summary);
            assert_eq!(a.classes, b.classes);
            assert_eq!((a.width, &a.images), (b.width, &b.images));
        }
    }
}
