//! Method `arc-fit`: random 2D and 3D polylines with degenerate moves stay
//! within the tolerance by the independent verifier, with exact endpoints,
//! pieces joined bit for bit, no more pieces than input segments and every
//! joint that is not G2 reported; a sampled circle and helix become a few
//! arcs; a square keeps its corners as lines; feed changes end blocks;
//! input arcs are kept.

use crate::common;
use common::{degenerate, polyline_run, polyline_run_with_feeds, pt2, pt3, tolerances, v};
use fairpath::choose::by_name;
use fairpath::geom::{Arc, Curve, Line, Vec3};
use fairpath::path::{Piece, Run};
use fairpath::smooth::{
    ArcFit, ArcFitOptions, CornerReason, SmoothError, SmoothedRun, Smoother, ARC_MAX_SWEEP,
};
use fairpath::verify::{verify_run, Continuity, VerifyOptions};
use proptest::prelude::*;
use std::f64::consts::PI;

/// The guarantees of `arc-fit` on `run` at `tol`, checked independently.
fn check_run(run: &Run, tol: f64) -> Result<SmoothedRun, TestCaseError> {
    let out = ArcFit::default().smooth_run(run, tol).unwrap();
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(tol));
    prop_assert!(
        rep.within(tol),
        "deviation bound {} > {tol} at {:?}, gaps {} {}",
        rep.deviation_bound,
        rep.worst_at,
        rep.start_gap,
        rep.end_gap
    );
    prop_assert_eq!(out.pieces.first().unwrap().start(), run.start().unwrap());
    prop_assert_eq!(out.pieces.last().unwrap().end(), run.end().unwrap());
    for w in out.pieces.windows(2) {
        prop_assert_eq!(w[0].end(), w[1].start(), "pieces must join bit for bit");
    }
    prop_assert!(out.pieces.len() <= run.pieces.len());
    for p in &out.pieces {
        let ok = match &p.curve {
            Curve::Line(l) => l.p0.is_finite() && l.p1.is_finite(),
            Curve::Arc(a) => {
                a.center.is_finite()
                    && a.sweep > 0.0
                    && a.sweep <= ARC_MAX_SWEEP
                    && a.r0.min(a.r1) >= fairpath::smooth::ARC_MIN_RADIUS_MM
                    && a.normal.x == 0.0
                    && a.normal.y == 0.0
            }
            Curve::Nurbs(_) => false,
        };
        prop_assert!(ok, "{:?}", p.curve);
        prop_assert!(p.source_lines.0 <= p.source_lines.1);
    }
    for j in &rep.joints {
        if j.class != Continuity::G2 {
            prop_assert!(
                out.kept_corners
                    .iter()
                    .any(|k| k.at.dist(j.at) <= tol * 1e-6),
                "{:?} joint at {:?} not reported",
                j.class,
                j.at
            );
        }
    }
    Ok(out)
}

fn check(pts: &[Vec3], tol: f64) -> Result<SmoothedRun, TestCaseError> {
    check_run(&polyline_run(pts), tol)
}

/// `n` points of the helix of radius `r` about the origin, one turn per
/// `per_turn` segments, Z falling by `fall` per turn, rounded to `decimals`.
fn helix(r: f64, per_turn: usize, segments: usize, fall: f64, decimals: i32) -> Vec<Vec3> {
    let round = |x: f64| {
        let s = 10f64.powi(decimals);
        (x * s).round() / s
    };
    (0..=segments)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / per_turn as f64;
            let z = -fall * k as f64 / per_turn as f64;
            v(round(r * a.cos()), round(r * a.sin()), round(z))
        })
        .collect()
}

fn arcs(out: &SmoothedRun) -> usize {
    out.pieces
        .iter()
        .filter(|p| matches!(p.curve, Curve::Arc(_)))
        .count()
}

