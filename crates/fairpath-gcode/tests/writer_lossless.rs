//! Nothing but moves is lost where the writer replaces a run: N numbers,
//! comments, blank lines, the input's number style, and the blending
//! tolerance of the input's G64.

use fairpath::geom::{Arc, Curve, Line, Plane, Vec3};
use fairpath::path::Piece;
use fairpath_gcode::{parse, write_gcode, ArcWords, GcodeWriteOptions, Program};
use proptest::prelude::*;

fn opts() -> GcodeWriteOptions {
    GcodeWriteOptions {
        chord_mm: 0.01,
        header: false,
        ..Default::default()
    }
}

fn line(a: Vec3, b: Vec3, lines: (usize, usize), feed: f64) -> Piece {
    Piece {
        curve: Curve::Line(Line { p0: a, p1: b }),
        rapid: false,
        source_lines: lines,
        feed: Some(feed),
    }
}

fn unchanged(p: &Program) -> Vec<Vec<Piece>> {
    p.runs().into_iter().map(|r| r.pieces).collect()
}

const NUMBERED: &str = "N10 G21 G90\n\
N20 G0 X0 Y0\n\
N30 G1 X1 F100 (first)\n\
N40 X2 Y0.5 ; second\n\
(between)\n\
\n\
N50 X3 Y0\n\
N60 M2\n";

#[test]
fn n_numbers_and_comments_of_unchanged_blocks_stay_on_them() {
    let p = parse(NUMBERED.as_bytes()).unwrap();
    let out = write_gcode(&p, &unchanged(&p), &opts()).unwrap();
    assert_eq!(
        out,
        "N10 G21 G90\n\
N20 G0 X0 Y0\n\
(first)\n\
N30 G1 X1 F100\n\
; second\n\
N40 G1 X2 Y0.5\n\
(between)\n\
\n\
N50 G1 X3 Y0\n\
N60 M2\n"
    );
    // The same moves (on other line numbers: the comments moved up).
    let curves = |p: &Program| -> Vec<(Curve, Option<f64>)> {
        p.pieces().into_iter().map(|c| (c.curve, c.feed)).collect()
    };
    assert_eq!(curves(&parse(out.as_bytes()).unwrap()), curves(&p));
}

#[test]
fn a_merged_range_starts_with_its_first_n_and_names_the_others() {
    let p = parse(NUMBERED.as_bytes()).unwrap();
    let one = line(Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0), (3, 7), 100.0);
    let out = write_gcode(&p, &[vec![one]], &opts()).unwrap();
    assert_eq!(
        out,
        "N10 G21 G90\n\
N20 G0 X0 Y0\n\
(first)\n\
; second\n\
(between)\n\
\n\
(N40 N50 merged into the next block)\n\
N30 G1 X3 F100\n\
N60 M2\n"
    );
    let q = parse(out.as_bytes()).unwrap();
    assert_eq!(q.runs().len(), 1);
    assert_eq!(q.pieces().last().unwrap().end(), Vec3::new(3.0, 0.0, 0.0));
}

#[test]
fn n_numbers_no_block_took_are_named_after_the_run() {
    // The second piece has no length: nothing is written for it.
    let p = parse(NUMBERED.as_bytes()).unwrap();
    let a = Vec3::new(3.0, 0.0, 0.0);
    let pieces = vec![
        line(Vec3::ZERO, a, (3, 4), 100.0),
        line(a, a, (7, 7), 100.0),
    ];
    let out = write_gcode(&p, &[pieces], &opts()).unwrap();
    assert!(
        out.contains("N30 G1 X3 F100\n(between)\n\n(N50 merged into the blocks above)\nN60 M2\n"),
        "{out}"
    );
    assert!(
        out.contains("(N40 merged into the next block)\nN30 G1"),
        "{out}"
    );
}

#[test]
fn the_n_number_goes_on_the_arc_not_on_its_plane_line() {
    let text = "N1 G21 G90 G17\nN2 G0 X5 Y0 Z0\nN3 G1 X0 Z5 F600 (arc)\nN4 M2\n";
    let p = parse(text.as_bytes()).unwrap();
    let arc = Arc::from_center(
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Plane::Zx.normal(),
        false,
        1,
        0.0,
    )
    .unwrap();
    let piece = Piece {
        curve: Curve::from(arc),
        rapid: false,
        source_lines: (3, 3),
        feed: Some(600.0),
    };
    let o = GcodeWriteOptions {
        arcs: Some(ArcWords::Ijk),
        ..opts()
    };
    let out = write_gcode(&p, &[vec![piece]], &o).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    let g18 = lines.iter().position(|l| *l == "G18").unwrap();
    assert_eq!(lines[g18 - 1], "(arc)", "{out}");
    assert!(lines[g18 + 1].starts_with("N3 G"), "{out}");
    assert_eq!(lines[g18 + 2], "G17", "{out}");
    parse(out.as_bytes()).unwrap();
}

