#![allow(dead_code)]
use std::path::PathBuf;

/// The shared reference programs (`/work/shared/paths` beside the repo), or
/// None (with a message) if absent.
pub fn shared_paths() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/paths");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: shared test data not found at {}", dir.display());
        None
    }
}

/// All files under `dir`, sorted.
pub fn files_under(dir: &std::path::Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x == "ngc" || x == "gcode" || x == "nc")
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

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
