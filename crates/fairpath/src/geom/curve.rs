//! The parametric-curve interface shared by lines, arcs and NURBS, with the
//! generic algorithms built on it: curvature, arc length, flattening.

use super::Vec3;
use crate::math;
use alloc::vec::Vec;

/// A parametric curve `C(t)`, `t` in [`ParamCurve::domain`], coordinates in mm.
pub trait ParamCurve {
    /// Parameter interval `(t0, t1)`.
    fn domain(&self) -> (f64, f64);
    /// Position `C(t)`.
    fn eval(&self, t: f64) -> Vec3;
    /// First derivative `C'(t)`.
    fn deriv1(&self, t: f64) -> Vec3;
    /// Second derivative `C''(t)`.
    fn deriv2(&self, t: f64) -> Vec3;
    /// `(C'(t), C''(t))`, the same values as [`ParamCurve::deriv1`] and
    /// [`ParamCurve::deriv2`]; curves that find both in one evaluation (a
    /// NURBS's basis derivatives) override it.
    fn derivs12(&self, t: f64) -> (Vec3, Vec3) {
        (self.deriv1(t), self.deriv2(t))
    }
    /// `(C(t), C'(t), C''(t))`, the same values as [`ParamCurve::eval`] and
    /// [`ParamCurve::derivs12`]; a polynomial spline finds all three in one
    /// evaluation of its basis (samplers that want a point and its frame).
    fn eval_derivs12(&self, t: f64) -> (Vec3, Vec3, Vec3) {
        let (d1, d2) = self.derivs12(t);
        (self.eval(t), d1, d2)
    }

    fn start(&self) -> Vec3 {
        self.eval(self.domain().0)
    }
    fn end(&self) -> Vec3 {
        self.eval(self.domain().1)
    }
    /// Curvature `|C' x C''| / |C'|^3` (1/mm); 0 where `C'` vanishes.
    fn curvature(&self, t: f64) -> f64 {
        let (d1, d2) = self.derivs12(t);
        curvature_from(d1, d2)
    }
    /// Curvature vector `kappa * N` (1/mm): the part of `C''` normal to
    /// `C'`, divided by `|C'|^2`. Equal curvature vectors on both sides of a
    /// joint with equal unit tangents make the joint G2.
    fn curvature_vector(&self, t: f64) -> Vec3 {
        let (d1, d2) = self.derivs12(t);
        curvature_vector_from(d1, d2)
    }
    /// Unit tangent, or `None` where the curve is singular.
    fn unit_tangent(&self, t: f64) -> Option<Vec3> {
        self.deriv1(t).normalized(0.0)
    }
    /// The parameters, domain ends included, between which the curve is
    /// one smooth (polynomial or rational) piece: a NURBS's distinct knots.
    /// Quadrature works interval by interval and flattening samples them:
    /// across knots a spline may turn or bulge between samples that see
    /// nothing of it (a control point displaced 0.2 mm on a clamped spline
    /// of 32 points lies between two of seven samples over the whole
    /// domain).
    fn breaks(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        alloc::vec![a, b]
    }
    /// The breaks strictly inside `(a, b)`, in order (what
    /// [`ParamCurve::breaks`] has there; a NURBS finds them by bisection of
    /// its knots, without listing all of them).
    fn breaks_within(&self, a: f64, b: f64) -> Vec<f64> {
        self.breaks()
            .into_iter()
            .filter(|&t| t > a && t < b)
            .collect()
    }
    /// The length over `[a, b]` (`a < b`) within `accuracy` mm from a
    /// closed form, where the curve has one (lines, arcs); `None`: the
    /// caller integrates `|C'|`.
    fn closed_length(&self, _a: f64, _b: f64, _accuracy: f64) -> Option<f64> {
        None
    }
    /// Whether `C'` is a polynomial of degree at most 2 in `t` between
    /// breaks (a non-rational B-spline of degree at most 3): three values
    /// of it then give it all over a break interval, and arc length is
    /// integrated from those ([`arc_length_between`]).
    fn quadratic_deriv1(&self) -> bool {
        false
    }
}

