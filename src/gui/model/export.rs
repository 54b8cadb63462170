//! Export formats, encoded in memory (the [`crate::gui::Files`] hook writes them).

use crate::render::Image;
use crate::tree::RayTree;

/// What can be exported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportKind {
    /// The image, 8-bit sRGB PNG.
    ImagePng,
    /// The image, linear float OpenEXR.
    ImageExr,
    /// The selected pixel's tree, JSON (`raytree.tree/2`).
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

/// Linear float OpenEXR bytes, and the warning `render` gives when channels beyond the 32-bit
/// float range (or NaN) had to be clamped.
pub fn exr(image: &Image) -> Result<(Vec<u8>, Option<String>), String> {
    let (bytes, clamped) = crate::codec::exr_clamped(image).map_err(|e| e.to_string())?;
    let warning = (clamped > 0).then(|| {
        format!(
            "{clamped} pixels had a channel beyond the 32-bit float range (3.4e38) and were clamped to it"
        )
    });
    Ok((bytes, warning))
}

/// Pretty JSON of a tree; refused, as by `raytree trace --json`, when the tree holds a NaN or an
/// infinity (JSON would write it as `null`, which reads as "absent").
pub fn tree_json(tree: &RayTree) -> Result<Vec<u8>, String> {
    if let Some(at) = crate::finite::first_nonfinite(tree) {
        return Err(format!(
            "the tree holds a non-finite number at {at}; JSON cannot carry it, so none was written (the tree panel shows it)"
        ));
    }
    serde_json::to_vec_pretty(tree).map_err(|e| e.to_string())
}

/// The warning `raytree diagram` gives when shapes with non-finite coordinates were left out of
/// an SVG.
#[must_use]
pub fn svg_warning(dropped: usize) -> Option<String> {
    (dropped > 0).then(|| {
        format!(
            "{dropped} shapes with non-finite coordinates (not a number or infinite) were left out"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodings_have_their_magic_numbers() {
        let mut scene = crate::Scene::default_scene();
        scene.camera = scene.camera.with_size(8, 4);
        let (img, _, _) = crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
        .into_parts();
        assert_eq!(&png(&img).unwrap()[1..4], b"PNG");
        let (bytes, warning) = exr(&img).unwrap();
        assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01]);
        assert_eq!(warning, None);
        let tree = crate::trace_pixel(&scene, 3, 2).unwrap();
        let back: RayTree = serde_json::from_slice(&tree_json(&tree).unwrap()).unwrap();
        assert_eq!(back.nodes.len(), tree.nodes.len());
        assert_eq!(
            ExportKind::TreeJson.file_name("a/b", Some([3, 2])),
            "a/b-tree-3-2.json"
        );
    }

    #[test]
    fn non_finite_values_are_clamped_with_a_warning_or_refused() {
        let mut scene = crate::Scene::default_scene();
        scene.camera = scene.camera.with_size(8, 4);
        let mut img = crate::render(
            &crate::integrator::SceneIntegrator::new(&scene),
            &crate::render::RenderOptions::new(),
            &|_| {},
        )
        .image;
        img.pixels[1].x = 1e42;
        img.pixels[2].y = f64::NAN;
        let (bytes, warning) = exr(&img).unwrap();
        assert_eq!(
            warning.as_deref(),
            Some(
                "2 pixels had a channel beyond the 32-bit float range (3.4e38) and were clamped to it"
            )
        );
        let back = image::load_from_memory(&bytes).unwrap().into_rgb32f();
        assert!(back.pixels().flat_map(|p| p.0).all(f32::is_finite));
        let mut tree = crate::trace_pixel(&scene, 3, 2).unwrap();
        tree.nodes[1].radiance.z = f64::INFINITY;
        let e = tree_json(&tree).unwrap_err();
        assert!(
            e.contains("non-finite number at nodes[1].radiance[2]"),
            "{e}"
        );
        assert_eq!(svg_warning(0), None);
        assert!(svg_warning(3).unwrap().starts_with("3 shapes"));
    }
}
