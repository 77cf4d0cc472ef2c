//! What is passed through rather than smoothed: canned cycles (their moves
//! equal to LinuxCNC's, checked against `rs274 -g`), words of other
//! dialects (E), runs that end at feed changes, and the moves pinned
//! around block-delete lines.
//!
//! The rs274 comparisons are skipped with a message when LinuxCNC 2.9's
//! `rs274` is not installed, unless `FAIRPATH_REQUIRE_RS274` is set.

use crate::common;

use fairpath::geom::Vec3;
use fairpath_gcode::{
    parse, parse_with, CycleError, ErrorKind, MoveKind, ParseOptions, PinReason, Program,
};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A motion call: kind and end point in mm.
#[derive(Clone, Debug, PartialEq)]
enum Call {
    Traverse(Vec3),
    Feed(Vec3),
    Arc(Vec3),
}

impl Call {
    fn same(&self, other: &Call, tol: f64) -> bool {
        let close = |a: Vec3, b: Vec3| a.dist(b) <= tol;
        match (self, other) {
            (Call::Traverse(a), Call::Traverse(b))
            | (Call::Feed(a), Call::Feed(b))
            | (Call::Arc(a), Call::Arc(b)) => close(*a, *b),
            _ => false,
        }
    }
}

fn have_rs274() -> bool {
    let probe = {
        let _guard = common::RS274.lock().unwrap_or_else(|e| e.into_inner());
        Command::new("rs274").arg("-g").arg("/dev/null").output()
    };
    if probe.is_ok() {
        return true;
    }
    assert!(
        std::env::var_os("FAIRPATH_REQUIRE_RS274").is_none(),
        "rs274 is required (FAIRPATH_REQUIRE_RS274) but not installed"
    );
    eprintln!("rs274 (linuxcnc-uspace) not installed: skipped");
    false
}

fn nums(l: &str) -> Vec<f64> {
    let start = l.find('(').unwrap() + 1;
    let inner = &l[start..l[start..].find(')').map_or(l.len(), |i| start + i)];
    inner
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
        .collect()
}

/// A fresh directory for one program (rs274 writes its parameter file in
/// the current directory).
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "fairpath-passthrough-{}-{name}",
        std::process::id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The motion calls `rs274 -g` prints for the program at `file` (in mm:
/// it prints the units in force), or its error. Arcs are read in the XY
/// plane only.
fn rs274(file: &Path) -> Result<Vec<Call>, String> {
    // One at a time (see `common::RS274`).
    let out = {
        let _guard = common::RS274.lock().unwrap_or_else(|e| e.into_inner());
        Command::new("rs274")
            .arg("-g")
            .arg(file)
            .current_dir(file.parent().unwrap())
            .output()
            .map_err(|e| e.to_string())?
    };
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).replace("executing", ""));
    }
    let mut scale = 1.0;
    let mut calls = Vec::new();
    for l in String::from_utf8_lossy(&out.stdout).lines() {
        if l.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)") {
            scale = 25.4;
        } else if l.contains("USE_LENGTH_UNITS(CANON_UNITS_MM)") {
            scale = 1.0;
        } else if l.contains("STRAIGHT_TRAVERSE(") || l.contains("STRAIGHT_FEED(") {
            let n = nums(l);
            let p = Vec3::new(n[0] * scale, n[1] * scale, n[2] * scale);
            calls.push(if l.contains("TRAVERSE") {
                Call::Traverse(p)
            } else {
                Call::Feed(p)
            });
        } else if l.contains("ARC_FEED(") {
            let n = nums(l);
            calls.push(Call::Arc(Vec3::new(
                n[0] * scale,
                n[1] * scale,
                n[5] * scale,
            )));
        }
    }
    Ok(calls)
}

fn ours(p: &Program) -> Vec<Call> {
    p.moves()
        .iter()
        .map(|m| {
            let e = m.piece.end();
            match m.kind {
                MoveKind::Rapid => Call::Traverse(e),
                MoveKind::Arc => Call::Arc(e),
                _ => Call::Feed(e),
            }
        })
        .collect()
}

