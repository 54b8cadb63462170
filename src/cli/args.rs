//! Command-line arguments (clap derive).

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// raytree: a Whitted ray tracer and Monte Carlo path tracer that explains every pixel.
#[derive(Debug, Parser)]
#[command(name = "raytree", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render an image (PNG, sRGB 8-bit; or EXR, linear float).
    Render(RenderArgs),
    /// Print the full ray tree of one pixel.
    Trace(TraceArgs),
    /// Sweep offset strategies x epsilons x scene scales; count self-hit (acne) and leak pixels.
    Acne(AcneArgs),
    /// Print which effects the scene calls for, and why.
    Effects(EffectsArgs),
    /// Measure what accuracy costs in time: a settings sweep against a reference.
    Cost(CostArgs),
    /// Compare two images (PNG or EXR): error metrics and a false-colour error map.
    Compare(CompareArgs),
    /// Convergence: rel-RMSE against a reference versus spp and seconds, per series (log-log
    /// plot, CSV, fitted slopes).
    Converge(ConvergeArgs),

    /// Open the inspector window: click a pixel, see its ray tree.
    View(ViewArgs),
    /// Draw a cross-section diagram of one pixel's ray tree (SVG or PNG).
    Diagram(DiagramArgs),
    /// Explain one pixel in a few sentences: what it sees, where energy went, what is suspicious.
    Explain(ExplainArgs),
    /// Trace one pixel under two sets of overrides (or two scenes) and print where the trees differ.
    Diff(DiffArgs),
    /// Whitted vs path tracing side by side, the difference image, and what Whitted misses by
    /// light path class; or any two integrators (--pair) and whether they differ beyond the noise.
    Versus(VersusArgs),
    /// Convert a pbrt-v4 or Mitsuba 3 scene (or raytree JSON) to raytree JSON, listing what was
    /// approximated.
    Convert(ConvertArgs),
    /// The worst pixels: ranked by their excess over a robust neighbourhood estimate (and, for
    /// a scene, by the standard error of their mean), with the trace/explain command for each.
    Outliers(OutliersArgs),
    /// Veach's figure: the bidirectional render split by strategy (s, t), one image per
    /// strategy weighted and unweighted, a labelled contact sheet and each strategy's share.
    Strategies(StrategiesArgs),
}

