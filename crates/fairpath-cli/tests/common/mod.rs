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

/// Programs on which the corpus tests (`shared_programs.rs`,
/// `linuxcnc_rs274.rs`) run `auto` at 0.05 mm only, not at 0.01 mm (every
/// other method still runs at both). `auto` at 0.01 mm on the first three
/// (the two `blur_torus.ngc` count as one) took 87 s of the 644 s of work
/// of `shared_programs` and 118 s of the 549 s of smoothing of
/// `linuxcnc_rs274` (2026-11-28; issue 19: its fits through corners fail
/// and split again and again at small tolerances). The last four (one
/// text: the two `circle_a` files are the same) were the dearest after
/// them: `fairpath smooth` at 0.01 mm took 16.8 s on `circle_a.gcode`,
/// 17.2 s on `spiral_lines.ngc` and 15.6 s on `51MeanderAve.ngc`
/// (2026-11-28), when the clean-clone `.ci/run` had reached 30.5 minutes.
pub const AUTO_SMALL_TOL_SKIPPED: [&str; 7] = [
    "3D_Chips.ngc",
    "Cereal.ngc",
    "blur_torus.ngc",
    "circle_a.gcode",
    "estlcam_circle_a.gcode",
    "spiral_lines.ngc",
    "51MeanderAve.ngc",
];

/// Whether `p` is one of [`AUTO_SMALL_TOL_SKIPPED`].
pub fn auto_small_tol_skipped(p: &Path) -> bool {
    AUTO_SMALL_TOL_SKIPPED.iter().any(|n| p.ends_with(n))
}

#[path = "../../../fairpath-gcode/tests/common/distinct.rs"]
mod distinct;
#[allow(unused_imports)]
pub use distinct::{distinct_texts, largest_first};
