//! A sure bound of the distance from the faired curve to the original
//! **curve**, with the original's points matched by projection instead of
//! by equal parameter (ours, beyond the thesis).
//!
//! Why: the thesis measures the tube by the difference spline
//! `D(t) = P_cur(t) - P_orig(t)` (eq. 2-16, [`super::tube`]), the distance
//! between points of equal parameter. That is at least the distance from
//! the curve to the original path, and often much more: where a bend
//! tightens or widens, its points slide along the path, and the equal-
//! parameter distance counts the slide as deviation. The project's
//! tolerance is the distance to the path (every point of the output within
//! `R` of the original), so the slide is free; on the thesis' square
//! (docs/thesis-cases.md) a global optimiser that is allowed it finds
//! several times the gain of one that is not at R = 0.025 mm
//! (docs/tuning.md, "sliding tube").
//!
//! The bound: for any function `phi`, `dist(C(u), O) <= |C(u) - O(phi(u))|`.
//! On a span `[a, b]` of the curve `C`, `phi` is the straight line from
//! `phi(a)` to `phi(b)`, the parameters of the original's points nearest
//! `C(a)` and `C(b)` (Newton's method from `a` and `b`, keeping the
//! nearest point it visits, `a` and `b` themselves included). Split where
//! `phi` crosses the original's knots, each piece of `C(u) - O(phi(u))` is
//! one cubic polynomial in `u` (`O` is one on each of its spans and `phi`
//! is linear), whose Bezier points (both curves restricted to the piece by
//! blossoming) bound it by the convex hull, halved until within the
//! tolerance as [`super::tube::deviation_bound_on`] does. The span's
//! bound is the smaller of that and the equal-parameter bound, both sure.
//! Non-rational cubics only (the thesis' curves); other curves keep the
//! equal-parameter bound.

use super::spans::Span;
use super::spans::{bezier_of_span, bezier_point, Basis};
use super::tube::{deviation_bound_on, pieces_bound};
use crate::geom::cubic_span::span_of;
use crate::geom::Vec3;
use crate::math;
use alloc::vec::Vec;

/// Newton steps of one projection (ours): a curve faired inside a tube
/// stays within a few tube radii of the original, so the nearest point's
/// parameter is close to the equal one and a few steps reach it; any
/// parameter gives a sure bound, the nearest only a tighter one.
pub const PROJECTION_STEPS: usize = 6;

/// Deepest halving of a span's stretches in the sliding bound (ours): the
/// slide along the path varies along a span, and a straight match of a
/// long span's ends leaves the middle's slide as distance, so stretches
/// are matched at their ends and halved where loose; below 2^-8 of a span
/// the pieces are halved as Beziers instead (still a sure bound).
pub const MAX_SLIDE_DEPTH: u32 = 8;

/// Share of the bound's tolerance that a projection stops within (ours):
/// the matching's error adds to the bound, so it takes a small part.
pub const PROJECTION_SHARE: f64 = 0.1;

/// How the fairing measures the distance from the curve to the original.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum TubeMeasure {
    /// Between points of equal parameter: the difference spline of the
    /// thesis (eq. 2-16).
    #[default]
    EqualParameter,
    /// To the original curve, its points matched by projection (this
    /// module): the project's tolerance, which lets a bend's points slide
    /// along the path.
    Sliding,
}

/// The blossom `f(t1, t2, t3)` of the cubic Bezier `b` (de Casteljau with
/// one argument per level).
fn blossom(b: &[Vec3; 4], t: [f64; 3]) -> Vec3 {
    let mut d = *b;
    for (level, &tk) in t.iter().enumerate() {
        for i in 0..3 - level {
            d[i] = d[i].lerp(d[i + 1], tk);
        }
    }
    d[0]
}

/// The Bezier points of `b` restricted to `[t0, t1]` (local parameters).
fn restrict(b: &[Vec3; 4], t0: f64, t1: f64) -> [Vec3; 4] {
    [
        blossom(b, [t0, t0, t0]),
        blossom(b, [t0, t0, t1]),
        blossom(b, [t0, t1, t1]),
        blossom(b, [t1, t1, t1]),
    ]
}

/// The original curve (control points `pts` on a clamped, non-rational
/// cubic `basis`) as a function of the global parameter, its Bezier spans
/// made once: every distance the sliding tube measures projects onto it.
pub struct Original<'a> {
    pub(super) basis: &'a Basis<'a>,
    pub(super) pts: &'a [Vec3],
    /// Bezier points of each non-empty span, by knot index.
    beziers: Vec<[Vec3; 4]>,
}

