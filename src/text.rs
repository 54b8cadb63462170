//! A readable, indented rendering of a ray tree (the `trace` command's default output).

use crate::math::Rgb;
use crate::tree::{EndReason, Interface, NodeId, RayKind, RayNode, RayTree, ShadowInfo};
use std::fmt::Write;

/// How a NaN or an infinity is written in the text form: words, never a token a program would
/// read as a number (`NaN`, `inf`), so the text holds only finite numbers too. [`tree_text`]
/// ends with a note when any value was written so.
pub const NOT_FINITE: &str = "<not finite:";

/// `v` with `prec` decimals, or `<not finite: not a number>` / `<not finite: +infinite>` /
/// `<not finite: -infinite>`.
#[must_use]
pub fn num(v: f64, prec: usize) -> String {
    if v.is_finite() {
        format!("{v:.prec$}")
    } else {
        not_finite(v)
    }
}

/// `v` in scientific notation (`{:e}`, or `{:.prec$e}`), or the not-finite words of [`num`].
#[must_use]
pub fn sci(v: f64, prec: Option<usize>) -> String {
    match (v.is_finite(), prec) {
        (false, _) => not_finite(v),
        (true, Some(p)) => format!("{v:.p$e}"),
        (true, None) => format!("{v:e}"),
    }
}

fn not_finite(v: f64) -> String {
    let what = if v.is_nan() {
        "not a number"
    } else if v > 0.0 {
        "+infinite"
    } else {
        "-infinite"
    };
    format!("{NOT_FINITE} {what}>")
}

/// `s` with every token Rust's float formatting gives a non-finite number (`NaN`, `inf`,
/// `-inf`, standing alone, not inside a word) replaced by the words of [`num`]: the last guard
/// of every text output (standard output and error, Markdown, CSV, legends), so that a number
/// formatted without [`num`] still cannot reach a reader as a token it would parse.
#[must_use]
pub fn guard_nonfinite(s: &str) -> std::borrow::Cow<'_, str> {
    // A token inside a word or a path (`info`, `inf.png`, `out/NaN.json`) is a name, not a
    // number: only a token standing alone, or ending a sentence, is replaced.
    let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || "_/\\".contains(c));
    let mut out = String::new();
    let mut last = 0;
    let mut i = 0;
    while i < s.len() {
        let rest = &s[i..];
        let before = s[..i].chars().next_back();
        let hit = [
            ("-inf", f64::NEG_INFINITY),
            ("inf", f64::INFINITY),
            ("NaN", f64::NAN),
        ]
        .into_iter()
        .find(|(t, _)| {
            if !rest.starts_with(t) {
                return false;
            }
            let mut after = rest[t.len()..].chars();
            let next = after.next();
            let dotted_name = next == Some('.') && word(after.next());
            !word(next) && !dotted_name && next != Some('-')
        });
        match hit {
            Some((t, v)) if !word(before) && before != Some('.') => {
                out.push_str(&s[last..i]);
                out.push_str(&not_finite(v));
                i += t.len();
                last = i;
            }
            _ => i += rest.chars().next().map_or(1, char::len_utf8),
        }
    }
    if last == 0 {
        return std::borrow::Cow::Borrowed(s);
    }
    out.push_str(&s[last..]);
    std::borrow::Cow::Owned(out)
}

/// A colour as `[r, g, b]` with 4 significant digits.
#[must_use]
pub fn rgb(c: Rgb) -> String {
    format!("[{}, {}, {}]", num(c.x, 4), num(c.y, 4), num(c.z, 4))
}

/// A weight or colour, written as one number when its channels agree.
fn w(c: Rgb) -> String {
    if c.x == c.y && c.y == c.z {
        num(c.x, 4)
    } else {
        rgb(c)
    }
}

/// The JSON name of a unit enum variant (`"exact"` -> `exact`).
fn serde_name<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string(v)
        .unwrap_or_default()
        .trim_matches('"')
        .to_string()
}

