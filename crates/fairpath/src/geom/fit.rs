//! Least-squares cubic B-spline fitting of a polyline's vertices with a
//! fairness term, and a proven bound of the fit's distance from the
//! polyline (Piegl and Tiller, The NURBS Book, 2nd ed., section 9.4.1; seed
//! 002, Zhong et al., section 3).
//!
//! * Parameters: chord length (P&T eq. 9.5, seed eqs. 4-5), in mm, so that
//!   the fit runs at about unit speed and `|C''|` is about its curvature.
//! * Knots ([`averaged_knots`]): the averaging technique for approximation
//!   (P&T eqs. 9.68-9.69): interior knot `j` of `h` control points sits at
//!   the parameter interpolated at fractional data index `j n / (h - 3)`,
//!   so every span holds about the same number of data points (the seed's
//!   eq. 6 is the interpolation form, meant for `h = n + 1`).
//! * Control points ([`fit_cubic`]): minimise
//!   `sum_i |C(t_i) - Q_i|^2 + lambda * integral |C''(u)|^2 du`
//!   with the end control points fixed. Both terms are banded with half
//!   bandwidth 3 (a cubic has four non-zero basis functions per span), so
//!   the normal equations are solved by banded Cholesky in linear time
//!   ([`super::least_squares`]). The integral is exact: `C''` is linear on a
//!   span, so 2-point Gauss-Legendre integrates the products exactly.
//!   [`fit_cubic_weighted`] adds `mu * integral |C'''|^2` (constant on a
//!   span, also exact and banded): a weight on the change of curvature,
//!   which is what a jerk limit charges (not in the seed).
//! * Bound ([`span_errors`]): see its documentation.

use super::basis;
use super::least_squares::{BandedSpd, CholeskyBand};
use super::{point_segment_distance, Nurbs, Vec3};
use alloc::vec;
use alloc::vec::Vec;

/// Degree of the fitted B-splines.
pub const FIT_DEGREE: usize = 3;

/// How a fitted curve ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EndCondition {
    /// At the end data point, with whatever tangent the fit finds.
    Free,
    /// At the end data point, tangent to the given unit direction of travel
    /// and with zero curvature: the end control point and its two
    /// neighbours lie on the line through the end point along the
    /// direction, at the Greville abscissae (`P_1 = Q_0 + d xi_1`,
    /// `P_2 = Q_0 + d xi_2`, `xi_i = (u_{i+1} + u_{i+2} + u_{i+3}) / 3`), so a
    /// straight line along `d` is reproduced exactly (linear precision,
    /// P&T section 9.2.1). Joins a line along `d` with G2 continuity.
    Tangent(Vec3),
}

impl EndCondition {
    /// Control points fixed at this end besides the end point itself.
    fn extra_fixed(self) -> usize {
        match self {
            EndCondition::Free => 0,
            EndCondition::Tangent(_) => 2,
        }
    }
}

/// Why a fit could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitError {
    /// Fewer than two data points, parameters not increasing, or a knot
    /// vector that does not fit the data.
    BadInput,
    /// No control point is left free by the end conditions.
    TooFewControlPoints,
    /// The normal equations are singular (more control points than the data
    /// and the fairness term determine).
    Singular,
}

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
/// ([`basis::ders_basis_funs`], P&T A2.3) at degree 3.
pub fn cubic_basis(knots: &[f64], s: usize, t: f64) -> [[f64; 4]; 3] {
    let d = basis::ders_basis_funs(knots, FIT_DEGREE, s, t, 2);
    let four = |row: &[f64; basis::BASIS_LEN]| [row[0], row[1], row[2], row[3]];
    [four(&d[0]), four(&d[1]), four(&d[2])]
}

/// Values of the four cubic basis functions `N_{s-3..=s}` at `t` in span
/// `s`: [`cubic_basis`]`(..)[0]` by P&T A2.2 ([`basis::basis_funs`]: 6
/// divisions instead of the 30 or so of A2.3; the data term of every fit
/// and the bound of every span evaluate it once per data point).
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

/// Fits a clamped cubic B-spline with knot vector `knots` to the points
/// `pts` at parameters `params` (both ends exact, see [`EndCondition`]),
/// minimising the squared distances at the data plus `lambda` (mm^3) times
/// `integral |C''|^2`. Time linear in `pts.len() + control points`.
pub fn fit_cubic(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    start: EndCondition,
    end: EndCondition,
    lambda: f64,
) -> Result<Nurbs, FitError> {
    fit_cubic_weighted(pts, params, knots, start, end, lambda, 0.0)
}