impl<'a> Original<'a> {
    /// The original `pts` on `basis`; `None` unless a non-rational cubic
    /// (the sliding tube's curves).
    pub fn new(basis: &'a Basis<'a>, pts: &'a [Vec3]) -> Option<Original<'a>> {
        if basis.degree != 3 || basis.weights.is_some() {
            return None;
        }
        let mut beziers = alloc::vec![[Vec3::ZERO; 4]; pts.len()];
        for s in super::spans::nonempty_spans(basis, pts.len()) {
            beziers[s] = bezier_of_span(basis.knots, pts, s);
        }
        Some(Original {
            basis,
            pts,
            beziers,
        })
    }
}

impl Original<'_> {
    pub(super) fn domain(&self) -> (f64, f64) {
        let u = self.basis.knots;
        (u[self.basis.degree], u[self.pts.len()])
    }

    /// Span of `t` and its Bezier points, with the span's knots.
    pub(super) fn span(&self, t: f64) -> (usize, [Vec3; 4], f64, f64) {
        let s = span_of(self.basis.knots, self.pts.len(), t);
        let u = self.basis.knots;
        (s, self.beziers[s], u[s], u[s + 1])
    }

    /// The point and first two derivatives (in the global parameter).
    pub(super) fn derivs(&self, t: f64) -> (Vec3, Vec3, Vec3) {
        let (_, b, a, e) = self.span(t);
        let h = e - a;
        let tau = ((t - a) / h).clamp(0.0, 1.0);
        let (d1, d2) = super::spans::bezier_derivatives(&b, tau);
        (bezier_point(&b, tau), d1 * (1.0 / h), d2 * (1.0 / (h * h)))
    }

    /// The parameter of a point of the original near `p`, starting at `t`,
    /// and its distance from `p`: the nearest point that Newton's method
    /// visits (`t` included) within the domain, stopping once a step moves
    /// the point by at most `tol` mm (any parameter bounds the distance
    /// from above; the nearest one only tightens it).
    pub(super) fn project(&self, p: Vec3, t: f64, tol: f64) -> (f64, f64) {
        let (lo, hi) = self.domain();
        let mut t = t.clamp(lo, hi);
        let mut best = (f64::INFINITY, t);
        for _ in 0..=PROJECTION_STEPS {
            let (q, d1, d2) = self.derivs(t);
            let r = q - p;
            let d = r.norm();
            if d < best.0 {
                best = (d, t);
            }
            let f = r.dot(d1);
            let df = d1.dot(d1) + r.dot(d2);
            if df.is_nan() || df <= 0.0 {
                break;
            }
            let next = (t - f / df).clamp(lo, hi);
            if math::abs(next - t) * d1.norm() <= tol {
                // The point moves by at most `tol`: take its distance as
                // found (first order), bounded by the sure check.
                break;
            }
            t = next;
        }
        (best.1, best.0)
    }
}

/// A sure bound of the distance from the spans `spans` of the cubic
/// B-spline `cur` to the curve `orig` (the same clamped, non-rational
/// `basis`), within about `tol` mm of the largest distance this matching
/// gives (see the module documentation); for other curves, the
/// equal-parameter bound [`deviation_bound_on`].
pub fn sliding_bound_on(
    cur: &[Vec3],
    original: Option<&Original>,
    diff: &[Vec3],
    basis: &Basis,
    spans: &[usize],
    tol: f64,
) -> f64 {
    let Some(o) = original else {
        return deviation_bound_on(diff, basis, spans, tol);
    };
    let u = basis.knots;
    let mut bound: f64 = 0.0;
    for &s in spans {
        let c = bezier_of_span(u, cur, s);
        let slid = span_bound(o, &c, (u[s], u[s + 1]), tol);
        let equal = if slid > tol {
            deviation_bound_on(diff, basis, &[s], tol)
        } else {
            slid
        };
        bound = bound.max(slid.min(equal));
    }
    bound
}

/// The bound over one span of the curve (Bezier points `c`, global
/// parameters `ab`): branch and bound over stretches of the span, each
/// matched linearly between its ends' nearest points; a stretch whose
/// hull bound is not within `tol` of the largest distance found is split
/// at its middle, whose nearest point is found, down to
/// [`MAX_SLIDE_DEPTH`] (then its pieces are halved as Beziers).
fn span_bound(o: &Original, c: &[Vec3; 4], ab: (f64, f64), tol: f64) -> f64 {
    let (a, b) = ab;
    let ptol = tol * PROJECTION_SHARE;
    let (ta, da) = o.project(c[0], a, ptol);
    let (tb, db) = o.project(c[3], b, ptol);
    // The largest distance found at the stretches' ends (each the nearest
    // point's): what a stretch's bound is judged against. (The matched
    // differences are not: a stretch matched too coarsely overstates them.)
    let mut found = da.max(db);
    let mut stack = alloc::vec![((0.0, ta), (1.0, tb), 0u32)];
    let mut bound: f64 = 0.0;
    while let Some((n0, n1, depth)) = stack.pop() {
        let pieces = node_pieces(o, c, n0, n1);
        let norm = |b: &[Vec3; 4]| b.iter().map(|p| p.norm()).fold(0.0, f64::max);
        let h = pieces.iter().map(norm).fold(0.0, f64::max);
        if h <= found + tol || !h.is_finite() {
            bound = bound.max(h);
            continue;
        }
        if depth >= MAX_SLIDE_DEPTH {
            bound = bound.max(pieces_bound(
                pieces.into_iter().map(Span::Cubic).collect(),
                tol,
            ));
            continue;
        }
        let tm = 0.5 * (n0.0 + n1.0);
        let (t, d) = o.project(bezier_point(c, tm), 0.5 * (n0.1 + n1.1), ptol);
        found = found.max(d);
        stack.push((n0, (tm, t), depth + 1));
        stack.push(((tm, t), n1, depth + 1));
    }
    bound
}

