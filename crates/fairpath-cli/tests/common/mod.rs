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

/// `paths` without the programs whose bytes equal an earlier one's (the
/// shared corpus holds several copies, e.g. LinuxCNC's `quick-tests` and
/// `arc-intersections`): the same bytes give the same results, so a
/// corpus test runs each text once. Keeps the first path of each text,
/// in order.
pub fn distinct_texts(paths: Vec<PathBuf>) -> Vec<PathBuf> {
    let mut seen = std::collections::HashSet::new();
    paths
        .into_iter()
        .filter(|p| seen.insert(std::fs::read(p).unwrap_or_default()))
        .collect()
}
