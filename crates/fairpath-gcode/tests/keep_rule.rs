//! When a run is rewritten and when it is written as the program had it
//! (`emit::choose`, `KEEP_MARGIN`): a run of splines faired in place is
//! written when it plans no slower (it lowers the curvature at no cost in
//! blocks); a run of lines must gain the margin, else it keeps its blocks.

use crate::common;

use fairpath::verify::{report_without_deviation, VerifyOptions};
use fairpath_gcode::{parse, smooth_program, Controller, Format, SmoothOptions};

/// A G6.2 cubic through 32 points along a 100 mm line, two of them 0.2 mm
/// off (the thesis' case 5 kind), after a plunge at `feed` mm/min.
fn rippled_g6_2(feed: f64) -> String {
    let mut s = format!("G21 G90 G17 G94\nG0 X0 Y0 Z0\nG1 Z-1 F{feed}\n");
    for i in 0..32 {
        let x = 100.0 * i as f64 / 31.0;
        let y = match i {
            10 => 0.2,
            21 => -0.2,
            _ => 0.0,
        };
        let k = i.max(3) - 3;
        let head = if i == 0 { "G6.2 " } else { "  " };
        let tail = if i == 0 { " P4 Q1" } else { "" };
        s += &format!("{head}X{x:.4} Y{y:.4} R1 K{k}{tail}\n");
    }
    for _ in 0..4 {
        s += "G6.2 K29\n";
    }
    s + "G0 Z5\nM2\n"
}

/// Peak curvature of a program's feed runs, read from its text.
fn peak_curvature(text: &str, tolerance: f64) -> f64 {
    let verify = VerifyOptions::new(tolerance);
    parse(text.as_bytes())
        .unwrap()
        .runs()
        .iter()
        .map(|r| report_without_deviation(&r.pieces, &r.pieces, &verify).0)
        .map(|r| r.peak_curvature)
        .fold(0.0, f64::max)
}

/// At 3000 mm/min the ripples do not slow the machine: the faired spline
/// plans about as fast as the program's own (2.214 against 2.215 s on the
/// feed moves), short of the margin. It is written all the same (it had
/// been kept as written, and the summary claimed the fairing).
#[test]
fn a_spline_faired_at_a_feed_its_ripples_do_not_slow_is_written() {
    let tolerance = 0.25;
    let text = rippled_g6_2(3000.0);
    for format in [Format::G6_2, Format::Arcs] {
        let opts =
            SmoothOptions::new(tolerance, None, "fair", Some(format), Controller::Generic).unwrap();
        let (output, report) = smooth_program(&text, &opts).unwrap();
        assert_eq!(report.kept_runs, 0, "{format:?}");
        let t = report.times;
        assert!(t.written.feed <= t.input.feed, "{format:?}: {t:?}");
        let (before, after) = (
            peak_curvature(&text, tolerance),
            peak_curvature(&output.text, tolerance),
        );
        assert!(
            after < 0.05 * before,
            "{format:?}: {after} against {before}"
        );
    }
}

/// A run of lines whose corners of 0.9 degrees cost next to nothing at
/// 600 mm/min: its smoothing gains less than the margin, so the program's
/// blocks are kept.
#[test]
fn a_run_of_lines_that_gains_less_than_the_margin_is_kept() {
    let text = "G21 G90\nG0 X0 Y0\nG1 X20 F600\nX40 Y0.3\nX60 Y0\nX80 Y0.3\nG0 Z5\nM2\n";
    let opts = common::arcs_options(0.05, "bspline-corner");
    let (output, report) = smooth_program(text, &opts).unwrap();
    let t = report.times;
    assert!(
        t.exact.feed < t.input.feed
            && t.exact.feed > t.input.feed * (1.0 - fairpath_gcode::emit::KEEP_MARGIN),
        "the case needs a gain under the margin: {t:?}"
    );
    assert_eq!(report.kept_runs, 1, "{}", output.text);
    for line in ["G1 X20 F600", "X40 Y0.3", "X60 Y0", "X80 Y0.3"] {
        assert!(output.text.contains(line), "{}", output.text);
    }
    let arcs = output
        .text
        .lines()
        .filter(|l| l.starts_with("G2 ") || l.starts_with("G3 "))
        .count();
    assert_eq!(arcs, 0, "{}", output.text);
}
