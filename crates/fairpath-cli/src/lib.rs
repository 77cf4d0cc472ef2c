//! The machinery behind the `fairpath` command around the libraries'
//! pipeline (`fairpath::pipeline`, `fairpath_gcode::smooth_program`):
//! reading files, the machine file, atomic output that never replaces the
//! input unless asked, the summary, and the commands `smooth`, `simulate`,
//! `compare`, `check`, `report` and `stream`. The binary (`main.rs`) only parses
//! arguments; benchmarks drive the same code through this library.

#![recursion_limit = "256"]

pub mod check;
pub mod compare;
pub mod length;
pub mod machine;
pub mod methods;
pub mod output;
pub mod progress;
pub mod read;
pub mod report;
pub mod simulate_command;
pub mod smooth;
pub mod source_error;
pub mod stream;
pub mod summary;
pub mod usage;

/// The output format and the controller live in `fairpath-gcode` (its
/// `clap` feature makes them command-line values).
pub use fairpath_gcode::{Controller, Format};
