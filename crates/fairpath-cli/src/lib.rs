//! The machinery behind the `fairpath` command: the smoothing pipeline
//! (read, smooth, verify, render, verify the rendered text), the summary,
//! `check`, and atomic file output. The binary (`main.rs`) only parses
//! arguments; benchmarks drive the same pipeline through this library.

#![recursion_limit = "256"]

pub mod check;
pub mod compare;
pub mod machine;
pub mod output;
pub mod pipeline;
pub mod simulate_command;
pub mod stream;
pub mod summary;

/// The output format and the controller live in `fairpath-gcode` (its
/// `clap` feature makes them command-line values).
pub use fairpath_gcode::{Controller, Format};
