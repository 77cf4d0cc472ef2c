//! General-degree B-spline and NURBS curves (Piegl and Tiller, The NURBS
//! Book, 2nd ed.: A2.1 FindSpan, A2.3 DersBasisFuns, eq. 4.8 for rational
//! derivatives).

use super::basis::{self, BASIS_LEN};
use super::{arc::Arc, ParamCurve, Vec3};
use crate::math;
use alloc::vec;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// What evaluating a malformed curve gives.
const NAN_POINT: Vec3 = Vec3::new(f64::NAN, f64::NAN, f64::NAN);

/// A B-spline (weights `None`) or NURBS curve of any degree up to
/// [`Nurbs::MAX_DEGREE`], clamped or not.
///
/// Build it with [`Nurbs::new`], which checks the definition. The fields
/// are public for reading and for the library's own constructions; a curve
/// built as a struct literal must keep the same invariants
/// ([`Nurbs::validate`] checks them). Evaluating a curve that breaks them
/// gives NaN, never a panic.
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    pub degree: usize,
    /// Non-decreasing, `points.len() + degree + 1` values.
    pub knots: Vec<f64>,
    pub points: Vec<Vec3>,
    /// One positive weight per control point, or `None` for a polynomial
    /// B-spline.
    pub weights: Option<Vec<f64>>,
}

/// Why a NURBS definition is invalid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NurbsError {
    /// Degree 0 or above [`Nurbs::MAX_DEGREE`].
    #[error("degree {0} is not supported (1 to {max})", max = Nurbs::MAX_DEGREE)]
    BadDegree(usize),
    /// Fewer than `degree + 1` control points.
    #[error("{points} control points are too few for degree {degree} (at least degree + 1)")]
    TooFewPoints { points: usize, degree: usize },
    /// The knot vector does not have `points + degree + 1` values.
    #[error("{knots} knots given, {expected} expected (control points + degree + 1)")]
    KnotCount { knots: usize, expected: usize },
    /// `knots[index + 1] < knots[index]`.
    #[error("the knots decrease after knot {index}")]
    KnotsDecreasing { index: usize },
    /// The domain `[knots[degree], knots[points]]` is empty.
    #[error("the knots span no parameter range")]
    EmptyDomain,
    /// A weight count different from the point count, or a weight that is
    /// not positive and finite.
    #[error("weights must be one positive finite number per control point")]
    BadWeights,
    /// A knot, a coordinate or a weighted coordinate is NaN or infinite, or
    /// the domain is too wide for f64.
    #[error("a knot, coordinate or weighted coordinate is not a finite number")]
    NotFinite,
}

impl Nurbs {
    /// Highest degree supported: the evaluation keeps its basis functions
    /// in fixed arrays of `MAX_DEGREE + 1` values (no allocation per
    /// point). 7 covers the orders up to 8 of G6.2 and of LinuxCNC's G5.2
    /// ([`crate::controller::linuxcnc`]); tool paths use 2 and 3.
    pub const MAX_DEGREE: usize = basis::MAX_DEGREE;

    /// Checks the definition and builds the curve: degree 1 to
    /// [`Nurbs::MAX_DEGREE`], at least `degree + 1` points,
    /// `points + degree + 1` non-decreasing finite knots with a non-empty
    /// domain, finite coordinates, and (if given) one positive finite
    /// weight per point whose products with the coordinates (the
    /// homogeneous coordinates the evaluation sums) are finite.
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<Vec3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Nurbs, NurbsError> {
        check(degree, &knots, &points, weights.as_deref())?;
        Ok(Nurbs {
            degree,
            knots,
            points,
            weights,
        })
    }

    /// The checks of [`Nurbs::new`], for a curve built otherwise.
    pub fn validate(&self) -> Result<(), NurbsError> {
        check(
            self.degree,
            &self.knots,
            &self.points,
            self.weights.as_deref(),
        )
    }

    /// True when the lengths of the definition are consistent (what
    /// evaluation indexes by): the O(1) part of [`Nurbs::validate`].
    fn is_well_formed(&self) -> bool {
        (1..=Nurbs::MAX_DEGREE).contains(&self.degree)
            && self.points.len() > self.degree
            && self.knots.len() == self.points.len() + self.degree + 1
            && self
                .weights
                .as_ref()
                .is_none_or(|w| w.len() == self.points.len())
    }

