//! The inspector's light path expression filter: the text typed, its parse error, and the
//! selected pixel's tree before filtering. The tree the panels show (`Document::tree`) is the
//! filtered one, [`crate::lpe::filter_tree`]'s (the filter of `raytree trace --lpe` and
//! `raytree diagram --lpe`), so the tree, the overlay, the diagram, the samples and the exports
//! all show only the matching paths. Unlike the command line, a sample without a match keeps
//! its camera ray, so the sample count (the divisor of every per-sample mean) is the pixel's.

use crate::lpe::{Lpe, LpeError, filter_tree_all_samples};
use crate::tree::{NodeId, RayTree};

/// The filter's state (in [`crate::gui::Document::lpe`]).
#[derive(Clone, Debug, Default)]
pub struct LpeState {
    /// The text of the field.
    pub field: String,
    /// Why the text does not parse (the last good filter stays applied meanwhile).
    pub error: Option<LpeError>,
    /// The filter applied, `None` for none.
    pub active: Option<Lpe>,
    /// The selected pixel's tree before filtering (while a filter is applied).
    pub full: Option<RayTree>,
    /// What matched, in words ([`crate::lpe::LpeFilter::summary`]), or why nothing is filtered.
    pub summary: Option<String>,
    /// Whether `summary` says why the filter cannot apply (a Whitted tree).
    pub inapplicable: bool,
    /// While a filter is applied: each shown node's id in `full` (the filter renumbers).
    pub original: Vec<NodeId>,
}

impl LpeState {
    /// The field's text as it is being typed: parsed to show its error, not applied (issue 32:
    /// applying every keystroke applied the half-typed `C<RD>S+` of `C<RD>S+K`). The filter in
    /// force changes only through [`LpeState::set_text`] (Enter, or leaving the field).
    pub fn edit(&mut self, text: String) {
        self.field = text;
        let t = self.field.trim();
        self.error = if t.is_empty() {
            None
        } else {
            Lpe::parse(t).err()
        };
    }

    /// Whether the field shows something other than the filter in force (typed, not applied).
    #[must_use]
    pub fn pending(&self) -> bool {
        let active = self.active.as_ref().map_or("", |l| l.as_str());
        self.field.trim() != active
    }

    /// Take new text: parse it (an empty field removes the filter). Returns whether the filter
    /// applied changed.
    pub fn set_text(&mut self, text: String) -> bool {
        let before = self.active.as_ref().map(|l| l.as_str().to_owned());
        self.field = text;
        let t = self.field.trim();
        if t.is_empty() {
            self.error = None;
            self.active = None;
        } else {
            match Lpe::parse(t) {
                Ok(l) => {
                    self.error = None;
                    self.active = Some(l);
                }
                Err(e) => self.error = Some(e),
            }
        }
        before != self.active.as_ref().map(|l| l.as_str().to_owned())
    }

    /// The tree to show for `tree` (the pixel's, or `None`) under the filter; keeps the
    /// unfiltered tree in `full`. A sample without a matching path keeps its camera ray alone
    /// ([`filter_tree_all_samples`]), so shares stay shares of the whole pixel.
    pub fn apply(&mut self, tree: Option<RayTree>) -> Option<RayTree> {
        self.summary = None;
        self.inapplicable = false;
        self.full = None;
        self.original.clear();
        let tree = tree?;
        let Some(lpe) = &self.active else {
            return Some(tree);
        };
        let full = tree;
        match filter_tree_all_samples(&full, std::slice::from_ref(lpe)) {
            None => {
                self.summary = Some(
                    "not applied: a Whitted tree records no light paths (choose the path integrator)"
                        .into(),
                );
                self.inapplicable = true;
                Some(full)
            }
            Some(f) => {
                self.summary = Some(f.summary());
                self.full = Some(full);
                self.original = f.original;
                Some(f.tree)
            }
        }
    }

    /// The unfiltered id of node `shown` of the tree shown (itself when nothing is filtered).
    #[must_use]
    pub fn to_original(&self, shown: NodeId) -> NodeId {
        self.original.get(shown.index()).copied().unwrap_or(shown)
    }

    /// The shown node for unfiltered node `id` of `full` (the unfiltered tree): the node itself
    /// if the filter kept it, else its nearest kept ancestor; `None` if none is shown.
    #[must_use]
    pub fn from_original(&self, full: &RayTree, id: NodeId) -> Option<NodeId> {
        if self.full.is_none() {
            return (id.index() < full.nodes.len()).then_some(id);
        }
        let mut at = Some(id).filter(|i| i.index() < full.nodes.len());
        while let Some(i) = at {
            if let Some(k) = self.original.iter().position(|&o| o == i) {
                return Some(NodeId(k as u32));
            }
            at = full.node(i).parent;
        }
        None
    }

    /// The unfiltered tree of the selected pixel, given the tree shown.
    #[must_use]
    pub fn unfiltered<'a>(&'a self, shown: Option<&'a RayTree>) -> Option<&'a RayTree> {
        self.full.as_ref().or(shown)
    }
}
