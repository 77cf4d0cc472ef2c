//! `fairpath smooth` on what it passes through: feeds stay on their
//! stretch of path, canned cycles and E words are written as they were
//! (with a warning), programs without moves are copied unchanged.

use crate::common;
use common::{bin, shared};
use fairpath::geom::{point_segment_distance, Curve, ParamCurve, Vec3};
use fairpath::path::Piece;
use fairpath_gcode::{parse, read_json, Program};
use std::path::Path;
use std::process::Output;

fn smooth(input: &Path, out: &Path) -> Output {
    bin()
        .args([
            "smooth",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--tolerance", "0.05mm"])
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Distance from `q` to a piece of the input (lines exactly, other curves
/// by dense samples).
fn distance(q: Vec3, c: &Curve) -> f64 {
    match c {
        Curve::Line(l) => point_segment_distance(q, l.p0, l.p1),
        _ => {
            let (a, b) = c.domain();
            (0..=256)
                .map(|i| c.eval(a + (b - a) * i as f64 / 256.0).dist(q))
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// Every feed piece of `output` runs at the input's feed where it lies: at
/// points inside each written piece, the feed of the nearest input feed
/// move (or, within `tol` of moves of several feeds, one of theirs).
fn assert_feeds_stay(input: &Program, output: &[Piece], tol: f64) {
    let feeds: Vec<(&Curve, Option<f64>)> = input
        .moves()
        .iter()
        .filter(|m| !m.piece.rapid)
        .map(|m| (&m.piece.curve, m.piece.feed))
        .collect();
    for p in output.iter().filter(|p| !p.rapid) {
        let (a, b) = p.curve.domain();
        for s in [0.25, 0.5, 0.75] {
            let q = p.curve.eval(a + (b - a) * s);
            let near: Vec<(f64, Option<f64>)> = feeds
                .iter()
                .map(|(c, f)| (distance(q, c), *f))
                .filter(|(d, _)| *d <= tol)
                .collect();
            assert!(
                !near.is_empty(),
                "{:?}: {q:?} off the input",
                p.source_lines
            );
            let nearest = near.iter().min_by(|x, y| x.0.total_cmp(&y.0)).unwrap().1;
            let ok = p.feed == nearest || near.iter().any(|(_, f)| *f == p.feed);
            assert!(
                ok,
                "{:?}: feed {:?} at {q:?}, the input's is {nearest:?}",
                p.source_lines, p.feed
            );
        }
    }
}

/// The pieces of a written program (G-code or JSON).
fn written_pieces(path: &Path) -> Vec<Piece> {
    let text = std::fs::read_to_string(path).unwrap();
    if text.starts_with('{') {
        read_json(&text).unwrap()
    } else {
        parse(text.as_bytes()).unwrap().pieces()
    }
}

/// Regression, `linuxcnc/diagnostic/feed-tracking-test.ngc`: `X2.001 F10`
/// between moves at F1000 was merged with them (written `G1 X7 F10`, 1.03
/// s -> 42.0 s; the exact curves of the run, as JSON, lost the F10
/// stretch). Every format keeps each feed on its stretch.
#[test]
fn feed_tracking_test_keeps_every_feed_on_its_stretch() {
    let dir = tempfile::tempdir().unwrap();
    let input = shared("linuxcnc/diagnostic/feed-tracking-test.ngc").unwrap_or_else(|| {
        let p = dir.path().join("feed-tracking-test.ngc");
        std::fs::write(
            &p,
            "G90 G20\n\nG64 P0.005 Q0.0\n\nG0 X0 Y0 Z0\nG1 X1 F1000\nG1 X2 F1000\n\
             G1 X2.001 F10\nG1 X5 F1000\nG1 X6 F1000\nG1 X7 F1000\nM2\n",
        )
        .unwrap();
        p
    });
    let a = parse(&std::fs::read(&input).unwrap()).unwrap();
    for format in ["arcs", "g1", "json"] {
        let out = dir.path().join(format!("out.{format}"));
        let o = bin()
            .args([
                "smooth",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--tolerance", "0.05mm", "--format", format])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let b = written_pieces(&out);
        assert_feeds_stay(&a, &b, 0.05);
        // The F10 stretch is X2 .. X2.001 in, nothing more, nothing less.
        let slow: f64 = b
            .iter()
            .filter(|p| p.feed == Some(10.0 * 25.4))
            .map(|p| p.start().dist(p.end()))
            .sum();
        assert!((slow - 0.001 * 25.4).abs() < 1e-9, "{format}: {slow}");
    }
}

/// Feeds that change inside a contour with corners: the corners are
/// smoothed, and each feed keeps its stretch.
#[test]
fn feed_changes_inside_a_contour_stay_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ngc");
    let out = dir.path().join("out.ngc");
    let mut prog = String::from("G21 G90 F600\nG0 X0 Y0 Z0\nG1 X1 Y0\n");
    for i in 1..40 {
        let f = if (10..20).contains(&i) {
            " F150"
        } else if i == 20 {
            " F600"
        } else {
            ""
        };
        prog.push_str(&format!(
            "G1 X{} Y{}{f}\n",
            1 + i,
            if i % 2 == 0 { 0.0 } else { 0.3 }
        ));
    }
    prog.push_str("M2\n");
    std::fs::write(&input, &prog).unwrap();
    let o = smooth(&input, &out);
    assert!(o.status.success(), "{}", text(&o));
    let a = parse(prog.as_bytes()).unwrap();
    let b = written_pieces(&out);
    assert!(b.len() > a.moves().len(), "nothing was smoothed");
    assert_feeds_stay(&a, &b, 0.05);
}

/// Canned cycles and E words: written back verbatim, with a warning naming
/// the lines.
#[test]
fn cycles_and_e_words_are_written_back_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ngc");
    let out = dir.path().join("out.ngc");
    let prog = "G21 G90 F100\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1\nX2\nG80\nG1 X3 Y1 Z0\n\
                G1 X4 Y2\nG1 X5 Y2 E0.4\nG1 X6 Y3\nG1 X7 Y2\nM2\n";
    std::fs::write(&input, prog).unwrap();
    let o = smooth(&input, &out);
    let report = text(&o);
    assert!(o.status.success(), "{report}");
    assert!(
        report.contains("lines 3-4 (canned cycle)")
            && report.contains("line 8 (extruder word E (3D printers))"),
        "{report}"
    );
    let written = std::fs::read_to_string(&out).unwrap();
    for l in ["G81 X1 Y1 Z-1 R1\nX2\n", "G1 X5 Y2 E0.4\n"] {
        assert!(written.contains(l), "{written}");
    }
}

/// `linuxcnc/interp_state/sloc_toolchange.ngc` (tool changes, no moves)
/// was "the program has no moves", an error: now copied through.
#[test]
fn a_program_without_moves_is_copied_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let input = shared("linuxcnc/interp_state/sloc_toolchange.ngc").unwrap_or_else(|| {
        let p = dir.path().join("sloc_toolchange.ngc");
        std::fs::write(&p, "G20 G90\nM8\nM6 T0\nM6 T1\nM6 T2\nM9\nM2\n").unwrap();
        p
    });
    let out = dir.path().join("out.ngc");
    let o = smooth(&input, &out);
    let report = text(&o);
    assert!(o.status.success(), "{report}");
    assert!(report.contains("no moves"), "{report}");
    assert_eq!(std::fs::read(&input).unwrap(), std::fs::read(&out).unwrap());
    // simulate: zero time, a note; compare: an error that says why.
    let o = bin().arg("simulate").arg(&input).output().unwrap();
    let report = text(&o);
    assert!(o.status.success(), "{report}");
    assert!(
        report.contains("time:            0.0000 s") && report.contains("no moves"),
        "{report}"
    );
    let o = bin()
        .args(["compare", input.to_str().unwrap(), "--tolerance", "0.05mm"])
        .output()
        .unwrap();
    let report = text(&o);
    assert!(
        !o.status.success() && report.contains("no moves"),
        "{report}"
    );
}
