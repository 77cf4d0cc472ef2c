//! How far the curve is from the original, and how much of the tube is
//! left (thesis section 3.8, "3.6" in the checklist).
//!
//! The curve and the original share their knots, so their distance at
//! equal parameters is the difference spline `D(t) = P_cur(t) - P_orig(t)`
//! with control points `P_cur_i - P_orig_i` (eq. 2-16). The thesis'
//! maximum allowable distance (eq. 3-39) is
//! `D_allow = R - max_t |D(t)|`, the maximum found by sampling every knot
//! interval at `precision` steps ([`sampled_deviation`]). Sampling is
//! **not a bound**: the true maximum can lie between two samples, so a
//! curve accepted on samples alone may leave the tube. The fairing
//! therefore accepts a polygon only on a **sure bound**
//! ([`deviation_bound`]): the convex hull of a Bezier curve contains it
//! (section 2.3.3), so `max |D(t)|` over a span is at most the largest
//! `|b_j|` of the span's Bezier control points, and the spans are halved
//! (de Casteljau) until that bound is within a tolerance of the largest
//! value found on the curve. The coarsest form of it, the thesis' own
//! `max_t |D(t)| <= max_i |D_i|` over the B-spline's control points, is
//! [`hull_bound`].
//!
//! `|D(t)|` is the distance between points of equal parameter, which is at
//! least the distance from the curve to the original path: a curve within
//! `R` of the original by this measure is within `R` of it in the
//! project's sense (every point of the output within `R` of the original
//! path).

use super::spans::{nonempty_spans, Basis, Span};
use crate::geom::Vec3;
use alloc::vec::Vec;

/// Deepest halving of one span in [`deviation_bound`]: below that the
/// bound is kept as it is (still a sure bound, only less tight); the work
/// per span stays bounded whatever the tolerance.
pub const MAX_BOUND_DEPTH: u32 = 30;

/// The control points of the difference spline `a - b` (eq. 2-16).
pub fn difference(a: &[Vec3], b: &[Vec3]) -> Vec<Vec3> {
    a.iter().zip(b).map(|(p, q)| *p - *q).collect()
}

/// The largest `|D(t)|` of the difference spline (control points `diff`,
/// clamped on `basis`) at `precision` equal steps of every non-empty
/// knot interval, ends included (section 3.8). A sample, not a bound: it
/// never exceeds the true maximum, and may fall short of it.
pub fn sampled_deviation(diff: &[Vec3], basis: &Basis, precision: usize) -> f64 {
    let mut best: f64 = 0.0;
    for s in nonempty_spans(basis, diff.len()) {
        let b = Span::of(basis, diff, s);
        for j in 0..=precision {
            let tau = j as f64 / precision as f64;
            best = best.max(b.point(tau).norm());
        }
    }
    best
}

/// The thesis' convex-hull bound (section 2.3.4): `max_t |D(t)| <= max_i
/// |D_i|` over the difference spline's control points.
pub fn hull_bound(diff: &[Vec3]) -> f64 {
    diff.iter().map(|d| d.norm()).fold(0.0, f64::max)
}

/// A sure upper bound of `max_t |D(t)|` over the difference spline
/// (control points `diff`, clamped on `basis`) that exceeds the true
/// maximum by at most `tol` mm (unless a span needs more than
/// [`MAX_BOUND_DEPTH`] halvings; the result is a sure bound either way).
///
/// Branch and bound over the Bezier spans: a piece whose hull bound
/// `max_j |b_j|` is within `tol` of the largest value found on the curve
/// so far (at piece ends and middles) cannot hold a larger maximum than
/// that bound, and is accepted; others are halved.
pub fn deviation_bound(diff: &[Vec3], basis: &Basis, tol: f64) -> f64 {
    deviation_bound_on(diff, basis, &nonempty_spans(basis, diff.len()), tol)
}

/// [`deviation_bound`] over the non-empty knot spans `spans` only (knot
/// indices: span `s` runs from `knots[s]` to `knots[s + 1]`): a sure bound
/// of `|D(t)|` there, within `tol` of the largest value on them.
pub fn deviation_bound_on(diff: &[Vec3], basis: &Basis, spans: &[usize], tol: f64) -> f64 {
    pieces_bound(
        spans.iter().map(|&s| Span::of(basis, diff, s)).collect(),
        tol,
    )
}

/// A sure upper bound of `|D|` over Bezier pieces of a difference curve,
/// within `tol` of the largest value found on them (at piece ends and
/// middles): the branch and bound of [`deviation_bound`], on pieces made
/// elsewhere too ([`super::slide`]).
pub(super) fn pieces_bound(pieces: Vec<Span>, tol: f64) -> f64 {
    let mut found: f64 = 0.0;
    for b in &pieces {
        let (first, last) = b.ends();
        found = found
            .max(first.norm())
            .max(last.norm())
            .max(b.point(0.5).norm());
    }
    let mut stack: Vec<(Span, u32)> = pieces.into_iter().map(|b| (b, 0)).collect();
    let mut bound: f64 = 0.0;
    while let Some((b, depth)) = stack.pop() {
        let h = b.hull_norm();
        if h <= found + tol || depth >= MAX_BOUND_DEPTH || !h.is_finite() {
            bound = bound.max(h);
            continue;
        }
        let (l, r) = b.split_half();
        found = found
            .max(l.point(0.5).norm())
            .max(r.point(0.5).norm())
            .max(l.ends().1.norm());
        stack.push((l, depth + 1));
        stack.push((r, depth + 1));
    }
    bound
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    fn knots7() -> Vec<f64> {
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0]
    }

    #[test]
    fn the_bound_is_sure_and_tight() {
        let diff = vec![
            Vec3::ZERO,
            Vec3::new(0.1, 0.3, 0.0),
            Vec3::new(-0.2, 0.1, 0.05),
            Vec3::new(0.0, -0.4, 0.0),
            Vec3::new(0.3, 0.3, 0.1),
            Vec3::new(0.1, -0.1, 0.0),
            Vec3::ZERO,
        ];
        let u = knots7();
        let dense = sampled_deviation(&diff, &Basis::cubic(&u), 20_000);
        let coarse = sampled_deviation(&diff, &Basis::cubic(&u), 5);
        let tol = 1e-6;
        let bound = deviation_bound(&diff, &Basis::cubic(&u), tol);
        assert!(coarse <= dense + 1e-15);
        assert!(bound >= dense, "{bound} < {dense}");
        assert!(bound <= dense + tol + 1e-9, "{bound} vs {dense}");
        assert!(hull_bound(&diff) >= bound);
    }

    #[test]
    fn a_zero_difference_is_zero() {
        let diff = vec![Vec3::ZERO; 7];
        assert_eq!(deviation_bound(&diff, &Basis::cubic(&knots7()), 1e-6), 0.0);
        assert_eq!(sampled_deviation(&diff, &Basis::cubic(&knots7()), 5), 0.0);
    }
}
