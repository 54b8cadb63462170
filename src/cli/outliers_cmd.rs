//! `raytree outliers SCENE|IMAGE`: the worst pixels, ranked by their excess over a robust
//! neighbourhood estimate (`raytree::analysis::outliers`), and for a scene also by the standard
//! error of their mean, each with the `trace` / `explain` command to run next.

use super::args::{OutliersArgs, Overrides};
use super::load::load;
use super::output::read_image;
use super::say::{out, sayln};
use anyhow::{Result, bail};
use raytree::Image;
use raytree::analysis::outliers::{Outlier, by_std_error, rank};
use raytree::text::num;
use std::path::Path;

/// The most pixels one listing holds.
const MAX_TOP: usize = 10_000;

fn is_image(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png") || e.eq_ignore_ascii_case("exr"))
}

/// `s` as one shell word (single-quoted when it holds anything but `[A-Za-z0-9_./,=:+-]`).
fn shell_word(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_./,=:+-".contains(c));
    if plain {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// The override flags as given on the command line (this command's own flags and the input
/// left out), for the commands to run next: they trace the pixel the render rendered.
fn override_words(input: &Path) -> Vec<String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut out = Vec::new();
    let mut i = args
        .iter()
        .position(|a| a == "outliers")
        .map_or(0, |p| p + 1);
    while i < args.len() {
        let a = &args[i];
        if a == "--json" || a.starts_with("--top=") || a.starts_with("--window=") {
            i += 1;
        } else if a == "--top" || a == "--window" {
            i += 2;
        } else if Path::new(a) == input && !a.starts_with('-') {
            i += 1;
        } else {
            out.push(shell_word(a));
            i += 1;
        }
    }
    out
}

/// The `trace` and `explain` command lines for pixel `o`.
fn next_commands(scene: &str, flags: &[String], o: &Outlier) -> (String, String) {
    let tail = if flags.is_empty() {
        String::new()
    } else {
        format!(" {}", flags.join(" "))
    };
    let px = format!("--pixel {},{}", o.x, o.y);
    (
        format!("raytree trace {scene} {px}{tail}"),
        format!("raytree explain {scene} {px}{tail}"),
    )
}

/// Render `a.input` (a scene), or read it (an image); with the standard error of every pixel
/// mean for a scene.
fn image_of(a: &OutliersArgs) -> Result<(Image, Option<Vec<f64>>)> {
    if is_image(&a.input) {
        if format!("{:?}", a.overrides) != format!("{:?}", Overrides::default()) {
            bail!(
                "{} is an image: the settings overrides apply to a scene (give the scene to render it)",
                a.input.display()
            );
        }
        return Ok((read_image(&a.input)?, None));
    }
    let loaded = load(Some(&a.input), &a.overrides)?;
    let scene = loaded.scene;
    super::budget::check_aov_images(&scene, 0, super::budget::mib(a.overrides.max_memory))?;
    let integrator = raytree::SceneIntegrator::new(&scene);
    let r = raytree::aov::render_aovs(&integrator, &[], &|_| {})?;
    let se =
        r.mc.iter()
            .map(|m| {
                let v = m.rel_err * m.mean;
                if v.is_finite() { v } else { 0.0 }
            })
            .collect();
    Ok((r.beauty, Some(se)))
}

/// List the outliers.
pub fn run(a: &OutliersArgs) -> Result<()> {
    if !(1..=MAX_TOP).contains(&a.top) {
        bail!("--top: list 1..={MAX_TOP} pixels, got {}", a.top);
    }
    if a.window != 3 && a.window != 5 {
        bail!(
            "--window: the neighbourhood is 3 (3x3) or 5 (5x5), got {}",
            a.window
        );
    }
    let (img, se) = image_of(a)?;
    let by_excess = rank(&img, a.window, a.top);
    let by_se = se
        .as_ref()
        .map(|se| by_std_error(&img, se, a.window, a.top));
    let scene = if is_image(&a.input) {
        "SCENE".to_string()
    } else {
        shell_word(&a.input.display().to_string())
    };
    let flags = if is_image(&a.input) {
        Vec::new()
    } else {
        override_words(&a.input)
    };
    if a.json {
        let list = |v: &[Outlier]| -> Vec<serde_json::Value> {
            v.iter().map(|o| entry_json(&scene, &flags, o)).collect()
        };
        let doc = serde_json::json!({
            "input": a.input.display().to_string(),
            "size": [img.width, img.height],
            "window": a.window,
            "by_excess": list(&by_excess),
            "by_std_error": by_se.as_deref().map(list),
        });
        sayln!("{}", serde_json::to_string_pretty(&doc)?)?;
        return Ok(());
    }
    let mut s = format!(
        "{} ({}x{}): pixels ranked by their excess over the median of their {w}x{w} neighbourhood, in robust standard deviations (1.4826 MAD)\n",
        a.input.display(),
        img.width,
        img.height,
        w = a.window
    );
    s += &listing(&by_excess, &scene, &flags);
    if let Some(v) = &by_se {
        s += "\npixels ranked by the standard error of their mean (from the render's samples):\n";
        if v.is_empty() {
            s += "  none estimable: every pixel has a single sample or is black (raise --spp)\n";
        }
        s += &listing(v, &scene, &flags);
    }
    if is_image(&a.input) {
        s += "\n(SCENE: the scene that rendered the image, with the settings it was rendered with)\n";
    }
    out(&s)?;
    Ok(())
}

/// One line per pixel, then its two commands.
fn listing(v: &[Outlier], scene: &str, flags: &[String]) -> String {
    if v.is_empty() {
        return "  none: no pixel is brighter than its neighbourhood's median\n".into();
    }
    let mut s = String::new();
    for (i, o) in v.iter().enumerate() {
        let se = o
            .std_error
            .map_or(String::new(), |e| format!("  std error {}", num(e, 4)));
        s += &format!(
            "{:>3}. pixel {},{}  value {}  luminance {}  neighbourhood median {}  score {}{se}\n",
            i + 1,
            o.x,
            o.y,
            raytree::text::rgb(o.value),
            num(o.luminance, 4),
            num(o.median, 4),
            score_text(o.score),
        );
        let (trace, explain) = next_commands(scene, flags, o);
        s += &format!("     {trace}\n     {explain}\n");
    }
    s
}

/// A score, or words for the pixel whose own value is not finite.
fn score_text(v: f64) -> String {
    if v == f64::MAX {
        "(the pixel is not finite)".into()
    } else {
        format!("{v:.1}")
    }
}

fn entry_json(scene: &str, flags: &[String], o: &Outlier) -> serde_json::Value {
    let (trace, explain) = next_commands(scene, flags, o);
    let f = |v: f64| v.is_finite().then_some(v);
    serde_json::json!({
        "pixel": [o.x, o.y],
        "value": o.value.is_finite().then(|| o.value.to_array()),
        "finite": o.value.is_finite(),
        "luminance": f(o.luminance),
        "median": o.median,
        "scale": o.scale,
        "score": f(o.score).filter(|v| *v < f64::MAX),
        "std_error": o.std_error,
        "trace": trace,
        "explain": explain,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_words_quote_what_a_shell_would_split() {
        assert_eq!(shell_word("fixtures/caustic.json"), "fixtures/caustic.json");
        assert_eq!(shell_word("--spp"), "--spp");
        assert_eq!(shell_word("my scene.json"), "'my scene.json'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
        assert_eq!(shell_word(""), "''");
    }
}
