//! Helpers shared by the CLI's integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The `fairpath` binary.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fairpath"))
}

/// A reference program under `../shared/paths`, if that folder is there.
pub fn shared(rel: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/paths")
        .join(rel);
    p.exists().then_some(p)
}

/// A bundled example program.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}
pub mod rs274;

#[path = "../../../fairpath-gcode/tests/common/distinct.rs"]
mod distinct;
#[allow(unused_imports)]
pub use distinct::distinct_texts;
