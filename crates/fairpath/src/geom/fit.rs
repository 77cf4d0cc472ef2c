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
//!
//! This file holds the fit itself: the end conditions, the normal
//! equations and their solution. The other steps are in files private to
//! `geom` and re-exported here: the parameters and knots in
//! `fit_knots.rs`, the cubic basis on one knot span in `cubic_span.rs`, the
//! bound in `fit_bound.rs`, and knot insertion (shorter spans, cutting at
//! knots) in `knot_insertion.rs`.

pub use super::cubic_span::{
    cubic_basis, cubic_basis_d2_at_ends, cubic_basis_values, eval_in_span, span_of,
};
pub use super::fit_bound::{span_errors, span_errors_within};
pub use super::fit_knots::{averaged_knots, chord_params};
pub use super::knot_insertion::{split_at_knots, with_spans_at_most};

use super::least_squares::{BandedSpd, CholeskyBand};
use super::{Nurbs, Vec3};
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
    /// The start point, which the system solves relative to (see
    /// [`FitData`]).
    origin: Vec3,
}

/// The part of a fit's normal equations that does not depend on the
/// weights: the fixed control points, the basis at the data parameters and
/// the data term (the sum over the data points, most of a fit's cost).
/// [`FitData::system`] adds the weighted fairness terms and factors, so a
/// fit tried at several weights on the same parameters and knots (the
/// raises of the weights, the relaxation's lowered weights) builds this
/// once. The terms are summed in the order of [`FitSystem::new`], so the
/// system is the same to the bit.
#[derive(Clone, Debug)]
pub struct FitData {
    knots: Vec<f64>,
    ctrl: Vec<Vec3>,
    lo: usize,
    hi: usize,
    /// The data term.
    a: BandedSpd,
    /// The data term's part of the right-hand side from the fixed control
    /// points.
    fixed_rhs: Vec<Vec3>,
    basis: Vec<(usize, [f64; 4])>,
    /// The start point: the right-hand sides hold the data and the fixed
    /// control points relative to it, and the solution is shifted back.
    /// The same least-squares problem (the basis is a partition of unity
    /// and the fairness terms vanish on constants), but a coordinate that
    /// every point of the data shares is then exactly 0 in every sum and
    /// comes out as that coordinate to the bit: a fit of a pass in the
    /// plane `Y = 36.449` stays in it, where solving the absolute
    /// coordinates left its control points up to 4e-8 mm off the plane
    /// and the writer turned its arcs into helices (LinuxCNC's
    /// `blur_torus.ngc`).
    origin: Vec3,
}

/// A non-empty knot span: its index, its length and `N''` of its four
/// basis functions at its ends.
type SpanD2 = (usize, f64, ([f64; 4], [f64; 4]));

/// Adds `w` times the outer product of the basis values `b` of span `s`
/// to the normal equations: to `a` where both control points are free
/// (`lo..hi`), to `fixed_rhs` (the fixed point's pull) where one is fixed.
#[inline(always)]
fn add_term(
    (a, fixed_rhs): (&mut BandedSpd, &mut [Vec3]),
    ctrl: &[Vec3],
    (lo, hi): (usize, usize),
    s: usize,
    b: &[f64; 4],
    w: f64,
) {
    // All four control points free (every span but those next to the
    // ends): the same sums without the checks.
    if s - 3 >= lo && s < hi {
        a.add_outer4(s - 3 - lo, b, w);
        return;
    }
    let free = |i: usize| i >= lo && i < hi;
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
}

impl FitData {
    /// The data part of the system of a clamped cubic fit with knot vector
    /// `knots` to data at `params`, from `ends.0` to `ends.1` exactly (with
    /// the end conditions `conds`): [`FitSystem::new`] without its weights.
    pub fn new(
        params: &[f64],
        knots: &[f64],
        (start, end): (EndCondition, EndCondition),
        ends: (Vec3, Vec3),
    ) -> Result<FitData, FitError> {
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
        let origin = ends.0;
        let rel: Vec<Vec3> = ctrl.iter().map(|&c| c - origin).collect();
        let mut a = BandedSpd::zeros(hi - lo);
        let mut fixed_rhs = vec![Vec3::ZERO; hi - lo];
        // Data term.
        let mut basis = Vec::with_capacity(n);
        let mut s = FIT_DEGREE;
        for &t in params {
            while s + 1 < h && knots[s + 1] <= t {
                s += 1;
            }
            let b = cubic_basis_values(knots, s, t);
            add_term((&mut a, &mut fixed_rhs), &rel, (lo, hi), s, &b, 1.0);
            basis.push((s, b));
        }
        Ok(FitData {
            knots: knots.to_vec(),
            ctrl,
            lo,
            hi,
            a,
            fixed_rhs,
            basis,
            origin,
        })
    }

    /// The knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The factored system with weights `lambda` on `integral |C''|^2` and
    /// `mu` on `integral |C'''|^2` (see [`fit_cubic_weighted`]).
    pub fn system(&self, weights: (f64, f64)) -> Result<FitSystem, FitError> {
        self.clone().into_system(weights)
    }

