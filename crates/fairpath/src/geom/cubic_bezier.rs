//! One span of a polynomial cubic B-spline as the cubic Bezier curve it is
//! there ([`super::Nurbs::bezier_spans`]), on the spline's own parameter
//! interval: evaluated by its Bernstein form (P&T eq. 1.8 and 1.10, the
//! hodograph of a Bezier curve), a few multiply-adds per point where the
//! B-spline finds its knot span and its basis functions every time. The
//! planner flattens and samples a fit span by span (`feed::caps`), and
//! most of planning a run of fits is evaluating them.

use super::{ParamCurve, Vec3};

/// A cubic Bezier curve with control points `p` over the parameter
/// interval `[t0, t1]` (`t0 < t1`): `C(t) = sum B_i(s) p_i`,
/// `s = (t - t0) / (t1 - t0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicBezier {
    t0: f64,
    t1: f64,
    inv_h: f64,
    p: [Vec3; 4],
}

impl CubicBezier {
    /// `None` where `t0 < t1` does not hold or a number is not finite.
    pub fn new(p: [Vec3; 4], t0: f64, t1: f64) -> Option<CubicBezier> {
        let ok = t0 < t1 && t0.is_finite() && t1.is_finite() && p.iter().all(|q| q.is_finite());
        ok.then(|| CubicBezier {
            t0,
            t1,
            inv_h: 1.0 / (t1 - t0),
            p,
        })
    }

    fn s(&self, t: f64) -> f64 {
        (t - self.t0) * self.inv_h
    }
}

impl ParamCurve for CubicBezier {
    fn domain(&self) -> (f64, f64) {
        (self.t0, self.t1)
    }
    /// The end control points at the ends exactly.
    fn eval(&self, t: f64) -> Vec3 {
        if t <= self.t0 {
            return self.p[0];
        }
        if t >= self.t1 {
            return self.p[3];
        }
        let s = self.s(t);
        let r = 1.0 - s;
        let [p0, p1, p2, p3] = self.p;
        p0 * (r * r * r) + p1 * (3.0 * r * r * s) + p2 * (3.0 * r * s * s) + p3 * (s * s * s)
    }
    fn deriv1(&self, t: f64) -> Vec3 {
        self.derivs12(t).0
    }
    fn deriv2(&self, t: f64) -> Vec3 {
        self.derivs12(t).1
    }
    /// The hodograph `3 sum B_i^2(s) (p_{i+1} - p_i)` and its derivative,
    /// scaled by `1 / (t1 - t0)` per order.
    fn derivs12(&self, t: f64) -> (Vec3, Vec3) {
        let s = self.s(t);
        let r = 1.0 - s;
        let [p0, p1, p2, p3] = self.p;
        let (d0, d1, d2) = (p1 - p0, p2 - p1, p3 - p2);
        let h1 = 3.0 * self.inv_h;
        let h2 = 6.0 * self.inv_h * self.inv_h;
        let first = (d0 * (r * r) + d1 * (2.0 * r * s) + d2 * (s * s)) * h1;
        let second = ((d1 - d0) * r + (d2 - d1) * s) * h2;
        (first, second)
    }
    fn quadratic_deriv1(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::CubicBezier;
    use crate::geom::{Nurbs, ParamCurve, Vec3};
    use crate::seeded::Rng;

    /// Each Bezier span of a random cubic B-spline, as a [`CubicBezier`],
    /// has the spline's points and first two derivatives there, but for
    /// rounding.
    #[test]
    fn seeded_random_spans_are_the_spline_there() {
        let mut rng = Rng(23);
        for case in 0..300 {
            let n = 4 + rng.below(8);
            let scale = rng.decades(-2.0, 2.0);
            let points: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(rng.next(), rng.next(), rng.next()) * scale)
                .collect();
            let mut inner: Vec<f64> = (0..n - 4).map(|_| rng.next()).collect();
            inner.sort_by(f64::total_cmp);
            let mut knots = vec![0.0; 4];
            knots.extend(inner);
            knots.extend(vec![1.0; 4]);
            let Ok(spline) = Nurbs::new(3, knots, points, None) else {
                continue;
            };
            let breaks = spline.breakpoints();
            let spans = spline.bezier_spans();
            assert_eq!(spans.len() + 1, breaks.len(), "case {case}");
            for (w, span) in breaks.windows(2).zip(&spans) {
                let p = [
                    span.points[0],
                    span.points[1],
                    span.points[2],
                    span.points[3],
                ];
                let b = CubicBezier::new(p, w[0], w[1]).unwrap();
                for k in 0..=8 {
                    // Inside the span (at a knot the spline takes the
                    // span after it).
                    let t = w[0] + (w[1] - w[0]) * (0.01 + 0.98 * k as f64 / 8.0);
                    let (d1, d2) = spline.derivs12(t);
                    let (e1, e2) = b.derivs12(t);
                    let close = |a: Vec3, b: Vec3, size: f64| (a - b).norm() <= 1e-9 * size;
                    let h = w[1] - w[0];
                    assert!(close(spline.eval(t), b.eval(t), scale), "case {case}");
                    assert!(close(d1, e1, scale / h), "case {case}: {d1:?} {e1:?}");
                    assert!(close(d2, e2, scale / (h * h)), "case {case}: {d2:?} {e2:?}");
                }
            }
        }
    }
}
