//! The integration tests of this crate as one test binary: one build
//! and link instead of one per file, and the tests of every file
//! side by side on the cores (`cargo test -p fairpath-gcode --test integration FILE::`
//! runs one file's). Each file is a module; `common` holds their helpers.

mod auto_written;
mod common;
mod corpus;
mod errors;
mod evidence;
mod fuzz;
mod json_output;
mod keep_rule;
mod language;
mod lines_alternative;
mod modal;
mod motion_reading;
mod parts;
mod passthrough;
mod planar_passes;
mod plans;
mod render_memo;
mod roundtrip;
mod run_windows;
mod short_lines;
mod splines;
mod splines_rs274;
mod tiny_jogs;
mod windowed_plans;
mod writer;
mod writer_curves;
mod writer_lossless;
