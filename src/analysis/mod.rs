//! Analyses over many renders or recorded trees: the epsilon sweep ([`acne`]), what accuracy
//! costs in time ([`cost`]), and the invariants every recorded tree must satisfy
//! ([`invariants`]).

pub mod acne;
pub mod bias;
pub mod converge;
pub mod cost;
pub mod diff;
pub mod explain;
pub mod firefly;
pub mod growth;
#[cfg(test)]
mod hand_tree;
pub mod invariants;
pub mod outliers;
pub mod samples;
pub mod strategies;
pub mod strategy_parts;
pub mod teach;
