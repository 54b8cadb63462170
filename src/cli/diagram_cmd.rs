//! `raytree diagram`.

use super::args::DiagramArgs;
use super::load::{load, pair};
use super::output::{Inputs, Pending};
use super::say::{sayln, warnln};
use anyhow::{Result, anyhow, bail};
use raytree::RayKind;
use raytree::diagram::{Diagram, DiagramOptions, PlaneSpec, Style, Theme, to_png, to_svg_counting};

#[derive(Clone, Copy, PartialEq, Eq)]
enum Format {
    Svg,
    Png,
}

fn parse_kinds(s: &str) -> Result<Vec<RayKind>> {
    let mut kinds = Vec::new();
    for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let k = RayKind::ALL
            .into_iter()
            .find(|k| k.name() == part)
            .ok_or_else(|| {
                anyhow!(
                    "--kinds: unknown kind {part:?} (expected camera, reflected, refracted, shadow, diffuse)"
                )
            })?;
        kinds.push(k);
    }
    if kinds.is_empty() {
        bail!("--kinds: name at least one kind");
    }
    Ok(kinds)
}

/// What the flags say about the figure, checked before the scene is loaded.
struct Figure {
    format: Format,
    /// The pixel whose tree is drawn.
    pixel: (u32, u32),
    plane: PlaneSpec,
    width: u32,
    height: u32,
    theme: Theme,
    kinds: Vec<RayKind>,
    lpes: Vec<raytree::lpe::Lpe>,
}

impl Figure {
    /// Parse and check every flag of the figure, in the order the errors have always come.
    fn parse(a: &DiagramArgs) -> Result<Self> {
        let format = match a
            .output
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("svg") => Format::Svg,
            Some("png") => Format::Png,
            _ => bail!(
                "cannot write {}: the output must end in .svg or .png",
                a.output.display()
            ),
        };
        let pixel = pair("pixel", &a.pixel, ',')?;
        let plane = match a.plane_ray {
            Some(id) => PlaneSpec::Ray(raytree::NodeId(id)),
            None => PlaneSpec::parse(&a.plane).map_err(|e| anyhow!("--plane: {e}"))?,
        };
        if !(0.0..=1.0).contains(&a.min_share) {
            bail!(
                "--min-share: must be a share of the pixel in 0..=1 (0 draws every ray), got {}",
                a.min_share
            );
        }
        let (width, height) = match &a.overrides.size {
            Some(s) => pair("size", s, 'x')?,
            None => (1280, 720),
        };
        if !(64..=16384).contains(&width) || !(64..=16384).contains(&height) {
            bail!(
                "--size: the figure's width and height must be in 64..=16384, got {width}x{height}"
            );
        }
        let theme = match a.theme.as_str() {
            "light" => Theme::Light,
            "dark" => Theme::Dark,
            t => bail!("--theme: unknown theme {t:?} (expected light or dark)"),
        };
        let kinds = a
            .kinds
            .as_deref()
            .map_or_else(|| Ok(RayKind::ALL.to_vec()), parse_kinds)?;
        let lpes = super::trace_cmd::parse_lpes(&a.lpe)?;
        Ok(Self {
            format,
            pixel,
            plane,
            width,
            height,
            theme,
            kinds,
            lpes,
        })
    }
}

