//! `fairpath smooth --method arc-fit --controller linuxcnc` on the reference
//! programs: the written program verifies (`fairpath check`) and has fewer
//! motion blocks than the input's feed moves (LinuxCNC's S-curve planner
//! caps the speed at the end of every block, so fewer, longer blocks run
//! faster there).

use crate::common;
use common::{bin, shared};
use std::path::Path;

/// Feed moves (G1/G2/G3 blocks) of the program at `path`, as read.
fn feed_moves(path: &Path) -> usize {
    let program = fairpath_gcode::parse(&std::fs::read(path).unwrap()).unwrap();
    program.runs().iter().map(|r| r.pieces.len()).sum()
}

/// Smooths `rel` (under `../shared/paths`) with `arc-fit` for LinuxCNC at
/// `tol` mm and checks the output; returns (input, output) feed moves.
fn arc_fit(rel: &str, tol: &str) -> Option<(usize, usize)> {
    let Some(input) = shared(rel) else {
        eprintln!("../shared/paths not found: skipped");
        return None;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let o = bin()
        .args([
            "smooth",
            input.to_str().unwrap(),
            "--tolerance",
            &format!("{tol}mm"),
            "--method",
            "arc-fit",
            "--controller",
            "linuxcnc",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{rel}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let c = bin()
        .args([
            "check",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--tolerance",
            &format!("{tol}mm"),
        ])
        .output()
        .unwrap();
    assert!(
        c.status.success(),
        "check {rel}: {}{}",
        String::from_utf8_lossy(&c.stdout),
        String::from_utf8_lossy(&c.stderr)
    );
    Some((feed_moves(&input), feed_moves(&out)))
}

#[test]
fn butterfly_has_fewer_blocks() {
    let Some((input, output)) = arc_fit("synthetic/butterfly-80.ngc", "0.05") else {
        return;
    };
    assert_eq!(input, 80);
    assert!(output < input, "{output} blocks for {input} feed moves");
}

/// Five turns of 72 moves each: a few helical arcs (at most 350 degrees
/// each).
#[test]
fn helix_becomes_a_few_arcs() {
    for tol in ["0.05", "0.01"] {
        let Some((input, output)) = arc_fit("synthetic/helix.ngc", tol) else {
            return;
        };
        assert_eq!(input, 360);
        assert!(output <= 6, "{output} blocks at {tol}");
    }
}

/// `linuxcnc/quick-tests/straight_segments.ngc`: 1,000 collinear G91 moves
/// of 0.0005 in inside an o-word loop become one line. The input's f64 sum
/// of the increments ends 1.5e-13 mm from the written `X0.5`, and the
/// written program was refused as moving a run endpoint; end points now
/// count as equal within the rounding share of the tolerance.
#[test]
fn straight_segments_merged_into_one_line_is_written() {
    let Some((input, output)) = arc_fit("linuxcnc/quick-tests/straight_segments.ngc", "0.05")
    else {
        return;
    };
    assert!(input > 1000, "{input}");
    assert!(output < 10, "{output} blocks");
}

/// `--controller linuxcnc` without `--method` writes with arc-fit (its
/// planners cap the speed per block).
#[test]
fn linuxcnc_defaults_to_arc_fit() {
    let Some(input) = shared("synthetic/helix.ngc") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let o = bin()
        .args(["smooth", input.to_str().unwrap(), "--tolerance", "0.05mm"])
        .args(["--controller", "linuxcnc", "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{text}");
    assert!(text.contains("(arc-fit, arcs for linuxcnc"), "{text}");
    assert!(feed_moves(&out) <= 6);
}

/// Regression, `synthetic/helix.ngc` with arc-fit: the summary said
/// "6 arcs (0 helical)" for six helical G3 blocks (arcs that a method
/// makes itself were counted as arcs only).
#[test]
fn helix_arcs_are_counted_as_helical() {
    let Some(input) = shared("synthetic/helix.ngc") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ngc");
    let o = bin()
        .args(["smooth", input.to_str().unwrap(), "--tolerance", "0.05mm"])
        .args(["--method", "arc-fit", "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{text}");
    let arcs = feed_moves(&out);
    assert!(
        text.contains(&format!("{arcs} arcs ({arcs} helical)")),
        "{arcs} arcs written: {text}"
    );
}