/// `C'` over one break interval `[u, v]` of a curve whose `C'` is a
/// polynomial of degree at most 2 there ([`ParamCurve::quadratic_deriv1`]),
/// as the Lagrange interpolant of three of its values inside the interval
/// (at a break a spline's derivative may jump, and the side a curve
/// evaluates there is its own): exact but for rounding, and about a fifth
/// of a B-spline basis evaluation per point.
struct QuadraticDeriv {
    u: f64,
    inv_h: f64,
    d: [Vec3; 3],
}

/// Where in `[0, 1]` of a break interval [`QuadraticDeriv`] samples `C'`.
const QUADRATIC_NODES: [f64; 3] = [0.125, 0.5, 0.875];

impl QuadraticDeriv {
    fn of<C: ParamCurve + ?Sized>(c: &C, u: f64, v: f64) -> QuadraticDeriv {
        let h = v - u;
        QuadraticDeriv {
            u,
            inv_h: 1.0 / h,
            d: QUADRATIC_NODES.map(|s| c.deriv1(u + s * h)),
        }
    }

    /// `C'(t)`.
    fn at(&self, t: f64) -> Vec3 {
        let [s0, s1, s2] = QUADRATIC_NODES;
        let s = (t - self.u) * self.inv_h;
        let l0 = (s - s1) * (s - s2) / ((s0 - s1) * (s0 - s2));
        let l1 = (s - s0) * (s - s2) / ((s1 - s0) * (s1 - s2));
        let l2 = (s - s0) * (s - s1) / ((s2 - s0) * (s2 - s1));
        self.d[0] * l0 + self.d[1] * l1 + self.d[2] * l2
    }
}

/// The intervals of a curve's smooth pieces within `[a, b]`, in order,
/// covering it, from its breaks strictly inside ([`ParamCurve::breaks_within`]).
fn smooth_intervals_from(a: f64, inner: Vec<f64>, b: f64) -> Vec<(f64, f64)> {
    let mut cuts: Vec<f64> = Vec::with_capacity(inner.len() + 2);
    cuts.push(a);
    cuts.extend(inner);
    cuts.push(b);
    cuts.windows(2).map(|w| (w[0], w[1])).collect()
}

/// Curvature from the first two derivatives.
pub fn curvature_from(d1: Vec3, d2: Vec3) -> f64 {
    let s = d1.norm();
    if s == 0.0 {
        return 0.0;
    }
    d1.cross(d2).norm() / (s * s * s)
}

/// Curvature vector `(C'' - (C''.T)T) / |C'|^2` from the first two derivatives.
pub fn curvature_vector_from(d1: Vec3, d2: Vec3) -> Vec3 {
    let s2 = d1.norm_sq();
    if s2 == 0.0 {
        return Vec3::ZERO;
    }
    (d2 - d1 * (d2.dot(d1) / s2)) / s2
}

// 5-point Gauss-Legendre nodes and weights on [-1, 1].
const GL5_X: [f64; 5] = [
    0.0,
    -0.538_469_310_105_683_1,
    0.538_469_310_105_683_1,
    -0.906_179_845_938_664,
    0.906_179_845_938_664,
];
const GL5_W: [f64; 5] = [
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
    0.236_926_885_056_189_1,
];

fn gl5(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let h = 0.5 * (b - a);
    let m = 0.5 * (a + b);
    let mut s = 0.0;
    for i in 0..5 {
        s += GL5_W[i] * f(m + h * GL5_X[i]);
    }
    s * h
}

/// Relative accuracy below which arc-length bisection stops: the rounding
/// of the sums of `|C'|` is a few ulps of the length, so asking a curve
/// 1e6 mm long for 1e-12 mm would bisect to the depth limit without ever
/// converging.
const LENGTH_ROUNDING_FLOOR: f64 = 64.0 * f64::EPSILON;

/// Most intervals the arc-length quadrature bisects into: a bound on the
/// work for curves whose derivative has a singularity the quadrature cannot
/// resolve (and on input with absurd coordinates). Smooth curves need a few
/// hundred at most.
const MAX_LENGTH_INTERVALS: u32 = 1 << 16;