    /// [`FitData::system`], consuming the data part.
    pub fn into_system(self, (lambda, mu): (f64, f64)) -> Result<FitSystem, FitError> {
        let FitData {
            knots,
            ctrl,
            lo,
            hi,
            mut a,
            mut fixed_rhs,
            basis,
            origin,
        } = self;
        let h = ctrl.len();
        let rel: Vec<Vec3> = ctrl.iter().map(|&c| c - origin).collect();
        let u = &knots;
        // Non-empty spans with their length and `N''` at their ends (once,
        // for both terms).
        let spans: Vec<SpanD2> = if lambda > 0.0 || mu > 0.0 {
            (FIT_DEGREE..h)
                .filter_map(|s| {
                    let len = u[s + 1] - u[s];
                    (len > 0.0).then(|| (s, len, cubic_basis_d2_at_ends(u, s)))
                })
                .collect()
        } else {
            Vec::new()
        };
        let spans = || spans.iter().copied();
        // Fairness term, exact by 2-point Gauss-Legendre per span.
        if lambda > 0.0 {
            let g = 0.5 / crate::math::sqrt(3.0);
            for (s, len, (e0, e1)) in spans() {
                // N'' is linear on the span: the Gauss points from its ends.
                for x in [0.5 - g, 0.5 + g] {
                    let b: [f64; 4] = core::array::from_fn(|k| e0[k] * (1.0 - x) + e1[k] * x);
                    add_term(
                        (&mut a, &mut fixed_rhs),
                        &rel,
                        (lo, hi),
                        s,
                        &b,
                        lambda * 0.5 * len,
                    );
                }
            }
        }
        // Jerk term, exact: C''' is constant on each span.
        if mu > 0.0 {
            for (s, len, (e0, e1)) in spans() {
                let d3: [f64; 4] = core::array::from_fn(|k| (e1[k] - e0[k]) / len);
                add_term((&mut a, &mut fixed_rhs), &rel, (lo, hi), s, &d3, mu * len);
            }
        }
        let chol = a.cholesky(PIVOT_REL).map_err(|_| FitError::Singular)?;
        Ok(FitSystem {
            knots,
            ctrl,
            lo,
            hi,
            chol,
            fixed_rhs,
            basis,
            origin,
        })
    }
}

impl FitSystem {
    /// The system of a clamped cubic fit with knot vector `knots` to data
    /// at `params`, from `ends.0` to `ends.1` exactly (with the end
    /// conditions `conds`), with weights `lambda` on `integral |C''|^2` and
    /// `mu` on `integral |C'''|^2` (see [`fit_cubic_weighted`]).
    pub fn new(
        params: &[f64],
        knots: &[f64],
        conds: (EndCondition, EndCondition),
        ends: (Vec3, Vec3),
        weights: (f64, f64),
    ) -> Result<FitSystem, FitError> {
        FitData::new(params, knots, conds, ends)?.into_system(weights)
    }

    /// Points at the system's data parameters of `c`, a clamped cubic
    /// B-spline on the system's knots (from the basis values the system
    /// keeps: a dot product per point).
    pub fn points_at_data(&self, c: &Nurbs) -> Vec<Vec3> {
        let mut out = Vec::new();
        self.points_at_data_into(&c.points, &mut out);
        out
    }

    /// [`FitSystem::points_at_data`] of the control points `ctrl`, into
    /// `out` (its contents replaced).
    pub fn points_at_data_into(&self, ctrl: &[Vec3], out: &mut Vec<Vec3>) {
        out.clear();
        out.extend(self.basis.iter().map(|(s, b)| {
            let q = &ctrl[s - 3..=*s];
            q[0] * b[0] + q[1] * b[1] + q[2] * b[2] + q[3] * b[3]
        }));
    }

    /// The control points of [`FitSystem::solve`] into `ctrl`, with `rhs`
    /// as room for the right-hand side (both reused by a caller that
    /// solves many times: the relaxation's steps).
    pub fn solve_into(
        &self,
        pts: &[Vec3],
        rhs: &mut Vec<Vec3>,
        ctrl: &mut Vec<Vec3>,
    ) -> Result<(), FitError> {
        if pts.len() != self.basis.len() {
            return Err(FitError::BadInput);
        }
        let (lo, hi) = (self.lo, self.hi);
        rhs.clear();
        rhs.extend_from_slice(&self.fixed_rhs);
        for (q, (s, b)) in pts.iter().zip(&self.basis) {
            for (j, &bj) in b.iter().enumerate() {
                let gj = s - 3 + j;
                if gj >= lo && gj < hi && bj != 0.0 {
                    rhs[gj - lo] += (*q - self.origin) * bj;
                }
            }
        }
        self.chol.solve(rhs);
        ctrl.clear();
        ctrl.extend_from_slice(&self.ctrl);
        for (c, r) in ctrl[lo..hi].iter_mut().zip(rhs.iter()) {
            *c = *r + self.origin;
        }
        if ctrl.iter().any(|p| !p.is_finite()) {
            return Err(FitError::Singular);
        }
        Ok(())
    }

    /// The curve of the system's knots with control points `ctrl`.
    pub fn curve(&self, ctrl: Vec<Vec3>) -> Nurbs {
        Nurbs {
            degree: FIT_DEGREE,
            knots: self.knots.clone(),
            points: ctrl,
            weights: None,
        }
    }

    /// The fit to `pts` (one per parameter of the system; the end points
    /// and end conditions are the system's, whatever `pts` holds there).
    pub fn solve(&self, pts: &[Vec3]) -> Result<Nurbs, FitError> {
        let (mut rhs, mut ctrl) = (Vec::new(), Vec::new());
        self.solve_into(pts, &mut rhs, &mut ctrl)?;
        Ok(self.curve(ctrl))
    }
}

/// A Cholesky pivot below this share of its diagonal entry means the normal
/// equations are singular to working precision (about `1e4` times the f64
/// epsilon: the fit would amplify rounding by more than that).
const PIVOT_REL: f64 = 1e-12;
