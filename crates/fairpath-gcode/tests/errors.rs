//! Bad input: typed errors with line and column, never a panic.
use fairpath_gcode::{parse, ErrorKind};
use proptest::prelude::*;

fn err(text: &[u8]) -> fairpath_gcode::GcodeError {
    parse(text).expect_err("should fail")
}

#[test]
fn malformed_numbers() {
    let e = err(b"G1 X1\nG1 X1.2.3\n");
    assert_eq!((e.line, e.column), (2, 4));
    assert!(matches!(
        e.kind,
        ErrorKind::MalformedNumber { letter: 'X', .. }
    ));
    assert_eq!(e.to_string(), "2:4: malformed number for word X: \"1.2.3\"");
    let e = err(b"G0 Xnan");
    assert_eq!(
        (e.line, e.column, e.kind),
        (1, 4, ErrorKind::MissingValue('X'))
    );
    let e = err(b"G0 Xinf");
    assert_eq!(e.kind, ErrorKind::MissingValue('X'));
    let e = err(b"G0 X");
    assert_eq!(e.kind, ErrorKind::MissingValue('X'));
    let e = err(b"G0 X-");
    assert!(matches!(e.kind, ErrorKind::MalformedNumber { .. }));
    // Exponent notation reads as X1 and the word E5, passed through.
    let p = parse(b"G0 X1e5").unwrap();
    assert_eq!(p.passthrough().len(), 1);
    let big = format!("G0 X1{}", "0".repeat(400));
    assert_eq!(err(big.as_bytes()).kind, ErrorKind::NumberOutOfRange('X'));
}

#[test]
fn garbage_and_utf8() {
    let e = err(b"G0 X1\n(ok)\nG1 X\xff\xfe1\n");
    assert_eq!((e.line, e.column, e.kind), (3, 5, ErrorKind::InvalidUtf8));
    let e = err(b"G0 X1 \x01");
    assert_eq!((e.line, e.column), (1, 7));
    assert!(matches!(e.kind, ErrorKind::UnexpectedCharacter('\u{1}')));
    let e = err(b"G0 X1 $H");
    assert_eq!(e.column, 7);
    // A non-ASCII character in a comment is fine.
    assert!(parse("(Durchmesser \u{2300} 3 mm)\nG0 X1".as_bytes()).is_ok());
    assert!(parse(b"G0 X1 (unclosed").unwrap_err().kind == ErrorKind::UnclosedComment);
}

#[test]
fn unsupported_features() {
    for (text, line, col) in [
        // Parameters of the machine, subroutines in other files.
        (&b"G0 X0\n#5221=2\n"[..], 2, 1),
        (b"G0 X#5221", 1, 5),
        (b"G0 X[1+#<_current_tool>]", 1, 8),
        (b"G0 X0\nO<slot> call\n", 2, 1),
        (b"G17.1", 1, 1),
        (b"G0 X0\nG16 X1 Y1", 2, 1),
        (b"G0 X0\nG87 X1 Y1 Z-1 R1 I1 J1 K1 F10", 2, 1),
        (b"G0 X0\nG76 P1 Z-1 I-1 J1 K1", 2, 1),
    ] {
        let e = err(text);
        assert!(e.is_unsupported(), "{e}");
        assert_eq!((e.line, e.column), (line, col), "{e}");
    }
}

#[test]
fn semantic_errors() {
    let e = err(b"G1 X1 Y1 X2");
    assert_eq!((e.column, e.kind), (10, ErrorKind::DuplicateWord('X')));
    let e = err(b"G0 G1 X1");
    assert_eq!(e.kind, ErrorKind::ConflictingGCodes("motion"));
    let e = err(b"G20 G21");
    assert_eq!(e.kind, ErrorKind::ConflictingGCodes("units"));
    let e = err(b"G0 X1\nG17.5 X1");
    assert!(matches!(e.kind, ErrorKind::UnknownGCode(_)));
    let e = err(b"G0 X1\nG162 X1");
    assert_eq!((e.line, e.column), (2, 1));
    let e = err(b"(start)\nX1");
    assert_eq!((e.line, e.kind), (2, ErrorKind::NoMotionMode));
    let e = err(b"G0 X0 Y0\nG2 X1.5 Y0 I0.5 J0.3");
    assert!(matches!(e.kind, ErrorKind::ArcRadiusMismatch { .. }), "{e}");
    let e = err(b"G0 X0 Y0\nG2 X10 R2");
    assert!(matches!(e.kind, ErrorKind::ArcRadiusTooSmall { .. }));
    let e = err(b"G0 X0 Y0\nG2 X0 Y0 R2");
    assert_eq!(e.kind, ErrorKind::ArcRadiusFullCircle);
    let e = err(b"G0 X0 Y0\nG2 X1 Y1");
    assert_eq!(e.kind, ErrorKind::ArcWithoutCenter);
    // `G2 I1` is a full circle in LinuxCNC (checked with rs274); the R form
    // without an end point is an error.
    let e = err(b"G0 X0 Y0\nG2 R1");
    assert_eq!(e.kind, ErrorKind::ArcWithoutAxes);
    let e = err(b"G0 X0 Y0\nG2 X2 I1 P0");
    assert_eq!(e.kind, ErrorKind::BadTurns(0.0));
    let e = err(b"G0 X0 Y0\nG2 X2 I1 R1");
    assert_eq!(e.kind, ErrorKind::ArcRadiusAndCenter);
}