/// Points along a gently curving path: a random walk of the heading.
fn wander(turns: Vec<f64>, step: f64, lift: f64) -> Vec<Vec3> {
    let mut p = Vec3::ZERO;
    let mut h: f64 = 0.0;
    let mut out = vec![p];
    for (k, t) in turns.into_iter().enumerate() {
        h += t;
        p += v(
            step * h.cos(),
            step * h.sin(),
            lift * (k as f64 * 0.3).sin(),
        );
        out.push(p);
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_2d_polylines_stay_within(
        base in prop::collection::vec(pt2(10.0), 2..40),
        ops in prop::collection::vec(any::<u8>(), 0..40),
        tol in tolerances(),
    ) {
        check(&degenerate(base, ops), tol)?;
    }

    #[test]
    fn random_3d_polylines_stay_within(
        base in prop::collection::vec(pt3(10.0), 2..40),
        ops in prop::collection::vec(any::<u8>(), 0..40),
        tol in tolerances(),
    ) {
        check(&degenerate(base, ops), tol)?;
    }

    /// Dense, gently curving paths (where arcs do fit), flat or with a
    /// wavy Z, short and long moves, with degenerate moves mixed in.
    #[test]
    fn random_curving_paths_stay_within_with_fewer_blocks(
        turns in prop::collection::vec(-0.3f64..0.3, 2..300),
        step in prop_oneof![Just(0.01), Just(0.2), Just(3.0)],
        lift in prop_oneof![Just(0.0), Just(0.02), Just(1.0)],
        ops in prop::collection::vec(any::<u8>(), 0..300),
        tol in tolerances(),
    ) {
        check(&degenerate(wander(turns, step, lift), ops), tol)?;
    }

    /// Points on circles of random radius, in either direction, one after
    /// another (reversals of curvature, tangent and not).
    #[test]
    fn random_circle_pieces_stay_within(
        pieces in prop::collection::vec((0.003f64..50.0, -6.0f64..6.0, 3usize..80), 1..6),
        tol in tolerances(),
    ) {
        let mut pts = vec![Vec3::ZERO];
        let mut h: f64 = 0.0;
        for (r, sweep, n) in pieces {
            let p = *pts.last().unwrap();
            let left = v(-h.sin(), h.cos(), 0.0) * sweep.signum();
            let c = p + left * r;
            let a0 = (p.y - c.y).atan2(p.x - c.x);
            for k in 1..=n {
                let a = a0 + sweep * k as f64 / n as f64;
                pts.push(v(c.x + r * a.cos(), c.y + r * a.sin(), 0.0));
            }
            h += sweep;
        }
        check(&pts, tol)?;
    }
}

/// Radius 8, 72 segments a turn (`../shared/paths/synthetic/helix.ngc`):
/// one turn flat, and the file's five turns falling 1 mm a turn, rounded to
/// its four decimals, at 0.05 and 0.01 mm.
#[test]
fn sampled_circle_and_helix_become_a_few_arcs() {
    for tol in [0.05, 0.01] {
        for decimals in [4, 12] {
            let circle = check(&helix(8.0, 72, 72, 0.0, decimals), tol).unwrap();
            // At most 350 degrees an arc: 70 segments, then the last two
            // (on a tangent arc, not a line that would fit too).
            assert_eq!(
                circle.pieces.len(),
                2,
                "tol {tol} {decimals}: {:?}",
                circle.pieces
            );
            assert_eq!(arcs(&circle), 2);
            let helix = check(&helix(8.0, 72, 360, 1.0, decimals), tol).unwrap();
            assert!(helix.pieces.len() <= 6, "tol {tol}: {}", helix.pieces.len());
            assert_eq!(arcs(&helix), helix.pieces.len());
            for p in &helix.pieces {
                let Curve::Arc(a) = &p.curve else {
                    unreachable!()
                };
                assert!(a.rise < 0.0 && (a.r0 - 8.0).abs() < tol);
            }
        }
    }
}

/// Consecutive arcs leave tangent to where the previous one ended.
#[test]
fn arcs_follow_on_tangent() {
    let tol = 0.01;
    // An S: a half circle left in 40 moves, then a half circle right in 30
    // (with equal angular steps the joint would lie on the chord of its
    // neighbours and be merged away).
    let mut pts = Vec::new();
    for k in 0..=40 {
        let a = -PI / 2.0 + PI * k as f64 / 40.0;
        pts.push(v(10.0 * a.cos(), 10.0 + 10.0 * a.sin(), 0.0));
    }
    for k in 1..=30 {
        let a = 3.0 * PI / 2.0 - PI * k as f64 / 30.0;
        pts.push(v(6.0 * a.cos(), 26.0 + 6.0 * a.sin(), 0.0));
    }
    let out = check(&pts, tol).unwrap();
    assert_eq!(out.pieces.len(), 2, "{:?}", out.pieces);
    assert_eq!(arcs(&out), 2);
    let rep = verify_run(
        &polyline_run(&pts).pieces,
        &out.pieces,
        &VerifyOptions::new(tol),
    );
    assert_eq!(rep.joints[0].class, Continuity::G1);
    assert_eq!(out.kept_corners.len(), 1);
}

/// A square with 90-degree corners: four lines (their sides split in
/// collinear moves are merged), the three inner corners kept.
#[test]
fn square_keeps_its_corners_as_lines() {
    let corners = [
        v(0.0, 0.0, 0.0),
        v(10.0, 0.0, 0.0),
        v(10.0, 10.0, 0.0),
        v(0.0, 10.0, 0.0),
        v(0.0, 0.0, 0.0),
    ];
    for split in [1, 5] {
        let mut pts = vec![corners[0]];
        for w in corners.windows(2) {
            for k in 1..=split {
                pts.push(w[0].lerp(w[1], k as f64 / split as f64));
            }
        }
        for tol in [0.01, 0.05, 0.5] {
            let out = check(&pts, tol).unwrap();
            assert_eq!(out.pieces.len(), 4);
            assert!(out.pieces.iter().all(|p| matches!(p.curve, Curve::Line(_))));
            let at: Vec<Vec3> = out.kept_corners.iter().map(|k| k.at).collect();
            assert_eq!(at, corners[1..4].to_vec());
            assert!(out
                .kept_corners
                .iter()
                .all(|k| k.reason == CornerReason::NoRoom));
        }
    }
}

/// A feed change ends a block, even where one arc or line would fit.
#[test]
fn feed_changes_end_blocks() {
    let pts = helix(8.0, 72, 36, 0.0, 12);
    let run = polyline_run_with_feeds(
        &pts,
        &[1000.0; 18]
            .iter()
            .chain(&[500.0; 18])
            .copied()
            .collect::<Vec<_>>(),
    );
    let out = check_run(&run, 0.05).unwrap();
    assert_eq!(out.pieces.len(), 2);
    assert_eq!(out.pieces[0].feed, Some(1000.0));
    assert_eq!(out.pieces[1].feed, Some(500.0));
    assert_eq!(out.pieces[0].source_lines, (1, 18));
    assert_eq!(out.pieces[1].source_lines, (19, 36));
    let line = polyline_run_with_feeds(
        &[
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            v(3.0, 0.0, 0.0),
        ],
        &[1000.0, 10.0, 10.0],
    );
    let out = check_run(&line, 0.05).unwrap();
    assert_eq!(out.pieces.len(), 2);
    assert_eq!(out.pieces[1].source_lines, (2, 3));
}

/// An arc of the input is a block already: kept as it is, and the lines
/// either side are fitted on their own.
#[test]
fn input_arcs_are_kept() {
    let mut run = polyline_run(&helix(8.0, 72, 20, 0.0, 12));
    let end = run.end().unwrap();
    let arc =
        Arc::from_center(end, v(-8.0, 0.0, 0.0), Vec3::ZERO, Vec3::Z, false, 1, 1e-9).unwrap();
    run.pieces.push(Piece {
        curve: Curve::from(arc),
        rapid: false,
        source_lines: (21, 21),
        feed: Some(1000.0),
    });
    run.pieces.push(Piece {
        curve: Curve::Line(Line::new(v(-8.0, 0.0, 0.0), v(-8.0, -5.0, 0.0))),
        rapid: false,
        source_lines: (22, 22),
        feed: Some(1000.0),
    });
    let out = check_run(&run, 0.05).unwrap();
    assert_eq!(out.pieces.len(), 3);
    assert_eq!(out.pieces[1].curve, Curve::from(arc));
    assert_eq!(out.pieces[0].source_lines, (1, 20));
}

#[test]
fn degenerate_runs() {
    let p = v(1.0, 2.0, 3.0);
    // Nothing but zero-length moves.
    let out = ArcFit::default()
        .smooth_run(&polyline_run(&[p, p, p]), 0.05)
        .unwrap();
    assert!(out.pieces.is_empty() || out.pieces.iter().all(|q| q.start() == p));
    // An exact reversal stays a corner.
    let out = check(
        &[v(0.0, 0.0, 0.0), v(5.0, 0.0, 0.0), v(1.0, 0.0, 0.0)],
        0.05,
    )
    .unwrap();
    assert_eq!(out.pieces.len(), 2);
    assert_eq!(out.kept_corners[0].reason, CornerReason::Reversal);
    // Tiny circles (below the smallest radius written) stay lines.
    let tiny = helix(0.001, 12, 12, 0.0, 12);
    let out = check(&tiny, 0.0001).unwrap();
    assert_eq!(arcs(&out), 0);
    // Huge coordinates, nearly straight stretches.
    let far: Vec<Vec3> = (0..50)
        .map(|k| v(1e6 + k as f64, 1e-9 * (k * k) as f64, 0.0))
        .collect();
    let out = check(&far, 0.01).unwrap();
    assert_eq!(out.pieces.len(), 1);
    // Non-finite input is an error, not a panic.
    let bad = polyline_run(&[Vec3::ZERO, v(f64::NAN, 0.0, 0.0), v(1.0, 1.0, 0.0)]);
    assert!(matches!(
        ArcFit::default().smooth_run(&bad, 0.05),
        Err(SmoothError::NotFinite { .. })
    ));
    assert!(ArcFit::default().smooth_run(&bad, -1.0).is_err());
    let opts = ArcFitOptions {
        max_lookahead: 1,
        ..ArcFitOptions::default()
    };
    assert!(ArcFit { options: opts }
        .smooth_run(&polyline_run(&tiny), 0.05)
        .is_err());
}

/// A long seeded run of 100k moves (a wavy spiral with noise): within the
/// tolerance, far fewer blocks. (Its speed is for the benchmark to
/// measure; this checks the result.)
#[test]
fn seeded_long_run() {
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let pts: Vec<Vec3> = (0..100_000)
        .map(|k| {
            let a = k as f64 * 0.004;
            let r = 20.0 + a + 3.0 * (a * 0.1).sin();
            v(
                r * a.cos() + 0.002 * rnd(),
                r * a.sin() + 0.002 * rnd(),
                0.0,
            )
        })
        .collect();
    let out = check(&pts, 0.05).unwrap();
    assert!(out.pieces.len() * 20 < pts.len(), "{}", out.pieces.len());
}

#[test]
fn known_by_name() {
    assert_eq!(by_name("arc-fit").unwrap().name(), "arc-fit");
    assert!(fairpath::choose::METHODS.contains(&"arc-fit"));
}
