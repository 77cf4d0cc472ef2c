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

/// `paths`, the largest file first (ties in the order given): a corpus
/// test that hands programs to a pool of workers one at a time ends with
/// the last ones running alone, so the dearest (by size, a proxy) go first
/// and the tail is short. (`shared_programs` had one program running alone
/// on one core for about two minutes at the end of `.ci/run`.)
#[allow(dead_code)]
pub fn largest_first(mut paths: Vec<PathBuf>) -> Vec<PathBuf> {
    paths.sort_by_key(|p| std::cmp::Reverse(std::fs::metadata(p).map_or(0, |m| m.len())));
    paths
}