/// Settings every tracing command can override (defaults come from the scene file).
#[derive(Debug, Clone, Default, Args)]
pub struct Overrides {
    /// Image size WIDTHxHEIGHT.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Samples per pixel (stratified, box filter).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Deepest recursion (0 = camera and shadow rays only).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Offset epsilon in world units.
    #[arg(long, allow_hyphen_values = true)]
    pub epsilon: Option<f64>,
    /// Offset strategy: normal (P +/- eps N), ray (t_min = eps), scaled (eps relative to |P|)
    /// or robust (floating-point error bounds, ignores --epsilon).
    #[arg(long, value_name = "normal|ray|scaled|robust")]
    pub offset: Option<String>,
    /// Fresnel model.
    #[arg(long, value_name = "exact|schlick|none")]
    pub fresnel: Option<String>,
    /// Shadow rays through transmissive objects.
    #[arg(long, value_name = "opaque|translucent")]
    pub shadows: Option<String>,
    /// Stop rays whose throughput falls below this (0 = the exhaustive tree; default: chosen
    /// from --tolerance and the scene).
    #[arg(long, allow_hyphen_values = true)]
    pub min_weight: Option<f64>,
    /// What one cut branch may still add to a pixel, in display units (default 1/510, half an
    /// 8-bit step); sets the automatic min weight.
    #[arg(long, allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
    /// Per-sample ray budget: a sample that reaches it spawns no more secondary rays.
    #[arg(long)]
    pub max_rays: Option<u64>,
    /// Memory budget in MiB: commands refuse (before any work) what may need more [default:
    /// 4096, or half the address-space limit (`ulimit -v`) when that is smaller].
    #[arg(long, value_name = "MIB")]
    pub max_memory: Option<u64>,
    /// Integrator: whitted (the lecture's recursion), path (Monte Carlo path tracing), light
    /// (light tracing) or bdpt (bidirectional path tracing).
    #[arg(long, value_name = "whitted|path|light|bdpt")]
    pub integrator: Option<String>,
    /// Path integrator: Russian roulette from this bounce on (default 5).
    #[arg(long, value_name = "N")]
    pub rr_depth: Option<u32>,
    /// Bidirectional path tracing: the MIS heuristic over its strategies, balance (the
    /// default, pbrt's) or power (exponent 2, Mitsuba's).
    #[arg(long, value_name = "balance|power")]
    pub mis: Option<String>,
    /// Sampler: stratified or sobol (default: sobol under the path integrator, stratified
    /// under Whitted).
    #[arg(long, value_name = "stratified|sobol")]
    pub sampler: Option<String>,
    /// Seed of the per-pixel sample positions (0 = the default positions).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Shadow rays per area light (emissive sphere, quad, triangle) per hit; turns area
    /// lights on.
    #[arg(long, value_name = "N")]
    pub light_samples: Option<u32>,
    /// Rays sampled per rough reflection or refraction lobe (materials with roughness > 0)
    /// at the first rough hit of a path.
    #[arg(long, value_name = "N")]
    pub glossy_samples: Option<u32>,
    /// Thin-lens aperture radius in world units (0 = pinhole); sets camera.aperture_radius.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub aperture: Option<f64>,
    /// Distance of the plane in focus (> 0); sets camera.focus_distance.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub focus: Option<f64>,
    /// Pixel filter: box, tent:RADIUS or gaussian:SIGMA (radius 3 sigma), in pixels.
    #[arg(
        long,
        value_name = "box|tent:R|gaussian:SIGMA",
        allow_hyphen_values = true
    )]
    pub filter: Option<String>,
    /// What --spp means: auto (the default: where the image depends on the film position
    /// alone, every pixel takes max(2, spp/16) samples and only pixels on an edge go on to
    /// --spp) or uniform (every pixel takes --spp samples).
    #[arg(long, value_name = "auto|uniform")]
    pub antialiasing: Option<String>,
    /// Adaptive antialiasing: pixels whose first --spp samples (and their 8 neighbours' means)
    /// differ by more than this contrast ((max - min) / (max + min + 0.01) in a channel, e.g.
    /// 0.05) take --max-spp samples in all.
    #[arg(long, value_name = "THRESHOLD", allow_hyphen_values = true)]
    pub adaptive: Option<f64>,
    /// Adaptive antialiasing: samples of a refined pixel in all (default 16 x --spp).
    #[arg(long, value_name = "N")]
    pub max_spp: Option<u32>,
    /// From this depth on (0 = the camera ray's hit), a glass hit follows reflection or
    /// refraction chosen by Russian roulette instead of both (exact in expectation, noisy).
    #[arg(long, value_name = "DEPTH")]
    pub dielectric_roulette: Option<u32>,
    /// A glass hit whose throughput is below this weight follows reflection or refraction
    /// chosen by Russian roulette instead of both (0: always both; default: chosen from the
    /// scene's brightest radiance, see `raytree effects`).
    #[arg(long, value_name = "WEIGHT")]
    pub roulette_below: Option<f64>,
    /// Mitsuba scenes: give `$NAME` the value VALUE (overrides the scene's `<default>`);
    /// repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
}

/// `raytree render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Output image: .png or .exr.
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    /// Also count self-hit and leaking rays (extra intersections per ray).
    #[arg(long, conflicts_with_all = ["denoise", "features"])]
    pub diagnose: bool,
    /// Write the image denoised (edge-avoiding a-trous filter guided by albedo, normal and
    /// per-pixel variance; docs/denoise.md). Traced trees stay the raw samples.
    #[arg(long)]
    pub denoise: bool,
    /// Also write the denoiser's guide buffers beside the image: OUT.albedo.EXT and
    /// OUT.normal.EXT (the normal mapped from [-1, 1] to [0, 1]).
    #[arg(long)]
    pub features: bool,
    /// Also write the image of the paths matching a light path expression (OSL grammar, path
    /// integrator), NAME=LPE, to OUTPUT.NAME.png/.exr; repeatable.
    #[arg(long = "aov", value_name = "NAME=LPE")]
    pub aov: Vec<String>,
    /// Also write a Monte Carlo debug view with a legend to OUTPUT.view-VIEW.png: noise, spp,
    /// path-length, roulette, dropped or share:AOV; repeatable.
    #[arg(long = "debug-view", value_name = "VIEW")]
    pub debug_view: Vec<String>,
    /// Also write the samples each pixel took as a grey PNG (white = the most; with
    /// --adaptive, the refined pixels).
    #[arg(long, value_name = "PNG")]
    pub spp_map: Option<PathBuf>,
    /// Let the files this command derives from the output's name (`--features`, `--aov`,
    /// `--debug-view`) replace existing files of those names, which are refused otherwise.
    #[arg(long)]
    pub force: bool,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree trace`.
#[derive(Debug, Args)]
pub struct TraceArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Pixel X,Y (0,0 is top-left).
    #[arg(long, value_name = "X,Y")]
    pub pixel: String,
    /// Print JSON (schema raytree.tree/2) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Keep only the paths whose light path expression (OSL grammar, e.g. `C<RD>S+L`) matches;
    /// repeat for any of several. Needs the path integrator.
    #[arg(long, value_name = "EXPR")]
    pub lpe: Vec<String>,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree acne`.