/// [`fit_cubic`] plus `mu` (mm^5) times `integral |C'''|^2`: a term on the
/// rate of change of curvature, which a jerk-limited machine pays for
/// (`|dkappa/ds| v^3 <= J`), where `lambda` acts on the curvature itself.
/// `C'''` is constant on a span (the difference of `C''` at its ends over
/// its length), so the integral is exact. Still banded, still linear time.
pub fn fit_cubic_weighted(
    pts: &[Vec3],
    params: &[f64],
    knots: &[f64],
    start: EndCondition,
    end: EndCondition,
    lambda: f64,
    mu: f64,
) -> Result<Nurbs, FitError> {
    let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
        return Err(FitError::BadInput);
    };
    let system = FitSystem::new(params, knots, (start, end), (first, last), (lambda, mu))?;
    system.solve(pts)
}

/// The normal equations of a fit at fixed parameters, knots, end points,
/// end conditions and weights, factored once: [`FitSystem::solve`] then
/// fits any data at those parameters in linear time (one banded
/// back-substitution). The data term of every point has weight 1.
#[derive(Clone, Debug)]
pub struct FitSystem {
    knots: Vec<f64>,
    /// The control points, fixed ones set (end points and the tangent
    /// conditions), free ones zero.
    ctrl: Vec<Vec3>,
    /// Free control points: `lo..hi`.
    lo: usize,
    hi: usize,
    chol: CholeskyBand,
    /// The right-hand side's part from the fixed control points.
    fixed_rhs: Vec<Vec3>,
    /// Knot span and basis values at each data parameter.
    basis: Vec<(usize, [f64; 4])>,
}