/// The difference pieces of one stretch of a span of the curve (Bezier
/// points `c`) from local parameter `n0.0` to `n1.0`, matched linearly to
/// the original from parameter `n0.1` to `n1.1`: split where the match
/// crosses the original's knots, each piece one cubic.
fn node_pieces(o: &Original, c: &[Vec3; 4], n0: (f64, f64), n1: (f64, f64)) -> Vec<[Vec3; 4]> {
    let u = o.basis.knots;
    let ((t0, pa), (t1, pb)) = (n0, n1);
    let (lo, hi) = if pa <= pb { (pa, pb) } else { (pb, pa) };
    let mut cuts: Vec<f64> = Vec::with_capacity(4);
    cuts.push(0.0);
    if pb != pa {
        for &k in &u[o.basis.degree + 1..o.pts.len()] {
            if k > lo && k < hi {
                cuts.push((k - pa) / (pb - pa));
            }
        }
    }
    cuts.push(1.0);
    cuts.sort_by(f64::total_cmp);
    let mut pieces: Vec<[Vec3; 4]> = Vec::with_capacity(cuts.len());
    for w in cuts.windows(2) {
        let (f0, f1) = (w[0], w[1]);
        if f1 <= f0 {
            continue;
        }
        let (g0, g1) = (pa + (pb - pa) * f0, pa + (pb - pa) * f1);
        let (_, ob, oa, oe) = o.span(0.5 * (g0 + g1));
        let h = oe - oa;
        let orig = restrict(&ob, (g0 - oa) / h, (g1 - oa) / h);
        let cur = restrict(c, t0 + (t1 - t0) * f0, t0 + (t1 - t0) * f1);
        pieces.push(core::array::from_fn(|j| cur[j] - orig[j]));
    }
    pieces
}

/// The largest distance from the curve `cur` to the curve `orig` (the
/// same clamped, non-rational cubic `basis`) at `precision` equal steps of
/// every non-empty knot interval, each sample's nearest point found as in
/// [`sliding_bound_on`] (a sample, not a bound: as
/// [`super::tube::sampled_deviation`]; each projection stops within
/// `tol` mm); for other curves that function.
pub fn sampled_sliding(
    cur: &[Vec3],
    orig: &[Vec3],
    original: Option<&Original>,
    basis: &Basis,
    precision: usize,
    tol: f64,
) -> f64 {
    let Some(o) = original else {
        let diff = super::tube::difference(cur, orig);
        return super::tube::sampled_deviation(&diff, basis, precision);
    };
    let u = basis.knots;
    let mut best: f64 = 0.0;
    for s in super::spans::nonempty_spans(basis, cur.len()) {
        let c = bezier_of_span(u, cur, s);
        for j in 0..=precision {
            let tau = j as f64 / precision as f64;
            let p = bezier_point(&c, tau);
            let (_, d) = o.project(p, u[s] + (u[s + 1] - u[s]) * tau, tol);
            best = best.max(d);
        }
    }
    best
}

impl TubeMeasure {
    /// A sure bound of the distance from the spans `spans` of `cur`
    /// (difference `diff` from the original) to the original as this
    /// measure measures it: [`sliding_bound_on`] with `original`, or
    /// [`deviation_bound_on`] at equal parameters.
    pub fn bound_on(
        self,
        cur: &[Vec3],
        original: Option<&Original>,
        diff: &[Vec3],
        basis: &Basis,
        spans: &[usize],
        tol: f64,
    ) -> f64 {
        let original = original.filter(|_| self == TubeMeasure::Sliding);
        sliding_bound_on(cur, original, diff, basis, spans, tol)
    }

    /// The distance from `cur` to the original `orig` sampled at
    /// `precision` steps of every span, as this measure measures it
    /// ([`sampled_sliding`]).
    pub fn sampled(
        self,
        cur: &[Vec3],
        orig: &[Vec3],
        original: Option<&Original>,
        basis: &Basis,
        precision: usize,
        tol: f64,
    ) -> f64 {
        let original = original.filter(|_| self == TubeMeasure::Sliding);
        sampled_sliding(cur, orig, original, basis, precision, tol)
    }
}