#[derive(Debug, Args)]
pub struct AcneArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Offset strategies, comma-separated.
    #[arg(long, default_value = "normal,ray,scaled,robust")]
    pub strategies: String,
    /// Epsilons, comma-separated.
    #[arg(long, default_value = "1e-7,1e-6,1e-5,1e-4,1e-3,1e-2,1e-1")]
    pub epsilons: String,
    /// Scene scales, comma-separated (the scene is scaled about the origin, then moved away).
    #[arg(long, default_value = "1e-3,1e-2,1e-1,1,1e1,1e2,1e3,1e4,1e5,1e6")]
    pub scales: String,
    /// How far the scaled scene is moved from the origin, per unit scale and axis.
    #[arg(long, default_value_t = 1e3)]
    pub shift: f64,
    /// Size of each render, WIDTHxHEIGHT.
    #[arg(long, value_name = "WxH", default_value = "48x36")]
    pub size: String,
    /// Output directory (report.md, report.json, heat maps, plot.png); replaced if it holds an
    /// earlier report.
    #[arg(short, long, default_value = "acne-report")]
    pub output: PathBuf,
    /// Integrator: whitted (the lecture's recursion), path (Monte Carlo path tracing), light
    /// or bdpt; under light and bdpt only the camera's rays are diagnosed (the light subpaths
    /// are traced without the self-hit recorder).
    #[arg(long, value_name = "whitted|path|light|bdpt")]
    pub integrator: Option<String>,
    /// Path integrator: Russian roulette from this bounce on (default 5).
    #[arg(long, value_name = "N")]
    pub rr_depth: Option<u32>,
    /// Sampler: stratified or sobol (default: sobol under the path integrator, stratified
    /// under Whitted).
    #[arg(long, value_name = "stratified|sobol")]
    pub sampler: Option<String>,
    /// Seed of the per-pixel sample positions (0 = the default positions).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Shadow rays per area light (emissive sphere, quad, triangle) per hit; turns area
    /// lights on.
    #[arg(long, value_name = "N")]
    pub light_samples: Option<u32>,
    /// Rays sampled per rough reflection or refraction lobe at the first rough hit of a path.
    #[arg(long, value_name = "N")]
    pub glossy_samples: Option<u32>,
    /// Thin-lens aperture radius in world units (0 = pinhole); scaled with the scene.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub aperture: Option<f64>,
    /// Distance of the plane in focus (> 0); scaled with the scene.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub focus: Option<f64>,
    /// Pixel filter: box, tent:RADIUS or gaussian:SIGMA (radius 3 sigma), in pixels.
    #[arg(
        long,
        value_name = "box|tent:R|gaussian:SIGMA",
        allow_hyphen_values = true
    )]
    pub filter: Option<String>,
}