impl FitSystem {
    /// The system of a clamped cubic fit with knot vector `knots` to data
    /// at `params`, from `ends.0` to `ends.1` exactly (with the end
    /// conditions `conds`), with weights `lambda` on `integral |C''|^2` and
    /// `mu` on `integral |C'''|^2` (see [`fit_cubic_weighted`]).
    pub fn new(
        params: &[f64],
        knots: &[f64],
        (start, end): (EndCondition, EndCondition),
        ends: (Vec3, Vec3),
        (lambda, mu): (f64, f64),
    ) -> Result<FitSystem, FitError> {
        let n = params.len();
        if n < 2 || knots.len() < 2 * (FIT_DEGREE + 1) {
            return Err(FitError::BadInput);
        }
        let h = knots.len() - FIT_DEGREE - 1;
        let (ua, ub) = (knots[FIT_DEGREE], knots[h]);
        if params[0] != ua || params[n - 1] != ub || ub <= ua {
            return Err(FitError::BadInput);
        }
        let lo = 1 + start.extra_fixed();
        let hi = h - 1 - end.extra_fixed();
        if lo >= hi {
            return Err(FitError::TooFewControlPoints);
        }
        // Fixed control points.
        let mut ctrl = vec![Vec3::ZERO; h];
        ctrl[0] = ends.0;
        ctrl[h - 1] = ends.1;
        let greville = |i: usize| (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0;
        if let EndCondition::Tangent(d) = start {
            for (i, c) in ctrl.iter_mut().enumerate().take(3).skip(1) {
                *c = ends.0 + d * (greville(i) - ua);
            }
        }
        if let EndCondition::Tangent(d) = end {
            for (i, c) in ctrl.iter_mut().enumerate().skip(h - 3).take(2) {
                *c = ends.1 - d * (ub - greville(i));
            }
        }
        let free = |i: usize| i >= lo && i < hi;
        let mut a = BandedSpd::zeros(hi - lo);
        let mut fixed_rhs = vec![Vec3::ZERO; hi - lo];
        let mut add_term = |s: usize, b: &[f64; 4], w: f64| {
            for j in 0..4 {
                let gj = s - 3 + j;
                if !free(gj) || b[j] == 0.0 {
                    continue;
                }
                for k in 0..4 {
                    let gk = s - 3 + k;
                    let v = w * b[j] * b[k];
                    if free(gk) {
                        if gk <= gj {
                            a.add(gj - lo, gk - lo, v);
                        }
                    } else {
                        fixed_rhs[gj - lo] -= ctrl[gk] * v;
                    }
                }
            }
        };
        // Data term.
        let mut basis = Vec::with_capacity(n);
        let mut s = FIT_DEGREE;
        for &t in params {
            while s + 1 < h && knots[s + 1] <= t {
                s += 1;
            }
            let b = cubic_basis_values(knots, s, t);
            add_term(s, &b, 1.0);
            basis.push((s, b));
        }
        // Non-empty spans with their length and `N''` at their ends.
        let spans = || {
            (FIT_DEGREE..h).filter_map(|s| {
                let len = knots[s + 1] - knots[s];
                (len > 0.0).then(|| (s, len, cubic_basis_d2_at_ends(knots, s)))
            })
        };
        // Fairness term, exact by 2-point Gauss-Legendre per span.
        if lambda > 0.0 {
            let g = 0.5 / crate::math::sqrt(3.0);
            for (s, len, (e0, e1)) in spans() {
                // N'' is linear on the span: the Gauss points from its ends.
                for x in [0.5 - g, 0.5 + g] {
                    let b: [f64; 4] = core::array::from_fn(|k| e0[k] * (1.0 - x) + e1[k] * x);
                    add_term(s, &b, lambda * 0.5 * len);
                }
            }
        }
        // Jerk term, exact: C''' is constant on each span.
        if mu > 0.0 {
            for (s, len, (e0, e1)) in spans() {
                let d3: [f64; 4] = core::array::from_fn(|k| (e1[k] - e0[k]) / len);
                add_term(s, &d3, mu * len);
            }
        }
        let chol = a.cholesky(PIVOT_REL).map_err(|_| FitError::Singular)?;
        Ok(FitSystem {
            knots: knots.to_vec(),
            ctrl,
            lo,
            hi,
            chol,
            fixed_rhs,
            basis,
        })
    }

    /// Points at the system's data parameters of `c`, a clamped cubic
    /// B-spline on the system's knots (from the basis values the system
    /// keeps: a dot product per point).
    pub fn points_at_data(&self, c: &Nurbs) -> Vec<Vec3> {
        self.basis
            .iter()
            .map(|(s, b)| {
                let q = &c.points[s - 3..=*s];
                q[0] * b[0] + q[1] * b[1] + q[2] * b[2] + q[3] * b[3]
            })
            .collect()
    }

    /// The fit to `pts` (one per parameter of the system; the end points
    /// and end conditions are the system's, whatever `pts` holds there).
    pub fn solve(&self, pts: &[Vec3]) -> Result<Nurbs, FitError> {
        if pts.len() != self.basis.len() {
            return Err(FitError::BadInput);
        }
        let (lo, hi) = (self.lo, self.hi);
        let mut rhs = self.fixed_rhs.clone();
        for (q, (s, b)) in pts.iter().zip(&self.basis) {
            for (j, &bj) in b.iter().enumerate() {
                let gj = s - 3 + j;
                if gj >= lo && gj < hi && bj != 0.0 {
                    rhs[gj - lo] += *q * bj;
                }
            }
        }
        self.chol.solve(&mut rhs);
        let mut ctrl = self.ctrl.clone();
        ctrl[lo..hi].copy_from_slice(&rhs);
        if ctrl.iter().any(|p| !p.is_finite()) {
            return Err(FitError::Singular);
        }
        Ok(Nurbs {
            degree: FIT_DEGREE,
            knots: self.knots.clone(),
            points: ctrl,
            weights: None,
        })
    }
}

/// A Cholesky pivot below this share of its diagonal entry means the normal
/// equations are singular to working precision (about `1e4` times the f64
/// epsilon: the fit would amplify rounding by more than that).
const PIVOT_REL: f64 = 1e-12;

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
    let multiple = |s: usize| knots[s] == knots[s - 1];
    for i in 0..n - 1 {
        let (t0, t1) = (params[i], params[i + 1]);
        while s + 1 < h && knots[s + 1] <= t0 {
            s += 1;
            if multiple(s) {
                at_a = eval_in_span(knots, &c.points, s, t0);
            }
        }
        // Data residual at t0.
        err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[i]));
        let mut a = t0;
        loop {
            let b = if s + 1 < h { knots[s + 1].min(t1) } else { t1 };
            let (ca, c2a) = at_a;
            let (cb, c2b) = eval_in_span(knots, &c.points, s, b);
            let sag = c2a.norm().max(c2b.norm()) * (b - a) * (b - a) / 8.0;
            let lo_g = i.saturating_sub(1);
            let hi_g = (i + 1).min(n - 2);
            let mut best = f64::INFINITY;
            for g in lo_g..=hi_g {
                best = best.min(seg_dist(g, ca).max(seg_dist(g, cb)));
            }
            let e = &mut err[s - FIT_DEGREE];
            *e = e.max(best + sag);
            at_a = (cb, c2b);
            if b >= t1 || s + 1 >= h {
                break;
            }
            a = b;
            s += 1;
            if multiple(s) {
                at_a = eval_in_span(knots, &c.points, s, a);
            }
        }
        if i == n - 2 {
            err[s - FIT_DEGREE] = err[s - FIT_DEGREE].max(at_a.0.dist(pts[n - 1]));
        }
    }
    err
}

