//! The all-G1 alternative the arcs format tries where its arcs fell back to
//! lines (`emit::choose`, `Emitter::finer_lines_chord`).

use crate::common;

use fairpath_gcode::{smooth_program, Controller, Format, SmoothOptions};

/// LinuxCNC's `random_lines_0.001in.ngc` (25 um moves under a blending
/// `G64`) with `bspline-fit` at 0.05 mm: the arcs fell back to lines on
/// every block, and the all-G1 alternative, rendered at the arcs' chord,
/// was the same 1471 lines (1.294 s written). At the finer chord that G1
/// output renders at (half the output share kept for the controller's
/// blending) it is what `--format g1` writes, and wins.
#[test]
fn random_lines_0_001in_arcs_format_writes_what_g1_writes() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let path = dir.join("linuxcnc/performance/random_lines_0.001in.ngc");
    let text = std::fs::read_to_string(path).unwrap();
    let written = |format| {
        let opts = SmoothOptions::new(0.05, None, "bspline-fit", Some(format), Controller::Generic)
            .unwrap();
        let (output, report) = smooth_program(&text, &opts).unwrap();
        (output.text, report.times.written.total)
    };
    let (arcs_text, arcs) = written(Format::Arcs);
    let (g1_text, g1) = written(Format::G1);
    assert!(
        !arcs_text.contains("G2") && !arcs_text.contains("G3"),
        "the arcs format wrote arcs"
    );
    assert!(arcs <= g1 * 1.001, "arcs {arcs} s against G1 {g1} s");
    assert!(arcs < 1.2, "arcs {arcs} s (1.294 s at the arcs' chord)");
    assert!(g1_text.lines().count() > 0);
}

/// The same program and method on a machine with a block time of 1 ms
/// (`MachineLimits::block_time`): a stretch of equal moves is no longer cut
/// at the spacing of its slowest sample all through its fast part, where
/// each move would then take the block time (1.944 s written when it was;
/// `render::lines::FLOOR_CUT_SHARE`).
#[test]
fn random_lines_0_001in_with_a_block_time_keeps_fast_moves_above_it() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let path = dir.join("linuxcnc/performance/random_lines_0.001in.ngc");
    let text = std::fs::read_to_string(path).unwrap();
    let mut opts =
        SmoothOptions::new(0.05, None, "bspline-fit", None, Controller::Generic).unwrap();
    let machine = fairpath::feed::limits::MachineLimits {
        block_time: 0.001,
        ..*opts.machine()
    };
    opts.set_machine(machine, false).unwrap();
    let (_, report) = smooth_program(&text, &opts).unwrap();
    let written = report.times.written.total;
    assert!(written < 1.7, "written {written} s (1.944 s before)");
}
