//! A polynomial cubic B-spline held as its Bezier spans
//! ([`Nurbs::cubic_bezier_points`]), for code that evaluates one curve many
//! times: a point or a frame is a binary search over the breakpoints and a
//! few multiply-adds of the Bernstein form ([`CubicBezier`]), where the
//! B-spline finds its knot span and computes its basis functions (Piegl
//! and Tiller A2.1-A2.3) at every call. The renderer samples each piece
//! hundreds of times while fitting arcs to it (`render::arcs`).

use super::{CubicBezier, Nurbs, ParamCurve, Vec3};
use alloc::vec::Vec;

/// The same curve as a [`Nurbs`] of degree 3 without weights, on the same
/// parameter, up to rounding; its ends are the spline's own end points to
/// the bit.
#[derive(Clone, Debug, PartialEq)]
pub struct BezierSpline {
    /// The breakpoints, increasing: span `i` covers `[breaks[i], breaks[i + 1]]`.
    breaks: Vec<f64>,
    spans: Vec<CubicBezier>,
    start: Vec3,
    end: Vec3,
}

impl BezierSpline {
    /// `n` as its Bezier spans; `None` where [`Nurbs::cubic_bezier_points`]
    /// has none (a rational curve, another degree, an invalid curve) or a
    /// span is degenerate.
    pub fn of(n: &Nurbs) -> Option<BezierSpline> {
        let (breaks, points) = n.cubic_bezier_points()?;
        let spans = breaks
            .windows(2)
            .zip(points)
            .map(|(w, p)| CubicBezier::new(p, w[0], w[1]))
            .collect::<Option<Vec<CubicBezier>>>()?;
        if spans.is_empty() {
            return None;
        }
        Some(BezierSpline {
            breaks,
            spans,
            start: n.start(),
            end: n.end(),
        })
    }

    /// The span that evaluates `t`: the one starting at or before it (at a
    /// breakpoint the span after it, as [`Nurbs::find_span`] takes the knot
    /// span after a knot), clamped to the first and last.
    fn span(&self, t: f64) -> &CubicBezier {
        let i = self.breaks.partition_point(|&b| b <= t);
        &self.spans[i.saturating_sub(1).min(self.spans.len() - 1)]
    }
}

impl ParamCurve for BezierSpline {
    fn domain(&self) -> (f64, f64) {
        (self.breaks[0], self.breaks[self.breaks.len() - 1])
    }
    /// The spline's end points at and beyond the ends.
    fn eval(&self, t: f64) -> Vec3 {
        let (a, b) = self.domain();
        if t <= a {
            self.start
        } else if t >= b {
            self.end
        } else {
            self.span(t).eval(t)
        }
    }
    fn deriv1(&self, t: f64) -> Vec3 {
        self.derivs12(t).0
    }
    fn deriv2(&self, t: f64) -> Vec3 {
        self.derivs12(t).1
    }
    fn derivs12(&self, t: f64) -> (Vec3, Vec3) {
        let (a, b) = self.domain();
        self.span(t.clamp(a, b)).derivs12(t.clamp(a, b))
    }
    fn start(&self) -> Vec3 {
        self.start
    }
    fn end(&self) -> Vec3 {
        self.end
    }
    fn breaks(&self) -> Vec<f64> {
        self.breaks.clone()
    }
    fn breaks_within(&self, a: f64, b: f64) -> Vec<f64> {
        self.breaks
            .iter()
            .copied()
            .filter(|&k| k > a && k < b)
            .collect()
    }
    fn quadratic_deriv1(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::BezierSpline;
    use crate::geom::{Nurbs, ParamCurve, Vec3};
    use crate::seeded::Rng;

    /// A random cubic B-spline (clamped or not) and the same as Bezier spans have the
    /// same points and first two derivatives at random parameters (the
    /// knots and the ends included) but for rounding, the same ends to the
    /// bit, and the same breakpoints.
    #[test]
    fn seeded_random_splines_evaluate_as_their_bezier_spans() {
        let mut rng = Rng(41);
        let mut checked = 0;
        for case in 0..300 {
            let n = 4 + rng.below(12);
            let scale = rng.decades(-2.0, 3.0);
            let points: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(rng.next(), rng.next(), rng.next()) * scale)
                .collect();
            let mut inner: Vec<f64> = (0..n - 4).map(|_| rng.next()).collect();
            // Some double knots.
            if n > 5 && rng.below(3) == 0 {
                inner[1] = inner[0];
            }
            inner.sort_by(f64::total_cmp);
            // Clamped, or (one case in four) with knots outside the
            // domain at both ends, unclamped.
            let (lo, hi) = if rng.below(4) == 0 {
                ([-0.3, -0.2, -0.1, 0.0], [1.0, 1.1, 1.2, 1.3])
            } else {
                ([0.0; 4], [1.0; 4])
            };
            let mut knots = lo.to_vec();
            knots.extend(inner);
            knots.extend(hi);
            let Ok(spline) = Nurbs::new(3, knots, points, None) else {
                continue;
            };
            let spans = BezierSpline::of(&spline).expect("a polynomial cubic");
            assert_eq!(spans.breaks(), spline.breakpoints(), "case {case}");
            assert_eq!(spans.start(), spline.start(), "case {case}");
            assert_eq!(spans.end(), spline.end(), "case {case}");
            assert_eq!(spans.domain(), spline.domain(), "case {case}");
            let mut ts: Vec<f64> = (0..20).map(|_| rng.next()).collect();
            ts.extend(spline.breakpoints());
            let breaks = spline.breakpoints();
            for t in ts {
                let (d1, d2) = spline.derivs12(t);
                let (e1, e2) = spans.derivs12(t);
                // Rounding grows as the span (length `h`) shrinks: a
                // derivative of order k by 1 / h^k.
                let i = breaks
                    .partition_point(|&b| b <= t)
                    .clamp(1, breaks.len() - 1);
                let h = breaks[i] - breaks[i - 1];
                let close = |a: Vec3, b: Vec3, size: f64| (a - b).norm() <= 1e-9 * size;
                assert!(
                    close(spline.eval(t), spans.eval(t), scale),
                    "case {case} t {t}"
                );
                assert!(close(d1, e1, scale / h), "case {case} t {t}: {d1:?} {e1:?}");
                assert!(
                    close(d2, e2, scale / (h * h)),
                    "case {case} t {t}: {d2:?} {e2:?}"
                );
            }
            checked += 1;
        }
        assert!(checked > 200, "{checked} splines checked");
    }

    #[test]
    fn a_rational_or_quadratic_curve_has_no_bezier_spline() {
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let quad = Nurbs::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], pts.clone(), None).unwrap();
        assert!(BezierSpline::of(&quad).is_none());
        let pts4 = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let rational = Nurbs::new(3, knots, pts4, Some(vec![1.0, 2.0, 2.0, 1.0])).unwrap();
        assert!(BezierSpline::of(&rational).is_none());
    }
}
