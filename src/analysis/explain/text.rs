//! The explanation as text.

use super::{Explanation, SentenceKind, rgb};
use crate::tree::NodeId;
use std::fmt::Write;

/// The explanation as text: one sentence a line, `- ` then the text and the node ids.
#[must_use]
pub fn explanation_text(e: &Explanation) -> String {
    let mut out = format!(
        "pixel ({}, {})  value {}\n",
        e.pixel[0],
        e.pixel[1],
        rgb(e.radiance)
    );
    let mut last = None;
    for s in &e.sentences {
        if last != Some(s.kind) {
            let head = match s.kind {
                SentenceKind::Sees => "what it sees",
                SentenceKind::Event => "events",
                SentenceKind::Energy => "where energy went",
                SentenceKind::Suspicious => "suspicious",
            };
            let _ = writeln!(out, "{head}:");
            last = Some(s.kind);
        }
        let _ = writeln!(out, "- {}  ({})", s.text, node_list(&s.nodes));
    }
    if !e
        .sentences
        .iter()
        .any(|s| s.kind == SentenceKind::Suspicious)
    {
        out.push_str("suspicious: nothing (no self-hit, leak, trapped TIR chain, clipped or non-finite value)\n");
    }
    out
}

/// `#12, #14`, at most 12 ids and then how many more.
#[must_use]
pub fn node_list(nodes: &[NodeId]) -> String {
    const MAX: usize = 12;
    let mut s: Vec<String> = nodes
        .iter()
        .take(MAX)
        .map(|n| format!("#{}", n.0))
        .collect();
    if nodes.len() > MAX {
        s.push(format!("and {} more", nodes.len() - MAX));
    }
    s.join(", ")
}
