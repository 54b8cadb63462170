//! Hostile input (issue 13): every case runs the release binary under a memory cap and a
//! timeout, and must end with exit 0 or 2, no panic, no temp file left behind, and no change to
//! files it was not asked to write. The cases live in `tests/hostile/*.rs`, one module per area.

mod common;

#[path = "hostile/harness.rs"]
mod harness;

#[path = "hostile/outputs.rs"]
mod outputs;

#[path = "hostile/streams.rs"]
mod streams;

#[path = "hostile/loader.rs"]
mod loader;

#[path = "hostile/bounds.rs"]
mod bounds;

#[path = "hostile/commands.rs"]
mod commands;

#[path = "hostile/finite.rs"]
mod finite;

#[path = "hostile/scenes.rs"]
mod scenes;

#[path = "hostile/round3.rs"]
mod round3;
