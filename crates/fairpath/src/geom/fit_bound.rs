//! A proven bound, for every knot span of a fitted cubic B-spline, of the
//! curve's distance from the polyline of the data and of the data residuals
//! ([`span_errors`]; the proof is in its documentation).
//!
//! It needs only the curve, the data and their parameters, not how the
//! curve was made: every fit and the band relaxation ([`super::band_fit`])
//! are judged by it, so it is kept apart from the fit.

use super::cubic_span::eval_in_span;
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
    let h = c.points.len();
    let knots = &c.knots;
    let mut err = vec![0.0f64; h - FIT_DEGREE];
    let n = pts.len();
    let seg_dist = |g: usize, p: Vec3| point_segment_distance(p, pts[g], pts[g + 1]);
    let mut s = FIT_DEGREE;
    // Value and second derivative at the start of the current piece: the
    // end of the previous one, since both are continuous across a simple
    // knot (re-evaluated after a multiple knot, where `C''` may jump).
    let mut at_a = eval_in_span(knots, &c.points, s, params[0]);
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
                at_a = eval_in_span(knots, &c.points, s, t0);
                a_dists = None;
            }
        }
        // Data residual at t0.
        err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[i]));
        let mut a = t0;
        let lo_g = i.saturating_sub(1);
        let hi_g = (i + 1).min(n - 2);
        loop {
            let b = if s + 1 < h { knots[s + 1].min(t1) } else { t1 };
            let (ca, c2a) = at_a;
            let (cb, c2b) = eval_in_span(knots, &c.points, s, b);
            let sag = c2a.norm().max(c2b.norm()) * (b - a) * (b - a) / 8.0;
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
            at_a = (cb, c2b);
            a_dists = Some((lo_g, b_dists));
            if b >= t1 || s + 1 >= h {
                break;
            }
            a = b;
            s += 1;
            if multiple(s) {
                at_a = eval_in_span(knots, &c.points, s, a);
                a_dists = None;
            }
        }
        if i == n - 2 {
            err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[n - 1]));
        }
    }
    err
}