#[test]
fn empty_programs() {
    for t in [&b""[..], b"\n\n", b"%\n%\n", b"(just a comment)\n"] {
        let p = parse(t).unwrap();
        assert!(p.is_empty());
        assert!(p.runs().is_empty());
    }
}

const TOKENS: &[&str] = &[
    "G0", "G1", "G2", "G3", "G17", "G18", "G19", "G20", "G21", "G90", "G91", "G90.1", "G91.1",
    "G40", "G41", "G43", "G49", "G54", "G55", "G80", "G92", "G28", "G53", "G93", "G94", "G4",
    "G64", "G38.2", "G33", "M3", "M8", "M30", "S100", "T1", "F100", "F0", "X1", "X-1.5", "Y2",
    "Z-0.5", "I1", "J-1", "K0.5", "R1", "R-1", "P2", "P0", "A10", "N10", "(c)", ";c", "%", "/",
    "X0", "Y0", "X1e5", "#1", "[", "o1", "O12", " ", "\n", "\r\n", "X.", "X-", "G", "(", ")",
    "X1.2.3", "E1", "H1", "D1", "Q1", "L2", "X1000000", "X1e300", "R0.0001", "I0", "J0",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = parse(&bytes);
    }

    #[test]
    fn token_soup_never_panics(toks in proptest::collection::vec(0..TOKENS.len(), 0..60)) {
        let text: String = toks.iter().map(|&i| TOKENS[i]).collect::<Vec<_>>().join(" ");
        if let Ok(p) = parse(text.as_bytes()) {
            let runs: Vec<_> = p.runs().into_iter().map(|r| r.pieces).collect();
            let opts = fairpath_gcode::GcodeWriteOptions::default();
            let out = fairpath_gcode::write_gcode(&p, &runs, &opts).unwrap();
            let _ = parse(out.as_bytes()).unwrap();
            let json = fairpath_gcode::write_json(&p, &runs).unwrap();
            let _ = fairpath_gcode::read_json(&json).unwrap();
        }
    }
}

/// Tokens that mostly make valid programs, to exercise the writers.
const VALID: &[&str] = &[
    "\nG0", "\nG1", "\nG2", "\nG3", "\nG17", "\nG18", "\nG19", "\nG20", "\nG21", "\nG90", "\nG91",
    "\nG90.1", "\nG91.1", "\nM8", "\nF100", "\n(c)", "X1", "X-1.5", "Y2", "Z-0.5", "I1", "J-1",
    "K0.5", "R1", "R-1", "X0", "Y0", "X3", "Y-3", "\nG92 X0", "\nG55", "\nG54", "\nG41", "\nG40",
    "F50", "S10", "A5",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    #[test]
    fn valid_soup_writes_and_rereads(toks in proptest::collection::vec(0..VALID.len(), 0..40)) {
        let body: String = toks.iter().map(|&i| VALID[i]).collect::<Vec<_>>().join(" ");
        let text = format!("G1 F10 X0.5{body}");
        if let Ok(p) = parse(text.as_bytes()) {
            let runs: Vec<_> = p.runs().into_iter().map(|r| r.pieces).collect();
            let opts = fairpath_gcode::GcodeWriteOptions::default();
            let out = fairpath_gcode::write_gcode(&p, &runs, &opts).unwrap();
            let q = parse(out.as_bytes());
            prop_assert!(q.is_ok(), "{text:?} -> {out:?}: {:?}", q.err());
            let q = q.unwrap();
            // Same rapids, same end position.
            let last = p.pieces().last().cloned();
            if let (Some(a), Some(b)) = (last.filter(|a| a.start() != a.end()), q.pieces().last()) {
                prop_assert!(a.end().dist(b.end()) < 1e-3, "{text:?} -> {out:?}");
            }
            let json = fairpath_gcode::write_json(&p, &runs).unwrap();
            prop_assert_eq!(fairpath_gcode::read_json(&json).unwrap().len(), p.pieces().len());
        }
    }
}

/// The soup CI found (2026-11-28): bare `G3` words inside a run, then a
/// zero-length `G1 Y0` and a `G17 X1` that reads as `G1` only because of
/// that `G1`. The rewritten run must keep the mode the following line needs.
#[test]
fn regression_bare_g3_lines_then_a_zero_g1_inside_a_run() {
    let text = "G1 F10 X0.5\nG19 \nG3 X3 J-1 \nG3 \nG3 \nG1 Y0 \nG17 X1";
    let p = parse(text.as_bytes()).unwrap();
    let runs: Vec<_> = p.runs().into_iter().map(|r| r.pieces).collect();
    let opts = fairpath_gcode::GcodeWriteOptions::default();
    let out = fairpath_gcode::write_gcode(&p, &runs, &opts).unwrap();
    let q = parse(out.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{out}"));
    let (a, b) = (p.pieces(), q.pieces());
    let (a, b) = (a.last().unwrap(), b.last().unwrap());
    assert!(a.end().dist(b.end()) < 1e-3, "{out}");
}
