//! A clamped cubic B-spline as its Bezier spans, built one span at a time
//! from the control points and knots the fairing moves (no [`Nurbs`]
//! built per evaluation): the curve, its difference splines (thesis eq.
//! 2-16: `D(t) = sum (P_i - Q_i) N_i(t)`, the same knots) and their
//! samples, bounds and curvature are all read from these.
//!
//! The Bezier control points of span `s` (`u_s < u_{s+1}`) are the blossom
//! (polar form) values `b_j = f(u_s^(3-j), u_(s+1)^j)` (Sederberg, CAGD,
//! ch. 6; the thesis' eq. 2-15), each by de Boor's algorithm with a
//! different argument on each level: O(1) per span, so walking all spans
//! is linear in the number of control points (knot insertion of every
//! breakpoint, as `Nurbs::bezier_spans` does, is quadratic).
//!
//! [`Nurbs`]: crate::geom::Nurbs

use crate::geom::Vec3;
use alloc::vec::Vec;

/// Degree of the curves the fairing works on.
pub(super) const DEGREE: usize = 3;

/// Knot indices `s` of the non-empty spans `u_s < u_{s+1}` of a clamped
/// cubic with `count` control points, in order (`3 <= s < count`).
pub(super) fn nonempty_spans(knots: &[f64], count: usize) -> Vec<usize> {
    (DEGREE..count)
        .filter(|&s| knots[s] < knots[s + 1])
        .collect()
}

/// The blossom `f(a, b, c)` of span `s`: de Boor's algorithm with `a`,
/// `b`, `c` on its three levels (symmetric in them).
fn blossom(knots: &[f64], pts: &[Vec3], s: usize, args: [f64; 3]) -> Vec3 {
    let u = knots;
    let mut d = [pts[s - 3], pts[s - 2], pts[s - 1], pts[s]];
    for (r, &t) in (1..=DEGREE).zip(args.iter()) {
        // Level r: d_j = (1 - alpha) d_{j-1} + alpha d_j for j = s-3+r..=s,
        // alpha = (t - u_j) / (u_{j+4-r} - u_j) (de Boor's recurrence; the
        // denominators cover the non-empty span s, so they are positive).
        for k in (r..=DEGREE).rev() {
            let j = s - DEGREE + k;
            let den = u[j + DEGREE + 1 - r] - u[j];
            let alpha = (t - u[j]) / den;
            d[k] = d[k - 1] * (1.0 - alpha) + d[k] * alpha;
        }
    }
    d[DEGREE]
}

/// The Bezier control points of the non-empty span `s` of the cubic
/// B-spline (`knots`, `pts`): the curve on `[u_s, u_{s+1}]` is
/// `sum b_j B_j^3(tau)`, `tau = (t - u_s) / (u_{s+1} - u_s)`.
pub(super) fn bezier_of_span(knots: &[f64], pts: &[Vec3], s: usize) -> [Vec3; 4] {
    let (a, b) = (knots[s], knots[s + 1]);
    [
        blossom(knots, pts, s, [a, a, a]),
        blossom(knots, pts, s, [a, a, b]),
        blossom(knots, pts, s, [a, b, b]),
        blossom(knots, pts, s, [b, b, b]),
    ]
}

/// A cubic Bezier curve at `tau` in `[0, 1]` (de Casteljau).
pub(super) fn bezier_point(b: &[Vec3; 4], tau: f64) -> Vec3 {
    let l = |p: Vec3, q: Vec3| p.lerp(q, tau);
    let (p01, p12, p23) = (l(b[0], b[1]), l(b[1], b[2]), l(b[2], b[3]));
    let (p012, p123) = (l(p01, p12), l(p12, p23));
    l(p012, p123)
}

/// First and second derivatives of a cubic Bezier curve with respect to
/// `tau` (curvature does not depend on the parameterisation, so these
/// give the B-spline's curvature on the span).
pub(super) fn bezier_derivatives(b: &[Vec3; 4], tau: f64) -> (Vec3, Vec3) {
    let d = [b[1] - b[0], b[2] - b[1], b[3] - b[2]];
    let s = 1.0 - tau;
    let d1 = (d[0] * (s * s) + d[1] * (2.0 * s * tau) + d[2] * (tau * tau)) * 3.0;
    let d2 = ((d[1] - d[0]) * s + (d[2] - d[1]) * tau) * 6.0;
    (d1, d2)
}

/// The two halves of a cubic Bezier curve split at `tau = 1/2`.
pub(super) fn split_half(b: &[Vec3; 4]) -> ([Vec3; 4], [Vec3; 4]) {
    let m = |p: Vec3, q: Vec3| (p + q) * 0.5;
    let (p01, p12, p23) = (m(b[0], b[1]), m(b[1], b[2]), m(b[2], b[3]));
    let (p012, p123) = (m(p01, p12), m(p12, p23));
    let mid = m(p012, p123);
    ([b[0], p01, p012, mid], [mid, p123, p23, b[3]])
}

/// The cubic B-spline (`knots`, `pts`) at `t` (in the domain): the Bezier
/// span containing it (the last span at the domain's end).
pub(super) fn eval(knots: &[f64], pts: &[Vec3], t: f64) -> Vec3 {
    let s = crate::geom::cubic_span::span_of(knots, pts.len(), t);
    let b = bezier_of_span(knots, pts, s);
    let (a, e) = (knots[s], knots[s + 1]);
    bezier_point(&b, ((t - a) / (e - a)).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Nurbs, ParamCurve};
    use alloc::vec;

    fn curve() -> Nurbs {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(3.0, -1.0, 0.0),
            Vec3::new(4.0, 1.0, 1.0),
            Vec3::new(6.0, 0.5, 0.0),
            Vec3::new(7.0, 3.0, -1.0),
            Vec3::new(9.0, 0.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.7, 1.0, 1.0, 3.0, 3.0, 3.0, 3.0];
        Nurbs::new(3, knots, pts, None).unwrap()
    }

    #[test]
    fn spans_are_the_curve() {
        let c = curve();
        let spans = nonempty_spans(&c.knots, c.points.len());
        assert_eq!(spans, vec![3, 4, 6]);
        let reference = c.bezier_spans();
        assert_eq!(reference.len(), spans.len());
        for (&s, r) in spans.iter().zip(&reference) {
            let b = bezier_of_span(&c.knots, &c.points, s);
            for (p, q) in b.iter().zip(&r.points) {
                assert!(p.dist(*q) < 1e-12, "{p:?} {q:?}");
            }
        }
        for i in 0..=60 {
            let t = 3.0 * i as f64 / 60.0;
            assert!(eval(&c.knots, &c.points, t).dist(c.eval(t)) < 1e-12);
        }
    }

    #[test]
    fn derivatives_give_the_curvature() {
        let c = curve();
        let s = 6;
        let b = bezier_of_span(&c.knots, &c.points, s);
        let (a, e) = (c.knots[s], c.knots[s + 1]);
        for i in 0..=8 {
            let tau = i as f64 / 8.0;
            let (d1, d2) = bezier_derivatives(&b, tau);
            let k = crate::geom::curvature_from(d1, d2);
            let kr = c.curvature(a + (e - a) * tau);
            assert!((k - kr).abs() <= 1e-9 * kr.max(1.0), "{k} {kr}");
        }
        let (l, r) = split_half(&b);
        assert!(bezier_point(&l, 0.5).dist(bezier_point(&b, 0.25)) < 1e-12);
        assert!(bezier_point(&r, 0.5).dist(bezier_point(&b, 0.75)) < 1e-12);
    }
}
