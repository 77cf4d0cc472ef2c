//! A proven bound, for every knot span of a fitted cubic B-spline, of the
//! curve's distance from the polyline of the data and of the data residuals
//! ([`span_errors`]; the proof is in its documentation).
//!
//! It needs only the curve, the data and their parameters, not how the
//! curve was made: every fit and the band relaxation ([`super::band_fit`])
//! are judged by it, so it is kept apart from the fit.

use super::cubic_span::{cubic_basis_values, eval_in_span};
use super::fit::FIT_DEGREE;
use super::{point_segment_distance, Nurbs, Vec3};
use alloc::vec;
use alloc::vec::Vec;

/// For every knot span of `c` (a clamped cubic B-spline whose domain starts
/// at `params[0]` and ends at the last parameter), an upper bound of
///
/// * the distance from every point of the span to the polyline `pts`, and
/// * `|C(t_i) - Q_i|` for the data points with parameter in the span (each
///   data point within that of the fit: the fit follows all of the data).
///
/// The bound is proved as follows. Cut the domain at the data parameters and
/// the knots; on a piece `[a, b]` inside data interval `i`, `C` is one cubic
/// and `C''` is linear, so `M = max(|C''(a)|, |C''(b)|)` bounds `|C''|` and
/// `C(t)` lies within `M (b - a)^2 / 8` of the chord `C(a) C(b)` (the
/// interpolation error of a linear interpolant). The distance to a fixed
/// segment is a convex function of the point, so along the chord it is at
/// most its larger end value. Hence for segment `g` of the polyline
/// (`g` in `i - 1, i, i + 1`),
/// `dist(C(t), polyline) <= max(d_g(C(a)), d_g(C(b))) + M (b - a)^2 / 8`,
/// and the smallest of the three is kept. Time linear in the data and spans.
pub fn span_errors(c: &Nurbs, pts: &[Vec3], params: &[f64]) -> Vec<f64> {
    // No bound exceeds an infinite limit: the bounds of every span.
    bounds_up_to(c, pts, params, f64::INFINITY).0
}

/// [`span_errors`], or, as soon as one span's bound exceeds `limit`,
/// `Err` with that bound (the bounds of the other spans not computed): a
/// fit that fails its target is known to fail for the price of the spans
/// up to the first that misses it.
pub fn span_errors_within(
    c: &Nurbs,
    pts: &[Vec3],
    params: &[f64],
    limit: f64,
) -> Result<Vec<f64>, f64> {
    match bounds_up_to(c, pts, params, limit) {
        (err, None) => Ok(err),
        (_, Some(e)) => Err(e),
    }
}

