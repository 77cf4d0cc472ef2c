//! Fairness measures of a curve.

use super::{Curve, ParamCurve};
use crate::math;

/// Largest number of doublings of the samples per span in
/// [`curvature_variation_energy`] (16 * 2^10 samples per knot span).
const ENERGY_MAX_DOUBLINGS: u32 = 10;

/// The curvature variation energy `E = integral (dkappa/ds)^2 ds` (1/mm^3),
/// the fairness measure of seed 001 (the energy its proportional
/// coefficient minimises) and of the CAGD literature (Moreton and Sequin's
/// minimum variation curves). Zero for lines and circular arcs.
///
/// Computed per knot span as `sum ((kappa_i+1 - kappa_i)/dt)^2 dt / |C'|`
/// at midpoints (second-order accurate), doubling the samples until two
/// estimates agree to the relative accuracy `rel_accuracy`; `rel_accuracy`
/// bounds the relative error of the result (up to the last doubling).
pub fn curvature_variation_energy(c: &Curve, rel_accuracy: f64) -> f64 {
    let spans = match c {
        Curve::Line(_) | Curve::Arc(_) => return 0.0,
        Curve::Nurbs(n) => n.breakpoints(),
    };
    spans
        .windows(2)
        .map(|w| span_energy(c, w[0], w[1], rel_accuracy))
        .sum()
}

fn span_energy(c: &Curve, a: f64, b: f64, rel: f64) -> f64 {
    let estimate = |n: usize| -> f64 {
        let dt = (b - a) / n as f64;
        let mut e = 0.0;
        let mut k0 = c.curvature(a);
        for i in 0..n {
            let t1 = a + dt * (i + 1) as f64;
            let k1 = c.curvature(t1);
            let speed = c.deriv1(t1 - 0.5 * dt).norm();
            if speed > 0.0 {
                let dk = (k1 - k0) / dt;
                e += dk * dk * dt / speed;
            }
            k0 = k1;
        }
        e
    };
    let mut n = 16;
    let mut last = estimate(n);
    for _ in 0..ENERGY_MAX_DOUBLINGS {
        n *= 2;
        let next = estimate(n);
        if math::abs(next - last) <= rel * next.max(last) {
            return next;
        }
        last = next;
    }
    last
}
