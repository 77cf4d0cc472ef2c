//! Lines too short to say where they point are not written
//! (`fairpath::render::absorb`).

use crate::common;

use fairpath::budget::SHORT_LINE_SHARE;
use fairpath::geom::{Curve, ParamCurve};
use fairpath_gcode::{read_motion, smooth_program, Controller, SmoothOptions};

/// Turn (rad) below which a written line continues the piece before it:
/// the rounding of a 0.1 um line's ends turns it by up to about 1e-3.
const CONTINUES: f64 = 2e-3;

/// Lines of the written runs no longer than `max_len` that continue the
/// piece before them (same feed, same point, nearly the same direction).
fn short_lines_written(text: &str, max_len: f64) -> usize {
    let (_, runs) = read_motion(text.as_bytes()).unwrap();
    runs.iter()
        .flat_map(|r| r.pieces.windows(2))
        .filter(|w| {
            let short = matches!(&w[1].curve, Curve::Line(l) if l.length() <= max_len);
            let turn = match (w[0].curve.unit_tangent(1.0), w[1].curve.unit_tangent(0.0)) {
                (Some(a), Some(b)) => a.angle_to(b),
                _ => f64::INFINITY,
            };
            short
                && turn < CONTINUES
                && w[0].feed == w[1].feed
                && w[0].curve.end() == w[1].curve.start()
        })
        .count()
}

/// LinuxCNC's LHchips4.ngc with `bspline-corner`: two corner transitions
/// on one segment left a line of 0.1 to 0.3 um between them, which the
/// rounding of its written ends (to 1e-7 mm) turned by up to 6e-4 rad:
/// two corners with no room, where the planned speed of the text read
/// back fell to a few mm/s, and 116 of the 1134 runs of its first 20,000
/// lines came back slower than the program's own and were written again
/// as the program wrote them.
#[test]
fn lhchips4_remnant_lines_between_transitions_are_merged() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let text = std::fs::read_to_string(dir.join("linuxcnc/performance/LHchips4.ngc")).unwrap();
    let opts = SmoothOptions::new(0.05, None, "bspline-corner", None, Controller::Generic).unwrap();
    let (output, report) = smooth_program(&text, &opts).unwrap();
    let max_len = SHORT_LINE_SHARE * report.budget.render();
    assert!(report.stats.absorbed_lines > 0);
    assert_eq!(short_lines_written(&text, max_len), 0, "the program's own");
    assert_eq!(short_lines_written(&output.text, max_len), 0);
    assert!(report.written.within);
    assert!(report.times.written.total < report.times.input.total);
}
