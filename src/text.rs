//! A readable, indented rendering of a ray tree (the `trace` command's default output).

use crate::math::Rgb;
use crate::tree::{EndReason, NodeId, RayKind, RayNode, RayTree};
use std::fmt::Write;

fn rgb(c: Rgb) -> String {
    format!("[{:.4}, {:.4}, {:.4}]", c.x, c.y, c.z)
}

/// A weight or colour, written as one number when its channels agree.
fn w(c: Rgb) -> String {
    if c.x == c.y && c.y == c.z {
        format!("{:.4}", c.x)
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

fn deg(cos: f64) -> f64 {
    cos.clamp(-1.0, 1.0).acos().to_degrees()
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
            "  LEAK (offset skipped {} at {:.3e})",
            l.object_name, l.distance
        );
    }
    s
}

/// One line describing a node (without indentation).
#[must_use]
pub fn node_line(n: &RayNode) -> String {
    let mut s = node_summary(n);
    s.push_str(&diagnostic_text(n));
    s
}

fn node_summary(n: &RayNode) -> String {
    let mut s = format!("{} #{}", n.kind.name(), n.id.0);
    if n.kind == RayKind::Shadow {
        if let Some(sh) = &n.shadow {
            let _ = write!(s, " -> {}", sh.light_name);
            match n.end {
                EndReason::LightBehind => {
                    let _ = write!(s, ": {}", end_text(n.end));
                    return s;
                }
                EndReason::Blocked => {
                    let names: Vec<&str> =
                        sh.blockers.iter().map(|b| b.object_name.as_str()).collect();
                    let _ = write!(s, ": blocked by {}", names.join(", "));
                }
                EndReason::Attenuated => {
                    let _ = write!(s, ": transmittance {}", w(sh.transmittance));
                    for b in &sh.blockers {
                        let _ = write!(
                            s,
                            " ({} chord {:.4} passes {})",
                            b.object_name,
                            b.chord,
                            w(b.factor)
                        );
                    }
                }
                _ => s.push_str(": unblocked"),
            }
            let _ = write!(
                s,
                "  theta {:.2} deg  E {}  brdf*cos {}  contribution {}",
                deg(sh.cos_theta),
                w(sh.irradiance),
                w(n.weight),
                rgb(n.weight * n.radiance)
            );
        }
        return s;
    }
    match &n.hit {
        None => s.push_str(" -> miss (background)"),
        Some(h) => {
            let _ = write!(
                s,
                " -> {} [{}] t={:.4} theta_i={:.2} deg {}",
                h.object_name,
                h.material,
                h.t,
                deg(h.cos_i),
                if h.entering { "outside" } else { "inside" }
            );
            if let Some(t) = h.triangle {
                let _ = write!(s, " triangle {t}");
            }
        }
    }
    if n.kind != RayKind::Camera {
        let _ = write!(s, "  weight {}", w(n.weight));
    }
    if let Some(i) = &n.interface {
        let _ = write!(s, "  n1 {:.3} -> n2 {:.3}", i.n1, i.n2);
        match i.cos_t {
            Some(ct) => {
                let _ = write!(s, " theta_t={:.2} deg", deg(ct));
            }
            None => s.push_str(" TIR"),
        }
        let _ = write!(s, " R={:.4} T={:.4}", i.fresnel.r, i.fresnel.t);
    }
    if let Some(a) = &n.attenuation {
        let _ = write!(s, "  Beer: {:.4} inside -> {}", a.distance, w(a.factor));
    }
    let _ = write!(s, "  local {}  L {}", rgb(n.local), rgb(n.radiance));
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

/// The whole tree as indented text.
#[must_use]
pub fn tree_text(tree: &RayTree) -> String {
    let st = &tree.settings;
    let mut out = format!(
        "pixel ({}, {})  radiance {}  spp {}  max_depth {}  fresnel {}  shadows {}  offset {} {:e}\n",
        tree.pixel[0],
        tree.pixel[1],
        rgb(tree.radiance),
        st.spp,
        st.max_depth,
        serde_name(&st.fresnel),
        serde_name(&st.shadows),
        serde_name(&st.offset.strategy),
        st.offset.epsilon,
    );
    for s in &tree.samples {
        let _ = writeln!(
            out,
            "sample {} at ({:.3}, {:.3})  radiance {}",
            s.index,
            s.film[0],
            s.film[1],
            rgb(s.radiance)
        );
        node_text(tree, s.root, "", true, &mut out);
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
