//! Specific behaviour of the G-code writer.
use fairpath_gcode::{parse, write_gcode, GcodeWriteOptions};

fn write_unchanged(text: &str) -> String {
    let p = parse(text.as_bytes()).unwrap();
    let runs: Vec<_> = p.runs().into_iter().map(|r| r.pieces).collect();
    let opts = GcodeWriteOptions {
        chord_mm: 0.01,
        header: false,
        ..Default::default()
    };
    write_gcode(&p, &runs, &opts).unwrap()
}

#[test]
fn comments_feed_and_modal_motion() {
    let text =
        "G21 G90\nG0 X0 Y0\nG1 X10 F100\n(inside)\nG2 X20 Y0 I5 J0\nM8\nX30 Y0 I5 S100\nM2\n";
    let out = write_unchanged(text);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0..3], ["G21 G90", "G0 X0 Y0", "G1 X10 F100"]);
    assert_eq!(lines[3], "(inside)");
    assert!(lines[4].starts_with("G1 X"));
    let m8 = lines.iter().position(|l| *l == "M8").unwrap();
    assert_eq!(lines[m8 - 1], "G1 X20 Y0");
    // The next line relied on modal G2: the word is inserted.
    assert_eq!(lines[m8 + 1], "G2 X30 Y0 I5 S100");
    assert_eq!(*lines.last().unwrap(), "M2");
}

#[test]
fn incremental_runs_are_written_incrementally() {
    let text = "G91\nG1 X1.5 F100\nX1.5\nY-2\nM2\n";
    let out = write_unchanged(text);
    assert_eq!(out, "G91\nG1 X1.5 F100\nG1 X1.5\nG1 Y-2\nM2\n");
}

#[test]
fn inch_output_keeps_original_end_text() {
    let text = "G20\nG0 X0 Y0\nG1 X0.12345678 F10\nG3 X0.12345678 Y0.3 R0.15\nM2\n";
    let out = write_unchanged(text);
    let q = parse(out.as_bytes()).unwrap();
    // The arc end re-reads exactly as the program's text.
    let want = fairpath::geom::Vec3::new(0.12345678 * 25.4, 0.3 * 25.4, 0.0);
    assert_eq!(q.pieces().last().unwrap().end(), want);
    assert!(out.contains("Y0.3"));
    assert!(out.contains("F10"));
}

#[test]
fn feed_restored_after_run() {
    // The smoother's pieces carry a different feed: the original modal feed
    // is restored after the run.
    let text = "G0 X0\nG1 X1 F100\nX2\nG0 X5\nG1 X6\n";
    let p = parse(text.as_bytes()).unwrap();
    let mut runs: Vec<_> = p.runs().into_iter().map(|r| r.pieces).collect();
    for piece in &mut runs[0] {
        piece.feed = Some(50.0);
    }
    let opts = GcodeWriteOptions {
        header: false,
        ..Default::default()
    };
    let out = write_gcode(&p, &runs, &opts).unwrap();
    assert_eq!(out, "G0 X0\nG1 X1 F50\nG1 X2\nF100\nG0 X5\nG1 X6 F100\n");
}