/// The angle of a cosine in degrees, 2 decimals (a NaN cosine stays not finite).
fn deg(cos: f64) -> String {
    num(cos.clamp(-1.0, 1.0).acos().to_degrees(), 2)
}

/// Why-text of an end reason.
#[must_use]
pub fn end_text(e: EndReason) -> &'static str {
    match e {
        EndReason::Pending => "pending",
        EndReason::Miss => "missed everything: background",
        EndReason::Surface => "surface neither reflects nor transmits: local shading only",
        EndReason::Continued => "secondary rays traced",
        EndReason::MaxDepth => "secondary rays cut by max_depth",
        EndReason::MinWeight => "secondary rays cut by min_weight",
        EndReason::RayBudget => "secondary rays cut by the sample's ray budget (max_rays)",
        EndReason::Unblocked => "reaches the light",
        EndReason::Attenuated => "reaches the light, attenuated by translucent blockers",
        EndReason::Blocked => "blocked",
        EndReason::LightBehind => "light is behind the surface: no shadow ray",
        EndReason::RussianRoulette => "path ended by Russian roulette",
        EndReason::Absorbed => "path ended: the BSDF sample carried nothing",
    }
}

/// The diagnostics of a node, as a suffix: `  SELF-HIT` and `  LEAK skipped <name> at <d>`.
#[must_use]
pub fn diagnostic_text(n: &RayNode) -> String {
    let mut s = String::new();
    if n.self_hit {
        s.push_str("  SELF-HIT (re-hit the surface it left)");
    }
    if let Some(l) = &n.leak {
        let _ = write!(
            s,
            "  LEAK (offset skipped {} at {})",
            l.object_name,
            sci(l.distance, Some(3))
        );
    }
    s
}

/// One line describing a node (without indentation).
#[must_use]
pub fn node_line(n: &RayNode) -> String {
    let mut s = node_summary(n);
    s.push_str(&path_text(n));
    s.push_str(&diagnostic_text(n));
    s
}

/// The path integrator's fields of a node, as a suffix (empty for Whitted nodes):
/// `  | C<RD>L lobe diffuse pdf 0.3 f*cos/pdf 0.8 mis 0.7 rr 0.6 survived contribution ...`.
#[must_use]
pub fn path_text(n: &RayNode) -> String {
    use crate::tree::Pdf;
    let Some(p) = &n.path else {
        return String::new();
    };
    let mut s = format!("  | {}", p.lpe);
    if let Some([ls, ct]) = p.strategy {
        let _ = write!(s, " s={ls} t={ct}");
    }
    if let Some(u) = p.unweighted {
        let _ = write!(s, " unweighted {}", rgb(u));
    }
    if let Some(l) = p.lobe {
        let name = serde_json::to_string(&l).unwrap_or_default();
        let _ = write!(s, " lobe {}", name.trim_matches('"'));
    }
    match p.pdf {
        Some(Pdf::Density(d)) => {
            let _ = write!(s, " pdf {}", num(d, 4));
        }
        Some(Pdf::Delta(_)) => s.push_str(" pdf delta"),
        None => {}
    }
    if let Some(f) = p.bsdf_cos_pdf {
        let what = if n.kind == RayKind::Shadow {
            "f*cos"
        } else {
            "f*cos/pdf"
        };
        let _ = write!(s, " {what} {}", w(f));
    }
    if let Some(m) = p.mis_weight {
        let _ = write!(s, " mis {}", num(m, 4));
    }
    if let Some(r) = p.roulette {
        let _ = write!(
            s,
            " rr {} {}",
            num(r.probability, 4),
            if r.survived { "survived" } else { "killed" }
        );
    }
    if p.contribution != Rgb::ZERO {
        let _ = write!(s, " contribution {}", rgb(p.contribution));
    }
    s
}