/// Every number of a written block line (the words after the motion G).
fn numbers(out: &str) -> Vec<String> {
    out.lines()
        .filter(|l| l.starts_with("G1 ") || l.starts_with("G2 ") || l.starts_with("G3 "))
        .flat_map(|l| l.split_whitespace().skip(1))
        // F is written as the input wrote it.
        .filter(|w| !w.starts_with('F'))
        .map(|w| w[1..].to_string())
        .collect()
}

#[test]
fn a_program_that_always_writes_the_point_gets_it_everywhere() {
    // Fanuc style: `Z5.`; leading zeros dropped (`Y.5`).
    let text = "G21 G90\nG0 X0. Y0.\nG1 X10. Y.5 F500\nG1 X20. Y.25\nM30\n";
    let p = parse(text.as_bytes()).unwrap();
    let (a, b, c) = (
        Vec3::ZERO,
        Vec3::new(10.0, 0.5, 0.0),
        Vec3::new(20.0, 0.25, 0.0),
    );
    let mid = Vec3::new(5.0, 0.25, 0.0);
    let pieces = vec![
        line(a, mid, (3, 3), 500.0),
        line(mid, b, (3, 3), 500.0),
        line(b, c, (4, 4), 500.0),
    ];
    let out = write_gcode(&p, std::slice::from_ref(&pieces), &opts()).unwrap();
    assert!(out.contains("\nG1 X5. Y.25 F500\nG1 X10. Y.5\n"), "{out}");
    for n in numbers(&out) {
        assert!(n.contains('.'), "{n} in\n{out}");
        assert!(
            !n.trim_start_matches('-').starts_with("0."),
            "{n} in\n{out}"
        );
    }
    // The same program with whole numbers written without the point.
    let text = "G21 G90\nG0 X0 Y0\nG1 X10 Y0.5 F500\nG1 X20 Y0.25\nM30\n";
    let p = parse(text.as_bytes()).unwrap();
    let out = write_gcode(&p, std::slice::from_ref(&pieces), &opts()).unwrap();
    assert!(out.contains("\nG1 X5 Y0.25 F500\nG1 X10 Y0.5\n"), "{out}");
    // A controller that needs the point gets it whatever the input does.
    let o = GcodeWriteOptions {
        decimal_point: true,
        ..opts()
    };
    let out = write_gcode(&p, &[pieces], &o).unwrap();
    assert!(out.contains("\nG1 X5. Y0.25 F500\nG1 X10. Y0.5\n"), "{out}");
}

/// The path-control command in force at the first move of each run of
/// `out` read back, and after each run's last line.
fn path_control_around_runs(out: &str) -> Vec<(Option<String>, Option<String>)> {
    let q = parse(out.as_bytes()).unwrap();
    let lines = q.lines();
    q.run_spans()
        .iter()
        .map(|r| {
            let next = lines
                .iter()
                .skip(r.last_line)
                .find(|l| l.path_control_after != lines[r.last_line - 1].path_control_after);
            (
                lines[r.first_line - 1].path_control_after.clone(),
                next.and_then(|l| l.path_control_after.clone()),
            )
        })
        .collect()
}

/// `tolerance_parabolic_check.ngc` with its R expressions written out.
const PARABOLIC: &str = "G90 G20\n\
\n\
G64 P0.02 Q0.0\n\
\n\
(Line blend as baseline)\n\
G0 Z1\n\
G0 X0 Y0\n\
G0 Z0\n\
G1 X1 Y1 F1000\n\
G1 X0 Y2\n\
\n\
G0 X0 Y0\n\
G1 X0.75 Y1\n\
G3 X1 Y1 R0.176775 P3\n\
G3 X0.75 Y1 R0.176775 P3\n\
M30\n";

#[test]
fn tolerance_parabolic_check_runs_under_our_blend_and_the_input_s_after() {
    let p = parse(PARABOLIC.as_bytes()).unwrap();
    let o = GcodeWriteOptions {
        g64_blend_mm: Some(0.0005),
        ..opts()
    };
    let out = write_gcode(&p, &unchanged(&p), &o).unwrap();
    let ours = "G64 P0.0000196 Q0";
    assert_eq!(out.matches(ours).count(), 2, "{out}");
    assert_eq!(out.matches("G64 P0.02 Q0.0").count(), 3, "{out}");
    let around = path_control_around_runs(&out);
    assert_eq!(around.len(), 2, "{out}");
    for (inside, after) in around {
        assert_eq!(inside.as_deref(), Some(ours), "{out}");
        assert_eq!(after.as_deref(), Some("G64 P0.02 Q0.0"), "{out}");
    }
    // The input's P within the share: left alone.
    let o = GcodeWriteOptions {
        g64_blend_mm: Some(0.6),
        ..opts()
    };
    let out = write_gcode(&p, &unchanged(&p), &o).unwrap();
    assert_eq!(out.matches("G64").count(), 1, "{out}");
}

