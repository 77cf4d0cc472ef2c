//! A helper of the corpus tests of both crates (the CLI's tests include
//! this file by path).

use std::path::PathBuf;

/// `paths` without the programs whose bytes equal an earlier one's (the
/// shared corpus holds several copies, e.g. LinuxCNC's `quick-tests` and
/// `arc-intersections`): the same bytes give the same results, so a
/// costly corpus test runs each text once. Keeps the first path of each
/// text, in order.
pub fn distinct_texts(paths: Vec<PathBuf>) -> Vec<PathBuf> {
    let mut seen = std::collections::HashSet::new();
    paths
        .into_iter()
        .filter(|p| seen.insert(std::fs::read(p).unwrap_or_default()))
        .collect()
}
