//! The diagram of the document's selection: which sample is drawn, the library's
//! [`DiagramOptions`] for the panel and for the export (with the command line's title), and the
//! display list the panel paints. No egui: the session exports with these, the panel draws them.

use super::diagram_view::{DiagramView, PlaneChoice};
use super::document::Document;
use crate::diagram::paint::Prim;
use crate::diagram::{Diagram, DiagramOptions, PlaneSpec, Style, Theme, display_list};
use crate::tree::{NodeId, RayKind};

/// The sample holding node `id` (the overlay's rule).
pub(in crate::gui) fn sample_of(doc: &Document, id: NodeId) -> Option<usize> {
    let tree = doc.tree.as_ref()?;
    let mut cur = id;
    while let Some(p) = tree.nodes.get(cur.index())?.parent {
        cur = p;
    }
    tree.samples.iter().position(|s| s.root == cur)
}

// `DiagramView` is defined in `diagram_view.rs`, which the document holds; its methods read the
// document, so they are here and the document does not depend on them.
impl DiagramView {
    /// The sample drawn.
    #[must_use]
    pub fn sample(&self, doc: &Document) -> usize {
        self.sample
            .or_else(|| doc.node.and_then(|id| sample_of(doc, id)))
            .unwrap_or(0)
    }

    /// Library options for `doc` at `size`, the selection highlighted or not.
    #[must_use]
    pub fn options(&self, doc: &Document, size: [u32; 2], highlight: bool) -> DiagramOptions {
        let sample = self.sample(doc);
        let root = doc
            .tree
            .as_ref()
            .and_then(|t| t.samples.get(sample))
            .map_or(NodeId(0), |s| s.root);
        let plane = match self.plane {
            PlaneChoice::Auto => PlaneSpec::Auto,
            PlaneChoice::Incidence => PlaneSpec::Incidence,
            PlaneChoice::Camera => PlaneSpec::Camera,
            PlaneChoice::SelectedRay => PlaneSpec::Ray(doc.node.unwrap_or(root)),
            PlaneChoice::Axis { axis, value } => PlaneSpec::Axis { axis, value },
        };
        DiagramOptions {
            plane,
            width: size[0],
            height: size[1],
            // The panel's draw depth, and no deeper than the step-along-a-ray control shows.
            max_depth: match (self.draw_depth, doc.step.depth) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
            kinds: RayKind::ALL
                .into_iter()
                .zip(self.kinds)
                .filter_map(|(k, on)| on.then_some(k))
                .collect(),
            sample,
            zoom_offsets: self.zoom_offsets,
            highlight: if highlight { doc.node } else { None },
            label_depth: self.label_depth,
            min_share: self.min_share,
            zoom: self.zoom,
            pan: self.pan,
            all_samples: self.all_samples,
            ..DiagramOptions::default()
        }
    }
}

/// Diagram options for the document's selection at `size` pixels, as the panel draws them
/// (the selection highlighted).
#[must_use]
pub fn diagram_options(doc: &Document, size: [u32; 2]) -> DiagramOptions {
    doc.view.diagram.options(doc, size, true)
}

/// Diagram options for the export (1280x720): the panel's, the selection highlighted only when
/// "highlight the selection in exports" is on.
#[must_use]
pub fn export_options(doc: &Document) -> DiagramOptions {
    let v = doc.view.diagram;
    let mut opts = v.options(doc, [1280, 720], v.export_highlight);
    opts.title = export_title(doc, &opts);
    opts
}

/// The title line `raytree diagram` draws (`classic.json: pixel (400, 200), 17 rays`), so the
/// exported figure is the command line's.
fn export_title(doc: &Document, opts: &DiagramOptions) -> String {
    let (Some(tree), Some([x, y])) = (doc.tree.as_ref(), doc.selection) else {
        return String::new();
    };
    let name = doc
        .source
        .path
        .as_ref()
        .and_then(|p| p.file_name())
        .map_or("built-in classic".to_string(), |n| {
            n.to_string_lossy().into_owned()
        });
    let index = tree.samples.get(opts.sample).map_or(0, |s| s.index);
    let sample = if tree.samples.len() > 1 && opts.all_samples {
        format!(
            ", all {} samples (sample {index} in full)",
            tree.samples.len()
        )
    } else if tree.samples.len() > 1 || index > 0 {
        format!(", sample {index}")
    } else {
        String::new()
    };
    format!(
        "{name}: pixel ({x}, {y}){sample}, {} rays",
        tree.nodes.len()
    )
}

/// Build the display list of the selected pixel's diagram (what the panel paints).
pub fn build_display_list(doc: &Document, size: [u32; 2]) -> Result<Vec<Prim>, String> {
    let tree = doc.tree.as_ref().ok_or("select a pixel")?;
    let d =
        Diagram::build(&doc.scene, tree, &diagram_options(doc, size)).map_err(|e| e.to_string())?;
    Ok(display_list(&d, &Style::new(Theme::Dark)))
}