#[test]
fn a_bare_g64_or_p0_is_tightened_and_g61_is_left_alone() {
    let o = GcodeWriteOptions {
        g64_blend_mm: Some(0.001),
        ..opts()
    };
    for (head, tightened) in [
        ("G64", true),
        ("G64 P0", true),
        ("G64 Q0.01", true),
        ("G61", false),
        ("G61.1", false),
        ("G64 P0.0005", false),
        ("(none)", false),
    ] {
        let text = format!("G21 G90 {head}\nG0 X0 Y0\nG1 X1 F100\nG1 X2 Y1\nG0 Z5\nM2\n");
        let p = parse(text.as_bytes()).unwrap();
        let out = write_gcode(&p, &unchanged(&p), &o).unwrap();
        let around = path_control_around_runs(&out);
        if tightened {
            assert_eq!(around[0].0.as_deref(), Some("G64 P0.001 Q0"), "{out}");
            assert_eq!(around[0].1.as_deref(), Some(head), "{out}");
        } else {
            assert!(!out.contains("G64 P0.001"), "{out}");
        }
    }
}

#[test]
fn our_blend_follows_the_input_s_number_style() {
    let text = "G21 G90 G64\nG0 X0. Y0.\nG1 X1. F100.\nG1 X2. Y1.\nM2\n";
    let p = parse(text.as_bytes()).unwrap();
    let o = GcodeWriteOptions {
        g64_blend_mm: Some(0.001),
        ..opts()
    };
    let out = write_gcode(&p, &unchanged(&p), &o).unwrap();
    assert!(out.contains("\nG64 P0.001 Q0.\n"), "{out}");
}

/// One generated line of a run: the move's end, an N word, a comment.
#[derive(Clone, Debug)]
struct GenLine {
    end: (i32, i32),
    n: bool,
    comment: Option<u8>,
    /// A comment-only line before it.
    before: Option<u8>,
}

fn gen_line() -> impl Strategy<Value = GenLine> {
    (
        (-50i32..50, -50i32..50),
        any::<bool>(),
        proptest::option::of(0u8..50),
        proptest::option::of(0u8..50),
    )
        .prop_map(|(end, n, comment, before)| GenLine {
            end,
            n,
            comment,
            before,
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Whatever pieces replace a run (its moves merged in any groups), every
    /// N number and comment of the run's lines is written, in order, and
    /// the program reads back.
    #[test]
    fn n_numbers_and_comments_survive_any_merging(
        gen in proptest::collection::vec(gen_line(), 1..12),
        cuts in proptest::collection::vec(any::<bool>(), 12),
        semicolons in any::<bool>(),
    ) {
        let mut text = String::from("G21 G90\nG0 X0 Y0\n");
        let mut ns = Vec::new();
        let mut comments = Vec::new();
        // (line number, end point) of each move line.
        let mut moves: Vec<(usize, Vec3)> = Vec::new();
        let mut n_next = 100;
        for g in &gen {
            if let Some(c) = g.before {
                let c = format!("(before {c})");
                comments.push(c.clone());
                text.push_str(&c);
                text.push('\n');
            }
            let mut l = String::new();
            if g.n {
                l.push_str(&format!("N{n_next} "));
                ns.push(format!("N{n_next}"));
                n_next += 10;
            }
            l.push_str(&format!("G1 X{} Y{} F100", g.end.0, g.end.1));
            if let Some(c) = g.comment {
                let c = if semicolons { format!("; note {c}") } else { format!("(note {c})") };
                comments.push(c.clone());
                l.push(' ');
                l.push_str(&c);
            }
            text.push_str(&l);
            text.push('\n');
            moves.push((text.lines().count(), Vec3::new(g.end.0 as f64, g.end.1 as f64, 0.0)));
        }
        text.push_str("M2\n");
        let p = parse(text.as_bytes()).unwrap();
        prop_assert_eq!(p.runs().len(), 1);
        // Groups of consecutive moves, each one line piece.
        let mut pieces = Vec::new();
        let mut start = (moves[0].0, Vec3::ZERO);
        for (k, &(ln, end)) in moves.iter().enumerate() {
            if k + 1 == moves.len() || cuts[k] {
                pieces.push(line(start.1, end, (start.0, ln), 100.0));
                if k + 1 < moves.len() {
                    start = (moves[k + 1].0, end);
                }
            }
        }
        let out = write_gcode(&p, &[pieces], &opts()).unwrap();
        let q = parse(out.as_bytes());
        prop_assert!(q.is_ok(), "{:?}\n{}", q.err(), out);
        // Comments in order.
        let mut rest = out.as_str();
        for c in &comments {
            let at = rest.find(c.as_str());
            prop_assert!(at.is_some(), "{} missing or out of order in\n{}", c, out);
            rest = &rest[at.unwrap() + c.len()..];
        }
        // Every N word: on a block, or named in a merged comment.
        let blocks: Vec<&str> = out.lines().filter_map(|l| l.split_whitespace().next()).collect();
        let merged: String = out.lines().filter(|l| l.contains("merged into")).collect();
        for n in &ns {
            let v: i64 = n[1..].parse().unwrap();
            let named = merged.split([' ', '(']).any(|item| {
                match item.split_once('-') {
                    Some((a, b)) => {
                        let (a, b): (i64, i64) = (a[1..].parse().unwrap(), b[1..].parse().unwrap());
                        a <= v && v <= b
                    }
                    None => item == n,
                }
            });
            prop_assert!(blocks.contains(&n.as_str()) || named, "{} lost in\n{}", n, out);
        }
    }
}