/// rs274 prints 4 decimals of the units in force: half a unit in the last
/// place of an inch, with some room.
const PRINT_TOLERANCE_MM: f64 = 0.6e-4 * 25.4;

fn assert_same_as_rs274(name: &str, text: &str, program: &Program) {
    let dir = temp_dir(name);
    let file = dir.join(format!("{name}.ngc"));
    std::fs::write(&file, text).unwrap();
    let theirs = rs274(&file).unwrap_or_else(|e| panic!("{name}: rs274 rejects it: {e}"));
    let mine = ours(program);
    assert_eq!(
        mine.len(),
        theirs.len(),
        "{name}: {} moves, rs274 {}\nours {mine:?}\nrs274 {theirs:?}",
        mine.len(),
        theirs.len()
    );
    for (i, (a, b)) in mine.iter().zip(&theirs).enumerate() {
        assert!(
            a.same(b, PRINT_TOLERANCE_MM),
            "{name}: move {i}: ours {a:?}, rs274 {b:?}"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Every cycle code, G98/G99, modal repeats, L repeats in G90 and G91,
/// pecks, a start below R, the initial level kept across cycles.
const CYCLES_MM: &str = "G21 G90 G17 G94 F100 S1000 M3
G0 X0 Y0 Z5
G98 G81 X1 Y2 Z-3 R1
X4
G99 Y5 Z-4
G91 G81 X2 Y0 Z-2 R-1 L3
G90 G80
G0 Z10
G83 X10 Y10 Z-5 R2 Q2
G73 X12 Y10 Z-5 R2 Q1.5
G82 X14 Z-1 R1 P0.5
G85 X16 Z-1 R1
G89 X17 Z-1 R1 P1
G84 X18 Z-2 R1
G86 X19 Z-2 R1 P0.2
M5
M4
G74 X20 Z-2 R1
G80
G0 Z-1 (below R)
G98 G81 X21 Y0 Z-3 R2
G80
G1 X0 Y0 F200
G81 X1 Z-1 R1 L2
G0 X5
M2
";

const CYCLES_INCH: &str = "G20 G90 G17 F10
G0 X0 Y0 Z1
G83 X1 Y1 Z-0.5 R0.1 Q0.2
G91 G73 X0.5 Y0 Z-0.3 R-0.8 Q0.1 L2
G90 G80
G98 G81 X2 Y2 Z-0.25 R0.05
M2
";

const CYCLES_G18_G19: &str = "G21 G90 G18 F100
G0 X0 Y5 Z0
G81 X1 Z2 Y-1 R1
G83 Z4 Y-3 R1 Q1
G19
G0 X5
G81 Y1 Z1 X-1 R1
G91 G82 Y1 Z0 X-1 R-1 P0.1 L2
G90 G80
M2
";

#[test]
fn canned_cycles_make_linuxcncs_moves() {
    for (name, text) in [
        ("cycles_mm", CYCLES_MM),
        ("cycles_inch", CYCLES_INCH),
        ("cycles_g18_g19", CYCLES_G18_G19),
    ] {
        let p = parse(text.as_bytes()).unwrap_or_else(|e| panic!("{name}: {e}"));
        // Every cycle move is pinned and no cycle line is in a run.
        for m in p.moves() {
            let line = &p.lines()[m.line - 1].text;
            if line.contains("G8") || line.contains("G7") || !line.contains('G') {
                assert!(
                    m.pinned.is_some() || m.kind == MoveKind::Rapid,
                    "{name}: {line}"
                );
            }
        }
        assert!(
            p.passthrough().iter().all(|t| t.what == "canned cycle"),
            "{name}"
        );
        if have_rs274() {
            assert_same_as_rs274(name, text, &p);
        }
    }
}

#[test]
fn canned_cycle_moves_by_hand() {
    // G99 (the default) from Z5, R1: over, down to R, feed to the bottom,
    // rapid back to R.
    let p = parse(b"G21 F100\nG0 Z5\nG81 X1 Z-1 R1\nX2\nG80\n").unwrap();
    let ends: Vec<(MoveKind, [f64; 3])> = p
        .moves()
        .iter()
        .map(|m| {
            let e = m.piece.end();
            (m.kind, [e.x, e.y, e.z])
        })
        .collect();
    use MoveKind::{Linear as F, Rapid as R};
    assert_eq!(
        ends,
        vec![
            (R, [0., 0., 5.]),
            (R, [1., 0., 5.]),
            (R, [1., 0., 1.]),
            (F, [1., 0., -1.]),
            (R, [1., 0., 1.]),
            // The modal repeat at X2: over at the R plane.
            (R, [2., 0., 1.]),
            (F, [2., 0., -1.]),
            (R, [2., 0., 1.]),
        ]
    );
    assert!(p.moves()[1..]
        .iter()
        .all(|m| m.pinned == Some(PinReason::CannedCycle)));
    assert_eq!(p.moves()[3].piece.feed, Some(100.0));
    assert!(p.runs().is_empty());
    let notes: Vec<_> = p.passthrough().iter().map(|t| t.lines.clone()).collect();
    assert_eq!(notes, vec![3..=4]);
    // The position after the cycle is known: a run after it starts there.
    let p = parse(b"G21 F100\nG0 Z5\nG81 X1 Z-1 R1\nG80\nG1 X2 Y1\nG1 X3 Y0\n").unwrap();
    assert_eq!(p.runs().len(), 1);
    assert_eq!(p.runs()[0].pieces[0].start(), Vec3::new(1.0, 0.0, 1.0));
}

/// Programs LinuxCNC refuses are errors with the line of the cycle.
#[test]
fn bad_canned_cycles_are_errors_like_linuxcnc() {
    let missing = |letter| {
        ErrorKind::Cycle(CycleError::MissingWord {
            code: "G81",
            letter,
        })
    };
    let cases: Vec<(&str, Option<ErrorKind>)> = vec![
        ("G21 F100\nG0 Z5\nG81 X1 Z-1\n", Some(missing('R'))),
        ("G21 F100\nG0 Z5\nG81 X1 R1\n", Some(missing('Z'))),
        (
            "G21\nG0 Z5\nG81 X1 Z-1 R1\n",
            Some(ErrorKind::Cycle(CycleError::ZeroFeed)),
        ),
        ("G21 F100\nG0 Z5\nG81 X1 Z-1 R-2\n", None),
        ("G21 F100\nG0 Z5\nG84 X1 Z-1 R1\n", None),
        ("G21 F100 M3 S100\nG0 Z5\nG74 X1 Z-1 R1\n", None),
        ("G21 F100\nG0 Z5\nG86 X1 Z-1 R1 P1\n", None),
        ("G21 F100\nG0 Z5\nG83 X1 Z-1 R1\n", None),
        ("G21 F100\nG0 Z5\nG83 X1 Z-1 R1 Q-1\n", None),
        ("G21 F100\nG0 Z5\nG82 X1 Z-1 R1\n", None),
        ("G21 F100\nG0 Z5\nG81 X1 Z-1 R1 L0\n", None),
        ("G21 F100\nG0 Z5\nG93\nG81 X1 Z-1 R1 F100\n", None),
        (
            "G21 F100\nG0 Z5\nG81 X1 Z-1 R1 A5\n",
            Some(ErrorKind::Cycle(CycleError::AxisWord('A'))),
        ),
    ];
    let rs = have_rs274();
    for (i, (text, kind)) in cases.iter().enumerate() {
        let e = parse(text.as_bytes()).expect_err(text);
        assert_eq!(e.line, text.lines().count(), "{text}: {e}");
        assert!(matches!(e.kind, ErrorKind::Cycle(_)), "{text}: {e}");
        if let Some(k) = kind {
            assert_eq!(&e.kind, k, "{text}");
        }
        if rs {
            let dir = temp_dir(&format!("bad{i}"));
            let file = dir.join("bad.ngc");
            std::fs::write(&file, format!("{text}M2\n")).unwrap();
            assert!(rs274(&file).is_err(), "rs274 accepts {text}");
            let _ = std::fs::remove_dir_all(dir);
        }
    }
    // Not run: G76, G87, G88 (errors that say so).
    for text in [
        "G21 F100\nG87 X1 Z-1 R1 I1 J1 K1\n",
        "G21 F100\nG88 X1 Z-1 R1 P1\n",
    ] {
        assert!(parse(text.as_bytes()).unwrap_err().is_unsupported());
    }
}

/// `linuxcnc/test-active-states.ngc` (G81 with G98/G99 among offsets,
/// units changes and arcs) reads, and its moves are LinuxCNC's.
#[test]
fn test_active_states_reads_and_matches_rs274() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let file = dir.join("linuxcnc/test-active-states.ngc");
    let text = std::fs::read_to_string(&file).unwrap();
    let p = parse(text.as_bytes()).unwrap();
    assert!(p
        .moves()
        .iter()
        .any(|m| m.pinned == Some(PinReason::CannedCycle)));
    if have_rs274() {
        assert_same_as_rs274("test-active-states", &text, &p);
    }
}

/// The 3D-printer extruder word E: the line is passed through verbatim (its
/// move pinned) and ends runs; the passed-through lines are recorded.
#[test]
fn e_words_are_passed_through() {
    let text = b"G21 G90\nG1 X0 Y0 F1000\nG1 X1 Y0\nG1 X2 Y1\nG1 E-1 F2400\nG1 X3 Y1 F1000\n\
G1 X4 Y2\nG1 X5 Y2 E0.5\n(comment)\nG1 X6 Y3 E0.6\nG92 E0\nG1 X7 Y3\nG1 X8 Y4\n";
    let p = parse(text).unwrap();
    let spans: Vec<(usize, usize)> = p
        .run_spans()
        .iter()
        .map(|r| (r.first_line, r.last_line))
        .collect();
    assert_eq!(spans, vec![(2, 4), (6, 7), (12, 13)]);
    let pins: Vec<Option<PinReason>> = p.moves().iter().map(|m| m.pinned).collect();
    assert_eq!(pins[5], Some(PinReason::ForeignWords));
    assert_eq!(pins[6], Some(PinReason::ForeignWords));
    let notes = notes_of(&p);
    assert_eq!(
        notes,
        vec![
            (5..=5, "extruder word E (3D printers)"),
            (8..=11, "extruder word E (3D printers)")
        ]
    );
    // Exponent notation is X1 and E5.
    let p = parse(b"G1 X1e5 F100\n").unwrap();
    assert_eq!(p.moves()[0].piece.end(), Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(p.moves()[0].pinned, Some(PinReason::ForeignWords));
}

/// Regression, `linuxcnc/diagnostic/feed-tracking-test.ngc`: `X1 F1000`,
/// `X2 F1000`, `X2.001 F10`, `X5 F1000` ... was one run, smoothed to
/// `G1 X7 F10` (1.03 s -> 42.0 s). Each feed change now ends the run, so
/// every programmed feed keeps its stretch of path.
#[test]
fn feed_tracking_test_runs_end_at_feed_changes() {
    let text = "G90 G20\n\nG64 P0.005 Q0.0\n\nG0 X0 Y0 Z0\nG1 X1 F1000\nG1 X2 F1000\n\
G1 X2.001 F10\nG1 X5 F1000\nG1 X6 F1000\nG1 X7 F1000\nM2\n";
    if let Some(dir) = common::shared_paths() {
        let shared =
            std::fs::read_to_string(dir.join("linuxcnc/diagnostic/feed-tracking-test.ngc"))
                .unwrap();
        assert_eq!(shared.replace("\r\n", "\n").trim_end(), text.trim_end());
    }
    let p = parse(text.as_bytes()).unwrap();
    let spans: Vec<(usize, usize)> = p
        .run_spans()
        .iter()
        .map(|r| (r.first_line, r.last_line))
        .collect();
    assert_eq!(spans, vec![(6, 7), (8, 8), (9, 11)]);
    for run in p.runs() {
        let f = run.pieces[0].feed;
        assert!(run.pieces.iter().all(|x| x.feed == f));
    }
    // An F-only line between moves ends the run too, and lies between them.
    let p = parse(b"G1 X1 F100\nG1 X2\nF200\nG1 X3\nG1 X4\n").unwrap();
    let spans: Vec<(usize, usize)> = p
        .run_spans()
        .iter()
        .map(|r| (r.first_line, r.last_line))
        .collect();
    assert_eq!(spans, vec![(1, 2), (4, 5)]);
    assert_eq!(
        p.run_spans()[1].feed_before.as_ref().unwrap().mm_per_min,
        200.0
    );
}

fn pins(text: &str, block_delete: bool) -> Vec<Option<PinReason>> {
    let opts = ParseOptions {
        block_delete,
        ..Default::default()
    };
    parse_with(text.as_bytes(), &opts)
        .unwrap()
        .moves()
        .iter()
        .map(|m| m.pinned)
        .collect()
}

#[test]
fn block_delete_pins_what_depends_on_it() {
    use PinReason::{AfterBlockDelete as After, BlockDelete as Del};
    // The move after a `/` move starts where the `/` move ended: pinned.
    let text = "G21 G90 F100\nG1 X10 Y0\n/G1 X10 Y20\nG1 X20 Y10\nG1 X30 Y0\nG1 X40 Y5\n";
    assert_eq!(
        pins(text, false),
        vec![None, Some(Del), Some(After), None, None]
    );
    // Switch on: the `/` line is skipped, one run.
    assert_eq!(pins(text, true), vec![None, None, None, None]);
    let on = parse_with(
        text.as_bytes(),
        &ParseOptions {
            block_delete: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(on.runs().len(), 1);
    assert_eq!(on.moves()[1].piece.start(), Vec3::new(10.0, 0.0, 0.0));
    // Only Y set by the `/` line: pinned until a Y word.
    let text = "G21 G90 F100\nG1 X10 Y0\n/G1 Y20\nG1 X20\nG1 X30\nG1 X40 Y0\nG1 X50\n";
    assert_eq!(
        pins(text, false),
        vec![None, Some(Del), Some(After), Some(After), Some(After), None]
    );
    // G91: the increments do not depend on it.
    let text = "G21 G91 F100\nG1 X10\n/G1 Y20\nG1 X10\nG1 X10 Y5\n";
    assert_eq!(pins(text, false), vec![None, Some(Del), None, None]);
    // ... but an arc with an absolute centre (G90.1) does.
    let text = "G21 G91 G90.1 F100\nG1 X10\n/G1 Y20\nG2 X10 I15 J20\n";
    assert_eq!(pins(text, false), vec![None, Some(Del), Some(After)]);
    // A `/` line that changes the feed: feed moves pinned until F is set
    // outside block delete; rapids are not.
    let text = "G21 G90 F100\nG1 X1\n/F50\nG1 X2\nG0 X3\nG1 X4 F100\nG1 X5\n";
    assert_eq!(pins(text, false), vec![None, Some(After), None, None, None]);
    // A `/` line that changes the motion mode: a modal line after it is
    // pinned, and all axes are unknown with the switch on until set.
    let text = "G21 G90 F100\nG1 X1\n/G0 X2\nX3\nG1 X4 Y0 Z0\nG1 X5\n";
    assert_eq!(
        pins(text, false),
        vec![None, Some(Del), Some(After), Some(After), None]
    );
    // A `/` line that changes other modal state: every later move pinned.
    for change in ["G20", "G91", "G55", "G92 X0", "G18", "G64 P0.1", "G98"] {
        let text = format!("G21 G90 F100\nG1 X1\n/{change}\nG1 X2\nG1 X3 Y1 Z0\nG1 X4\n");
        let p = pins(&text, false);
        assert!(p[1..].iter().all(|x| x.is_some()), "/{change}: {p:?}");
    }
    // A `/` line that restates the state changes nothing.
    let text = "G21 G90 F100\nG1 X1\n/G90 G21\nG1 X2\nG1 X3\n";
    assert_eq!(pins(text, false), vec![None, None, None]);
}

/// Lines of random programs around block delete.
const BD_LINES: &[&str] = &[
    "G1 X{a} Y{b}",
    "X{a}",
    "Y{b}",
    "G0 X{a} Y{b}",
    "G1 Z{b}",
    "F{f}",
    "G1 X{a} F{f}",
    "G90",
    "G91",
    "G55",
    "G92 X{a}",
    "M8",
];

fn bd_program(lines: &[(usize, bool, i32, i32, u32)]) -> String {
    let mut text = String::from("G21 G90 F100\nG1 X0 Y0\n");
    for &(k, deleted, a, b, f) in lines {
        if deleted {
            text.push('/');
        }
        let l = BD_LINES[k]
            .replace("{a}", &a.to_string())
            .replace("{b}", &b.to_string())
            .replace("{f}", &(100 * f).to_string());
        text.push_str(&l);
        text.push('\n');
    }
    text
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(1500))]
    /// A move that is not pinned when the `/` lines run means the same with
    /// the switch on: the same kind and feed, and the same start (absolute)
    /// or the same increment (G91). And every run has one feed.
    #[test]
    fn unpinned_moves_mean_the_same_with_the_switch_on(
        lines in proptest::collection::vec(
            (0..BD_LINES.len(), proptest::bool::weighted(0.25), -3..4i32, -3..4i32, 1..4u32),
            0..25,
        )
    ) {
        let text = bd_program(&lines);
        let read = |block_delete| {
            parse_with(text.as_bytes(), &ParseOptions { block_delete, ..Default::default() })
        };
        let (Ok(off), Ok(on)) = (read(false), read(true)) else {
            return Ok(());
        };
        for p in [&off, &on] {
            for run in p.runs() {
                let f = run.pieces[0].feed;
                proptest::prop_assert!(run.pieces.iter().all(|x| x.feed == f), "{text}");
            }
        }
        proptest::prop_assert!(on.moves().iter().all(|m| !matches!(
            m.pinned,
            Some(PinReason::BlockDelete | PinReason::AfterBlockDelete)
        )));
        for (lo, ln) in off.lines().iter().zip(on.lines()) {
            if lo.text.starts_with('/') || lo.moves.len() != ln.moves.len() {
                continue;
            }
            for (a, b) in off.moves()[lo.moves.clone()].iter().zip(&on.moves()[ln.moves.clone()]) {
                if a.pinned.is_some() {
                    continue;
                }
                proptest::prop_assert_eq!(a.kind, b.kind, "line {}\n{}", a.line, text);
                proptest::prop_assert_eq!(a.piece.feed, b.piece.feed, "line {}\n{}", a.line, text);
                let (sa, sb) = (a.piece.start(), b.piece.start());
                if lo.incremental {
                    let (da, db) = (a.piece.end() - sa, b.piece.end() - sb);
                    proptest::prop_assert!(da.dist(db) < 1e-9, "line {}\n{}", a.line, text);
                } else {
                    proptest::prop_assert_eq!(sa, sb, "line {}\n{}", a.line, text);
                }
            }
        }
    }
}

/// Feed moves pinned for what they run in or with (cutter compensation,
/// extra axes, probing) are noted as passed through, so the user is told
/// why they were not smoothed; a line that only changes state (the `G93`
/// line itself) and rapids are not.
#[test]
fn compensated_rotary_and_probing_feed_moves_are_noted_as_passed_through() {
    let text = "G21 G90 G17\nG0 X0 Y0 Z5\nG41 D1\nG1 Z-1 F300\nG1 X10\nG1 Y10\nG40\n\
                G1 X20\nG1 X30 A10\nG1 X40 A20\nG0 X0 A0\nG93 G1 X50 F10\nG94 F300\n\
                G1 X60\nG38.2 Z-10 F50\nM2\n";
    let p = parse(text.as_bytes()).unwrap();
    let notes = notes_of(&p);
    assert_eq!(
        notes,
        vec![
            (4..=6, "cutter radius compensation G41/G42"),
            (9..=10, "rotary or extra axes A B C U V W"),
            (15..=15, "threading, tapping, probing or G53"),
        ]
    );
}

/// The program's passed-through line ranges with what they hold.
fn notes_of(p: &fairpath_gcode::Program) -> Vec<(std::ops::RangeInclusive<usize>, &'static str)> {
    p.passthrough()
        .iter()
        .map(|t| (t.lines.clone(), t.what))
        .collect()
}
