//! The G-code writer with curves written as curves: G2/G3 arcs in all
//! three planes (IJK and R, incremental programs, absolute centres), NURBS
//! as G6.2 blocks, the dialects (decimal points, LinuxCNC's G64), runs kept
//! as the program wrote them, and text that reads back to what was meant.

use fairpath::geom::{Arc, Curve, Line, Nurbs, ParamCurve, Plane, Vec3};
use fairpath::path::Piece;
use fairpath_gcode::{
    parse, write_gcode, write_gcode_with, ArcWords, GcodeWriteOptions, NurbsBlocks, RunOutput,
};
use proptest::prelude::*;

fn piece(c: Curve) -> Piece {
    Piece {
        curve: c,
        rapid: false,
        source_lines: (3, 3),
        feed: Some(600.0),
    }
}

fn arcs_opts() -> GcodeWriteOptions {
    GcodeWriteOptions {
        chord_mm: 0.005,
        header: false,
        arcs: Some(ArcWords::Ijk),
        resolution_mm: Some(5e-7),
        ..Default::default()
    }
}

/// The one run of `text` replaced by `pieces`, written and read back.
fn write_one(text: &str, pieces: Vec<Piece>, o: &GcodeWriteOptions) -> (String, Vec<Piece>) {
    let p = parse(text.as_bytes()).unwrap();
    assert_eq!(p.runs().len(), 1, "{text}");
    let out = write_gcode(&p, &[pieces], o).unwrap();
    let q = parse(out.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{out}"));
    assert_eq!(q.runs().len(), 1, "{out}");
    let back = q.runs().remove(0).pieces;
    (out, back)
}

/// A quarter circle of radius 5 in `plane` from the point (a, b) = (5, 0)
/// with height `h0`, turning counter-clockwise (G3) or not, rising by
/// `rise`.
fn quarter(plane: Plane, h0: f64, ccw: bool, rise: f64) -> Arc {
    let start = plane.point([5.0, 0.0, h0]);
    let end = plane.point([0.0, if ccw { 5.0 } else { -5.0 }, h0 + rise]);
    let center = plane.point([0.0, 0.0, h0]);
    Arc::from_center(start, end, center, plane.normal(), !ccw, 1, 0.0).unwrap()
}

#[test]
fn arcs_are_written_as_g2_g3_in_their_plane_and_read_back() {
    for plane in Plane::ALL {
        for ccw in [true, false] {
            for rise in [0.0, 1.25] {
                let arc = quarter(plane, 2.0, ccw, rise);
                // The program: to the arc's start, then one feed move (the
                // run) that the arc replaces.
                let s = arc.p0;
                let e = arc.p1;
                let text = format!(
                    "G21 G90\nG0 X{} Y{} Z{}\nG1 X{} Y{} Z{} F600\nM2\n",
                    s.x, s.y, s.z, e.x, e.y, e.z
                );
                let (out, back) = write_one(&text, vec![piece(Curve::from(arc))], &arcs_opts());
                let g = if ccw { "G3" } else { "G2" };
                assert!(out.contains(g), "{plane:?} {ccw}: {out}");
                if plane != Plane::Xy {
                    // Plane on a line of its own, restored after the run.
                    assert!(out.contains(&format!("\n{}\n", plane.gword())), "{out}");
                    assert!(out.contains("\nG17\n"), "{out}");
                }
                assert_eq!(back.len(), 1, "{out}");
                let Curve::Arc(b) = &back[0].curve else {
                    panic!("read back as {:?}", back[0].curve)
                };
                assert_eq!(b.normal, arc.normal, "{out}");
                assert!((b.sweep - arc.sweep).abs() < 1e-6);
                for k in 0..=8 {
                    let t = k as f64 / 8.0;
                    assert!(b.eval(t).dist(arc.eval(t)) < 1e-5, "{plane:?}: {out}");
                }
                assert_eq!(b.p1, e, "the run's end is the program's own text");
            }
        }
    }
}

#[test]
fn r_form_when_asked_and_ijk_for_half_circles() {
    let arc = quarter(Plane::Xy, 0.0, true, 0.0);
    let text = "G21 G90\nG0 X5 Y0 Z0\nG1 X0 Y5 F600\nM2\n";
    let o = GcodeWriteOptions {
        arcs: Some(ArcWords::R),
        ..arcs_opts()
    };
    let (out, back) = write_one(text, vec![piece(Curve::from(arc))], &o);
    assert!(out.contains("G3 X0 Y5 R5"), "{out}");
    assert!(matches!(back[0].curve, Curve::Arc(_)));
    // A half circle: the R form leaves the side open, IJK is written.
    let half = Arc::from_center(
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(-5.0, 0.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let text = "G21 G90\nG0 X5 Y0 Z0\nG1 X-5 F600\nM2\n";
    let (out, _) = write_one(text, vec![piece(Curve::from(half))], &o);
    assert!(out.contains("G3 X-5 I-5"), "{out}");
}

#[test]
fn incremental_programs_get_incremental_arcs_and_absolute_centres_after_g90_1() {
    let arc = quarter(Plane::Xy, 0.0, true, 0.0);
    let text = "G21 G91\nG0 X5\nG1 X-5 Y5 F600\nM2\n";
    let (out, back) = write_one(text, vec![piece(Curve::from(arc))], &arcs_opts());
    assert!(out.contains("G3 X-5 Y5 I-5"), "{out}");
    assert_eq!(back[0].end(), Vec3::new(0.0, 5.0, 0.0));
    let text = "G21 G90 G90.1\nG0 X5\nG1 X0 Y5 F600\nM2\n";
    let (out, back) = write_one(text, vec![piece(Curve::from(arc))], &arcs_opts());
    assert!(out.contains("G3 X0 Y5 I0 J0"), "{out}");
    let Curve::Arc(b) = &back[0].curve else {
        panic!()
    };
    assert!(b.center.norm() < 1e-12);
}

#[test]
fn an_arc_shorter_than_the_rounding_is_a_line_not_a_full_circle() {
    // 0.2 nm long: its rounded ends coincide at 7 decimals.
    let arc = Arc::from_center(
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(5.0 * (4e-11f64).cos(), 5.0 * (4e-11f64).sin(), 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let line = Line::new(arc.p1, Vec3::new(10.0, 1.0, 0.0));
    let text = "G21 G90\nG0 X5 Y0\nG1 X10 Y1 F600\nM2\n";
    let (out, back) = write_one(
        text,
        vec![piece(Curve::from(arc)), piece(Curve::Line(line))],
        &arcs_opts(),
    );
    assert!(!out.contains("G3"), "{out}");
    assert!(back.iter().all(|p| matches!(p.curve, Curve::Line(_))));
}

/// `/tmp/sw2/r004_mixed.ngc` (`scripts/random-programs.py /tmp/sw2 21
/// 20261207 ...`) at 0.2 mm had `G2 X-21.4100696191 Z-0.5210075646
/// I-0.0000005024 J4049924.5898498651`: a 2 nm move on a radius of 4 km,
/// a sweep of 5e-13 rad. LinuxCNC up to 2.8 runs an arc of less than 1e-6
/// rad (`CIRCLE_FUZZ`) as a full circle (its issue #1528), and the
/// independent check's flattening (`scripts/independent-check.py`) did.
#[test]
fn regression_r004_mixed_an_arc_a_controller_runs_as_a_full_circle_is_a_line() {
    let r = 4.05e6;
    let center = Vec3::new(-21.41, r, 0.0);
    let start = Vec3::new(-21.41, 0.0, 0.0);
    let angle = 2e-6 / r;
    let end = center + Vec3::new(-r * angle.sin(), -r * angle.cos(), 0.0);
    let arc = Arc::from_center(start, end, center, Vec3::Z, true, 1, 0.0).unwrap();
    assert!(arc.sweep < 1e-12, "{}", arc.sweep);
    let line = Line::new(arc.p1, Vec3::new(-30.0, 1.0, 0.0));
    let text = "G21 G90\nG0 X-21.41 Y0\nG1 X-30 Y1 F600\nM2\n";
    let (out, back) = write_one(
        text,
        vec![piece(Curve::from(arc)), piece(Curve::Line(line))],
        &arcs_opts(),
    );
    assert!(!arc_line(&out), "{out}");
    assert!(back.iter().all(|p| matches!(p.curve, Curve::Line(_))));
    assert!(back[0].end().dist(end) < 1e-6, "{out}");
    // A short arc of a small radius that no version reads as a full circle
    // stays an arc: a 2 um move on a radius of 0.01 mm.
    assert!(writes_an_arc(0.01, 0.2));
    // 1.2 rad on a radius of 0.1 um: 18 nm from its chord, but
    // `r^2 sin(sweep)` is 9.3e-9 mm^2, below LinuxCNC's `CART_FUZZ` (1e-8
    // machine units), whose `pmCircleInit` then runs it as a full circle
    // less 1.2 rad: a line.
    assert!(!writes_an_arc(1e-4, 1.2));
}

/// Whether the counter-clockwise arc of radius `r` mm about the origin from
/// the x axis through `sweep` rad, followed by a line, is written as an
/// arc.
fn writes_an_arc(r: f64, sweep: f64) -> bool {
    let arc = Arc::from_center(
        Vec3::new(r, 0.0, 0.0),
        Vec3::new(r * sweep.cos(), r * sweep.sin(), 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let line = Line::new(arc.p1, Vec3::new(1.0, 1.0, 0.0));
    let text = format!("G21 G90\nG0 X{r} Y0\nG1 X1 Y1 F600\nM2\n");
    let (out, _) = write_one(
        &text,
        vec![piece(Curve::from(arc)), piece(Curve::Line(line))],
        &arcs_opts(),
    );
    arc_line(&out)
}

/// Whether `out` has a G2 or G3 block.
fn arc_line(out: &str) -> bool {
    out.lines()
        .any(|l| l.starts_with("G2 ") || l.starts_with("G3 "))
}

#[test]
fn full_circles_keep_their_turns() {
    let arc = Arc::from_center(
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(5.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        3,
        1e-7,
    )
    .unwrap();
    let text = "G21 G90\nG0 X5 Y0 Z0\nG1 Z3 F600\nM2\n";
    let (out, back) = write_one(text, vec![piece(Curve::from(arc))], &arcs_opts());
    assert!(out.contains("P3"), "{out}");
    let Curve::Arc(b) = &back[0].curve else {
        panic!()
    };
    assert!((b.sweep - arc.sweep).abs() < 1e-9);
}

#[test]
fn fanuc_numbers_carry_a_decimal_point() {
    let arc = quarter(Plane::Xy, 0.0, true, 0.0);
    let text = "G21 G90\nG0 X5 Y0 Z0\nG1 X0 Y5 F600\nM2\n";
    let o = GcodeWriteOptions {
        decimal_point: true,
        ..arcs_opts()
    };
    let (out, _) = write_one(text, vec![piece(Curve::from(arc))], &o);
    let arc_line = out.lines().find(|l| l.starts_with("G3")).unwrap();
    for w in arc_line.split_whitespace().skip(1) {
        if !w.starts_with('F') {
            assert!(w.contains('.'), "{w} in {arc_line}");
        }
    }
}

#[test]
fn linuxcnc_blending_is_written_around_runs_and_the_programs_own_restored() {
    let arc = quarter(Plane::Xy, 0.0, true, 0.0);
    let o = GcodeWriteOptions {
        g64_blend_mm: Some(0.0025),
        ..arcs_opts()
    };
    // The program's own G64 P0.01 is written back after the run.
    let text = "G21 G90 G64 P0.01\nG0 X5 Y0 Z0\nG1 X0 Y5 F600\nG0 Z5\nM2\n";
    let (out, _) = write_one(text, vec![piece(Curve::from(arc))], &o);
    let lines: Vec<&str> = out.lines().collect();
    let ours = lines.iter().position(|l| *l == "G64 P0.0025 Q0").unwrap();
    let theirs = lines.iter().position(|l| *l == "G64 P0.01").unwrap();
    assert!(ours < theirs, "{out}");
    assert!(lines[theirs - 1].starts_with("G3"), "{out}");
    // Without one, ours stays in force; in inch programs P is in inches.
    let text = "G20 G90\nG0 X0.5 Y0 Z0\nG1 X0 Y0.5 F20\nM2\n";
    let arc = Arc::from_center(
        Vec3::new(12.7, 0.0, 0.0),
        Vec3::new(0.0, 12.7, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        false,
        1,
        0.0,
    )
    .unwrap();
    let (out, _) = write_one(text, vec![piece(Curve::from(arc))], &o);
    // The program sets no path control: only for LinuxCNC (always).
    assert!(!out.contains("G64"), "{out}");
    let always = GcodeWriteOptions {
        g64_always: true,
        ..o
    };
    let (out, _) = write_one(text, vec![piece(Curve::from(arc))], &always);
    assert!(out.contains("\nG64 P0.0000984 Q0\n"), "{out}");
    assert_eq!(out.matches("G64").count(), 1, "{out}");
}

#[test]
fn nurbs_become_g6_2_blocks_and_the_run_end_stays_exact() {
    let n = Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(3.0, 2.0, 1.0),
            Vec3::new(4.0, 1.0 / 3.0, 1.0),
        ],
        None,
    )
    .unwrap();
    let text = "G21 G90\nG0 X0 Y0 Z0\nG1 X4 Y0.33333333333 Z1 F600\nM2\n";
    let p = parse(text.as_bytes()).unwrap();
    let end = p.runs()[0].end().unwrap();
    let mut n2 = n.clone();
    *n2.points.last_mut().unwrap() = end;
    let o = GcodeWriteOptions {
        nurbs: Some(NurbsBlocks::G6_2Fanuc { max_degree: 3 }),
        ..arcs_opts()
    };
    let (out, back) = write_one(text, vec![piece(Curve::from(n2.clone()))], &o);
    assert!(out.contains("G6.2 P4"), "{out}");
    // A G1 to the program's own end text follows the block.
    assert!(out.contains("G1 Y0.33333333333"), "{out}");
    assert_eq!(back.last().unwrap().end(), end);
    let Curve::Nurbs(b) = &back[0].curve else {
        panic!("{out}")
    };
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        assert!(b.eval(t).dist(n2.eval(t)) < 1e-6, "{out}");
    }
}

#[test]
fn runs_kept_as_written_are_copied_line_by_line() {
    let text = "G21 G90\nG0 X0 Y0\nG1 X1 F100 (a comment)\nN20 X2 Y1\nM5\nG0 Z5\n";
    let p = parse(text.as_bytes()).unwrap();
    let out = write_gcode_with(&p, &[RunOutput::Original], &arcs_opts()).unwrap();
    assert_eq!(out, text);
}

fn pt() -> impl Strategy<Value = Vec3> {
    (-50.0..50.0f64, -50.0..50.0f64, -5.0..5.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Random chains of lines and arcs: no NaN, no word without a number,
    /// no move line without a coordinate, and the text reads back within
    /// the rounding of the written coordinates.
    #[test]
    fn written_text_is_well_formed_and_reads_back(
        pts in prop::collection::vec(pt(), 2..12),
        turns in prop::collection::vec((any::<bool>(), 0usize..3), 12),
        inch in any::<bool>(),
    ) {
        let scale = if inch { 25.4 } else { 1.0 };
        let mut pieces = Vec::new();
        for (i, w) in pts.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            // The run starts and ends on a line (the program's ends).
            let (as_arc, plane) = turns[i];
            let as_arc = as_arc && i > 0 && i + 2 < pts.len();
            let plane = Plane::ALL[plane];
            let la = plane.local(a);
            let lb = plane.local(b);
            let chord = ((lb[0] - la[0]).powi(2) + (lb[1] - la[1]).powi(2)).sqrt();
            // An arc bulging by a tenth of its chord, else a line.
            let c = if as_arc && chord > 1.0 {
                let mid = [(la[0] + lb[0]) / 2.0, (la[1] + lb[1]) / 2.0];
                let d = [lb[0] - la[0], lb[1] - la[1]];
                let center = plane.point([mid[0] - d[1], mid[1] + d[0], la[2]]);
                Arc::from_center(a, b, center, plane.normal(), false, 1, 0.0)
                    .map(Curve::from)
                    .unwrap_or(Curve::Line(Line::new(a, b)))
            } else {
                Curve::Line(Line::new(a, b))
            };
            pieces.push(piece(c));
        }
        let mut text = String::from(if inch { "G20 G90\n" } else { "G21 G90\n" });
        let s = pts[0] / scale;
        text.push_str(&format!("G0 X{:.12} Y{:.12} Z{:.12}\n", s.x, s.y, s.z));
        let e = pts[pts.len() - 1] / scale;
        text.push_str(&format!("G1 X{:.12} Y{:.12} Z{:.12} F10\nM2\n", e.x, e.y, e.z));
        let p = parse(text.as_bytes()).unwrap();
        // The run as the program reads it (its end as written).
        let end = p.runs()[0].end().unwrap();
        let start = p.runs()[0].start().unwrap();
        let n = pieces.len();
        if let Some(Curve::Line(l)) = pieces.first_mut().map(|p| &mut p.curve) { l.p0 = start; }
        if let Some(Curve::Line(l)) = pieces.last_mut().map(|p| &mut p.curve) { l.p1 = end; }
        prop_assert!(matches!(pieces[0].curve, Curve::Line(_)) && matches!(pieces[n - 1].curve, Curve::Line(_)));
        let out = write_gcode(&p, &[pieces.clone()], &arcs_opts()).unwrap();
        prop_assert!(!out.contains("NaN") && !out.contains("inf"), "{}", out);
        for l in out.lines() {
            let t = l.trim();
            prop_assert!(t != "G1" && t != "G2" && t != "G3", "empty move: {}", out);
        }
        let q = parse(out.as_bytes()).unwrap();
        let back = q.runs();
        prop_assert_eq!(back.len(), 1);
        prop_assert_eq!(back[0].end().unwrap(), end);
        // Every written piece ends where the meant one does, within the
        // rounding (7 decimals here).
        let ends: Vec<Vec3> = pieces.iter().map(|p| p.end()).collect();
        for b in &back[0].pieces {
            let d = ends.iter().map(|e| e.dist(b.end())).fold(f64::INFINITY, f64::min);
            prop_assert!(d < 1e-5 * scale, "{} off: {}", d, out);
        }
    }
}

proptest! {
    /// With `period_s` and the pieces' planned speeds, every point of a
    /// piece shorter than `FINE_PERIODS` periods of travel at its speed
    /// (`k v Ts`) is written within the run's rounding times
    /// `(L / (k v Ts))^2`, and every other point within the run's rounding:
    /// rounding bends a short line no more than a longer one (the tort.ngc
    /// run at lines 83-90, whose micrometre lines read back kinked,
    /// planned 4.6% slower than rendered and was not written). Without
    /// speeds, the run's decimals only.
    #[test]
    fn pieces_shorter_than_a_few_periods_of_travel_get_more_decimals(
        steps in proptest::collection::vec((1e-4f64..0.2, -1.0f64..1.0, 1.0f64..400.0), 2..30),
    ) {
        let ts = 1e-3;
        let opts = GcodeWriteOptions { period_s: Some(ts), ..arcs_opts() };
        let (d0, rho0) = fairpath_gcode::output_decimals(&opts, 1.0, opts.decimals_mm);
        // A gently bending chain of lines of the drawn lengths.
        let mut p = Vec3::new(1.0, 2.0, 3.0);
        let mut dir = 0.0f64;
        let mut pieces = Vec::new();
        let mut speeds = Vec::new();
        for &(len, turn, v) in &steps {
            dir += 1e-3 * turn;
            let q = p + Vec3::new(dir.cos(), dir.sin(), 0.1) * (len / 1.01f64.sqrt());
            pieces.push(piece(Curve::Line(Line::new(p, q))));
            speeds.push(v);
            p = q;
        }
        let (s, e) = (pieces[0].start(), p);
        let text = format!(
            "G21 G90\nG0 X{} Y{} Z{}\nG1 X{:.12} Y{:.12} Z{:.12} F600\nM2\n",
            s.x, s.y, s.z, e.x, e.y, e.z
        );
        let prog = parse(text.as_bytes()).unwrap();
        let end = prog.runs()[0].end().unwrap();
        if let Some(Curve::Line(l)) = pieces.last_mut().map(|p| &mut p.curve) { l.p1 = end; }
        for with_speeds in [true, false] {
            let output = if with_speeds {
                RunOutput::Rendered(&pieces, &speeds)
            } else {
                RunOutput::Pieces(&pieces)
            };
            let out = write_gcode_with(&prog, &[output], &opts).unwrap();
            let back = parse(out.as_bytes()).unwrap().runs().remove(0).pieces;
            prop_assert_eq!(back.len(), pieces.len(), "{}", out);
            let mut finer = 0;
            for ((b, m), &v) in back.iter().zip(&pieces).zip(&speeds) {
                let len = m.start().dist(m.end());
                let travel = fairpath_gcode::FINE_PERIODS * v * ts;
                let share = if with_speeds { (len / travel).min(1.0) } else { 1.0 };
                let bound = (rho0 * share * share).max(0.5 * 3f64.sqrt() * 1e-12);
                let off = b.end().dist(m.end());
                prop_assert!(off <= bound * (1.0 + 1e-9), "{} off, bound {}: {}", off, bound, out);
                finer += usize::from(share < 0.1);
            }
            // The words of the short pieces carry more decimals than d0
            // (the last move ends on the run's end as the program wrote it).
            let moves: Vec<&str> = out.lines().filter(|l| l.starts_with("G1")).collect();
            let most = moves[..moves.len() - 1]
                .iter()
                .flat_map(|l| l.split(' '))
                .filter_map(|w| w.split_once('.').map(|(_, f)| f.len()))
                .max()
                .unwrap_or(0);
            if with_speeds && finer > 1 {
                prop_assert!(most > d0, "{}", out);
            } else if !with_speeds {
                prop_assert!(most <= d0, "{}", out);
            }
        }
    }
}

/// A short arc passed fast gets more decimals in its end and centre words
/// (`FINE_PERIODS`, the shorter of its chord and radius as its length);
/// passed slowly, the run's.
#[test]
fn a_small_arc_passed_fast_gets_more_decimals() {
    let opts = GcodeWriteOptions {
        period_s: Some(1e-3),
        ..arcs_opts()
    };
    let (d0, _) = fairpath_gcode::output_decimals(&opts, 1.0, opts.decimals_mm);
    // A quarter circle of radius 0.01 mm (chord 0.014 mm) about a centre
    // whose coordinates need every decimal.
    let c = Vec3::new(1.234567891234, 2.987654321987, 0.0);
    let at = |phi: f64| c + Vec3::new(phi.cos(), phi.sin(), 0.0) * 0.01;
    let (a0, a1) = (at(0.3), at(0.3 + std::f64::consts::FRAC_PI_2));
    let arc = Arc::from_center(a0, a1, c, Vec3::new(0.0, 0.0, 1.0), false, 1, 0.0).unwrap();
    let (s, e) = (a0 - Vec3::new(0.0, 1.0, 0.0), a1 - Vec3::new(1.0, 0.0, 0.0));
    let lead = Line::new(s, arc.p0);
    let tail = Line::new(arc.p1, e);
    let pieces = vec![
        piece(Curve::Line(lead)),
        piece(Curve::from(arc)),
        piece(Curve::Line(tail)),
    ];
    let text = format!(
        "G21 G90\nG0 X{} Y{} Z0\nG1 X{} Y{} F600\nM2\n",
        s.x, s.y, e.x, e.y
    );
    let prog = parse(text.as_bytes()).unwrap();
    let decimals_of_arc = |speed: f64| {
        let speeds = [speed; 3];
        let out = write_gcode_with(&prog, &[RunOutput::Rendered(&pieces, &speeds)], &opts).unwrap();
        let line = out
            .lines()
            .find(|l| l.starts_with("G3"))
            .unwrap()
            .to_string();
        let most = line
            .split(' ')
            .filter_map(|w| w.split_once('.').map(|(_, f)| f.len()))
            .max()
            .unwrap();
        (most, line)
    };
    // 3 periods at 100 mm/s: 0.3 mm, far above the radius.
    let (fast, line) = decimals_of_arc(100.0);
    assert!(fast > d0, "{line}");
    // At 1 mm/s, 0.003 mm: below the radius and the chord.
    let (slow, line) = decimals_of_arc(1.0);
    assert!(slow <= d0, "{line}");
}

proptest! {
    /// In an incremental run, short pieces written with more decimals leave
    /// the written position off the run's grid; the run still ends exactly
    /// where the program's does (regression: the block-delete test's G91
    /// zigzag, whose run end moved and was kept as written).
    #[test]
    fn an_incremental_run_with_finer_pieces_ends_on_the_programs_end(
        steps in proptest::collection::vec((1e-4f64..0.5, 1.0f64..400.0), 2..20),
        dy in -2.0f64..2.0,
    ) {
        let opts = GcodeWriteOptions { period_s: Some(1e-3), ..arcs_opts() };
        let total: f64 = steps.iter().map(|s| s.0).sum();
        let text = format!(
            "G21 G91\nG0 X1 Y2 Z3\nG1 X{:.4} Y{:.4} F600\nM2\n",
            total, dy
        );
        let prog = parse(text.as_bytes()).unwrap();
        let (start, end) = (prog.runs()[0].start().unwrap(), prog.runs()[0].end().unwrap());
        // Lines along a bow from the start to the end.
        let mut pieces = Vec::new();
        let mut speeds = Vec::new();
        let mut s = 0.0;
        let mut p = start;
        for (k, &(len, v)) in steps.iter().enumerate() {
            s += len;
            let f = s / total;
            let q = if k + 1 == steps.len() {
                end
            } else {
                start.lerp(end, f) + Vec3::new(0.0, 0.01 * (std::f64::consts::PI * f).sin(), 0.0)
            };
            pieces.push(piece(Curve::Line(Line::new(p, q))));
            speeds.push(v);
            p = q;
        }
        let out = write_gcode_with(&prog, &[RunOutput::Rendered(&pieces, &speeds)], &opts).unwrap();
        let back = parse(out.as_bytes()).unwrap().runs().remove(0);
        // Exactly but for the float sums of the increments (the verifier
        // allows a billionth of the tolerance).
        let off = back.end().unwrap().dist(end);
        prop_assert!(off <= 1e-12, "{} off: {}", off, out);
    }
}

/// Regression (`gcode-rs/reprap_cnc.gcode` under `auto`, whose G2
/// transitions next to arcs were written as arcs in the YZ plane): a
/// comment between a run's moves is copied in place, and left the writer
/// believing the program's plane (XY) was in force again while the text
/// had selected G19, so the next XY arc went out as `G2 ... I J` under G19,
/// which does not read.
#[test]
fn a_comment_after_an_arc_in_another_plane_keeps_the_written_plane() {
    let text = "G17\nG0 X5 Y0 Z2\nG1 X5 Y1 Z3 F600\n(between)\nG1 X6 Y2\nM2\n";
    let yz = Arc::from_center(
        Vec3::new(5.0, 0.0, 2.0),
        Vec3::new(5.0, 1.0, 3.0),
        Vec3::new(5.0, 1.0, 2.0),
        Plane::Yz.normal(),
        true,
        1,
        0.0,
    )
    .unwrap();
    let xy = Arc::from_center(
        Vec3::new(5.0, 1.0, 3.0),
        Vec3::new(6.0, 2.0, 3.0),
        Vec3::new(6.0, 1.0, 3.0),
        Plane::Xy.normal(),
        true,
        1,
        0.0,
    )
    .unwrap();
    let mut second = piece(Curve::from(xy));
    second.source_lines = (5, 5);
    let (out, back) = write_one(text, vec![piece(Curve::from(yz)), second], &arcs_opts());
    assert!(out.contains("(between)"), "{out}");
    assert_eq!(back.len(), 2, "{out}");
    for (p, q) in [yz, xy].iter().zip(&back) {
        let Curve::Arc(b) = &q.curve else {
            panic!("not an arc: {out}");
        };
        assert!(b.normal.dist(p.normal) < 1e-9, "{out}");
        assert!(b.p1.dist(p.p1) < 1e-6, "{out}");
    }
}

/// Regression (`synthetic/surface-raster.ngc`, `bspline-corner` for Fanuc:
/// its G6.2 rendering planned 208.9 s against the input's 98.0 s and was
/// kept as written): a short line passed fast is written with more
/// decimals than the run's, and the G6.2 block after it started from its
/// first control point rounded to the run's decimals. That reads back as a
/// straight move of a fraction of a micrometre with a corner at each end,
/// where the planner stops nearly; the block must start where the line
/// ended.
#[test]
fn a_g6_2_block_after_a_finer_short_line_starts_where_the_line_ended() {
    let opts = GcodeWriteOptions {
        period_s: Some(1e-3),
        nurbs: Some(NurbsBlocks::G6_2Fanuc { max_degree: 3 }),
        ..arcs_opts()
    };
    let (d0, _) = fairpath_gcode::output_decimals(&opts, 1.0, opts.decimals_mm);
    // A line of 0.01 mm to a point that needs every decimal, then a cubic
    // going on in its direction.
    let s = Vec3::new(1.0, 2.0, 0.5);
    let dir = Vec3::new(0.6, 0.8, 0.0);
    let p0 = Vec3::new(1.006123456789, 2.008164609052, 0.5);
    let n = Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![
            p0,
            p0 + dir,
            p0 + dir * 2.0 + Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(4.0, 5.0, 0.5),
        ],
        None,
    )
    .unwrap();
    let pieces = vec![piece(Curve::Line(Line::new(s, p0))), piece(Curve::from(n))];
    let text = "G21 G90\nG0 X1 Y2 Z0.5\nG1 X4 Y5 F600\nM2\n";
    let prog = parse(text.as_bytes()).unwrap();
    let speeds = [100.0, 100.0];
    let out = write_gcode_with(&prog, &[RunOutput::Rendered(&pieces, &speeds)], &opts).unwrap();
    let g1 = out.lines().find(|l| l.starts_with("G1")).unwrap();
    let most = g1
        .split(' ')
        .filter_map(|w| w.split_once('.').map(|(_, f)| f.len()))
        .max()
        .unwrap();
    assert!(most > d0, "the line is written finer than the run: {out}");
    let back = parse(out.as_bytes()).unwrap().runs().remove(0).pieces;
    assert_eq!(
        back.len(),
        2,
        "no move between the line and the block: {out}"
    );
    assert!(matches!(back[1].curve, Curve::Nurbs(_)), "{out}");
    assert_eq!(back[0].end(), back[1].curve.start(), "{out}");
    assert!(back[1].curve.start().dist(p0) < 1e-6, "{out}");
}
