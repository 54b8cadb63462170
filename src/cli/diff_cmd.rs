//! `raytree diff`: one pixel traced under two sets of overrides (or in two scenes), and where
//! the two trees differ (`raytree::analysis::diff`).

use super::args::{DiffArgs, Overrides};
use super::load::{apply, load, pair};
use super::say::{out, sayln};
use anyhow::{Result, anyhow, bail};
use clap::Parser;
use raytree::analysis::diff::{diff, diff_full_text, diff_text};
use raytree::{RayTree, Scene};

/// The override flags of a tracing command, parsed from one string.
#[derive(Debug, Parser)]
#[command(no_binary_name = true, disable_help_flag = true)]
struct OverrideLine {
    #[command(flatten)]
    o: Overrides,
}

/// Split `s` into words at whitespace; single or double quotes group words.
fn words(s: &str) -> Result<Vec<String>, String> {
    let (mut out, mut cur, mut quote, mut any) = (Vec::new(), String::new(), None, false);
    for c in s.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => cur.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                any = true;
            }
            (None, c) if c.is_whitespace() => {
                if any || !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
                any = false;
            }
            (None, c) => cur.push(c),
        }
    }
    if quote.is_some() {
        return Err("unclosed quote".into());
    }
    if any || !cur.is_empty() {
        out.push(cur);
    }
    Ok(out)
}

/// Parse the overrides string of side `side`.
fn parse_overrides(side: &str, s: &str) -> Result<Overrides> {
    let bad = |msg: String| anyhow!("--{side} {s:?}: {msg}");
    let w = words(s).map_err(bad)?;
    let line = OverrideLine::try_parse_from(w).map_err(|e| {
        let text = e.to_string();
        let first = text.lines().next().unwrap_or("").trim();
        bad(first.strip_prefix("error: ").unwrap_or(first).to_string())
    })?;
    Ok(line.o)
}

fn trace(scene: &mut Scene, o: &Overrides, x: u32, y: u32, side: &str) -> Result<RayTree> {
    let mib = super::budget::mib(o.max_memory);
    super::budget::fit_tree(scene, mib)?;
    let cam = &scene.camera;
    match super::budget::trace(scene, (x, y), mib)? {
        Some(t) => Ok(t),
        None => bail!(
            "--pixel {x},{y} is outside side {side}'s {}x{} image",
            cam.width,
            cam.height
        ),
    }
}

/// Trace both sides and print the difference. Exit 0 whether or not they differ.
pub fn run(a: &DiffArgs) -> Result<()> {
    let (x, y) = pair("pixel", &a.pixel, ',')?;
    let oa = parse_overrides("a", &a.a)?;
    let ob = parse_overrides("b", &a.b)?;
    let base_a = load(a.scene.as_deref(), &a.overrides)?;
    let mut scene_a = base_a.scene;
    let mut scene_b = match &a.scene_b {
        Some(p) => load(Some(p), &a.overrides)?.scene,
        None => scene_a.clone(),
    };
    apply(&mut scene_a, &oa).map_err(|e| anyhow!("--a: {e:#}"))?;
    apply(&mut scene_b, &ob).map_err(|e| anyhow!("--b: {e:#}"))?;
    let mem_a = Overrides {
        max_memory: oa.max_memory.or(a.overrides.max_memory),
        ..Overrides::default()
    };
    let mem_b = Overrides {
        max_memory: ob.max_memory.or(a.overrides.max_memory),
        ..Overrides::default()
    };
    let ta = trace(&mut scene_a, &mem_a, x, y, "a")?;
    let tb = trace(&mut scene_b, &mem_b, x, y, "b")?;
    let d = diff(&ta, &tb);
    if a.json {
        let se_finite = d.pixel.std_error.is_none_or(|e| e.is_finite());
        if !(d.radiance_a.is_finite()
            && d.radiance_b.is_finite()
            && d.pixel.mean.is_finite()
            && se_finite)
        {
            bail!(
                "pixel {x},{y}: a pixel value is not finite; JSON cannot carry it, so none was written (drop --json)"
            );
        }
        sayln!("{}", serde_json::to_string_pretty(&d)?)?;
    } else {
        let head = format!(
            "pixel ({x}, {y})\na: {}{}\nb: {}{}\n",
            a.scene
                .as_ref()
                .map_or("<built-in classic>".into(), |p| p.display().to_string()),
            if a.a.is_empty() {
                String::new()
            } else {
                format!("  {}", a.a)
            },
            a.scene_b
                .as_ref()
                .or(a.scene.as_ref())
                .map_or("<built-in classic>".into(), |p| p.display().to_string()),
            if a.b.is_empty() {
                String::new()
            } else {
                format!("  {}", a.b)
            },
        );
        out(&head)?;
        if a.full {
            out(&diff_full_text(&d, &ta, &tb))?;
        } else {
            out(&diff_text(&d, &ta, &tb))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_split_at_whitespace_and_keep_quotes() {
        assert_eq!(
            words("  --offset  normal ").unwrap(),
            ["--offset", "normal"]
        );
        assert_eq!(
            words("--size '64x36' \"\"").unwrap(),
            ["--size", "64x36", ""]
        );
        assert!(words("--offset 'normal").is_err());
        assert!(words("").unwrap().is_empty());
    }

    #[test]
    fn override_strings_parse_like_flags() {
        let o = parse_overrides("a", "--offset normal --epsilon 0 --max-depth 3").unwrap();
        assert_eq!(o.offset.as_deref(), Some("normal"));
        assert_eq!((o.epsilon, o.max_depth), (Some(0.0), Some(3)));
        let o = parse_overrides("b", "--epsilon -0.0001").unwrap();
        assert_eq!(o.epsilon, Some(-0.0001));
        for bad in ["--bogus", "--spp", "--spp many", "normal", "--help"] {
            let e = parse_overrides("a", bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--a {bad:?}: ")), "{e}");
        }
    }
}
