//! Modal semantics of the interpreter.
use fairpath::geom::{Curve, ParamCurve, Vec3};
use fairpath_gcode::{parse, MoveKind, PinReason, Units};

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    a.dist(b) < 1e-9
}

#[test]
fn incremental_and_start_at_origin() {
    let p = parse(b"G91 G1 X1 Y2 F100\nX1\nZ-1\n").unwrap();
    let ends: Vec<Vec3> = p.pieces().iter().map(|x| x.end()).collect();
    assert_eq!(ends, vec![v(1., 2., 0.), v(2., 2., 0.), v(2., 2., -1.)]);
    assert_eq!(p.pieces()[0].start(), Vec3::ZERO);
    // The first line changes the distance mode: pinned; the rest is a run.
    assert_eq!(p.moves()[0].pinned, Some(PinReason::StateChange));
    assert_eq!(p.runs().len(), 1);
    assert_eq!(p.runs()[0].pieces.len(), 2);
}

#[test]
fn inch_conversion_and_feed() {
    let p = parse(b"G20\nG1 X1 F10\nG21\nG1 X30 F100\n").unwrap();
    assert_eq!(p.units(), Units::Inch);
    let pcs = p.pieces();
    assert_eq!(pcs[0].end(), v(25.4, 0., 0.));
    assert_eq!(pcs[0].feed, Some(254.0));
    assert_eq!(pcs[1].end(), v(30., 0., 0.));
    assert_eq!(pcs[1].feed, Some(100.0));
    assert_eq!(p.lines()[1].units, Units::Inch);
    assert_eq!(p.lines()[3].units, Units::Mm);
}

#[test]
fn r_form_arcs_both_signs() {
    // Short arc (R>0) and long arc (R<0) from (0,0) to (10,0), radius 10.
    let p = parse(b"G0 X0 Y0\nG2 X10 Y0 R10 F100\nG0 X0 Y0\nG2 X10 Y0 R-10\n").unwrap();
    let Curve::Arc(short) = &p.moves()[1].piece.curve else {
        panic!()
    };
    let Curve::Arc(long) = &p.moves()[3].piece.curve else {
        panic!()
    };
    let s = 10f64.sqrt() * 0.0; // placate clippy on unused
    let _ = s;
    // G2 short: centre below the chord for clockwise from (0,0) to (10,0)
    // going over the top: centre (5, -sqrt(75)).
    assert!(
        close(short.center, v(5., -75f64.sqrt(), 0.)),
        "{:?}",
        short.center
    );
    assert!((short.sweep - std::f64::consts::PI / 3.0).abs() < 1e-9);
    assert!(close(long.center, v(5., 75f64.sqrt(), 0.)));
    assert!((long.sweep - 5.0 * std::f64::consts::PI / 3.0).abs() < 1e-9);
    assert!(close(short.end(), v(10., 0., 0.)));
    assert!(close(long.end(), v(10., 0., 0.)));
    // G2 clockwise about +Z: the short arc passes above the chord.
    assert!(short.eval(0.5).y > 0.0);
}