/// One line about node `n`: its kind and id, where it went and every number recorded on it.
fn node_summary(n: &RayNode) -> String {
    let mut s = format!("{} #{}", n.kind.name(), n.id.0);
    if n.kind == RayKind::Shadow {
        if let Some(sh) = &n.shadow {
            shadow_summary(n, sh, &mut s);
        }
        return s;
    }
    target_summary(n, &mut s);
    if n.kind != RayKind::Camera {
        let _ = write!(s, "  weight {}", w(n.weight));
    }
    if let Some(g) = &n.glossy {
        let _ = write!(
            s,
            "  sampled {} {}/{}{}  pdf {}  bsdf {}  cos {}",
            g.lobe.name(),
            g.sample + 1,
            g.count,
            if g.transmitted { " (through)" } else { "" },
            num(g.pdf, 4),
            w(g.bsdf),
            num(g.cos, 4)
        );
    }
    if let Some(i) = &n.interface {
        interface_summary(i, &mut s);
    }
    if let Some(a) = &n.attenuation {
        let _ = write!(
            s,
            "  Beer: {} inside -> {}",
            num(a.distance, 4),
            w(a.factor)
        );
    }
    // A light subpath carries flux from the light, not radiance back to the camera.
    if matches!(n.kind, RayKind::Light | RayKind::Connection) {
        let _ = write!(s, "  flux {}", rgb(n.throughput));
    } else {
        let _ = write!(s, "  local {}  L {}", rgb(n.local), rgb(n.radiance));
    }
    if n.truncated != Rgb::ZERO {
        let _ = write!(s, "  cut weight {}", w(n.truncated));
    }
    if matches!(
        n.end,
        EndReason::MaxDepth | EndReason::MinWeight | EndReason::RayBudget
    ) {
        let _ = write!(s, "  ({})", end_text(n.end));
    }
    s
}

/// A shadow ray `n` with its record `sh`: its light, whether it got through, and what
/// arrives.
fn shadow_summary(n: &RayNode, sh: &ShadowInfo, s: &mut String) {
    let _ = write!(s, " -> {}", sh.light_name);
    match n.end {
        EndReason::LightBehind => {
            let _ = write!(s, ": {}", end_text(n.end));
            return;
        }
        EndReason::Blocked => {
            let names: Vec<&str> = sh.blockers.iter().map(|b| b.object_name.as_str()).collect();
            let _ = write!(s, ": blocked by {}", names.join(", "));
        }
        EndReason::Attenuated => {
            let _ = write!(s, ": transmittance {}", w(sh.transmittance));
            for b in &sh.blockers {
                let _ = write!(
                    s,
                    " ({} chord {} passes {})",
                    b.object_name,
                    num(b.chord, 4),
                    w(b.factor)
                );
            }
        }
        _ => s.push_str(": unblocked"),
    }
    // A point or directional light delivers an irradiance E; an area-light sample a
    // Monte Carlo estimate L / pdf (its radiance over its solid-angle pdf).
    let arrives = match &sh.area {
        Some(a) => format!(
            "L {}  pdf {}  L/pdf {}",
            w(a.radiance),
            num(a.pdf, 4),
            w(sh.irradiance)
        ),
        None => format!("E {}", w(sh.irradiance)),
    };
    // What this light adds to its hit's radiance ("adds ... at the hit"), not to the
    // pixel: a path-traced line's own `contribution` after `|` is the pixel's share.
    let _ = write!(
        s,
        "  theta {} deg  {arrives}  brdf*cos {}  adds {} at the hit",
        deg(sh.cos_theta),
        w(n.weight),
        rgb(n.weight * n.radiance)
    );
}

