//! The integration tests of this crate as one test binary: one build
//! and link instead of one per file, and the tests of every file
//! side by side on the cores (`cargo test -p fairpath-cli --test integration FILE::`
//! runs one file's). Each file is a module; `common` holds their helpers.

mod arc_fit;
mod auto_no_slower;
mod block_delete;
mod bounded_work;
mod check_robust;
mod cli;
mod common;
mod fair_inputs;
mod habits;
mod issue16_targets;
mod issue21_targets;
mod issue5_targets;
mod language_rs274;
mod linuxcnc_rs274;
mod lossless;
mod lower_bound;
mod method_none;
mod passthrough;
mod progress;
mod report;
mod shared_programs;
mod simulate;
mod stream;
mod thesis_cases;
mod written_program;
