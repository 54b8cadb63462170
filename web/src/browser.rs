//! The wasm32 glue: start eframe on the page's canvas, the [`Host`] over the browser, and the
//! functions the page's JavaScript calls (`index.html` puts them on `window`: the test hooks
//! `raytreeSelectedTree()`, `raytreeState()`, `raytreePixelPosition(x, y)`, and the file
//! picker's and `hashchange`'s way in).

use crate::app::{Action, Host, Published, WebApp};
use raytree::gui::model::export::ExportKind;
use std::cell::RefCell;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

thread_local! {
    static ACTIONS: RefCell<Vec<Action>> = const { RefCell::new(Vec::new()) };
    static PUBLISHED: RefCell<Published> = RefCell::new(Published::default());
    static CONTEXT: RefCell<Option<egui::Context>> = const { RefCell::new(None) };
}

/// Queue `a` for the next frame and ask for that frame.
fn push(a: Action) {
    ACTIONS.with(|q| q.borrow_mut().push(a));
    CONTEXT.with(|c| {
        if let Some(ctx) = c.borrow().as_ref() {
            ctx.request_repaint();
        }
    });
}

struct Browser;

impl Host for Browser {
    fn now_ms(&self) -> f64 {
        web_sys::window()
            .and_then(|w| w.performance())
            .map_or(0.0, |p| p.now())
    }

    fn take_actions(&self) -> Vec<Action> {
        ACTIONS.with(|q| std::mem::take(&mut *q.borrow_mut()))
    }

    fn set_hash(&self, fragment: &str) {
        // replaceState: no `hashchange`, no history entry per click.
        if let Some(h) = web_sys::window().and_then(|w| w.history().ok()) {
            let _ = h.replace_state_with_url(&JsValue::NULL, "", Some(&format!("#{fragment}")));
        }
    }

    fn pick_files(&self) {
        if let Some(input) =
            element("raytree-file").and_then(|e| e.dyn_into::<web_sys::HtmlElement>().ok())
        {
            input.click();
        }
    }

    fn publish(&self, state: &Published) {
        PUBLISHED.with(|p| *p.borrow_mut() = state.clone());
    }
}

fn element(id: &str) -> Option<web_sys::Element> {
    web_sys::window()?.document()?.get_element_by_id(id)
}

/// Hand `bytes` to the browser as a download named `name`.
fn download(name: &str, bytes: &[u8]) -> std::io::Result<()> {
    let fail = |what: &str| std::io::Error::other(format!("cannot download {name}: {what}"));
    let array = js_sys::Uint8Array::from(bytes);
    let parts = js_sys::Array::of1(&array);
    let blob = web_sys::Blob::new_with_u8_array_sequence(&parts).map_err(|_| fail("no Blob"))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(|_| fail("no URL"))?;
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or_else(|| fail("no document"))?;
    let a: web_sys::HtmlAnchorElement = document
        .create_element("a")
        .map_err(|_| fail("no link"))?
        .dyn_into()
        .map_err(|_| fail("no link"))?;
    a.set_href(&url);
    a.set_download(name);
    a.click();
    let _ = web_sys::Url::revoke_object_url(&url);
    Ok(())
}

/// Start the page (wasm-bindgen calls this when the module is instantiated).
#[wasm_bindgen(start)]
pub fn start() {
    wasm_bindgen_futures::spawn_local(async {
        let Some(canvas) =
            element("raytree-canvas").and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        else {
            return;
        };
        let hash = web_sys::window()
            .and_then(|w| w.location().hash().ok())
            .unwrap_or_default();
        let result = eframe::WebRunner::new()
            .start(
                canvas,
                eframe::WebOptions::default(),
                Box::new(move |cc| {
                    let ctx = cc.egui_ctx.clone();
                    CONTEXT.with(|c| *c.borrow_mut() = Some(ctx.clone()));
                    let repaint = std::sync::Arc::new(move || ctx.request_repaint());
                    Ok(Box::new(WebApp::new(
                        Box::new(Browser),
                        download,
                        &hash,
                        repaint,
                    )))
                }),
            )
            .await;
        if let Err(e) = result
            && let Some(el) = element("raytree-status")
        {
            el.set_text_content(Some(&format!("the inspector could not start: {e:?}")));
        }
    });
}

