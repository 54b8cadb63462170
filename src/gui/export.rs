//! Export formats, encoded in memory (the [`super::Files`] hook writes them).

use crate::render::Image;
use crate::tree::RayTree;

/// What can be exported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportKind {
    /// The image, 8-bit sRGB PNG.
    ImagePng,
    /// The image, linear float OpenEXR.
    ImageExr,
    /// The selected pixel's tree, JSON (`raytree.tree/1`).
    TreeJson,
    /// The selected pixel's diagram, SVG.
    DiagramSvg,
    /// The selected pixel's diagram, PNG.
    DiagramPng,
}

impl ExportKind {
    /// All kinds, in button order.
    pub const ALL: [ExportKind; 5] = [
        ExportKind::ImagePng,
        ExportKind::ImageExr,
        ExportKind::TreeJson,
        ExportKind::DiagramSvg,
        ExportKind::DiagramPng,
    ];

    /// Button label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            ExportKind::ImagePng => "image PNG",
            ExportKind::ImageExr => "image EXR",
            ExportKind::TreeJson => "tree JSON",
            ExportKind::DiagramSvg => "diagram SVG",
            ExportKind::DiagramPng => "diagram PNG",
        }
    }

    /// File-name suffix appended to the export base (`scene` -> `scene.png`,
    /// `scene-tree-x-y.json`).
    #[must_use]
    pub fn file_name(self, base: &str, pixel: Option<[u32; 2]>) -> String {
        let p = pixel.map_or(String::new(), |[x, y]| format!("-{x}-{y}"));
        match self {
            ExportKind::ImagePng => format!("{base}.png"),
            ExportKind::ImageExr => format!("{base}.exr"),
            ExportKind::TreeJson => format!("{base}-tree{p}.json"),
            ExportKind::DiagramSvg => format!("{base}-diagram{p}.svg"),
            ExportKind::DiagramPng => format!("{base}-diagram{p}.png"),
        }
    }
}

/// 8-bit sRGB PNG bytes.
pub fn png(image: &Image) -> Result<Vec<u8>, String> {
    crate::codec::png(image).map_err(|e| e.to_string())
}

/// Linear float OpenEXR bytes.
pub fn exr(image: &Image) -> Result<Vec<u8>, String> {
    crate::codec::exr(image).map_err(|e| e.to_string())
}

/// Pretty JSON of a tree.
pub fn tree_json(tree: &RayTree) -> Result<Vec<u8>, String> {
    serde_json::to_vec_pretty(tree).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodings_have_their_magic_numbers() {
        let mut scene = crate::Scene::default_scene();
        scene.camera = scene.camera.with_size(8, 4);
        let (img, _) = crate::render(&scene, &|_| {});
        assert_eq!(&png(&img).unwrap()[1..4], b"PNG");
        assert_eq!(&exr(&img).unwrap()[..4], &[0x76, 0x2f, 0x31, 0x01]);
        let tree = crate::trace_pixel(&scene, 3, 2).unwrap();
        let back: RayTree = serde_json::from_slice(&tree_json(&tree).unwrap()).unwrap();
        assert_eq!(back.nodes.len(), tree.nodes.len());
        assert_eq!(
            ExportKind::TreeJson.file_name("a/b", Some([3, 2])),
            "a/b-tree-3-2.json"
        );
    }
}