/// `raytree effects`.
#[derive(Debug, Args)]
pub struct EffectsArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Scene JSON (default: the built-in classic scene); reloaded when it changes on disk.
    pub scene: Option<PathBuf>,
    /// Select pixel X,Y at start.
    #[arg(long, value_name = "X,Y")]
    pub pixel: Option<String>,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree cost`.
#[derive(Debug, Args)]
pub struct CostArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Report directory (cost.md, cost.csv, cost.json, cost.png).
    #[arg(short, long, default_value = "cost-report")]
    pub output: PathBuf,
    /// A small sweep at 160x90 (default size 320x180).
    #[arg(long)]
    pub quick: bool,
    /// Timed repeats per setting (median reported); default 5, quick 3.
    #[arg(long)]
    pub repeats: Option<u32>,
    /// Settings overrides (the base of the sweep).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// First image (.png or .exr).
    pub a: PathBuf,
    /// Second image (.png or .exr).
    pub b: PathBuf,
    /// Write a false-colour error map here (.png).
    #[arg(short = 'o', long = "output")]
    pub map: Option<PathBuf>,
    /// Error shown at the map's ends (full red/blue, or white with --abs; default: the largest).
    #[arg(long, allow_hyphen_values = true)]
    pub scale: Option<f64>,
    /// Compare only the pixels X0 <= x < X1, Y0 <= y < Y1 (metrics, interval and map).
    #[arg(long, value_name = "X0,Y0,X1,Y1", allow_hyphen_values = true)]
    pub region: Option<String>,
    /// Write the unsigned map (largest channel |A - B|, black to white) instead of the signed one.
    #[arg(long)]
    pub abs: bool,
}

/// `raytree diagram`. Here `--size` is the figure's size (the scene's image size is kept, so
/// `--pixel` means the same pixel as in `render`); `--max-depth` is the tracer's limit.
#[derive(Debug, Args)]
#[command(mut_arg("size", |a| a.help("Figure size WIDTHxHEIGHT in pixels [default: 1280x720]")))]
pub struct DiagramArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Pixel X,Y (0,0 is top-left).
    #[arg(long, value_name = "X,Y")]
    pub pixel: String,
    /// Draw only the paths whose light path expression matches (as `trace --lpe`; repeat for
    /// any of several). Needs the path integrator.
    #[arg(long, value_name = "EXPR")]
    pub lpe: Vec<String>,
    /// Output figure: .svg or .png.
    #[arg(short, long, default_value = "diagram.svg")]
    pub output: PathBuf,
    /// Slicing plane: auto (default: the plane of incidence, or the plane of a first-bounce ray
    /// holding more of the pixel), incidence, camera, ray=N, x=V, y=V, z=V or PX,PY,PZ,NX,NY,NZ.
    #[arg(long, default_value = "auto", allow_hyphen_values = true)]
    pub plane: String,
    /// The plane through ray N (a node id of `raytree trace`) and its parent ray; same as
    /// --plane ray=N.
    #[arg(long, value_name = "N", conflicts_with = "plane")]
    pub plane_ray: Option<u32>,
    /// Leave out rays carrying less than this share of the pixel (0.01 = 1 %; 0 draws every
    /// ray). The legend says how many were left out and how much of the pixel they carry.
    #[arg(long, value_name = "F", default_value_t = raytree::diagram::MIN_SHARE, allow_hyphen_values = true)]
    pub min_share: f64,
    /// Colour theme.
    #[arg(long, value_name = "light|dark", default_value = "light")]
    pub theme: String,
    /// Draw rays up to this depth only (the tracer's own limit is --max-depth).
    #[arg(long, value_name = "N")]
    pub draw_depth: Option<u32>,
    /// Ray kinds to draw, comma-separated.
    #[arg(long, value_name = "camera,reflected,refracted,shadow,diffuse")]
    pub kinds: Option<String>,
    /// Which sample of the pixel to draw (for spp > 1), numbered as `raytree trace` numbers
    /// them; default: the first (with --lpe, the first with a matching path; with
    /// --all-samples, the one that carries the most light).
    #[arg(long, value_name = "K")]
    pub sample: Option<usize>,
    /// Also draw every other sample of the pixel under --sample, faded by its value.
    #[arg(long)]
    pub all_samples: bool,
    /// Zoomed insets at spawn points showing the offset epsilon to scale.
    #[arg(long)]
    pub zoom_offsets: bool,
    /// Label angles, indices, R/T and Beer factors on depths up to N.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub label_depth: u32,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Report directory (converge.md, converge.csv, converge.json, converge.png, and the
    /// cached reference.exr and reference.json).
    #[arg(short, long, default_value = "converge-report")]
    pub output: PathBuf,
    /// Reference image (.exr or .png) of the render's size (default: rendered by the scene's
    /// integrator at --ref-spp, cached in the report directory).
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,
    /// Samples per pixel of the rendered reference [default: 1024; --quick 256].
    #[arg(long, value_name = "N")]
    pub ref_spp: Option<u32>,
    /// The curves run over 1, 2, 4, ... up to this many samples per pixel [default: 64;
    /// --quick 16].
    #[arg(long, value_name = "N")]
    pub max_spp: Option<u32>,
    /// Comma-separated series: default, light-only, bsdf-only (path integrator), sobol,
    /// stratified, rr:N (Russian roulette from bounce N), denoise [default: for the path
    /// integrator default,light-only,bsdf-only,stratified,denoise; else default,sobol,denoise].
    #[arg(long, value_name = "LIST")]
    pub series: Option<String>,
    /// A small run: 64 pixels wide, up to 16 spp against 256.
    #[arg(long)]
    pub quick: bool,
    /// Let the rendered reference replace a `reference.exr` or `reference.json` in the report
    /// directory that is not this command's cache (refused otherwise).
    #[arg(long)]
    pub force: bool,
    /// Settings overrides (--size sets the render size; default 160 pixels wide, the scene's
    /// aspect ratio).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree explain`.