/// Where a ray other than a shadow ray went: what it hit, or the miss, or where a connection
/// ends.
fn target_summary(n: &RayNode, s: &mut String) {
    match &n.hit {
        None if n.kind == RayKind::Connection => {
            let seen = if n.end == EndReason::Blocked {
                "blocked"
            } else {
                "unblocked"
            };
            // Light tracing's and BDPT's t = 1 connections end at the lens; BDPT's others at
            // a light sample (s = 1) or the light subpath's end vertex.
            let to = match n.path.as_ref().and_then(|p| p.strategy) {
                None | Some([_, 1]) => "the camera",
                Some([1, _]) => "a light sample",
                Some(_) => "the light subpath",
            };
            let _ = write!(s, " -> {to}: {seen}");
        }
        None => s.push_str(" -> miss (background)"),
        Some(h) => {
            let _ = write!(
                s,
                " -> {} [{}] t={} theta_i={} deg {}",
                h.object_name,
                h.material,
                num(h.t, 4),
                deg(h.cos_i),
                if h.entering { "outside" } else { "inside" }
            );
            if let Some(t) = h.triangle {
                let _ = write!(s, " triangle {t}");
            }
        }
    }
}

/// An interface crossed: the indices, the angle of transmission (or TIR), Fresnel's R and T
/// and the roulette that chose one ray.
fn interface_summary(i: &Interface, s: &mut String) {
    let _ = write!(s, "  n1 {} -> n2 {}", num(i.n1, 3), num(i.n2, 3));
    match i.cos_t {
        Some(ct) => {
            let _ = write!(s, " theta_t={} deg", deg(ct));
        }
        None => s.push_str(" TIR"),
    }
    let _ = write!(s, " R={} T={}", num(i.fresnel.r, 4), num(i.fresnel.t, 4));
    if let Some(c) = i.roulette {
        let _ = write!(
            s,
            "  roulette: the {} ray only (p {}, weight / p)",
            c.ray(),
            num(c.probability, 4)
        );
    }
}

/// Light tracing's splats of the pixel, each with the light path that made it.
fn splats_text(tree: &RayTree, out: &mut String) {
    if tree.splats.is_empty() {
        return;
    }
    let sum = crate::render::splat::splat_sum(&tree.splats);
    let _ = writeln!(
        out,
        "{} light-path splats landed here (sum {}, divided by {}: {})",
        tree.splats.len(),
        rgb(sum),
        tree.splat_divisor,
        rgb(sum / f64::from(tree.splat_divisor.max(1)))
    );
    let mut shown = None;
    for s in &tree.splats {
        let _ = writeln!(
            out,
            "splat of light path {} (seeded by pixel {},{} sample {}) at ({}, {})  strategy s={} t={}  {}  contribution {}  MIS weight {}",
            s.path,
            s.seed[0],
            s.seed[1],
            s.seed[2],
            num(s.film[0], 3),
            num(s.film[1], 3),
            s.strategy[0],
            s.strategy[1],
            s.lpe,
            rgb(s.contribution),
            num(s.mis_weight, 3)
        );
        // A light path that lands here twice is printed once.
        if shown != Some(s.root) {
            node_text(tree, s.root, "", true, out);
            shown = Some(s.root);
        }
    }
}

/// The whole tree as indented text.
#[must_use]
pub fn tree_text(tree: &RayTree) -> String {
    let st = &tree.settings;
    let (spp, sampler) = match tree.edge {
        Some(true) => (
            format!("{} (automatic antialiasing: an edge)", st.spp),
            "sobol",
        ),
        Some(false) => (
            format!(
                "{} (automatic antialiasing: no edge, {} taken)",
                st.spp,
                tree.samples.len()
            ),
            "sobol",
        ),
        None => (st.spp.to_string(), st.sampler_kind().name()),
    };
    let mut out = format!(
        "pixel ({}, {})  radiance {}  spp {}  max_depth {}  fresnel {}  shadows {}  offset {} {}  integrator {}  sampler {}\n",
        tree.pixel[0],
        tree.pixel[1],
        rgb(tree.radiance),
        spp,
        st.max_depth,
        serde_name(&st.whitted.fresnel),
        serde_name(&st.whitted.shadows),
        serde_name(&st.offset.strategy),
        sci(st.offset.epsilon, None),
        st.integrator.name(),
        sampler,
    );
    for s in &tree.samples {
        let _ = writeln!(
            out,
            "sample {} at ({}, {})  radiance {}",
            s.index,
            num(s.film[0], 3),
            num(s.film[1], 3),
            rgb(s.radiance)
        );
        node_text(tree, s.root, "", true, &mut out);
    }
    splats_text(tree, &mut out);
    let bad = out.matches(NOT_FINITE).count();
    if bad > 0 {
        let _ = writeln!(
            out,
            "note: {bad} values above are not finite (not a number or infinite), written as \"{NOT_FINITE} ...>\"; `--json` refuses such a tree"
        );
    }
    out
}

