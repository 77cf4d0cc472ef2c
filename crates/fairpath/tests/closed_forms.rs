//! The closed forms of the bspline-corner transition (seed 000) against
//! evaluation of the curve.

use crate::common;
use common::v;
use fairpath::geom::{point_segment_distance, ParamCurve, Vec3};
use fairpath::smooth::{
    corner_deviation, corner_error, corner_peak_curvature, edge_for_deviation, transition_curve,
};

/// Transition at the origin between directions at half-angle theta.
fn corner(theta: f64, l: f64) -> (fairpath::geom::Nurbs, Vec3, Vec3) {
    let a = v(1.0, 0.0, 0.0);
    let b = v((2.0 * theta).cos(), (2.0 * theta).sin(), 0.0);
    let q = Vec3::ZERO;
    let c = transition_curve([q + a * 2.0 * l, q + a * l, q, q + b * l, q + b * 2.0 * l]);
    (c, a, b)
}

#[test]
fn error_deviation_and_peak_curvature_match_evaluation() {
    for i in 1..60 {
        let theta = 0.02 + (i as f64) * (std::f64::consts::FRAC_PI_2 - 0.04) / 60.0;
        for &l in &[0.01, 0.3, 7.0] {
            let (c, a, b) = corner(theta, l);
            let mid = c.eval(0.5);
            // e = |P2 C(0.5)|
            assert!(
                (mid.norm() - corner_error(l, theta)).abs() < 1e-12 * l.max(1.0),
                "e at theta {theta}"
            );
            // deviation: the largest distance to the two segments, sampled densely
            let far = 10.0 * l;
            let mut dev: f64 = 0.0;
            let mut kmax: f64 = 0.0;
            let n = 4000;
            for k in 0..=n {
                let t = k as f64 / n as f64;
                let p = c.eval(t);
                let d = point_segment_distance(p, Vec3::ZERO, a * far).min(point_segment_distance(
                    p,
                    Vec3::ZERO,
                    b * far,
                ));
                dev = dev.max(d);
                kmax = kmax.max(c.curvature(t));
            }
            let want = corner_deviation(l, theta);
            assert!(
                (dev - want).abs() <= 1e-9 * l.max(1.0),
                "dev {dev} vs {want} at theta {theta}"
            );
            let kw = corner_peak_curvature(l, theta);
            assert!(
                (kmax - kw).abs() <= 1e-9 * kw,
                "kappa {kmax} vs {kw} at theta {theta}"
            );
            assert!((c.curvature(0.5) - kw).abs() <= 1e-9 * kw);
            // curvature is zero at both ends: G2 with the segments
            assert!(c.curvature(0.0) * l < 1e-12 && c.curvature(1.0) * l < 1e-12);
        }
    }
}

#[test]
fn edge_for_deviation_inverts_deviation() {
    for i in 1..50 {
        let theta = i as f64 * 0.031;
        let l = edge_for_deviation(0.05, theta);
        assert!((corner_deviation(l, theta) - 0.05).abs() < 1e-15);
    }
}

#[test]
fn paper_example_section_3_3() {
    // delta = 0.01 mm, theta = 35 deg: epsilon = delta / sin(theta) ~ 0.0174 mm
    // (the paper prints 0.0173), and L ~ 0.0479 gives e0 ~ 0.0195 mm.
    let theta = 35f64.to_radians();
    let eps = 0.01 / theta.sin();
    assert!((eps - 0.0174).abs() < 1e-4);
    let e0 = corner_error(0.0479, theta);
    assert!((e0 - 0.0196).abs() < 2e-4, "e0 {e0}");
    // alpha = e*/e0 with e* = delta/2 scales L to about 0.0123 mm
    let alpha = 0.005 / e0;
    assert!((alpha * 0.0479 - 0.0123).abs() < 2e-4);
}

#[test]
fn curvature_variation_energy_of_a_parabola_matches_the_integral() {
    use fairpath::geom::{curvature_variation_energy, Curve, Nurbs};
    // y = x^2 on [0, 1] as a quadratic Bezier: kappa(x) = 2 / (1 + 4x^2)^1.5,
    // dkappa/dx = -24 x / (1 + 4x^2)^2.5, ds = sqrt(1 + 4x^2) dx, so
    // E = int 576 x^2 / (1 + 4x^2)^5.5 dx, here by Simpson's rule.
    let c = Curve::from(
        Nurbs::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(0.5, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
            ],
            None,
        )
        .unwrap(),
    );
    let f = |x: f64| 576.0 * x * x / (1.0 + 4.0 * x * x).powf(5.5);
    let n = 20_000;
    let h = 1.0 / n as f64;
    let want = (0..=n)
        .map(|i| {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(i as f64 * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let got = curvature_variation_energy(&c, 1e-6);
    assert!((got - want).abs() <= 1e-4 * want, "{got} vs {want}");
    // Lines and circles do not vary their curvature.
    let line = Curve::Line(fairpath::geom::Line::new(Vec3::ZERO, Vec3::X));
    assert_eq!(curvature_variation_energy(&line, 1e-6), 0.0);
}

/// `total_curvature` is the angle a plane curve's tangent turns through:
/// the sweep of a circular arc (also written as a rational NURBS), zero on
/// a line, and for a cubic the integral against a fine midpoint sum.
#[test]
fn total_curvature_is_the_turning_angle() {
    use fairpath::geom::{total_curvature, Arc, Curve, Line, Nurbs, ParamCurve, Vec3};
    let z = Vec3::new(0.0, 0.0, 1.0);
    for (r, sweep) in [(3.0, 0.7), (10.0, 4.0), (0.5, 6.2)] {
        let end = Vec3::new(r * f64::cos(sweep), r * f64::sin(sweep), 0.0);
        let arc =
            Arc::from_center(Vec3::new(r, 0.0, 0.0), end, Vec3::ZERO, z, false, 1, 1e-9).unwrap();
        assert!((total_curvature(&Curve::from(arc), 1e-9) - sweep).abs() < 1e-8);
        let n = Nurbs::from_circular_arc(&arc);
        assert!((total_curvature(&n, 1e-9) - sweep).abs() < 1e-7);
    }
    let line = Line::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(total_curvature(&line, 1e-9), 0.0);
    let cubic = Nurbs::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 0.5),
            Vec3::new(4.0, 1.0, 0.0),
        ],
        None,
    )
    .unwrap();
    let steps = 200_000;
    let mut sum = 0.0;
    for i in 0..steps {
        let t = (i as f64 + 0.5) / steps as f64;
        sum += cubic.curvature(t) * cubic.deriv1(t).norm() / steps as f64;
    }
    assert!((total_curvature(&cubic, 1e-10) - sum).abs() < 1e-6, "{sum}");
}

