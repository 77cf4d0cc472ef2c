//! Relaxing fits inside the tolerance band (`geom::band_fit`): the relaxed
//! curve stays within the band with its ends and end conditions kept, and
//! it bends less than the least-squares fit it starts from.
use crate::common;

use common::v;
use fairpath::feed::limits::MachineLimits;
use fairpath::feed::plan::{plan_run, PlanOptions};
use fairpath::geom::band_fit::RelaxOptions;
use fairpath::geom::fit::{
    averaged_knots, chord_params, fit_cubic_weighted, EndCondition, FitSystem,
};
use fairpath::geom::{curvature_from, distance_to_polyline, Curve, Nurbs, ParamCurve, Vec3};
use fairpath::path::Piece;
use fairpath::smooth::fit_polyline_faired;
use proptest::prelude::*;

/// Largest distance from `c` (sampled at `n + 1` parameters) to the
/// polyline `pts`, and the largest curvature sampled.
fn sampled(c: &Nurbs, pts: &[Vec3], n: usize) -> (f64, f64) {
    let (a, b) = c.domain();
    let mut dist: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for i in 0..=n {
        let t = a + (b - a) * i as f64 / n as f64;
        dist = dist.max(distance_to_polyline(c.eval(t), pts).unwrap().0);
        peak = peak.max(curvature_from(c.deriv1(t), c.deriv2(t)));
    }
    (dist, peak)
}

/// Planned time (s) of `c` alone, from rest to rest, on the thesis machine.
fn planned(c: &Nurbs) -> f64 {
    let piece = Piece {
        curve: Curve::from(c.clone()),
        rapid: false,
        source_lines: (1, 1),
        feed: None,
    };
    let opts = PlanOptions {
        limits: MachineLimits::thesis(),
        override_feed: true,
        window: None,
        ends: Default::default(),
    };
    plan_run(&[piece], &opts).unwrap().time
}

/// Regression (the step-overs of `test_12mmflat.ngc`, where every
/// method crawled at 9 to 20 mm/s): relaxed, the fit through the step-over
/// stays within the band, keeps its ends and their tangents, peaks below
/// 0.3 of the curvature of the least-squares fit (2.7 against 21.5 1/mm)
/// and plans faster (0.96 against 1.46 s from rest to rest).
#[test]
fn relaxing_a_step_over_lowers_its_peak_curvature() {
    let pts = common::test_12mmflat_step_over();
    let n = pts.len();
    let target = 0.045;
    let (d_in, d_out) = (
        (pts[1] - pts[0]).normalized(0.0).unwrap(),
        (pts[n - 1] - pts[n - 2]).normalized(0.0).unwrap(),
    );
    let ends = (EndCondition::Tangent(d_in), EndCondition::Tangent(d_out));
    let fit = |relax: Option<&RelaxOptions>| {
        fit_polyline_faired(&pts, ends.0, ends.1, target, (1.0, 0.0), 6, relax)
            .unwrap()
            .curve
    };
    let plain = fit(None);
    let relaxed = fit(Some(&RelaxOptions::default()));
    let (d_plain, k_plain) = sampled(&plain, &pts, 20_000);
    let (d_relaxed, k_relaxed) = sampled(&relaxed, &pts, 20_000);
    assert!(
        d_plain <= target && d_relaxed <= target,
        "{d_plain} {d_relaxed}"
    );
    let (t_plain, t_relaxed) = (planned(&plain), planned(&relaxed));
    println!("peak {k_relaxed} vs {k_plain} 1/mm, planned {t_relaxed} vs {t_plain} s");
    assert!(k_relaxed < 0.3 * k_plain, "peak {k_relaxed} vs {k_plain}");
    assert!(t_relaxed < 0.8 * t_plain, "{t_relaxed} s vs {t_plain} s");
    // Ends exact, tangent along the leads with zero curvature.
    let (a, b) = relaxed.domain();
    assert_eq!(relaxed.eval(a), pts[0]);
    assert_eq!(relaxed.eval(b), pts[pts.len() - 1]);
    let d0 = relaxed.deriv1(a).normalized(0.0).unwrap();
    let d1 = relaxed.deriv1(b).normalized(0.0).unwrap();
    assert!(d0.dist(d_in) < 1e-12 && d1.dist(d_out) < 1e-12);
    assert!(curvature_from(relaxed.deriv1(a), relaxed.deriv2(a)) < 1e-9);
    assert!(curvature_from(relaxed.deriv1(b), relaxed.deriv2(b)) < 1e-9);
}

