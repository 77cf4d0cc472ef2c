#![allow(dead_code)]
use std::path::PathBuf;
use std::sync::Mutex;

/// Held while LinuxCNC's `rs274` runs: 2.9's dies of SIGBUS now and then
/// when two run at once (its shared tool-data memory), and the tests of
/// this binary run side by side, so every one runs it under this lock.
pub static RS274: Mutex<()> = Mutex::new(());

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

mod distinct;
#[allow(unused_imports)]
pub use distinct::distinct_texts;

/// Options for `method` at `tolerance` mm, written as arcs for a generic
/// controller (the default controller's format).
pub fn arcs_options(tolerance: f64, method: &str) -> fairpath_gcode::SmoothOptions {
    use fairpath_gcode::{Controller, Format, SmoothOptions};
    SmoothOptions::new(
        tolerance,
        None,
        method,
        Some(Format::Arcs),
        Controller::Generic,
    )
    .unwrap()
}