/// A clamped uniform cubic on `n` control points along a 100 mm line,
/// with the control points at `bumps` displaced in y.
fn bumped_line(n: usize, bumps: &[(usize, f64)]) -> fairpath::geom::Nurbs {
    let mut pts: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(100.0 * i as f64 / (n - 1) as f64, 0.0, 0.0))
        .collect();
    for &(i, dy) in bumps {
        pts[i].y += dy;
    }
    let mut knots = vec![0.0; 4];
    knots.extend((1..n - 3).map(|i| i as f64 / (n - 3) as f64));
    knots.extend([1.0; 4]);
    fairpath::geom::Nurbs::new(3, knots, pts, None).unwrap()
}

/// The thesis' "noisy line" (seed 003, case 5): 32 control points, two of
/// them displaced 0.2 mm.
fn line_with_two_bumps() -> fairpath::geom::Nurbs {
    bumped_line(32, &[(10, 0.2), (21, 0.2)])
}

/// Length of `c` as a polyline of `m` equal parameter steps.
fn fine_length(c: &fairpath::geom::Nurbs, m: usize) -> f64 {
    use fairpath::geom::ParamCurve;
    (0..m)
        .map(|i| {
            c.eval(i as f64 / m as f64)
                .dist(c.eval((i + 1) as f64 / m as f64))
        })
        .sum()
}

/// Regression (found by the `fair` work on the thesis' case 5): flattening
/// and arc length worked on the whole domain at once, and seven samples
/// over it fell outside both bumps, so the spline was flattened to one
/// chord 0.13 mm from it and planned as a straight line. They now work
/// knot interval by knot interval.
#[test]
fn flattening_and_length_see_a_bump_between_knots() {
    use fairpath::geom::{arc_length, flatten_params, point_segment_distance, ParamCurve};
    let c = line_with_two_bumps();
    let chord = 1e-3;
    let ts = flatten_params(&c, chord);
    for w in ts.windows(2) {
        let (p0, p1) = (c.eval(w[0]), c.eval(w[1]));
        for k in 1..50 {
            let q = c.eval(w[0] + (w[1] - w[0]) * k as f64 / 50.0);
            let d = point_segment_distance(q, p0, p1);
            assert!(d <= chord * 1.01, "chord error {d} in [{}, {}]", w[0], w[1]);
        }
    }
    // Length against a fine polyline.
    let fine = fine_length(&c, 400_000);
    let l = arc_length(&c, 1e-9);
    assert!((l - fine).abs() < 1e-6, "length {l} against {fine}");
    // Straight splines on many control points, with narrow bumps or none:
    // their lengths against fine polylines.
    for n in [32usize, 100, 400] {
        for bump in [0.0, 0.2] {
            let c = bumped_line(n, &[(n / 3, bump), (2 * n / 3, -bump)]);
            let fine = fine_length(&c, 400_000);
            let l = arc_length(&c, 1e-9);
            assert!(
                (l - fine).abs() < 1e-6,
                "{n} points, bump {bump}: {l} against {fine}"
            );
        }
    }
}

/// The same spline planned: its bumps cap the speed (it was planned as one
/// straight segment at the feed).
#[test]
fn the_planner_sees_a_bump_between_knots() {
    use fairpath::feed::limits::MachineLimits;
    use fairpath::feed::plan::{plan_run, PlanOptions};
    use fairpath::geom::Curve;
    use fairpath::path::Piece;
    let piece = Piece {
        curve: Curve::from(line_with_two_bumps()),
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
    let plan = plan_run(&[piece], &opts).unwrap();
    let lowest = plan
        .segments
        .iter()
        .map(|s| s.cap)
        .fold(f64::INFINITY, f64::min);
    // kappa^2 v^3 <= J at the bumps' peak curvature 0.038 1/mm: about
    // 240 mm/s, well under the 400 mm/s feed.
    assert!(lowest < 300.0, "lowest cap {lowest}");
}