/// Arc length of `c` over `[a, b]`, accurate to `accuracy` mm: adaptive
/// 5-point Gauss-Legendre quadrature of `|C'(t)|`, bisecting until the
/// whole-interval and two-halves estimates agree within the share of
/// `accuracy` that interval owns (or within `LENGTH_ROUNDING_FLOOR` of
/// the length). Bisection stops at a non-finite estimate (it would not
/// converge) and after `MAX_LENGTH_INTERVALS` intervals. A curve with a
/// [`ParamCurve::closed_length`] needs no quadrature.
///
/// Where `C'` is quadratic between breaks ([`ParamCurve::quadratic_deriv1`])
/// each break interval is integrated on its own, from three values of
/// `C'` (its Lagrange interpolant), with the share of `accuracy` its parameter
/// length owns.
pub fn arc_length_between<C: ParamCurve + ?Sized>(c: &C, a: f64, b: f64, accuracy: f64) -> f64 {
    if b > a {
        if let Some(length) = c.closed_length(a, b, accuracy) {
            return length;
        }
        if c.quadratic_deriv1() {
            let inner = c.breaks_within(a, b);
            let mut length = 0.0;
            let mut u = a;
            for v in inner.into_iter().chain(core::iter::once(b)) {
                let q = QuadraticDeriv::of(c, u, v);
                length += integrate(&|t| q.at(t).norm(), u, v, accuracy * (v - u) / (b - a));
                u = v;
            }
            return length;
        }
    }
    integrate_pieces(c, &|t| c.deriv1(t).norm(), a, b, accuracy)
}

/// [`integrate`] over each smooth piece of `c` within `[a, b]`
/// ([`ParamCurve::breaks`]), the accuracy shared by length of parameter.
fn integrate_pieces<C: ParamCurve + ?Sized>(
    c: &C,
    f: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    accuracy: f64,
) -> f64 {
    if b.partial_cmp(&a) != Some(core::cmp::Ordering::Greater) {
        return integrate(f, a, b, accuracy);
    }
    // A few knot intervals at a time: each is smooth inside, and the
    // halving test over a handful of them does not converge by accident as
    // it did over hundreds (`QUADRATURE_INTERVALS`).
    let inner = c.breaks_within(a, b);
    if inner.is_empty() {
        // One interval: the group below, without building the list (a plan
        // asks for the length of each stretch, most inside one knot span).
        return integrate(f, a, b, accuracy * (b - a) / (b - a));
    }
    let pieces = smooth_intervals_from(a, inner, b);
    pieces
        .chunks(QUADRATURE_INTERVALS)
        .map(|g| {
            let (u, v) = (g[0].0, g[g.len() - 1].1);
            integrate(f, u, v, accuracy * (v - u) / (b - a))
        })
        .sum()
}

/// Knot intervals integrated together by [`integrate_pieces`].
const QUADRATURE_INTERVALS: usize = 4;

/// `integral f(t) dt` over `[a, b]` by adaptive 5-point Gauss-Legendre,
/// halving an interval until its two halves agree with it within its share
/// of `accuracy` (or the rounding floor, the depth limit or the work limit
/// [`MAX_LENGTH_INTERVALS`]).
fn integrate(f: &impl Fn(f64) -> f64, a: f64, b: f64, accuracy: f64) -> f64 {
    fn rec(
        f: &impl Fn(f64) -> f64,
        (a, b): (f64, f64),
        whole: f64,
        acc: f64,
        depth: u32,
        budget: &mut u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let l = gl5(f, a, m);
        let r = gl5(f, m, b);
        let sum = l + r;
        let err = math::abs(sum - whole);
        let converged = err <= acc.max(LENGTH_ROUNDING_FLOOR * math::abs(sum));
        if depth == 0 || converged || !sum.is_finite() || *budget < 2 || m <= a || m >= b {
            return sum;
        }
        *budget -= 2;
        rec(f, (a, m), l, 0.5 * acc, depth - 1, budget)
            + rec(f, (m, b), r, 0.5 * acc, depth - 1, budget)
    }
    let whole = gl5(f, a, b);
    let mut budget = MAX_LENGTH_INTERVALS;
    rec(f, (a, b), whole, accuracy.max(0.0), 30, &mut budget)
}