/// Zigzags of random turns and lengths in 3D (the cases the relaxation
/// changes most: every vertex a corner it may take wide).
fn zigzag() -> impl Strategy<Value = Vec<Vec3>> {
    prop::collection::vec((0.3f64..3.0, -1.2f64..1.2, -1.2f64..1.2), 4..12).prop_map(|steps| {
        let mut p = Vec3::ZERO;
        let mut out = vec![p];
        for (len, a, b) in steps {
            let d = v(1.0, a, b).normalized(0.0).unwrap();
            p += d * len;
            out.push(p);
        }
        out
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Whatever the polyline and the tolerance, the relaxed fit lies
    /// within the target of the polyline (checked by dense sampling, not
    /// by the bound it was accepted on) and ends exactly at its ends.
    #[test]
    fn relaxed_fits_stay_within_the_band(pts in zigzag(), tol in 0.005f64..0.2) {
        let free = EndCondition::Free;
        if let Some(f) =
            fit_polyline_faired(&pts, free, free, tol, (1.0, 0.0), 6, Some(&RelaxOptions::default()))
        {
            let (d, _) = sampled(&f.curve, &pts, 20_000);
            prop_assert!(d <= tol, "{} > {}", d, tol);
            prop_assert!(f.bound <= tol);
            let (a, b) = f.curve.domain();
            prop_assert_eq!(f.curve.eval(a), pts[0]);
            prop_assert_eq!(f.curve.eval(b), pts[pts.len() - 1]);
        }
    }
}

/// A factored system solves any data at its parameters as a fresh fit
/// does (the relaxation solves hundreds of right-hand sides on one
/// factorisation).
#[test]
fn a_factored_system_fits_new_data_like_a_fresh_fit() {
    let pts: Vec<Vec3> = (0..40)
        .map(|i| {
            let t = i as f64 * 0.25;
            v(t, (0.7 * t).sin(), 0.1 * t * t)
        })
        .collect();
    let params = chord_params(&pts);
    let knots = averaged_knots(&params, 14);
    let ends = (EndCondition::Tangent(v(1.0, 0.0, 0.0)), EndCondition::Free);
    let weights = (0.01, 0.001);
    let sys = FitSystem::new(&params, &knots, ends, (pts[0], pts[39]), weights).unwrap();
    for shift in [0.0, 0.03, -0.2] {
        // New data, same end points.
        let data: Vec<Vec3> = pts
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                if i == 0 || i == 39 {
                    p
                } else {
                    p + v(0.0, shift * (i as f64).cos(), shift)
                }
            })
            .collect();
        let a = sys.solve(&data).unwrap();
        let b = fit_cubic_weighted(&data, &params, &knots, ends.0, ends.1, 0.01, 0.001).unwrap();
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!(p.dist(*q) < 1e-12, "{p:?} {q:?}");
        }
    }
    // Data of the wrong length is an error, not a panic.
    assert!(sys.solve(&pts[..10]).is_err());
}

/// At the smallest tolerance the library accepts (1 nm), the refinement of
/// knots (spans of 4 tolerances) and data (2 tolerances) would make
/// millions of spans on a 40 mm fit (of a gentle arc, which a fit follows
/// within 1 nm; 619 control points with the budget of 8 spans and points
/// per data point, and no result in two minutes without it).
#[test]
fn a_tiny_tolerance_keeps_the_relaxed_curve_small() {
    let pts: Vec<Vec3> = (0..=20)
        .map(|i| {
            let x = 2.0 * i as f64;
            // On a circle of 1 km radius: chords sag 0.5 nm.
            v(x, 1e6 - (1e12 - (x - 20.0) * (x - 20.0)).sqrt(), 0.0)
        })
        .collect();
    let free = EndCondition::Free;
    let tol = 1e-6;
    let relax = RelaxOptions::default();
    let f = fit_polyline_faired(&pts, free, free, tol, (1.0, 0.0), 6, Some(&relax)).unwrap();
    println!("{} control points", f.curve.points.len());
    assert!(f.curve.points.len() < 20_000, "{}", f.curve.points.len());
    let (d, _) = sampled(&f.curve, &pts, 20_000);
    assert!(d <= tol, "{d}");
}
