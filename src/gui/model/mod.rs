//! The inspector's model: the [`Document`](document::Document) and the plain data it is made
//! of (statistics, view options, the diagram's and the jobs' settings), with the computations
//! panels read from it (a pixel's breakdown, the film projection, export encoding). No egui and
//! no threads here: the jobs, the session and the panels build on this layer.

pub mod breakdown;
pub mod diagram;
pub mod diagram_view;
pub mod document;
pub mod export;
pub mod lab;
pub mod lpe_filter;
pub mod progressive;
pub mod project;
pub mod stats;