fn node_text(tree: &RayTree, id: NodeId, prefix: &str, last: bool, out: &mut String) {
    let n = tree.node(id);
    let _ = writeln!(
        out,
        "{prefix}{}{}",
        if last { "`- " } else { "|- " },
        node_line(n)
    );
    let child_prefix = format!("{prefix}{}", if last { "   " } else { "|  " });
    for (i, c) in n.children.iter().enumerate() {
        node_text(tree, *c, &child_prefix, i + 1 == n.children.len(), out);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_guard_replaces_nonfinite_tokens_and_nothing_else() {
        let s = format!(
            "value [{}, {}, {}] {}% rel {}% info infinite NaNa xinf",
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::INFINITY,
            f64::NAN
        );
        let g = guard_nonfinite(&s);
        assert_eq!(
            g,
            "value [<not finite: +infinite>, <not finite: -infinite>, <not finite: not a number>] \
             <not finite: +infinite>% rel <not finite: not a number>% info infinite NaNa xinf"
        );
        assert!(matches!(
            guard_nonfinite("all 1.5e3 fine"),
            std::borrow::Cow::Borrowed(_)
        ));
        assert_eq!(guard_nonfinite(">=inf"), ">=<not finite: +infinite>");
        for name in [
            "wrote inf.png",
            "dir/NaN.json",
            "a.inf",
            "inf-light",
            "x\\inf",
        ] {
            assert_eq!(guard_nonfinite(name), name, "a name is not a number");
        }
        assert_eq!(guard_nonfinite("is inf."), "is <not finite: +infinite>.");
    }

    use super::*;

    /// Every token of `s` a program would read as a non-finite number (`NaN`, `inf`, ...).
    fn nonfinite_tokens(s: &str) -> Vec<&str> {
        s.split(|c: char| !(c.is_ascii_alphanumeric() || "+-._".contains(c)))
            .filter(|t| t.parse::<f64>().is_ok_and(|v| !v.is_finite()))
            .collect()
    }

    #[test]
    fn non_finite_values_are_named_in_words_and_counted() {
        let mut scene = crate::Scene::default_scene();
        scene.camera = scene.camera.with_size(64, 36);
        let mut tree = crate::trace_pixel(&scene, 40, 20).unwrap();
        let clean = tree_text(&tree);
        assert!(!clean.contains(NOT_FINITE) && !clean.contains("note:"));
        tree.radiance.y = f64::NAN;
        tree.nodes[0].radiance = Rgb::new(f64::INFINITY, 0.5, f64::NEG_INFINITY);
        if let Some(h) = tree.nodes[0].hit.as_mut() {
            h.t = f64::NAN;
        }
        let text = tree_text(&tree);
        assert_eq!(nonfinite_tokens(&text), Vec::<&str>::new(), "{text}");
        assert!(text.contains("<not finite: not a number>"), "{text}");
        assert!(text.contains("[<not finite: +infinite>, 0.5000, <not finite: -infinite>]"));
        assert!(text.contains("t=<not finite: not a number>"), "{text}");
        assert!(text.ends_with("`--json` refuses such a tree\n"), "{text}");
        assert!(
            text.contains("note: 4 values above are not finite"),
            "{text}"
        );
        // The bare formatting this replaced would have written NaN and inf.
        assert!(!nonfinite_tokens(&format!("{:.4} {:.4}", f64::NAN, f64::INFINITY)).is_empty());
    }
}
