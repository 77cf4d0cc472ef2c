//! A clamped cubic B-spline on one knot span: which span a parameter falls
//! in ([`span_of`]), the four basis functions there with their derivatives
//! (the crate's one basis, [`super::basis`], at degree 3), and the curve's
//! value and second derivative from the span's polynomial
//! ([`eval_in_span`]).
//!
//! The fit's normal equations ([`super::fit`]) and the bound of a fitted
//! curve ([`super::fit_bound`]) are both built from these, once per data
//! point or span, so they live apart from either.

use super::basis;
use super::fit::FIT_DEGREE;
use super::Vec3;

/// Index `s` of the knot span `u[s] <= t < u[s+1]` of a clamped cubic knot
/// vector for `count` control points (the last non-empty span at the end).
pub fn span_of(knots: &[f64], count: usize, t: f64) -> usize {
    if t >= knots[count] {
        let mut s = count - 1;
        while s > FIT_DEGREE && knots[s] >= knots[count] {
            s -= 1;
        }
        return s;
    }
    // First index in FIT_DEGREE+1..=count with knots[i] > t, minus one.
    let i = knots[FIT_DEGREE + 1..=count].partition_point(|&k| k <= t);
    FIT_DEGREE + i
}

/// Values, first and second derivatives of the four cubic basis functions
/// `N_{s-3..=s}` at `t` in span `s`, with `0/0 = 0`: the crate's one basis
/// ([`basis::ders_basis_funs`]: at degree 3, P&T A2.2 and eq. 2.9).
pub fn cubic_basis(knots: &[f64], s: usize, t: f64) -> [[f64; 4]; 3] {
    let d = basis::ders_basis_funs(knots, FIT_DEGREE, s, t, 2);
    let four = |row: &[f64; basis::BASIS_LEN]| [row[0], row[1], row[2], row[3]];
    [four(&d[0]), four(&d[1]), four(&d[2])]
}

/// Values of the four cubic basis functions `N_{s-3..=s}` at `t` in span
/// `s`: [`cubic_basis`]`(..)[0]` by P&T A2.2 ([`basis::basis_funs`]: 6
/// divisions instead of the 11 that the derivatives add; the data term of
/// every fit and the bound of every span evaluate it once per data point).
pub fn cubic_basis_values(knots: &[f64], s: usize, t: f64) -> [f64; 4] {
    let n = basis::basis_funs(knots, FIT_DEGREE, s, t);
    [n[0], n[1], n[2], n[3]]
}

/// Second derivatives of the four cubic basis functions `N_{s-3..=s}` at
/// both ends of the non-empty span `s` (`knots[s] < knots[s + 1]`):
/// [`cubic_basis`]`(knots, s, knots[s])[2]` and at `knots[s + 1]`, from the
/// second-difference control points of [`eval_in_span`]. With
/// `D_m = u_{s+m+1} - u_{s+m-2}`, `E_0 = u_{s+1} - u_{s-1}`,
/// `E_1 = u_{s+2} - u_s`: at the start `6 / (E_0 D_0)`,
/// `-6 / E_0 (1 / D_0 + 1 / D_1)`, `6 / (E_0 D_1)`, 0; at the end 0,
/// `6 / (E_1 D_1)`, `-6 / E_1 (1 / D_1 + 1 / D_2)`, `6 / (E_1 D_2)`.
/// `N''` is linear on the span, so these two give it everywhere.
pub fn cubic_basis_d2_at_ends(knots: &[f64], s: usize) -> ([f64; 4], [f64; 4]) {
    let u = knots;
    let d = |m: usize| u[s + m + 1] - u[s + m - 2];
    let (d0, d1, d2) = (d(0), d(1), d(2));
    let (e0, e1) = (u[s + 1] - u[s - 1], u[s + 2] - u[s]);
    let start = [
        6.0 / (e0 * d0),
        -6.0 / e0 * (1.0 / d0 + 1.0 / d1),
        6.0 / (e0 * d1),
        0.0,
    ];
    let end = [
        0.0,
        6.0 / (e1 * d1),
        -6.0 / e1 * (1.0 / d1 + 1.0 / d2),
        6.0 / (e1 * d2),
    ];
    (start, end)
}

/// Position and second derivative of the cubic B-spline (`knots`, `pts`)
/// at `t`, using the polynomial of span `s` (so at a knot the one-sided
/// value of that span). The second derivative is linear on the span: the
/// degree-1 B-spline of the second-difference control points (P&T eq.
/// 3.8 applied twice), `P1_j = 3 (P_{j+1} - P_j) / (u_{j+4} - u_{j+1})`,
/// `P2_j = 2 (P1_{j+1} - P1_j) / (u_{j+4} - u_{j+2})`,
/// `C'' = P2_{s-3} (u_{s+1} - t) / h + P2_{s-2} (t - u_s) / h`,
/// `h = u_{s+1} - u_s`. An empty span falls back to [`cubic_basis`].
pub fn eval_in_span(knots: &[f64], pts: &[Vec3], s: usize, t: f64) -> (Vec3, Vec3) {
    let u = knots;
    let h = u[s + 1] - u[s];
    if h.is_nan() || h <= 0.0 {
        let b = cubic_basis(knots, s, t);
        let mut c = Vec3::ZERO;
        let mut c2 = Vec3::ZERO;
        for k in 0..4 {
            let p = pts[s - 3 + k];
            c += p * b[0][k];
            c2 += p * b[2][k];
        }
        return (c, c2);
    }
    let b = cubic_basis_values(knots, s, t);
    let q = [pts[s - 3], pts[s - 2], pts[s - 1], pts[s]];
    let c = q[0] * b[0] + q[1] * b[1] + q[2] * b[2] + q[3] * b[3];
    // Every denominator spans the non-empty span s.
    let p1 = |j: usize| (q[j + 1] - q[j]) * (3.0 / (u[s + j + 1] - u[s + j - 2]));
    let (d0, d1, d2) = (p1(0), p1(1), p1(2));
    let a0 = (d1 - d0) * (2.0 / (u[s + 1] - u[s - 1]));
    let a1 = (d2 - d1) * (2.0 / (u[s + 2] - u[s]));
    let w = (t - u[s]) / h;
    (c, a0 * (1.0 - w) + a1 * w)
}