/// The span bounds of [`span_errors`] up to the first that exceeds
/// `limit`, and that bound (`None`: none does, every span bounded).
fn bounds_up_to(c: &Nurbs, pts: &[Vec3], params: &[f64], limit: f64) -> (Vec<f64>, Option<f64>) {
    let h = c.points.len();
    let knots = &c.knots;
    let mut err = vec![0.0f64; h - FIT_DEGREE];
    let n = pts.len();
    let seg_dist = |g: usize, p: Vec3| point_segment_distance(p, pts[g], pts[g + 1]);
    let mut s = FIT_DEGREE;
    // Value and second derivative at the start of the current piece: the
    // end of the previous one, since both are continuous across a simple
    // knot (re-evaluated after a multiple knot, where `C''` may jump).
    let mut span = SpanEval::new(knots, &c.points);
    let mut at_a = span.eval(s, params[0]);
    // Distances of `at_a`'s point to segments `g0..g0 + 3` (NaN: not
    // known), kept from the piece before when `at_a` is its end: each
    // point's distances are computed once, not once per piece it bounds.
    let mut a_dists: Option<(usize, [f64; 3])> = None;
    let multiple = |s: usize| knots[s] == knots[s - 1];
    for i in 0..n - 1 {
        let (t0, t1) = (params[i], params[i + 1]);
        while s + 1 < h && knots[s + 1] <= t0 {
            s += 1;
            if multiple(s) {
                at_a = span.eval(s, t0);
                a_dists = None;
            }
        }
        // Data residual at t0.
        err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[i]));
        if err[s - FIT_DEGREE] > limit {
            let e = err[s - FIT_DEGREE];
            return (err, Some(e));
        }
        let mut a = t0;
        let lo_g = i.saturating_sub(1);
        let hi_g = (i + 1).min(n - 2);
        loop {
            let b = if s + 1 < h { knots[s + 1].min(t1) } else { t1 };
            let (ca, c2a) = at_a;
            let (cb, c2b) = span.eval(s, b);
            let sag = c2a.1.max(c2b.1) * (b - a) * (b - a) / 8.0;
            let known = |g: usize| match a_dists {
                Some((g0, d)) if g >= g0 && g < g0 + 3 && !d[g - g0].is_nan() => Some(d[g - g0]),
                _ => None,
            };
            let mut b_dists = [f64::NAN; 3];
            let mut best = f64::INFINITY;
            for g in lo_g..=hi_g {
                let da = known(g).unwrap_or_else(|| seg_dist(g, ca));
                let db = seg_dist(g, cb);
                b_dists[g - lo_g] = db;
                best = best.min(da.max(db));
            }
            let e = &mut err[s - FIT_DEGREE];
            *e = e.max(best + sag);
            if *e > limit {
                let e = *e;
                return (err, Some(e));
            }
            at_a = (cb, c2b);
            a_dists = Some((lo_g, b_dists));
            if b >= t1 || s + 1 >= h {
                break;
            }
            a = b;
            s += 1;
            if multiple(s) {
                at_a = span.eval(s, a);
                a_dists = None;
            }
        }
        if i == n - 2 {
            err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[n - 1]));
            if err[s - FIT_DEGREE] > limit {
                let e = err[s - FIT_DEGREE];
                return (err, Some(e));
            }
        }
    }
    (err, None)
}

/// Position and second derivative of a clamped cubic B-spline by
/// [`eval_in_span`], to the bit, with `|C''|`, keeping the span's
/// second-difference control points between calls on the same span (the
/// bound evaluates each span at every data parameter inside it).
struct SpanEval<'a> {
    knots: &'a [f64],
    pts: &'a [Vec3],
    /// The span whose `C''` end values `ends` hold, if any.
    span: Option<usize>,
    ends: (Vec3, Vec3),
}

impl<'a> SpanEval<'a> {
    fn new(knots: &'a [f64], pts: &'a [Vec3]) -> Self {
        SpanEval {
            knots,
            pts,
            span: None,
            ends: (Vec3::ZERO, Vec3::ZERO),
        }
    }

    /// `C(t)` and `(C''(t), |C''(t)|)` from the polynomial of span `s`.
    fn eval(&mut self, s: usize, t: f64) -> (Vec3, (Vec3, f64)) {
        let u = self.knots;
        let h = u[s + 1] - u[s];
        if h.is_nan() || h <= 0.0 {
            let (c, c2) = eval_in_span(u, self.pts, s, t);
            return (c, (c2, c2.norm()));
        }
        let b = cubic_basis_values(u, s, t);
        let q = [
            self.pts[s - 3],
            self.pts[s - 2],
            self.pts[s - 1],
            self.pts[s],
        ];
        let c = q[0] * b[0] + q[1] * b[1] + q[2] * b[2] + q[3] * b[3];
        if self.span != Some(s) {
            // As `eval_in_span`: every denominator spans the non-empty span s.
            let p1 = |j: usize| (q[j + 1] - q[j]) * (3.0 / (u[s + j + 1] - u[s + j - 2]));
            let (d0, d1, d2) = (p1(0), p1(1), p1(2));
            let a0 = (d1 - d0) * (2.0 / (u[s + 1] - u[s - 1]));
            let a1 = (d2 - d1) * (2.0 / (u[s + 2] - u[s]));
            self.span = Some(s);
            self.ends = (a0, a1);
        }
        let (a0, a1) = self.ends;
        let w = (t - u[s]) / h;
        let c2 = a0 * (1.0 - w) + a1 * w;
        (c, (c2, c2.norm()))
    }
}
