//! Fairness measures of a curve.

use super::{Curve, ParamCurve};
use crate::math;

/// Largest number of halvings of the subintervals in
/// [`curvature_variation_energy`] (2^8 Gauss rules per knot span).
const ENERGY_MAX_HALVINGS: u32 = 8;

// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const GL8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// The curvature variation energy `E = integral (dkappa/ds)^2 ds` (1/mm^3),
/// the fairness measure of seed 001 (the energy its proportional
/// coefficient minimises) and of the CAGD literature (Moreton and Sequin's
/// minimum variation curves). Zero for lines and circular arcs.
///
/// `E = integral (dkappa/dt)^2 / |C'| dt` by 8-point Gauss-Legendre rules
/// on each knot span (where the curve is smooth), `dkappa/dt` by central
/// differences at `1e-6` of the subinterval; subintervals are halved until
/// two estimates agree to `rel_accuracy`, which bounds the relative error
/// of the result (up to the last halving).
pub fn curvature_variation_energy(c: &Curve, rel_accuracy: f64) -> f64 {
    let spans = match c {
        Curve::Line(_) | Curve::Arc(_) => return 0.0,
        Curve::Nurbs(n) => n.breakpoints(),
    };
    spans
        .windows(2)
        .map(|w| span_energy(c, w[0], w[1], rel_accuracy))
        .fold(0.0, |a, b| a + b)
}

/// Step of the central difference of the curvature, relative to the
/// subinterval.
const DIFF_STEP: f64 = 1e-6;

fn gauss(c: &Curve, a: f64, b: f64) -> f64 {
    let (m, r) = (0.5 * (a + b), 0.5 * (b - a));
    let h = DIFF_STEP * (b - a);
    let f = |t: f64| {
        let speed = c.deriv1(t).norm();
        if speed > 0.0 {
            let dk = (c.curvature(t + h) - c.curvature(t - h)) / (2.0 * h);
            dk * dk / speed
        } else {
            0.0
        }
    };
    GL8.iter()
        .map(|&(x, w)| w * (f(m - r * x) + f(m + r * x)))
        .fold(0.0, |acc, v| acc + v)
        * r
}

fn span_energy(c: &Curve, a: f64, b: f64, rel: f64) -> f64 {
    let estimate = |n: usize| -> f64 {
        let dt = (b - a) / n as f64;
        (0..n)
            .map(|i| gauss(c, a + dt * i as f64, a + dt * (i + 1) as f64))
            .fold(0.0, |acc, v| acc + v)
    };
    let mut n = 1;
    let mut last = estimate(n);
    for _ in 0..ENERGY_MAX_HALVINGS {
        n *= 2;
        let next = estimate(n);
        if math::abs(next - last) <= rel * next.max(last) {
            return next;
        }
        last = next;
    }
    last
}
