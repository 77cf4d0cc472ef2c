//! The parameters and the knot vector of a fit ([`super::fit`]):
//! chord-length parameters of the data points ([`chord_params`]) and
//! averaged knots ([`averaged_knots`]), with clamped uniform knots as their
//! fallback; the module documentation of [`super::fit`] gives the formulas
//! and their sources.
//!
//! They depend on the data only, not on the fit's weights or end
//! conditions, so they are chosen before the fit and kept apart from it.

use super::fit::FIT_DEGREE;
use super::Vec3;
use alloc::vec;
use alloc::vec::Vec;

/// Chord-length parameters: `t_0 = 0`, `t_i = t_{i-1} + |Q_i - Q_{i-1}|` (mm).
pub fn chord_params(pts: &[Vec3]) -> Vec<f64> {
    let mut t = Vec::with_capacity(pts.len());
    let mut s = 0.0;
    t.push(0.0);
    for w in pts.windows(2) {
        s += w[0].dist(w[1]);
        t.push(s);
    }
    t
}

/// Clamped knot vector of `count` control points for data at `params`
/// (P&T eqs. 9.68-9.69, in the form given in the module documentation).
/// `count >= 4`; more control points than data points is allowed (the
/// fairness term then determines the fit).
pub fn averaged_knots(params: &[f64], count: usize) -> Vec<f64> {
    let n = params.len() - 1;
    let (a, b) = (params[0], params[n]);
    let spans = count - FIT_DEGREE;
    let mut u = Vec::with_capacity(count + FIT_DEGREE + 1);
    u.extend_from_slice(&[a; FIT_DEGREE + 1]);
    for j in 1..spans {
        let f = (j * n) as f64 / spans as f64;
        let i = (f as usize).min(n - 1);
        let alpha = f - i as f64;
        let k = params[i] + alpha * (params[i + 1] - params[i]);
        // Strictly inside the domain and increasing.
        if k > *u.last().unwrap() && k < b {
            u.push(k);
        } else {
            return uniform_knots(a, b, count);
        }
    }
    u.extend_from_slice(&[b; FIT_DEGREE + 1]);
    u
}

/// Clamped uniform knots on `[a, b]` (a fallback when the data parameters
/// leave no room for distinct averaged knots).
fn uniform_knots(a: f64, b: f64, count: usize) -> Vec<f64> {
    let spans = count - FIT_DEGREE;
    let mut u = vec![a; FIT_DEGREE + 1];
    for j in 1..spans {
        u.push(a + (b - a) * j as f64 / spans as f64);
    }
    u.extend_from_slice(&[b; FIT_DEGREE + 1]);
    u
}
