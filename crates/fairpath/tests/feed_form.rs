//! The planned time of a curve does not depend on how it is held: a cubic
//! B-spline plans the time of its own Bezier spans (the same curve cut at
//! its knots into pieces). The planner flattens a spline span by span, so
//! both forms get the same stretches; before, the whole curve's
//! chord-error cuts fell elsewhere, and with them the segment boundaries
//! where the acceleration stops: the thesis' square of ripples planned
//! 2.913 s as one B-spline against 2.824 s as its spans (which made the
//! writer prefer one form of a curve over another for nothing).

use crate::common;

use common::{planned_at_max_feed, Rng};
use fairpath::geom::{Curve, Nurbs, Vec3};
use fairpath::path::Piece;

fn pieces_of(curves: Vec<Nurbs>) -> Vec<Piece> {
    curves
        .into_iter()
        .map(|n| Piece {
            curve: Curve::from(n),
            rapid: false,
            source_lines: (1, 1),
            feed: Some(24000.0),
        })
        .collect()
}

/// The planned times (s) of `curve` as one piece and as its Bezier spans,
/// at the maximum feed on the thesis' machine.
fn form_gap(curve: &Nurbs) -> (f64, f64) {
    let whole = planned_at_max_feed(&pieces_of(vec![curve.clone()]));
    let spans = planned_at_max_feed(&pieces_of(curve.bezier_spans()));
    (whole, spans)
}

/// `examples/thesis/square-ripples.ngc`: the thesis' case 6, a square of
/// side 30 mm whose corners a spline through 29 points turns into ripples.
fn square_ripples() -> Nurbs {
    let knots = vec![
        0.0, 0.0, 0.0, 0.0, 11.63, 15.63, 18.0, 20.37, 24.37, 30.0, 36.0, 41.63, 45.63, 48.0,
        50.37, 54.37, 60.0, 66.0, 71.63, 75.63, 78.0, 80.37, 84.37, 90.0, 96.0, 101.63, 105.63,
        108.0, 110.37, 120.0, 120.0, 120.0, 120.0,
    ];
    let xy = [
        (12.0, 0.0),
        (14.638657, 1.238181),
        (23.022996, -1.936598),
        (25.648576, 1.438290),
        (31.077112, -1.077261),
        (28.561378, 4.352558),
        (30.837082, 6.056717),
        (29.793302, 12.472313),
        (29.793190, 17.527650),
        (30.837357, 23.943435),
        (28.560916, 25.647179),
        (31.077458, 31.077458),
        (25.647179, 28.560916),
        (23.943437, 30.837354),
        (17.527637, 29.793213),
        (12.472363, 29.793213),
        (6.056563, 30.837354),
        (4.352821, 28.560917),
        (-1.077458, 31.077458),
        (1.439085, 25.647180),
        (-0.837386, 23.943407),
        (0.207019, 17.527859),
        (0.205879, 12.471493),
        (-0.834586, 6.059214),
        (1.434380, 4.348316),
        (-1.073937, -1.074085),
        (7.825159, 3.035579),
        (5.361313, -3.429162),
        (12.0, 0.0),
    ];
    let points = xy.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
    Nurbs::new(3, knots, points, None).expect("a valid spline")
}

#[test]
fn square_ripples_plan_as_their_bezier_spans() {
    let (whole, spans) = form_gap(&square_ripples());
    assert!(
        (whole - spans).abs() <= 1e-9 * spans,
        "one B-spline {whole} s, its spans {spans} s"
    );
}

/// A clamped cubic with `n` control points wandering about a line, and
/// knots spaced unevenly (span lengths from 0.2 to 3 times the mean).
fn random_spline(rng: &mut Rng, n: usize) -> Nurbs {
    let mut points = Vec::with_capacity(n);
    let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
    for i in 0..n {
        if i > 0 {
            x += 1.0 + 4.0 * rng.unit();
            y += 3.0 * (rng.unit() - 0.5);
            z += 0.5 * (rng.unit() - 0.5);
        }
        points.push(Vec3::new(x, y, z));
    }
    let mut knots = vec![0.0; 4];
    let mut u = 0.0;
    for _ in 0..n - 4 {
        u += 0.2 + 2.8 * rng.unit();
        knots.push(u);
    }
    u += 0.2 + 2.8 * rng.unit();
    knots.extend([u; 4]);
    Nurbs::new(3, knots, points, None).expect("a valid spline")
}

#[test]
fn seeded_random_splines_plan_as_their_bezier_spans() {
    let mut rng = Rng(20261129);
    for case in 0..40 {
        let n = 5 + (case % 12);
        let c = random_spline(&mut rng, n);
        let (whole, spans) = form_gap(&c);
        // The two forms evaluate the same curve with different rounding:
        // a cap can land a bit either side, nothing more.
        assert!(
            (whole - spans).abs() <= 1e-6 * spans,
            "case {case} ({n} points): one B-spline {whole} s, its spans {spans} s"
        );
    }
}
