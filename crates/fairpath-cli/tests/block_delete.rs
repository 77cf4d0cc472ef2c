//! Block delete end to end: what `fairpath smooth` writes follows the
//! original with the block-delete switch off and on, and `fairpath check`
//! verifies both readings.

use crate::common;
use common::bin;
use fairpath_gcode::{parse_with, ParseOptions};
use std::path::Path;
use std::process::Output;

/// A corner right after the optional move (at X20 Y10): the old reader
/// smoothed it from the end of the `/` move, so with the switch on the
/// machine went from X10 Y0 straight to a point of the smoothed corner.
const PROGRAM: &str = "G21 G90 G17 F1000
G0 X0 Y0 Z0
G1 X5 Y0
G1 X10 Y0
/G1 X10 Y20
G1 X20 Y10
G1 X30 Y20
G1 X40 Y10
G1 X50 Y20
M2
";

fn check(original: &Path, smoothed: &Path) -> Output {
    bin()
        .args([
            "check",
            original.to_str().unwrap(),
            smoothed.to_str().unwrap(),
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

/// Regression: with the switch on, the smoothed program left the path
/// (the run after the `/` line started at the `/` move's end). Now the move
/// after it is written as it was, and `check` passes both readings.
#[test]
fn block_delete_switch_on_leaves_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ngc");
    let out = dir.path().join("out.ngc");
    std::fs::write(&input, PROGRAM).unwrap();
    let o = bin()
        .args([
            "smooth",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--tolerance", "0.05mm"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let written = std::fs::read_to_string(&out).unwrap();
    // The corners after the pinned move are smoothed (the output is not
    // the input), the `/` line and the move after it are kept.
    assert!(written.contains("/G1 X10 Y20\nG1 X20 Y10\n"), "{written}");
    assert!(
        written.lines().count() > PROGRAM.lines().count(),
        "{written}"
    );
    let c = check(&input, &out);
    let report = text(&c);
    assert!(c.status.success(), "{report}");
    assert!(
        report.contains("block delete off") && report.contains("block delete on"),
        "{report}"
    );
    assert_eq!(report.matches("PASS").count(), 3, "{report}");
    // Read with the switch on, the written program starts its moves where
    // the original does.
    let on = ParseOptions {
        block_delete: true,
        ..Default::default()
    };
    let a = parse_with(PROGRAM.as_bytes(), &on).unwrap();
    let b = parse_with(written.as_bytes(), &on).unwrap();
    let first_feed = |p: &fairpath_gcode::Program| {
        p.moves()
            .iter()
            .find(|m| m.line > 5 && !m.piece.rapid)
            .map(|m| m.piece.start())
            .unwrap()
    };
    assert_eq!(first_feed(&a), first_feed(&b));
}

/// What the old reader wrote (the corner at X20 Y10 cut by 0.04 mm, from
/// the `/` move's end) and a program that lost the `/`: `check` fails
/// them in the reading that shows it.
#[test]
fn check_fails_outputs_wrong_with_the_switch_on() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ngc");
    std::fs::write(&input, PROGRAM).unwrap();
    // The corner of the switch-off path, cut within 0.04 mm.
    let old = PROGRAM.replace("G1 X20 Y10\n", "G1 X19.96 Y10.04\nG1 X20.04 Y10.04\n");
    let bad = dir.path().join("old.ngc");
    std::fs::write(&bad, old).unwrap();
    let c = check(&input, &bad);
    let report = text(&c);
    assert_eq!(c.status.code(), Some(3), "{report}");
    let on_part = &report[report.find("block delete on").unwrap()..];
    assert!(on_part.contains("FAIL"), "{report}");
    // Without the `/`: another path with the switch on (and other runs
    // with it off).
    let lost = dir.path().join("lost.ngc");
    std::fs::write(&lost, PROGRAM.replace("/G1", "G1")).unwrap();
    let c = check(&input, &lost);
    let report = text(&c);
    assert_eq!(c.status.code(), Some(3), "{report}");
    let on_part = &report[report.find("block delete on").unwrap()..];
    assert!(on_part.contains("FAIL"), "{report}");
    // A program without `/` lines is checked once.
    let plain = dir.path().join("plain.ngc");
    std::fs::write(&plain, PROGRAM.replace("/G1 X10 Y20\n", "")).unwrap();
    let c = check(&plain, &plain);
    let report = text(&c);
    assert!(c.status.success(), "{report}");
    assert!(!report.contains("block delete"), "{report}");
}

/// In G91 the moves after a `/` line do not depend on it: they are
/// smoothed, written as increments, and follow the original with the
/// switch on too (from wherever the skipped move left the machine).
#[test]
fn incremental_runs_after_block_delete_are_smoothed_and_follow_both_readings() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ngc");
    let out = dir.path().join("out.ngc");
    let mut prog = String::from("G21 G91 G17 F3000\nG0 X0 Y0 Z0\nG1 X5 Y0\n/G1 X0 Y20\n");
    for i in 0..40 {
        prog.push_str(if i % 2 == 0 {
            "G1 X1 Y0.3\n"
        } else {
            "G1 X1 Y-0.3\n"
        });
    }
    prog.push_str("G90\nM2\n");
    std::fs::write(&input, &prog).unwrap();
    let o = bin()
        .args([
            "smooth",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--tolerance", "0.2mm"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(
        !written.contains("G1 X1 Y0.3\n"),
        "not smoothed:\n{written}"
    );
    let c = bin()
        .args(["check", input.to_str().unwrap(), out.to_str().unwrap()])
        .args(["--tolerance", "0.2mm"])
        .output()
        .unwrap();
    let report = text(&c);
    assert!(c.status.success(), "{report}");
    assert_eq!(report.matches("PASS").count(), 3, "{report}");
}

/// A `/` line right after a smoothed run, before the next motion word:
/// the run is written with G2/G3, so the writer restores the program's G1
/// on a line of its own; without it the lines after the `/` line ran as
/// arcs with the switch on (or, with a motion word inserted only into the
/// `/` line, read differently in each position of the switch).
#[test]
fn a_block_delete_line_after_a_run_sees_the_programs_motion_mode() {
    let dir = tempfile::tempdir().unwrap();
    for tail in [
        "/X40 Y0\nX41 Y1\nX42 Y0\n",
        "/G0 X40 Y0\nX41 Y1\nG1 X42 Y0\nX43 Y1\n",
    ] {
        let mut prog = String::from("G21 G90 G17 F3000\nG0 X0 Y0 Z0\n");
        for i in 0..30 {
            prog.push_str(&format!(
                "G1 X{} Y{}\n",
                i + 1,
                if i % 2 == 0 { 0.3 } else { 0.0 }
            ));
        }
        prog.push_str(tail);
        prog.push_str("M2\n");
        let input = dir.path().join("in.ngc");
        let out = dir.path().join("out.ngc");
        std::fs::write(&input, &prog).unwrap();
        let o = bin()
            .args([
                "smooth",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args(["--tolerance", "0.2mm"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{tail}: {}", text(&o));
        let written = std::fs::read_to_string(&out).unwrap();
        assert!(
            written.contains("G2 ") || written.contains("G3 "),
            "{written}"
        );
        assert!(
            written.contains(&format!("G1\n{}", tail.lines().next().unwrap())),
            "{written}"
        );
        let on = ParseOptions {
            block_delete: true,
            ..Default::default()
        };
        assert!(parse_with(written.as_bytes(), &on).is_ok(), "{written}");
        let c = bin()
            .args(["check", input.to_str().unwrap(), out.to_str().unwrap()])
            .args(["--tolerance", "0.2mm"])
            .output()
            .unwrap();
        let report = text(&c);
        assert!(c.status.success(), "{tail}: {report}");
        assert_eq!(report.matches("PASS").count(), 3, "{report}");
    }
}
