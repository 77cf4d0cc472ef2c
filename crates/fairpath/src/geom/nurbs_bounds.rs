//! Sure bounds of a NURBS curve's derivatives from its control points, for
//! the verifier's second-order bound on curves it cannot bound otherwise
//! (rational curves, such as circular arcs written as rational quadratics,
//! and degrees above 3).
//!
//! The derivative of a B-spline `sum N_i,p P_i` over knots `u` is the
//! B-spline of degree `p - 1` with control points
//! `Q_i = p (P_i+1 - P_i) / (u_i+p+1 - u_i+1)` (Piegl and Tiller, The NURBS
//! Book, 2nd ed., eq. 3.8), and a B-spline lies in the convex hull of its
//! control points, so `max |Q_i|` bounds the derivative everywhere. For a
//! rational curve `C = A / w` with the homogeneous `A = sum N_i w_i P_i` and
//! `w = sum N_i w_i`, differentiating `C w = A` twice gives
//! `C' = (A' - w' C) / w` and `C'' = (A'' - 2 w' C' - w'' C) / w` (eq. 4.8);
//! with `w >= min w_i > 0` and, after moving the origin to a control point,
//! `|C| <= max |P_i - P_0|` (positive weights keep the curve in the hull),
//! every term has a bound from control points alone.

use super::{Nurbs, ParamCurve, Vec3};
use alloc::vec::Vec;

/// Control points of the derivative of the degree-`p` B-spline over
/// `knots` with (homogeneous) coefficients `c` (eq. 3.8); a coefficient
/// whose knot span is empty belongs to a basis function that is zero
/// everywhere and is given as zero.
fn derivative_points(p: usize, knots: &[f64], c: &[(Vec3, f64)]) -> Vec<(Vec3, f64)> {
    (0..c.len().saturating_sub(1))
        .map(|i| {
            let span = knots[i + p + 1] - knots[i + 1];
            if span > 0.0 {
                let s = p as f64 / span;
                ((c[i + 1].0 - c[i].0) * s, (c[i + 1].1 - c[i].1) * s)
            } else {
                (Vec3::ZERO, 0.0)
            }
        })
        .collect()
}

fn max_norms(c: &[(Vec3, f64)]) -> (f64, f64) {
    c.iter().fold((0.0f64, 0.0f64), |(a, w), (v, s)| {
        (a.max(v.norm()), w.max(s.abs()))
    })
}

impl Nurbs {
    /// True when the curve is continuously differentiable over its domain:
    /// degree at least 2 and no interior knot repeated more than
    /// `degree - 1` times (a B-spline is `C^(p - m)` at a knot of
    /// multiplicity `m`).
    pub fn is_c1(&self) -> bool {
        let p = self.degree;
        if p < 2 {
            // Degree 1 is C1 only without interior knots: one line.
            let (a, b) = self.domain();
            return !self.knots.iter().any(|&k| k > a && k < b);
        }
        let (a, b) = self.domain();
        let mut run = 0;
        let mut prev = f64::NAN;
        for &k in &self.knots {
            if k > a && k < b {
                run = if k == prev { run + 1 } else { 1 };
                if run > p - 1 {
                    return false;
                }
            }
            prev = k;
        }
        true
    }

    /// An upper bound of `|C''(t)|` over the whole domain from the control
    /// points (see the module documentation), or `None` when the curve is
    /// not C1 (a kink has no second-derivative bound) or not well formed.
    /// Sure but not tight: for polynomial cubics the largest `|C''|` at a
    /// breakpoint is smaller.
    pub fn second_derivative_bound(&self) -> Option<f64> {
        if self.validate().is_err() || !self.is_c1() {
            return None;
        }
        let p = self.degree;
        let origin = self.points[0];
        let weight = |i: usize| self.weights.as_ref().map_or(1.0, |w| w[i]);
        let homogeneous: Vec<(Vec3, f64)> = self
            .points
            .iter()
            .enumerate()
            .map(|(i, &q)| ((q - origin) * weight(i), weight(i)))
            .collect();
        let m0 = self
            .points
            .iter()
            .map(|&q| (q - origin).norm())
            .fold(0.0, f64::max);
        let w_min = (0..self.points.len())
            .map(weight)
            .fold(f64::INFINITY, f64::min);
        let d1 = derivative_points(p, &self.knots, &homogeneous);
        let d2 = derivative_points(p - 1, &self.knots[1..self.knots.len() - 1], &d1);
        let (a1, w1) = max_norms(&d1);
        let (a2, w2) = max_norms(&d2);
        let c1 = (a1 + w1 * m0) / w_min;
        let c2 = (a2 + 2.0 * w1 * c1 + w2 * m0) / w_min;
        c2.is_finite().then_some(c2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Arc;
    use core::f64::consts::PI;

    fn largest_sampled(n: &Nurbs) -> f64 {
        let (a, b) = n.domain();
        (0..=4000)
            .map(|k| n.derivs(a + (b - a) * k as f64 / 4000.0)[2].norm())
            .fold(0.0, f64::max)
    }

    #[test]
    fn bounds_a_circle_written_as_rational_quadratics() {
        for (r, sweep) in [(25.47, 0.5 * PI), (10.0, 1.5 * PI), (0.3, 2.0 * PI)] {
            let arc = Arc::from_center(
                Vec3::new(r, 0.0, 0.0),
                Vec3::new(r * sweep.cos(), r * sweep.sin(), 0.0),
                Vec3::ZERO,
                Vec3::new(0.0, 0.0, 1.0),
                false,
                1,
                1e-9,
            )
            .unwrap();
            let n = Nurbs::from_circular_arc(&arc);
            // Pieces of 90 degrees meet at double knots: C0 in the
            // parameter, so the bound is per Bezier span.
            assert_eq!(n.is_c1(), sweep <= 0.5 * PI);
            for span in n.bezier_spans() {
                let bound = span.second_derivative_bound().unwrap();
                let seen = largest_sampled(&span);
                assert!(bound >= seen, "r {r}: bound {bound} < sampled {seen}");
                assert!(
                    bound < 100.0 * seen,
                    "r {r}: bound {bound} far above {seen}"
                );
            }
        }
    }

    #[test]
    fn bounds_polynomial_splines_of_high_degree() {
        let pts: Vec<Vec3> = (0..9)
            .map(|i| Vec3::new(i as f64, ((i * 7) % 5) as f64, ((i * 3) % 4) as f64))
            .collect();
        let mut knots = alloc::vec![0.0; 6];
        knots.extend([0.3, 0.5, 0.8]);
        knots.extend([1.0; 6]);
        let n = Nurbs::new(5, knots, pts, None).unwrap();
        assert!(n.second_derivative_bound().unwrap() >= largest_sampled(&n));
    }

    #[test]
    fn no_bound_across_a_kink() {
        // Degree 2 with a double interior knot: C0 there.
        let pts = alloc::vec![
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
        ];
        let knots = alloc::vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
        let n = Nurbs::new(2, knots, pts, None).unwrap();
        assert!(!n.is_c1());
        assert_eq!(n.second_derivative_bound(), None);
    }
}