/// Draw the cross-section diagram of one pixel's ray tree to an SVG or PNG file.
pub fn run(a: &DiagramArgs) -> Result<()> {
    let fig = Figure::parse(a)?;
    let (x, y) = fig.pixel;
    let mut overrides = a.overrides.clone();
    overrides.size = None; // the figure's size, not the image's
    let loaded = load(a.scene.as_deref(), &overrides)?;
    let scene = &loaded.scene;
    let cam = &scene.camera;
    let Some(tree) = raytree::trace_pixel(scene, x, y) else {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            cam.width,
            cam.height
        );
    };
    // Only the paths matching --lpe (their ids renumbered, as `trace --lpe` prints them).
    let (tree, matched, _) = super::trace_cmd::filter_lpe(tree, &a.lpe, &fig.lpes)?;
    if !fig.lpes.is_empty() && tree.samples.is_empty() {
        bail!(
            "--lpe {}: no path of pixel {x},{y} matches, so there is nothing to draw",
            a.lpe.join(" | ")
        );
    }
    if let PlaneSpec::Ray(id) = fig.plane
        && id.index() >= tree.nodes.len()
    {
        bail!(
            "--plane-ray {}: the pixel's tree has {} rays (#0 to #{})",
            id.0,
            tree.nodes.len(),
            tree.nodes.len() - 1
        );
    }
    let position = sample_position(a, scene, &tree, &fig.lpes)?;
    let pending = Pending::create(
        &a.output,
        &Inputs::new(loaded.inputs.iter().map(|p| p.as_path())),
    )?;
    let title = title(a, &tree, fig.pixel, tree.samples[position].index, &matched);
    let (width, height) = (fig.width, fig.height);
    let opts = DiagramOptions {
        plane: fig.plane,
        width,
        height,
        max_depth: a.draw_depth,
        kinds: fig.kinds,
        sample: position,
        zoom_offsets: a.zoom_offsets,
        all_samples: a.all_samples,
        highlight: None,
        label_depth: a.label_depth,
        min_share: a.min_share,
        title,
        ..DiagramOptions::default()
    };
    let diagram = Diagram::build(scene, &tree, &opts)?;
    let bytes = encode(a, &diagram, &Style::new(fig.theme), fig.format);
    pending.commit(&bytes)?;
    sayln!(
        "wrote {} ({width}x{height}, {} rays drawn, {} left out under {} of the pixel, {} off the plane; {})",
        a.output.display(),
        diagram.rays.len(),
        diagram.dropped_rays,
        raytree::diagram::percent(a.min_share),
        diagram.off_plane_rays,
        diagram.plane_text
    )?;
    Ok(())
}

/// The position in `tree` of the sample drawn in full.
///
/// `--sample K` names the pixel's sample K (as `raytree trace` numbers them), also when
/// --lpe has dropped the samples without a matching path: its position in the tree.
/// Without it, the first sample the tree holds; with --all-samples, the one that carries
/// the most light (the figure is framed and labelled on it, so a black sample 0 would
/// frame the haze, not the light).
fn sample_position(
    a: &DiagramArgs,
    scene: &raytree::Scene,
    tree: &raytree::RayTree,
    lpes: &[raytree::lpe::Lpe],
) -> Result<usize> {
    let wanted = a.sample;
    let found = match wanted {
        None if a.all_samples => raytree::diagram::all_samples::brightest(tree),
        None => (!tree.samples.is_empty()).then_some(0),
        Some(k) => tree.samples.iter().position(|s| s.index as usize == k),
    };
    let Some(position) = found else {
        let k = wanted.unwrap_or(0);
        if lpes.is_empty() {
            bail!(
                "--sample {k}: the pixel has {} sample(s) (spp {})",
                tree.samples.len(),
                scene.settings.spp
            );
        }
        let kept: Vec<String> = tree.samples.iter().map(|s| s.index.to_string()).collect();
        bail!(
            "--sample {k}: it has no path matching --lpe {}; the samples that do: {}",
            a.lpe.join(" | "),
            kept.join(", ")
        );
    };
    Ok(position)
}

/// The figure's title: scene, pixel, the sample `index` drawn, rays, and the paths --lpe kept.
fn title(
    a: &DiagramArgs,
    tree: &raytree::RayTree,
    (x, y): (u32, u32),
    index: u32,
    matched: &str,
) -> String {
    let name = a
        .scene
        .as_ref()
        .and_then(|p| p.file_name())
        .map_or("built-in classic".to_string(), |n| {
            n.to_string_lossy().into_owned()
        });
    let sample = if tree.samples.len() > 1 && a.all_samples {
        format!(
            ", all {} samples (sample {} in full)",
            tree.samples.len(),
            index
        )
    } else if tree.samples.len() > 1 || index > 0 {
        format!(", sample {index}")
    } else {
        String::new()
    };
    format!(
        "{name}: pixel ({x}, {y}){sample}, {} rays{}",
        tree.nodes.len(),
        if matched.is_empty() {
            String::new()
        } else {
            format!(", {}", matched.trim_end())
        }
    )
}

/// The diagram as SVG or PNG bytes; an SVG warns about the shapes it had to leave out.
fn encode(a: &DiagramArgs, diagram: &Diagram, style: &Style, format: Format) -> Vec<u8> {
    match format {
        Format::Svg => {
            let (svg, dropped) = to_svg_counting(diagram, style);
            if dropped > 0 {
                warnln!(
                    "warning: {dropped} shapes with non-finite coordinates (not a number or infinite) were left out of {}",
                    a.output.display()
                );
            }
            svg.into_bytes()
        }
        Format::Png => to_png(diagram, style),
    }
}