/// The selected tree as the tree JSON export writes it (`null` without a selection).
#[wasm_bindgen]
pub fn raytree_selected_tree() -> Option<String> {
    PUBLISHED.with(|p| p.borrow().tree_json.clone())
}

/// The page's state as a JSON object (scene, progress, selection, frame times, messages).
#[wasm_bindgen]
pub fn raytree_state() -> String {
    PUBLISHED.with(|p| p.borrow().state_json.clone())
}

/// Canvas coordinates (CSS pixels) of the centre of image pixel (x, y) as drawn last frame,
/// and the image's zoom (CSS pixels per image pixel).
#[wasm_bindgen]
pub fn raytree_pixel_position(x: u32, y: u32) -> Option<Vec<f32>> {
    let [a, b] = PUBLISHED.with(|p| p.borrow().pixel_frame)?;
    let (x, y) = (x as f32, y as f32);
    let zoom = b[0] - a[0];
    Some(vec![a[0] + zoom * x, a[1] + (b[1] - a[1]) * y, zoom])
}

/// The fragment changed (`hashchange`).
#[wasm_bindgen]
pub fn raytree_hash_changed(hash: String) {
    push(Action::Fragment(hash));
}

/// A file from the picker: queued until [`raytree_upload_done`].
#[wasm_bindgen]
pub fn raytree_upload(name: String, bytes: Vec<u8>) {
    UPLOADS.with(|u| u.borrow_mut().push((name, bytes)));
}

thread_local! {
    static UPLOADS: RefCell<Vec<(String, Vec<u8>)>> = const { RefCell::new(Vec::new()) };
}

/// The picker's files are all given: open them.
#[wasm_bindgen]
pub fn raytree_upload_done() {
    let files = UPLOADS.with(|u| std::mem::take(&mut *u.borrow_mut()));
    push(Action::Upload(files));
}

/// Show `message` in the page's bar (a file the page refused before reading it).
#[wasm_bindgen]
pub fn raytree_message(message: String) {
    push(Action::Message(message));
}

/// The byte limit for an uploaded file named `name` (the page checks it before reading).
#[wasm_bindgen]
pub fn raytree_upload_limit(name: String) -> f64 {
    crate::files::limit_for(&name) as f64
}

/// The refusal message for a file over its limit.
#[wasm_bindgen]
pub fn raytree_too_large(name: String, size: f64) -> String {
    crate::files::too_large(&name, size as u64, crate::files::limit_for(&name))
}

/// Export as the Export buttons do: `image-png`, `image-exr`, `tree-json`, `diagram-svg` or
/// `diagram-png`; `false` for another name.
#[wasm_bindgen]
pub fn raytree_export(kind: String) -> bool {
    let kind = match kind.as_str() {
        "image-png" => ExportKind::ImagePng,
        "image-exr" => ExportKind::ImageExr,
        "tree-json" => ExportKind::TreeJson,
        "diagram-svg" => ExportKind::DiagramSvg,
        "diagram-png" => ExportKind::DiagramPng,
        _ => return false,
    };
    push(Action::Export(kind));
    true
}

/// Forget the worst frame time so far.
#[wasm_bindgen]
pub fn raytree_reset_frames() {
    push(Action::ResetFrames);
}

/// Start a background job as its button does: `versus` (the comparison of the integrators
/// chosen), `strategies` (the split by strategy), `denoise` (the denoised image) or `acne`
/// (the acne lab).
#[wasm_bindgen]
pub fn raytree_start(job: String) {
    push(Action::Start(job));
}
