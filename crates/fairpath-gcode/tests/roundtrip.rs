//! Passthrough is lossless; G-code and JSON output read back to the same
//! geometry.
use crate::common;

use fairpath::geom::{flatten_params, Curve, ParamCurve, SegmentGrid, Vec3};
use fairpath_gcode::{parse, read_json, write_gcode, write_json, GcodeWriteOptions, Program};

const CHORD: f64 = 0.001;

fn unchanged(p: &Program) -> Vec<Vec<fairpath::Piece>> {
    p.runs().into_iter().map(|r| r.pieces).collect()
}

fn opts() -> GcodeWriteOptions {
    GcodeWriteOptions {
        chord_mm: CHORD,
        header: false,
        ..Default::default()
    }
}

/// Lines of `text` with their endings.
fn split(text: &str) -> Vec<&str> {
    text.split_inclusive('\n').collect()
}

/// Checks that every line of `p` outside run move lines appears in `out`, in
/// order, unchanged or with a motion word inserted.
fn check_passthrough(name: &str, p: &Program, out: &str) {
    let spans = p.run_spans();
    let mut in_run = vec![false; p.lines().len() + 1];
    for s in spans {
        for l in &p.lines()[s.first_line - 1..s.last_line] {
            // Lines of a spline block carry part of its move.
            if !l.moves.is_empty() || l.in_block {
                in_run[l.number] = true;
            }
        }
    }
    let out_lines = split(out);
    let mut j = 0;
    for l in p.lines() {
        if in_run[l.number] {
            continue;
        }
        let want = format!("{}{}", l.text, l.ending);
        let found = out_lines[j..].iter().position(|o| {
            *o == want || {
                // an inserted "Gn " motion word
                let o2 = o
                    .replacen("G0 ", "", 1)
                    .replacen("G1 ", "", 1)
                    .replacen("G2 ", "", 1)
                    .replacen("G3 ", "", 1);
                o2 == want && l.uses_modal_motion
            }
        });
        match found {
            Some(k) => j += k + 1,
            None => panic!(
                "{name}: line {} {:?} missing or out of order",
                l.number, l.text
            ),
        }
    }
}

/// Densely flattened original geometry of all moves.
fn grid_of(p: &Program) -> SegmentGrid {
    let mut segs = Vec::new();
    for piece in p.pieces() {
        let c = &piece.curve;
        match c {
            Curve::Line(l) => segs.push((l.p0, l.p1)),
            _ => {
                let ts = flatten_params(c, CHORD * 0.01);
                for w in ts.windows(2) {
                    segs.push((c.eval(w[0]), c.eval(w[1])));
                }
            }
        }
    }
    SegmentGrid::new(segs, 0.01)
}

fn check_roundtrip(name: &str, p: &Program, out: &str) {
    let q =
        parse(out.as_bytes()).unwrap_or_else(|e| panic!("{name}: output does not re-read: {e}"));
    // Run ends re-read exactly (absolute runs) or within rounding.
    let grid = grid_of(p);
    let mut ends: Vec<Vec3> = q.pieces().iter().map(|x| x.end()).collect();
    ends.sort_by(|a, b| {
        a.x.total_cmp(&b.x)
            .then(a.y.total_cmp(&b.y))
            .then(a.z.total_cmp(&b.z))
    });
    for r in p.run_spans() {
        let e = p.moves()[r.moves.end - 1].piece.end();
        let best = ends.iter().map(|x| x.dist(e)).fold(f64::INFINITY, f64::min);
        let tol = if r.incremental { 1e-4 } else { 1e-9 };
        assert!(
            best <= tol,
            "{name}: run ending on line {} not reproduced ({best})",
            r.last_line
        );
    }
    // Every re-read point lies on the original geometry within the chord
    // tolerance, which counts the rounding of written coordinates (plus the
    // grid's own flattening at a hundredth of it).
    for piece in q.pieces() {
        let e = piece.end();
        let d = grid.nearest(e, 0.01).map_or(f64::INFINITY, |x| x.0);
        assert!(
            d <= CHORD * 1.02,
            "{name}: output point {e:?} (line {}) is {d} mm off the original",
            piece.source_lines.0
        );
    }
}

