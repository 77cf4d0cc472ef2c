//! The evidence describes what was written: a run the writer kept as the
//! program had it (its rendering planned no faster) counts with its own
//! length, joints and curvature, not with the curves that were never
//! written. Checked against the written text read back.

use crate::common;

use fairpath::geom::Continuity;
use fairpath::path::Run;
use fairpath::verify::{report_without_deviation, VerifyOptions};
use fairpath_gcode::entry::LENGTH_ACCURACY_SHARE;
use fairpath_gcode::{parse, smooth_program, Evidence};

const TOLERANCE: f64 = 0.05;

fn example(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The runs of the written text, read back.
fn written_runs(text: &str) -> Vec<Run> {
    parse(text.as_bytes())
        .expect("the output reads back")
        .runs()
}

/// Peak curvature and corners of `runs` as the verifier classifies them.
fn peak_and_corners(runs: &[Run]) -> (f64, usize) {
    let verify = VerifyOptions::new(TOLERANCE);
    runs.iter().fold((0.0, 0), |(peak, corners), r| {
        let (own, _) = report_without_deviation(&r.pieces, &r.pieces, &verify);
        let c0 = own
            .joints
            .iter()
            .filter(|j| j.class == Continuity::G0)
            .count();
        (peak.max(own.peak_curvature), corners + c0)
    })
}

/// `examples/pocket-corners.ngc` with `auto`: two of its three runs plan no
/// faster when written and are kept as the program had them. The summary
/// printed the curves of those runs: a peak curvature of 17,035 1/mm (a
/// hairpin that was never written) and no corner.
#[test]
fn pocket_corners_evidence_describes_the_runs_kept_as_written() {
    let text = example("pocket-corners.ngc");
    let opts = common::arcs_options(TOLERANCE, "auto");
    let (output, report) = smooth_program(&text, &opts).unwrap();
    let kept = report.kept.iter().filter(|&&k| k).count();
    assert_eq!(kept, report.kept_runs);
    assert!(kept > 0, "the case needs a run kept as written");
    let e = Evidence::of(&report, TOLERANCE * LENGTH_ACCURACY_SHARE);
    let written = written_runs(&output.text);
    assert_eq!(written.len(), report.kept.len());

    // Kept runs are written exactly as the program had them: their corners
    // are the evidence's, one for one.
    let kept_written: Vec<Run> = written
        .iter()
        .zip(&report.kept)
        .filter(|(_, &k)| k)
        .map(|(r, _)| r.clone())
        .collect();
    let (_, kept_corners) = peak_and_corners(&kept_written);
    assert_eq!(e.corners_in_kept_runs, kept_corners);
    assert!(e.joints[1] >= kept_corners, "{:?}", e.joints);

    // The length and peak curvature are those of the written path (the
    // rewritten runs are arcs within the output share of their curves).
    let written_length: f64 = written.iter().map(|r| r.length(1e-6)).sum();
    let rel = (e.length_after - written_length).abs() / written_length;
    assert!(
        rel < 1e-4,
        "evidence {} mm, written {written_length} mm",
        e.length_after
    );
    let (written_peak, _) = peak_and_corners(&written);
    assert!(
        e.peak_curvature <= 1.1 * written_peak,
        "evidence peak {} 1/mm, written {written_peak} 1/mm",
        e.peak_curvature
    );
}

/// With every run kept (`none` writes the program back), the evidence is
/// the program's own: its corners, its length, its arcs' curvature.
#[test]
fn a_program_written_back_is_described_as_itself() {
    let text = "G21 G90\nG0 X0 Y0\nG1 X10 F1000\nG2 X20 Y0 R5\nG1 Y-10\nX0\nG0 Z5\nM2\n";
    let opts = common::arcs_options(TOLERANCE, "none");
    let (_, report) = smooth_program(text, &opts).unwrap();
    assert!(report.kept.iter().all(|&k| k));
    let e = Evidence::of(&report, TOLERANCE * LENGTH_ACCURACY_SHARE);
    let (peak, corners) = peak_and_corners(&parse(text.as_bytes()).unwrap().runs());
    assert_eq!(e.corners_in_kept_runs, corners);
    assert_eq!(e.joints[1], corners);
    assert_eq!(corners, 2, "the arc meets the lines tangentially");
    assert!((e.peak_curvature - 0.2).abs() < 1e-9 && peak == e.peak_curvature);
    assert!((e.length_after - e.length_before).abs() < 1e-9);
}
