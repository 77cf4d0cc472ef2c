//! A pass in a principal plane is written in that plane, end to end
//! (fits, fairing, rendering, rounding): no feed line of an XZ pass names
//! Y. The fits keep a coordinate the whole pass shares to the bit
//! (`fairpath::geom::fit::FitData` solves relative to its start point;
//! the regression test of that is `fairpath`'s `tests/fit_planar.rs`);
//! this checks nothing after them moves the pass off its plane by as much
//! as the output's last digit.

use fairpath_gcode::{smooth_program, Controller, Format, SmoothOptions};

/// One XZ pass at `y` (inches, G18): a wavy profile of `points` points
/// over 1.6 in.
fn xz_pass(y: f64, points: usize, amp: f64) -> String {
    let mut out = format!("G20 G90\nG18\nF40\nG0 X0 Y{y:.4} Z0.1\nG1 Z0\n");
    for i in 1..points {
        let x = 1.6 * i as f64 / (points - 1) as f64;
        let z = amp * (7.0 * x).sin() * (1.3 * x).cos();
        out += &format!("X{x:.4} Z{z:.4}\n");
    }
    out + "G0 Z0.1\nM2\n"
}

/// The lines of `text` between the rapid to the pass and the rapid off
/// it: its feed moves.
fn feed_lines(text: &str) -> Vec<&str> {
    let lines: Vec<&str> = text.lines().collect();
    let first = lines.iter().position(|l| l.starts_with("G0 X0")).unwrap();
    let last = lines.iter().rposition(|l| l.starts_with("G0 Z")).unwrap();
    lines[first + 1..last].to_vec()
}

/// Passes at several heights and waves, by the fitting methods: arcs
/// were written, and no feed line names Y.
#[test]
fn a_pass_in_the_xz_plane_is_written_without_a_y_word() {
    for (y, amp) in [(1.435, 0.05), (0.127, 0.02), (2.3917, 0.08)] {
        let text = xz_pass(y, 160, amp);
        for method in ["bspline-fit", "auto"] {
            let opts =
                SmoothOptions::new(0.05, None, method, Some(Format::Arcs), Controller::Generic)
                    .unwrap();
            let (out, report) = smooth_program(&text, &opts).unwrap();
            assert!(report.written.within, "{method} at Y{y}");
            let feed = feed_lines(&out.text);
            assert!(
                feed.iter().any(|l| l.contains("G2") || l.contains("G3")),
                "{method} at Y{y}: no arc"
            );
            for l in feed {
                assert!(!l.contains('Y'), "{method} at Y{y}: {l}");
            }
        }
    }
}
