//! Invariants of `bspline-corner` on random 2D and 3D polylines, degenerate
//! ones included, at several tolerances: within tolerance (checked by the
//! independent verifier), G2 at every joint but kept corners, endpoints exact.

use crate::common;
use common::{check_smoothed as check, degenerate, polyline_run, pt2, pt3, tolerances as tol, v};
use fairpath::geom::Vec3;
use fairpath::smooth::{BsplineCorner, BsplineCornerOptions, ErrorTarget, Smoother};
use fairpath::verify::{verify_run, Continuity, VerifyOptions};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_2d(pts in prop::collection::vec(pt2(20.0), 2..40), tol in tol(), half in any::<bool>()) {
        let o = BsplineCornerOptions { target: if half { ErrorTarget::HalfBand } else { ErrorTarget::FullBand }, ..Default::default() };
        check(&pts, tol, &BsplineCorner { options: o })?;
    }

    #[test]
    fn random_3d(pts in prop::collection::vec(pt3(5.0), 2..40), tol in tol(), lambda in 0.0..0.9f64) {
        let o = BsplineCornerOptions { lambda, ..Default::default() };
        check(&pts, tol, &BsplineCorner { options: o })?;
    }

    #[test]
    fn degenerate_3d(base in prop::collection::vec(pt3(3.0), 2..25), ops in prop::collection::vec(any::<u8>(), 25), tol in tol()) {
        let pts = degenerate(base, ops);
        check(&pts, tol, &BsplineCorner::default())?;
    }

    #[test]
    fn dense_short_segments(start in pt3(1.0), steps in prop::collection::vec(pt3(0.01), 2..200), tol in tol()) {
        let mut pts = vec![start];
        for s in steps { let p = *pts.last().unwrap() + s; pts.push(p); }
        check(&pts, tol, &BsplineCorner::default())?;
    }
}

#[test]
fn full_band_has_lower_peak_curvature_than_half_band() {
    let pts: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = i as f64 * 0.3;
            v(10.0 * t.cos(), 10.0 * t.sin(), 0.0) * (1.0 + 0.1 * (i % 3) as f64)
        })
        .collect();
    let run = polyline_run(&pts);
    let peak = |target| {
        let s = BsplineCorner {
            options: BsplineCornerOptions {
                target,
                ..Default::default()
            },
        };
        let out = s.smooth_run(&run, 0.05).unwrap();
        verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05)).peak_curvature
    };
    let full = peak(ErrorTarget::FullBand);
    let half = peak(ErrorTarget::HalfBand);
    assert!(full < half, "full {full} half {half}");
}

#[test]
fn reversal_is_kept_and_reported() {
    let pts = [
        v(0.0, 0.0, 0.0),
        v(10.0, 0.0, 0.0),
        v(5.0, 0.0, 0.0),
        v(5.0, 5.0, 0.0),
    ];
    let run = polyline_run(&pts);
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert_eq!(out.kept_corners.len(), 1);
    assert_eq!(out.kept_corners[0].at, v(10.0, 0.0, 0.0));
    assert_eq!(out.transitions, 1);
}

#[test]
fn collinear_vertices_pass_straight_through() {
    let pts: Vec<Vec3> = (0..=10)
        .map(|i| v(i as f64, 0.0, 0.0))
        .chain([v(10.0, 5.0, 0.0)])
        .collect();
    let run = polyline_run(&pts);
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert_eq!(out.merged_collinear, 9);
    assert_eq!(out.transitions, 1);
}

#[test]
fn bad_tolerances_are_rejected() {
    let run = polyline_run(&[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0)]);
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-12, 1e9] {
        assert!(
            BsplineCorner::default().smooth_run(&run, t).is_err(),
            "tolerance {t}"
        );
    }
}

/// Regression: gcode-rs/_viaconstructor_simple.ngc plunges to Y14.828427124746183
/// and then moves to Y14.828427, a 1.2e-7 mm reversal that made a transition
/// too small to classify. Such moves are zero-length and dropped.
#[test]
fn regression_viaconstructor_rounding_reversal() {
    let pts = [
        v(22.0, 14.828427124746183, 5.0),
        v(22.0, 14.828427124746183, -9.0),
        v(22.0, 14.828427, -9.0),
        v(22.0, 68.0, -9.0),
        v(75.171573, 68.0, -9.0),
        v(22.0, 14.828427, -9.0),
    ];
    let run = polyline_run(&pts);
    let out = BsplineCorner::default().smooth_run(&run, 0.01).unwrap();
    assert_eq!(out.dropped_zero_length, 1);
    assert!(out.kept_corners.is_empty());
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.01));
    assert!(rep.within(0.01));
    assert!(rep.joints.iter().all(|j| j.class == Continuity::G2));
}

/// Regression: linuxcnc/diagnostic/test-active-states.ngc has a run made of
/// zero-length moves only; the smoothed run is empty and verifies.
#[test]
fn regression_run_of_zero_length_moves() {
    let p = v(1.0, 2.0, 3.0);
    let run = polyline_run(&[p, p, p]);
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert!(out.pieces.is_empty());
    assert!(verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05)).within(0.05));
}

#[test]
fn closed_loop_keeps_its_seam_and_blends_it_when_the_run_goes_on() {
    let hex: Vec<Vec3> = (0..=6)
        .map(|i| {
            let a = i as f64 * std::f64::consts::PI / 3.0;
            v(
                10.0 * a.cos(),
                10.0 * a.sin(),
                if i % 2 == 0 { 0.0 } else { 3.0 },
            )
        })
        .collect();
    let run = polyline_run(&hex);
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert_eq!(out.transitions, 5);
    assert_eq!(out.pieces.first().unwrap().start(), hex[0]);
    assert_eq!(out.pieces.last().unwrap().end(), hex[6]);
    // Twice around: the closing vertex is now inside the run and blended.
    let twice: Vec<Vec3> = hex.iter().chain(hex[1..].iter()).copied().collect();
    let run = polyline_run(&twice);
    let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
    assert_eq!(out.transitions, 11);
    let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05));
    assert!(rep.within(0.05));
    assert!(rep.joints.iter().all(|j| j.class == Continuity::G2));
}

/// Regression: the verifier's peak curvature on synthetic/butterfly-80.ngc
/// depended on whether the sample count happened to include the knot
/// where every transition peaks; it now samples the knots. A square corner
/// must report exactly the closed form.
#[test]
fn regression_peak_curvature_is_sampled_at_the_knot() {
    use fairpath::smooth::{corner_peak_curvature, edge_for_deviation, BAND_USE};
    for len in [3.0, 7.0, 10.0, 13.0] {
        let run = polyline_run(&[v(0.0, 0.0, 0.0), v(len, 0.0, 0.0), v(len, len, 0.0)]);
        let out = BsplineCorner::default().smooth_run(&run, 0.05).unwrap();
        let rep = verify_run(&run.pieces, &out.pieces, &VerifyOptions::new(0.05));
        let theta = std::f64::consts::FRAC_PI_4;
        let want = corner_peak_curvature(edge_for_deviation(0.05 * BAND_USE, theta), theta);
        assert!(
            (rep.peak_curvature - want).abs() <= 1e-9 * want,
            "{} vs {want}",
            rep.peak_curvature
        );
    }
}