/// Total curvature of the whole curve, `integral kappa ds` (the angle its
/// tangent turns through, radians, for a plane curve), accurate to
/// `accuracy` radians: `kappa |C'| = |C' x C''| / |C'|^2` integrated over
/// the parameter. Divided by the length it is the average curvature the
/// thesis reports (seed 003, Table 4-1).
pub fn total_curvature<C: ParamCurve + ?Sized>(c: &C, accuracy: f64) -> f64 {
    let (a, b) = c.domain();
    integrate_pieces(
        c,
        &|t| {
            let (d1, d2) = c.derivs12(t);
            let n2 = d1.dot(d1);
            if n2 > 0.0 {
                d1.cross(d2).norm() / n2
            } else {
                0.0
            }
        },
        a,
        b,
        accuracy,
    )
}

/// Arc length of the whole curve, accurate to `accuracy` mm.
pub fn arc_length<C: ParamCurve + ?Sized>(c: &C, accuracy: f64) -> f64 {
    let (a, b) = c.domain();
    arc_length_between(c, a, b, accuracy)
}

/// Parameters at which chords of `c` stay within `chord` mm of the curve.
/// A span is accepted when its chord error measured at seven interior
/// points, and the estimate `max|C''_n| dt^2 / 8` from the part of `C''`
/// normal to the tangent (exact for a parabola), are both within `chord`;
/// otherwise it is halved. Returns
/// increasing parameters from start to end, both included.
pub fn flatten_params<C: ParamCurve + ?Sized>(c: &C, chord: f64) -> Vec<f64> {
    let (a, b) = c.domain();
    flatten_params_between(c, a, b, chord)
}

/// Most spans [`flatten_params`] splits a curve into: a bound on time and
/// memory for curves no machine could run (a program whose coordinates
/// reach 1e100 mm would otherwise need 2^40 spans). Beyond it the last
/// spans are kept longer than the chord asks; any caller that needs the
/// chord bound verifies what it writes. A 10 m circle at a chord of 1 nm
/// needs 2e5 spans.
const MAX_FLATTEN_SPANS: usize = 1 << 20;

/// [`flatten_params`] over the parameter interval `[a, b]` of `c`: chords
/// within `chord` mm of the curve there, `a` and `b` included.
pub fn flatten_params_between<C: ParamCurve + ?Sized>(
    c: &C,
    a: f64,
    b: f64,
    chord: f64,
) -> Vec<f64> {
    let mut out = Vec::new();
    out.push(a);
    let mut budget = MAX_FLATTEN_SPANS;
    // The tests of a span sample its knots too: a spline's bulge between
    // knots could hide between seven samples over a span of many knot
    // intervals (a control point displaced 0.2 mm on a clamped spline of
    // 32 points did), while at the knots of its support a cubic moves by
    // 1/6, 2/3 and 1/6 of the displacement.
    let breaks: Vec<f64> = c.breaks_within(a, b);
    flatten_rec(c, (a, b), chord, 40, &mut budget, &breaks, &mut out);
    out
}

/// The interior breaks of `c` within `(t0, t1)`, from the sorted `breaks`.
fn breaks_within(breaks: &[f64], t0: f64, t1: f64) -> &[f64] {
    let lo = breaks.partition_point(|&t| t <= t0);
    let hi = breaks.partition_point(|&t| t < t1);
    &breaks[lo..hi.max(lo)]
}

fn chord_error<C: ParamCurve + ?Sized>(c: &C, t0: f64, t1: f64, knots: &[f64]) -> f64 {
    let p0 = c.eval(t0);
    let p1 = c.eval(t1);
    let mut e: f64 = 0.0;
    for k in 1..8 {
        let q = c.eval(t0 + (t1 - t0) * (k as f64 / 8.0));
        e = e.max(super::polyline::point_segment_distance(q, p0, p1));
    }
    for &t in knots {
        e = e.max(super::polyline::point_segment_distance(c.eval(t), p0, p1));
    }
    e
}