/// `c` (a clamped cubic B-spline) with knots inserted (Boehm) so that no
/// knot span is longer than `max_span`: the same curve, with control
/// points every `max_span` or closer.
pub fn with_spans_at_most(c: &Nurbs, max_span: f64) -> Nurbs {
    let mut knots = c.knots.clone();
    let mut pts = c.points.clone();
    let mut s = FIT_DEGREE;
    while s + 1 < knots.len() - FIT_DEGREE {
        let (a, b) = (knots[s], knots[s + 1]);
        let len = b - a;
        if len > max_span {
            let k = crate::math::ceil(len / max_span) as usize;
            // Insert from the right so that span s keeps its start.
            for j in (1..k).rev() {
                let t = a + len * j as f64 / k as f64;
                insert_knot(&mut knots, &mut pts, s, t);
            }
            s += k;
        } else {
            s += 1;
        }
    }
    Nurbs {
        degree: FIT_DEGREE,
        knots,
        points: pts,
        weights: None,
    }
}

/// Inserts `t` once into the cubic B-spline (`knots`, `pts`), in span `s`
/// (`knots[s] <= t < knots[s + 1]`), by Boehm's algorithm (P&T A5.1 with
/// `r = 1`): the curve is unchanged.
fn insert_knot(knots: &mut Vec<f64>, pts: &mut Vec<Vec3>, s: usize, t: f64) {
    let p = FIT_DEGREE;
    let mut q = [Vec3::ZERO; FIT_DEGREE];
    for (k, qk) in q.iter_mut().enumerate() {
        let i = s - p + 1 + k;
        let alpha = (t - knots[i]) / (knots[i + p] - knots[i]);
        *qk = pts[i - 1] * (1.0 - alpha) + pts[i] * alpha;
    }
    // New points: pts[..s-p+1], q[0..p], pts[s..] (pts[s-p+1..s] replaced).
    pts.splice(s - p + 1..s, q);
    knots.insert(s + 1, t);
}

/// Cuts the clamped cubic B-spline `c` at every `max_spans`-th knot into
/// clamped pieces, each the same curve over its part of the domain (so they
/// join with C2 continuity), by knot insertion on a local window (time
/// linear in the size of `c`). Consecutive pieces share their joint point
/// bit for bit; the first starts and the last ends at `c`'s end points.
pub fn split_at_knots(c: &Nurbs, max_spans: usize) -> Vec<Nurbs> {
    let h = c.points.len();
    let spans = h - FIT_DEGREE;
    let max_spans = max_spans.max(1);
    if spans <= max_spans {
        return vec![c.clone()];
    }
    let u = &c.knots;
    let mut out: Vec<Nurbs> = Vec::new();
    let mut a = FIT_DEGREE;
    while a < h {
        let b = (a + max_spans).min(h);
        // Window: points a-3..=b (or ..h-1), knots a-3..=b+4 (or ..=h+3).
        let p_hi = if b < h { b } else { h - 1 };
        let mut pts: Vec<Vec3> = c.points[a - 3..=p_hi].to_vec();
        let mut knots: Vec<f64> = u[a - 3..=p_hi + 4].to_vec();
        let (ua, ub) = (u[a], u[b]);
        if a > FIT_DEGREE {
            // Local index of u[a] is 3; insert twice (multiplicity 3).
            insert_knot(&mut knots, &mut pts, 3, ua);
            insert_knot(&mut knots, &mut pts, 4, ua);
            // C(ua) is now local point 2: drop the two before it.
            pts.drain(..2);
            knots.drain(..2);
            knots[0] = ua;
        }
        if b < h {
            let sb = knots.iter().rposition(|&k| k == ub).unwrap();
            insert_knot(&mut knots, &mut pts, sb, ub);
            insert_knot(&mut knots, &mut pts, sb + 1, ub);
            // C(ub) is the point before the first of the three copies.
            let first = sb;
            pts.truncate(first);
            knots.truncate(first + 4);
            *knots.last_mut().unwrap() = ub;
        }
        if let Some(prev) = out.last() {
            // Identical arithmetic on identical data gives the same joint;
            // make it so regardless.
            pts[0] = *prev.points.last().unwrap();
        }
        out.push(Nurbs {
            degree: FIT_DEGREE,
            knots,
            points: pts,
            weights: None,
        });
        a = b;
    }
    out
}
