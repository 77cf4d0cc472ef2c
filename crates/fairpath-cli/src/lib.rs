//! The machinery behind the `fairpath` command: the smoothing pipeline
//! (read, smooth, verify, render, verify the rendered text), the summary,
//! `check`, and atomic file output. The binary (`main.rs`) only parses
//! arguments; benchmarks drive the same pipeline through this library.

pub mod check;
pub mod compare;
pub mod output;
pub mod parallel;
pub mod pipeline;
pub mod simulate;
pub mod summary;

/// Output format of `fairpath smooth`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Dense G1 moves at the chord tolerance, in the program's units.
    Gcode,
    /// Exact curves (lines, NURBS), always in mm.
    Json,
}
