//! Whitted paths in words: "floor seen through the glass ball".

use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use std::fmt::Write;

/// The chain of nodes from the sample's camera ray down to `id`.
pub(super) fn chain(tree: &RayTree, id: NodeId) -> Vec<&RayNode> {
    let mut out = vec![tree.node(id)];
    while let Some(p) = out.last().and_then(|n| n.parent) {
        out.push(tree.node(p));
    }
    out.reverse();
    out
}

/// One interaction on the way from the eye: the surface `object` the next ray left.
struct Step<'a> {
    object: &'a str,
    refracted: bool,
    inside_reflections: usize,
    tir: usize,
    /// Reflections off the outside in a row (more than one only through self-hits).
    outside_reflections: usize,
}

/// The path of node `id` in words, eye outward collapsed per object: "floor seen through the
/// glass ball", "background reflected in the mirror ball".
pub(super) fn path_words(tree: &RayTree, id: NodeId) -> String {
    let nodes = chain(tree, id);
    let mut steps: Vec<Step> = Vec::new();
    for w in nodes.windows(2) {
        let (p, c) = (w[0], w[1]);
        let Some(h) = &p.hit else { continue };
        let tir = p.interface.as_ref().is_some_and(|i| i.tir);
        let refracted = c.kind == RayKind::Refracted;
        let inside = c.kind == RayKind::Reflected && !h.entering;
        match steps.last_mut() {
            Some(s) if s.object == h.object_name && (refracted || inside || s.refracted) => {
                s.refracted |= refracted;
                s.inside_reflections += usize::from(inside);
                s.tir += usize::from(inside && tir);
            }
            Some(s) if s.object == h.object_name && !s.refracted => s.outside_reflections += 1,
            _ => steps.push(Step {
                object: &h.object_name,
                refracted: refracted || inside,
                inside_reflections: usize::from(inside),
                tir: usize::from(inside && tir),
                outside_reflections: usize::from(!(refracted || inside)),
            }),
        }
    }
    let last = nodes[nodes.len() - 1];
    let what = last
        .hit
        .as_ref()
        .map_or("background", |h| h.object_name.as_str());
    let mut s = what.to_string();
    if steps.is_empty() {
        s.push_str(" seen directly");
        return s;
    }
    for (i, st) in steps.iter().rev().enumerate() {
        if i > 0 {
            s.push(',');
        }
        if st.refracted {
            let _ = write!(
                s,
                "{} through the {}",
                if i == 0 { " seen" } else { "" },
                st.object
            );
            if st.inside_reflections > 0 {
                let k = st.inside_reflections;
                let _ = write!(
                    s,
                    " ({k} {}internal reflection{})",
                    if st.tir == k { "total " } else { "" },
                    if k == 1 { "" } else { "s" }
                );
            }
        } else {
            let _ = write!(s, " reflected in the {}", st.object);
            if st.outside_reflections > 1 {
                let _ = write!(s, " ({} times)", st.outside_reflections);
            }
        }
    }
    s
}