    /// Piegl-Tiller A2.1: the span index `i` with `knots[i] <= t < knots[i+1]`
    /// (the last non-empty span at the domain end). For a curve that is not
    /// well formed (see [`Nurbs::validate`]), `degree`.
    pub fn find_span(&self, t: f64) -> usize {
        if !self.is_well_formed() {
            return self.degree;
        }
        let n = self.points.len() - 1;
        let p = self.degree;
        if t >= self.knots[n + 1] {
            // last non-empty span
            let mut i = n;
            while i > p && self.knots[i] >= self.knots[n + 1] {
                i -= 1;
            }
            return i;
        }
        if t <= self.knots[p] {
            let mut i = p;
            while i < n && self.knots[i + 1] <= self.knots[p] {
                i += 1;
            }
            return i;
        }
        let (mut lo, mut hi) = (p, n + 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if t < self.knots[mid] {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    }

    /// [`basis::basis_funs`] of this curve's knots and degree. Only for a
    /// well-formed curve (`degree <= MAX_DEGREE`).
    fn basis(&self, span: usize, t: f64) -> [f64; BASIS_LEN] {
        basis::basis_funs(&self.knots, self.degree, span, t)
    }

    /// Position at `t` (clamped to the domain), by A2.2 and A4.1; NaN for a
    /// curve that is not well formed.
    fn point_at(&self, t: f64) -> Vec3 {
        if !self.is_well_formed() {
            return NAN_POINT;
        }
        let (a, b) = self.domain();
        let t = clamp_to_domain(t, a, b);
        let p = self.degree;
        let span = self.find_span(t);
        let n = self.basis(span, t);
        let pts = &self.points[span - p..=span];
        match &self.weights {
            None => {
                let mut o = Vec3::ZERO;
                for (pt, &v) in pts.iter().zip(n.iter()) {
                    o += *pt * v;
                }
                o
            }
            Some(w) => {
                let mut o = Vec3::ZERO;
                let mut ws = 0.0;
                for ((pt, &v), &wi) in pts.iter().zip(n.iter()).zip(w[span - p..=span].iter()) {
                    o += *pt * (v * wi);
                    ws += v * wi;
                }
                o / ws
            }
        }
    }

    /// Upper bound of the length: the length of the control polygon.
    pub fn polygon_length(&self) -> f64 {
        self.points.windows(2).map(|w| w[0].dist(w[1])).sum()
    }

    /// [`basis::ders_basis_funs`] of this curve's knots and degree. Only
    /// for a well-formed curve (`degree <= MAX_DEGREE`).
    fn ders_basis(&self, span: usize, t: f64, nd: usize) -> [[f64; BASIS_LEN]; 3] {
        debug_assert!(self.is_well_formed(), "evaluating a malformed NURBS");
        basis::ders_basis_funs(&self.knots, self.degree, span, t, nd)
    }

    /// Position and first two derivatives at `t` (clamped to the domain).
    pub fn derivs(&self, t: f64) -> [Vec3; 3] {
        self.derivs_upto(t, 2)
    }

    /// Position and derivatives up to order `nd <= 2` (the others are
    /// zero); NaN for a curve that is not well formed.
    fn derivs_upto(&self, t: f64, nd: usize) -> [Vec3; 3] {
        if !self.is_well_formed() {
            return [NAN_POINT; 3];
        }
        let (a, b) = self.domain();
        let t = clamp_to_domain(t, a, b);
        let p = self.degree;
        let span = self.find_span(t);
        let ders = self.ders_basis(span, t, nd);
        match &self.weights {
            None => {
                let mut out = [Vec3::ZERO; 3];
                for (o, row) in out.iter_mut().zip(ders.iter()) {
                    for (pt, &n) in self.points[span - p..=span].iter().zip(row.iter()) {
                        *o += *pt * n;
                    }
                }
                out
            }
            Some(w) => {
                // Homogeneous derivatives A^(k), w^(k), then eq. 4.8.
                let mut aw = [Vec3::ZERO; 3];
                let mut ww = [0.0; 3];
                for (k, (awk, wwk)) in aw.iter_mut().zip(ww.iter_mut()).enumerate() {
                    for (j, dkj) in ders[k].iter().take(p + 1).enumerate() {
                        let i = span - p + j;
                        *awk += self.points[i] * (w[i] * dkj);
                        *wwk += w[i] * dkj;
                    }
                }
                let c0 = aw[0] / ww[0];
                let c1 = (aw[1] - c0 * ww[1]) / ww[0];
                let c2 = (aw[2] - c1 * (2.0 * ww[1]) - c0 * ww[2]) / ww[0];
                [c0, c1, c2]
            }
        }
    }

    /// Distinct knot values inside the domain, ends included: the breaks
    /// between polynomial pieces.
    pub fn breakpoints(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        let mut out: Vec<f64> = vec![a];
        for &k in &self.knots {
            if k > *out.last().unwrap() && k < b {
                out.push(k);
            }
        }
        out.push(b);
        out
    }

    /// A circular arc as a rational quadratic NURBS (Piegl and Tiller A7.1):
    /// pieces of at most 90 degrees, weights `cos(half piece angle)`.
    /// Exact for circular arcs (`r0 == r1`, no rise); for spiral or helical
    /// arcs use [`Nurbs::approximate`] instead.
    pub fn from_circular_arc(arc: &Arc) -> Nurbs {
        let n_pieces = math::ceil(arc.sweep / (0.5 * PI)).max(1.0) as usize;
        let dphi = arc.sweep / n_pieces as f64;
        let w1 = math::cos(0.5 * dphi);
        let v = arc.normal.cross(arc.u);
        let r = arc.r0;
        let mut points = Vec::with_capacity(2 * n_pieces + 1);
        let mut weights = Vec::with_capacity(2 * n_pieces + 1);
        let at = |a: f64| arc.center + (arc.u * math::cos(a) + v * math::sin(a)) * r;
        points.push(arc.eval(0.0));
        weights.push(1.0);
        for i in 0..n_pieces {
            let a0 = dphi * i as f64;
            let am = a0 + 0.5 * dphi;
            let a1 = a0 + dphi;
            // The middle control point is the intersection of the end
            // tangents: at distance r / cos(dphi/2) from the centre.
            points.push(arc.center + (at(am) - arc.center) / w1);
            weights.push(w1);
            points.push(if i + 1 == n_pieces {
                arc.eval(1.0)
            } else {
                at(a1)
            });
            weights.push(1.0);
        }
        let mut knots = vec![0.0, 0.0, 0.0];
        for i in 1..n_pieces {
            let k = i as f64 / n_pieces as f64;
            knots.push(k);
            knots.push(k);
        }
        knots.extend_from_slice(&[1.0, 1.0, 1.0]);
        Nurbs {
            degree: 2,
            knots,
            points,
            weights: Some(weights),
        }
    }

    /// A piecewise cubic (C1 Hermite, knots of multiplicity 3) approximation
    /// of any curve, within `accuracy` mm of it: spans are halved until the
    /// distance between curve and approximation, sampled at 7 points per span,
    /// is below `accuracy` (the Hermite error is O(h^4), so the sampled
    /// maximum is close to the true one).
    pub fn approximate<C: ParamCurve + ?Sized>(c: &C, accuracy: f64) -> Nurbs {
        let (a, b) = c.domain();
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let n0 = 4;
        let mut stack: Vec<(f64, f64, u32)> = (0..n0)
            .rev()
            .map(|i| {
                (
                    a + (b - a) * i as f64 / n0 as f64,
                    a + (b - a) * (i + 1) as f64 / n0 as f64,
                    0,
                )
            })
            .collect();
        while let Some((t0, t1, depth)) = stack.pop() {
            let bez = hermite(c, t0, t1);
            let mut err: f64 = 0.0;
            for i in 1..8 {
                let s = i as f64 / 8.0;
                err = err.max(bezier_eval(&bez, s).dist(c.eval(t0 + (t1 - t0) * s)));
            }
            if err <= accuracy || depth >= 30 {
                spans.push((t0, t1));
            } else {
                let tm = 0.5 * (t0 + t1);
                stack.push((tm, t1, depth + 1));
                stack.push((t0, tm, depth + 1));
            }
        }
        let mut points = Vec::with_capacity(3 * spans.len() + 1);
        let mut knots = vec![a; 4];
        for (i, &(t0, t1)) in spans.iter().enumerate() {
            let bez = hermite(c, t0, t1);
            if i == 0 {
                points.push(bez[0]);
            }
            points.extend_from_slice(&bez[1..]);
            if i + 1 < spans.len() {
                knots.extend_from_slice(&[t1, t1, t1]);
            }
        }
        knots.extend_from_slice(&[b; 4]);
        Nurbs {
            degree: 3,
            knots,
            points,
            weights: None,
        }
    }
}

/// `t` within `[a, b]`. Unlike `f64::clamp`, it does not panic when the
/// bounds are NaN or reversed (a curve built around [`Nurbs::new`]'s
/// checks): the result is then meaningless but evaluation goes on.
fn clamp_to_domain(t: f64, a: f64, b: f64) -> f64 {
    t.max(a).min(b)
}

/// The checks of [`Nurbs::new`].
fn check(
    degree: usize,
    knots: &[f64],
    points: &[Vec3],
    weights: Option<&[f64]>,
) -> Result<(), NurbsError> {
    if degree == 0 || degree > Nurbs::MAX_DEGREE {
        return Err(NurbsError::BadDegree(degree));
    }
    if points.len() < degree + 1 {
        return Err(NurbsError::TooFewPoints {
            points: points.len(),
            degree,
        });
    }
    let expected = points.len() + degree + 1;
    if knots.len() != expected {
        return Err(NurbsError::KnotCount {
            knots: knots.len(),
            expected,
        });
    }
    if knots.iter().any(|k| !k.is_finite()) || points.iter().any(|p| !p.is_finite()) {
        return Err(NurbsError::NotFinite);
    }
    if let Some(index) = knots.windows(2).position(|w| w[1] < w[0]) {
        return Err(NurbsError::KnotsDecreasing { index });
    }
    let (a, b) = (knots[degree], knots[points.len()]);
    if b <= a {
        return Err(NurbsError::EmptyDomain);
    }
    // Evaluation takes differences of knots (P&T A2.2): the whole range of
    // the knot vector must be a finite f64.
    if !(knots[knots.len() - 1] - knots[0]).is_finite() {
        return Err(NurbsError::NotFinite);
    }
    if let Some(w) = weights {
        if w.len() != points.len() || w.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(NurbsError::BadWeights);
        }
        if points.iter().zip(w).any(|(p, &wi)| !(*p * wi).is_finite()) {
            return Err(NurbsError::NotFinite);
        }
    }
    Ok(())
}

fn hermite<C: ParamCurve + ?Sized>(c: &C, t0: f64, t1: f64) -> [Vec3; 4] {
    let h = (t1 - t0) / 3.0;
    let p0 = c.eval(t0);
    let p3 = c.eval(t1);
    [p0, p0 + c.deriv1(t0) * h, p3 - c.deriv1(t1) * h, p3]
}

fn bezier_eval(b: &[Vec3; 4], s: f64) -> Vec3 {
    let m = 1.0 - s;
    b[0] * (m * m * m) + b[1] * (3.0 * m * m * s) + b[2] * (3.0 * m * s * s) + b[3] * (s * s * s)
}

impl ParamCurve for Nurbs {
    /// `(knots[degree], knots[points])`; NaN for a curve that is not well
    /// formed.
    fn domain(&self) -> (f64, f64) {
        if !self.is_well_formed() {
            return (f64::NAN, f64::NAN);
        }
        (self.knots[self.degree], self.knots[self.points.len()])
    }
    fn eval(&self, t: f64) -> Vec3 {
        if !self.is_well_formed() {
            return NAN_POINT;
        }
        // Clamped ends are the end control points exactly (no rounding from
        // the rational division).
        let (a, b) = self.domain();
        let p = self.degree;
        let n = self.points.len();
        if t <= a && self.knots[..=p].iter().all(|&k| k == a) {
            return self.points[0];
        }
        if t >= b && self.knots[n..].iter().all(|&k| k == b) {
            return self.points[n - 1];
        }
        self.point_at(t)
    }
    fn deriv1(&self, t: f64) -> Vec3 {
        self.derivs_upto(t, 1)[1]
    }
    fn deriv2(&self, t: f64) -> Vec3 {
        self.derivs(t)[2]
    }
    /// One basis evaluation for both (the first derivative's arithmetic
    /// does not depend on how many derivatives are asked for, so the values
    /// are those of [`Nurbs::deriv1`] to the bit).
    fn derivs12(&self, t: f64) -> (Vec3, Vec3) {
        let [_, d1, d2] = self.derivs(t);
        (d1, d2)
    }
    /// One basis evaluation for all three inside the domain of a
    /// polynomial (non-rational) curve: the basis values of
    /// [`basis::ders_basis_funs`] are [`basis::basis_funs`]'s to the bit
    /// and summed in the same order, so the point is [`Nurbs::eval`]'s.
    /// At the ends (where `eval` returns the end control points) and on
    /// rational curves, `eval` and [`ParamCurve::derivs12`].
    fn eval_derivs12(&self, t: f64) -> (Vec3, Vec3, Vec3) {
        let (a, b) = self.domain();
        if self.weights.is_none() && a < t && t < b {
            let [p, d1, d2] = self.derivs(t);
            return (p, d1, d2);
        }
        let (d1, d2) = self.derivs12(t);
        (self.eval(t), d1, d2)
    }
    fn curvature(&self, t: f64) -> f64 {
        let [_, d1, d2] = self.derivs(t);
        super::curvature_from(d1, d2)
    }
    fn curvature_vector(&self, t: f64) -> Vec3 {
        let [_, d1, d2] = self.derivs(t);
        super::curvature_vector_from(d1, d2)
    }
    /// Non-rational, of degree at most 3.
    fn quadratic_deriv1(&self) -> bool {
        self.weights.is_none() && self.degree <= 3
    }
    /// The distinct knots in the domain ([`Nurbs::breakpoints`]).
    fn breaks(&self) -> Vec<f64> {
        self.breakpoints()
    }
    fn breaks_within(&self, a: f64, b: f64) -> Vec<f64> {
        let (lo, hi) = self.domain();
        let (a, b) = (a.max(lo), b.min(hi));
        let from = self.knots.partition_point(|&k| k <= a);
        let mut out: Vec<f64> = Vec::new();
        for &k in &self.knots[from..] {
            if k >= b {
                break;
            }
            if out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }
}
