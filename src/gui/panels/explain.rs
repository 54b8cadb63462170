//! The "Explain" panel: `raytree explain`'s sentences for the selected pixel
//! ([`crate::analysis::explain`]), under their four headings. Each sentence is a link: clicking
//! it selects its first node (the tree panel opens its levels and scrolls to it); a sentence
//! about several nodes has a button for each id under it.

use crate::analysis::explain::{Explanation, SentenceKind, explain};
use crate::gui::model::document::{Command, Document};
use crate::gui::style::SELECTED;
use crate::tree::NodeId;
use egui::{Color32, RichText};

/// Node buttons shown under a sentence; the rest are counted.
const IDS_SHOWN: usize = 12;

/// The explanation of the current tree, rebuilt when the tree changes.
#[derive(Default)]
pub struct ExplainCache {
    version: Option<u64>,
    explanation: Option<Explanation>,
}

impl ExplainCache {
    /// The explanation shown (for tests).
    #[must_use]
    pub fn explanation(&self) -> Option<&Explanation> {
        self.explanation.as_ref()
    }

    fn sync(&mut self, doc: &Document) {
        if self.version == Some(doc.tree_version)
            && doc.tree.is_some() == self.explanation.is_some()
        {
            return;
        }
        self.version = Some(doc.tree_version);
        self.explanation = doc.tree.as_ref().map(|t| explain(t, &doc.scene));
    }
}

fn heading(kind: SentenceKind) -> &'static str {
    match kind {
        SentenceKind::Sees => "what it sees",
        SentenceKind::Event => "events",
        SentenceKind::Energy => "where energy went",
        SentenceKind::Suspicious => "suspicious",
    }
}

fn colour(kind: SentenceKind) -> Color32 {
    match kind {
        SentenceKind::Suspicious => crate::gui::style::WARNING,
        _ => Color32::PLACEHOLDER,
    }
}

/// The sentences, each selecting its nodes.
pub fn explain_ui(
    ui: &mut egui::Ui,
    doc: &Document,
    cache: &mut ExplainCache,
    cmds: &mut Vec<Command>,
) {
    cache.sync(doc);
    let Some(e) = &cache.explanation else {
        ui.label("Click a pixel to explain it.");
        return;
    };
    let mut last = None;
    for s in &e.sentences {
        if last != Some(s.kind) {
            last = Some(s.kind);
            ui.label(RichText::new(heading(s.kind)).strong());
        }
        let selected = doc.node.is_some_and(|n| s.nodes.contains(&n));
        // One node: its id ends the sentence (the sentence is its link); several: a row of
        // id buttons under it.
        let line = match s.nodes.as_slice() {
            [one] => format!("{}  (#{})", s.text, one.0),
            _ => s.text.clone(),
        };
        let mut text = RichText::new(line);
        if colour(s.kind) != Color32::PLACEHOLDER {
            text = text.color(colour(s.kind));
        }
        if selected {
            text = text.color(SELECTED);
        }
        let resp = ui
            .add(egui::Button::selectable(selected, text).wrap())
            .on_hover_text("select its first node in the tree");
        if resp.clicked()
            && let Some(first) = s.nodes.first()
        {
            cmds.push(Command::SelectNode(Some(*first)));
        }
        if s.nodes.len() > 1 {
            ui.horizontal_wrapped(|ui| {
                ui.add_space(12.0);
                for id in s.nodes.iter().take(IDS_SHOWN) {
                    node_button(ui, doc, *id, cmds);
                }
                if s.nodes.len() > IDS_SHOWN {
                    ui.small(format!("and {} more", s.nodes.len() - IDS_SHOWN));
                }
            });
        }
    }
    if !e
        .sentences
        .iter()
        .any(|s| s.kind == SentenceKind::Suspicious)
    {
        ui.label(RichText::new("suspicious").strong());
        ui.small("nothing (no self-hit, leak, trapped TIR chain, clipped or non-finite value)");
    }
}

fn node_button(ui: &mut egui::Ui, doc: &Document, id: NodeId, cmds: &mut Vec<Command>) {
    let on = doc.node == Some(id);
    if ui
        .add(egui::Button::selectable(
            on,
            RichText::new(format!("#{}", id.0)).small().monospace(),
        ))
        .clicked()
    {
        cmds.push(Command::SelectNode(Some(id)));
    }
}