fn flatten_rec<C: ParamCurve + ?Sized>(
    c: &C,
    (t0, t1): (f64, f64),
    chord: f64,
    depth: u32,
    budget: &mut usize,
    breaks: &[f64],
    out: &mut Vec<f64>,
) {
    let dt = t1 - t0;
    let tm = 0.5 * (t0 + t1);
    let normal_d2 = |t: f64| {
        let (d1, d2) = c.derivs12(t);
        let s = d1.norm();
        if s > 0.0 {
            d1.cross(d2).norm() / s
        } else {
            d2.norm()
        }
    };
    let knots = breaks_within(breaks, t0, t1);
    let d2 = normal_d2(t0).max(normal_d2(tm)).max(normal_d2(t1));
    let est = d2 * dt * dt / 8.0;
    // A non-finite estimate (a curve whose evaluation overflows) does not
    // improve by halving: the span is taken as it is.
    let accept = |e: f64| e <= chord || !e.is_finite();
    let done = accept(est) && accept(chord_error(c, t0, t1, knots));
    if done || depth == 0 || *budget < 2 || tm <= t0 || tm >= t1 {
        out.push(t1);
    } else {
        *budget -= 2;
        flatten_rec(c, (t0, tm), chord, depth - 1, budget, knots, out);
        flatten_rec(c, (tm, t1), chord, depth - 1, budget, knots, out);
    }
}

#[cfg(test)]
mod tests {
    use super::{arc_length_between, integrate_pieces, ParamCurve};
    use crate::geom::{Curve, Nurbs, Vec3};
    use crate::seeded::Rng;

    /// The arc length of a polynomial B-spline of degree 1 to 3 from three
    /// values of `C'` per knot interval is the length integrated from `C'`
    /// itself, within the accuracy asked: random splines with simple,
    /// double and full knots (where `C'` jumps), over random sub-intervals.
    #[test]
    fn seeded_random_lengths_from_the_quadratic_derivative_are_the_lengths() {
        let mut rng = Rng(19);
        let mut checked = 0;
        for case in 0..600 {
            let degree = 1 + case % 3;
            let n = degree + 1 + rng.below(8);
            let scale = rng.decades(-2.0, 2.0);
            let points: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(rng.next(), rng.next(), 0.3 * rng.next()) * scale)
                .collect();
            // Clamped knots; interior knots at random, some repeated.
            let mut inner: Vec<f64> = (0..n - degree - 1).map(|_| rng.next()).collect();
            inner.sort_by(f64::total_cmp);
            if inner.len() >= 2 && case % 5 == 0 {
                inner[1] = inner[0];
            }
            let mut knots = vec![0.0; degree + 1];
            knots.extend(inner);
            knots.extend(vec![1.0; degree + 1]);
            let Ok(nurbs) = Nurbs::new(degree, knots, points, None) else {
                continue;
            };
            let c = Curve::from(nurbs);
            assert!(c.quadratic_deriv1());
            let (a, b) = {
                let (x, y) = (rng.next(), rng.next());
                (x.min(y), x.max(y))
            };
            if b <= a {
                continue;
            }
            let accuracy = 1e-9 * scale;
            let fast = arc_length_between(&c, a, b, accuracy);
            // Knot interval by knot interval, from `C'` itself (over a
            // group of intervals a kink of a spline with a double knot
            // can pass the halving test by accident).
            let mut cuts = vec![a];
            cuts.extend(c.breaks_within(a, b));
            cuts.push(b);
            let general: f64 = cuts
                .windows(2)
                .map(|w| {
                    let share = accuracy * (w[1] - w[0]) / (b - a);
                    integrate_pieces(&c, &|t| c.deriv1(t).norm(), w[0], w[1], share)
                })
                .sum();
            assert!(
                (fast - general).abs() <= 2.0 * accuracy + 1e-12 * general,
                "case {case}: {fast} against {general}"
            );
            checked += 1;
        }
        assert!(checked > 500, "{checked}");
    }

    /// A rational curve is integrated from `C'` itself.
    #[test]
    fn a_rational_curve_has_no_quadratic_derivative() {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let rational =
            Nurbs::new(2, knots.clone(), pts.clone(), Some(vec![1.0, 0.7, 1.0])).unwrap();
        let plain = Nurbs::new(2, knots, pts, None).unwrap();
        assert!(!rational.quadratic_deriv1());
        assert!(plain.quadratic_deriv1());
    }
}