#[test]
fn ijk_absolute_centre_g90_1() {
    let p = parse(b"G0 X10 Y0\nG90.1 G3 X0 Y10 I0 J0 F100\n").unwrap();
    let Curve::Arc(a) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!(close(a.center, Vec3::ZERO));
    assert!((a.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    // Default incremental IJK.
    let p = parse(b"G0 X10 Y0\nG3 X0 Y10 I-10 J0 F100\n").unwrap();
    let Curve::Arc(b) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!(close(b.center, Vec3::ZERO));
}

#[test]
fn planes_g18_g19() {
    // G18: ZX plane, G2 clockwise about +Y.
    let p = parse(b"G0 X10 Y0 Z0\nG18 G2 X0 Z10 I-10 K0 F100\n").unwrap();
    let Curve::Arc(a) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!(close(a.center, Vec3::ZERO));
    assert!(close(a.normal, v(0., -1., 0.)));
    assert!(close(a.end(), v(0., 0., 10.)));
    // G19: YZ plane, G3 counter-clockwise about +X.
    let p = parse(b"G0 X0 Y10 Z0\nG19 G3 Y0 Z10 J-10 K0 F100\n").unwrap();
    let Curve::Arc(b) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!(close(b.normal, v(1., 0., 0.)));
    assert!((b.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    // A centre word off the plane must be zero.
    assert!(parse(b"G0 X10\nG2 X0 Y10 I-10 K1").is_err());
    assert!(parse(b"G0 X10\nG3 X0 Y10 I-10 K0").is_ok());
}

/// Regression: LinuxCNC's `test_12mmflat.ngc` has a `G18` line between a
/// G1 and the XZ arcs of every pass; it ended the run there, so the 3
/// degree corner between line and arc was never smoothed.
#[test]
fn a_plane_change_alone_does_not_end_a_run() {
    let p = parse(b"G0 X0 Y0 Z0\nG1 X10 F100\nG18\nG2 X20 Z1 R50\nG17\nG1 X30 Y1\nM2\n").unwrap();
    assert_eq!(p.runs().len(), 1);
    assert_eq!(p.runs()[0].pieces.len(), 3);
    assert!(p.moves().iter().all(|m| m.pinned.is_none()));
    // The arc was read in the XZ plane.
    let Curve::Arc(a) = &p.moves()[2].piece.curve else {
        panic!()
    };
    assert!(close(a.normal, v(0., -1., 0.)));
    // On a move line the plane word is part of the line's text: pinned.
    let p = parse(b"G0 X0 Y0 Z0\nG1 X10 F100\nG18 G2 X20 Z1 R50\nG1 X30\nM2\n").unwrap();
    assert_eq!(p.moves()[2].pinned, Some(PinReason::StateChange));
    assert_eq!(p.runs().len(), 2);
    // Restating the plane changes nothing either way.
    let p = parse(b"G0 X0 Y0\nG1 X10 F100\nG17 G1 X20 Y1\nG17\nX30\nM2\n").unwrap();
    assert_eq!(p.runs().len(), 1);
}

#[test]
fn helix_full_circles_and_turns() {
    let p = parse(b"G0 X10 Y0 Z0\nG3 X10 Y0 Z-3 I-10 J0 P3 F100\n").unwrap();
    let Curve::Arc(a) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!((a.sweep - 6.0 * std::f64::consts::PI).abs() < 1e-9);
    assert!((a.rise - (-3.0)).abs() < 1e-12);
    assert!(close(a.end(), v(10., 0., -3.)));
    assert_eq!(p.moves()[1].kind, MoveKind::Arc);
    // Full circle without P.
    let p = parse(b"G0 X10 Y0\nG2 X10 Y0 I-10 J0 F100\n").unwrap();
    let Curve::Arc(b) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!((b.sweep - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    // Small radius mismatch within tolerance: a spiral arc.
    let p = parse(b"G0 X10 Y0\nG3 X0 Y10.005 I-10 J0 F100\n").unwrap();
    let Curve::Arc(c) = &p.moves()[1].piece.curve else {
        panic!()
    };
    assert!((c.r1 - c.r0 - 0.005).abs() < 1e-9);
}

#[test]
fn modal_axis_words_and_runs() {
    let text = b"G21 G90\nG0 X0 Y0 Z1\nG1 Z0 F500\nX10\n(comment)\nY10\nF600\nX0\nG1 X0 Y0 M8\nX5\nM5\nX6\nG0 Z5\nG1 X7 A10\nX8\nX9\nM2\n";
    let p = parse(text).unwrap();
    let runs = p.run_spans();
    // Z0..Y10 (lines 3-6), the feed changes (F600 on line 7) so X0 (8)
    // starts another run, line 9 pinned breaks, line 10 alone, line 11 M5
    // breaks, line 12 alone, rapid, line 14 pinned (A), 15-16.
    let spans: Vec<(usize, usize)> = runs.iter().map(|r| (r.first_line, r.last_line)).collect();
    assert_eq!(spans, vec![(3, 6), (8, 8), (10, 10), (12, 12), (15, 16)]);
    assert_eq!(p.moves()[5].pinned, Some(PinReason::ExtraWords));
    let feeds: Vec<Option<f64>> = p.runs()[0].pieces.iter().map(|x| x.feed).collect();
    assert_eq!(feeds, vec![Some(500.), Some(500.), Some(500.)]);
    assert_eq!(p.runs()[1].pieces[0].feed, Some(600.));
}

#[test]
fn unknown_position_after_offsets() {
    let p = parse(b"G0 X0 Y0 Z0\nG55\nG1 X1 F100\nG1 Y1 Z1\nG1 X2\nX3\n").unwrap();
    let pins: Vec<_> = p.moves().iter().map(|m| m.pinned).collect();
    assert_eq!(
        pins,
        vec![
            None,
            Some(PinReason::UnknownStart),
            Some(PinReason::UnknownStart),
            None,
            None
        ]
    );
    // G92 sets the position.
    let p = parse(b"G92 X5 Y5 Z5\nG1 X6 F100\n").unwrap();
    assert_eq!(p.pieces()[0].start(), v(5., 5., 5.));
    assert_eq!(p.moves()[0].pinned, None);
}

#[test]
fn cutter_comp_feed_mode_and_block_delete_pin() {
    let p =
        parse(b"G0 X0 Y0\nG41 D1\nG1 X1 F100\nX2\nG40\nG1 X3\nG93\nG1 X4 F2\n/G1 X5\n").unwrap();
    let pins: Vec<_> = p.moves().iter().map(|m| m.pinned).collect();
    assert_eq!(
        pins,
        vec![
            None,
            Some(PinReason::CutterComp),
            Some(PinReason::CutterComp),
            None,
            Some(PinReason::FeedMode),
            Some(PinReason::BlockDelete)
        ]
    );
}

#[test]
fn lexical_variants() {
    let p = parse(
        b"%\nN10 g00 x  15.000 y - 2 (c)\nG01X1Y1Z-1F100;c\nO1000\n%\ngarbage after the end\n",
    )
    .unwrap();
    assert_eq!(p.pieces()[0].end(), v(15., -2., 0.));
    assert_eq!(p.pieces()[1].end(), v(1., 1., -1.));
    assert!(!p.lines()[5].interpreted);
    // CRLF endings kept.
    let p = parse(b"G0 X1\r\nG1 X2 F1\r\n").unwrap();
    assert_eq!(p.lines()[0].ending, "\r\n");
    assert_eq!(p.lines()[0].text, "G0 X1");
}

/// Regression: linuxcnc/quick-tests/tangent_arcs.ngc programs `G2 J-1`,
/// centre words without axis words: a full circle back to the current point.
#[test]
fn regression_tangent_arcs_centre_only_full_circle() {
    let p = parse(b"G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10 F100\nG2 J-5\nG1 Y10\n").unwrap();
    let pcs = p.pieces();
    let Curve::Arc(a) = &pcs[2].curve else {
        panic!("not an arc")
    };
    assert!((a.sweep - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    assert_eq!(pcs[2].start(), v(10., 0., 0.));
    assert_eq!(pcs[2].end(), v(10., 0., 0.));
    assert!(close(a.eval(0.25), v(15., -5., 0.))); // clockwise: 12 to 3 o'clock
                                                   // R form still needs an end point.
    assert!(parse(b"G21\nG0 X0 Y0\nG2 R5\n").is_err());
}