#[test]
#[ignore = "corpus: run by .ci/run (cargo test --workspace -- --include-ignored)"]
fn passthrough_and_roundtrip_on_shared_programs() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    let mut n = 0;
    for f in common::files_under(&dir) {
        let name = f.strip_prefix(&dir).unwrap().display().to_string();
        if name.contains("surface-raster-large") {
            continue; // benchmark size; covered by surface-raster
        }
        let bytes = std::fs::read(&f).unwrap();
        let Ok(p) = parse(&bytes) else { continue };
        let out = write_gcode(&p, &unchanged(&p), &opts()).unwrap();
        check_passthrough(&name, &p, &out);
        check_roundtrip(&name, &p, &out);
        n += 1;
    }
    eprintln!("{n} programs written back and re-read");
}

#[test]
fn unchanged_program_without_runs_is_byte_identical() {
    let text = "%\n(only rapids)\r\nG0 X1 Y2\nM8\nG0 Z5\n%\n";
    let p = parse(text.as_bytes()).unwrap();
    assert!(p.runs().is_empty());
    let out = write_gcode(&p, &[], &opts()).unwrap();
    assert_eq!(out, text);
    let with_header = write_gcode(&p, &[], &GcodeWriteOptions::default()).unwrap();
    assert!(with_header.starts_with("%\n(smoothed by fairpath)\n(only rapids)"));
}

#[test]
fn json_roundtrip_on_shared_programs() {
    let Some(dir) = common::shared_paths() else {
        return;
    };
    for f in common::files_under(&dir) {
        let name = f.strip_prefix(&dir).unwrap().display().to_string();
        if name.contains("surface-raster-large") {
            continue;
        }
        let bytes = std::fs::read(&f).unwrap();
        let Ok(p) = parse(&bytes) else { continue };
        let json = write_json(&p, &unchanged(&p)).unwrap();
        let back = read_json(&json).unwrap();
        let orig = p.pieces();
        assert_eq!(back.len(), orig.len(), "{name}");
        for (a, b) in orig.iter().zip(&back) {
            assert_eq!(a.rapid, b.rapid);
            assert_eq!(a.source_lines, b.source_lines);
            assert_eq!(a.feed, b.feed);
            match &a.curve {
                Curve::Line(_) => assert_eq!(a.curve, b.curve, "{name}"),
                c => {
                    let tol = if let Curve::Arc(arc) = c {
                        if arc.is_circular(1e-12 * arc.r0.max(1.0)) {
                            1e-9
                        } else {
                            fairpath_gcode::ARC_APPROX_MM * 1.01
                        }
                    } else {
                        1e-12
                    };
                    assert!(a.start().dist(b.start()) <= 1e-9, "{name}");
                    assert!(a.end().dist(b.end()) <= 1e-9, "{name}");
                    // Same curve: sample the written one, measure against a
                    // fine polyline of the original.
                    let ts = flatten_params(c, 1e-6);
                    let pts: Vec<Vec3> = ts.iter().map(|&t| c.eval(t)).collect();
                    let (t0, t1) = b.curve.domain();
                    for k in 0..=20 {
                        let q = b.curve.eval(t0 + (t1 - t0) * k as f64 / 20.0);
                        let d = fairpath::geom::distance_to_polyline(q, &pts).unwrap().0;
                        assert!(d <= tol + 1e-6, "{name}: {d}");
                    }
                }
            }
        }
        // The JSON re-serialises identically.
        let again =
            serde_json::to_string(&serde_json::from_str::<serde_json::Value>(&json).unwrap())
                .unwrap();
        assert_eq!(again.len(), json.len());
    }
}