#[derive(Debug, Args)]
pub struct ExplainArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Pixel X,Y (0,0 is top-left).
    #[arg(long, value_name = "X,Y")]
    pub pixel: String,
    /// Print JSON (pixel, radiance, shares, sentences) instead of text.
    #[arg(long)]
    pub json: bool,
    /// Settings overrides.
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree diff`.
#[derive(Debug, Args)]
pub struct DiffArgs {
    /// Scene JSON for both sides (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// A second scene JSON: then SCENE is side a and this is side b.
    pub scene_b: Option<PathBuf>,
    /// Pixel X,Y (0,0 is top-left).
    #[arg(long, value_name = "X,Y")]
    pub pixel: String,
    /// Overrides of side a, as one string ("--offset normal --epsilon 0").
    #[arg(
        long = "a",
        value_name = "ARGS",
        default_value = "",
        allow_hyphen_values = true
    )]
    pub a: String,
    /// Overrides of side b, as one string ("--offset robust").
    #[arg(
        long = "b",
        value_name = "ARGS",
        default_value = "",
        allow_hyphen_values = true
    )]
    pub b: String,
    /// Print JSON (the TreeDiff) instead of text.
    #[arg(long)]
    pub json: bool,
    /// After the summary, list every changed field of every ray and the unmatched subtrees.
    #[arg(long)]
    pub full: bool,
    /// Overrides of both sides (applied before --a and --b).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree versus`.
#[derive(Debug, Args)]
pub struct VersusArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Output directory (A.png and B.png, e.g. whitted.png and path.png, side-by-side.png,
    /// difference.png, breakdown.json).
    #[arg(short, long, default_value = "versus")]
    pub output: PathBuf,
    /// The two integrators, A,B (whitted, path, light, bdpt). whitted,path breaks the
    /// difference down by light transport class; any other pair tests B - A against the noise
    /// (mean per channel with its 95 % interval over 8x8 blocks).
    #[arg(long, value_name = "A,B", default_value = "whitted,path")]
    pub pair: String,
    /// Break the difference down over this pixel rectangle only, X0,Y0,X1,Y1 (X1 and Y1
    /// excluded); default the whole image.
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    pub region: Option<String>,
    /// Print the breakdown as JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Settings overrides (the integrator is set by the command).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree strategies`.
#[derive(Debug, Args)]
pub struct StrategiesArgs {
    /// Scene JSON (default: the built-in classic scene).
    pub scene: Option<PathBuf>,
    /// Output directory (sheet.png, report.md, report.json, and per strategy sS-tT.png and
    /// sS-tT-unweighted.png; background.png and longer.png when they are not black).
    #[arg(short, long, default_value = "strategies")]
    pub output: PathBuf,
    /// Paths with up to this many bounces get an image per strategy; longer ones are summed
    /// into longer.png (0..=6).
    #[arg(long, default_value_t = 3)]
    pub bounces: u32,
    /// Settings overrides (the integrator is bdpt: the command splits its render).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `raytree convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Scene: pbrt-v4 (.pbrt), Mitsuba 3 (.xml), glTF 2.0 (.gltf, .glb) or raytree JSON.
    pub scene: PathBuf,
    /// Output JSON (never one of the files the scene reads).
    #[arg(short, long, default_value = "scene.json")]
    pub output: PathBuf,
    /// Mitsuba scenes: give `$NAME` the value VALUE; repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
}

/// `raytree outliers`.
#[derive(Debug, Args)]
pub struct OutliersArgs {
    /// A scene (rendered first, with the overrides) or an image (.png or .exr).
    pub input: PathBuf,
    /// How many pixels to list (per ranking).
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub top: usize,
    /// The neighbourhood: 3 (3x3) or 5 (5x5).
    #[arg(long, value_name = "3|5", default_value_t = 3)]
    pub window: u32,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Settings overrides (for a scene).
    #[command(flatten)]
    pub overrides: Overrides,
}
