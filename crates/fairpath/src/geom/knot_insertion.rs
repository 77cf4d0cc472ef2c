//! Knot insertion in a clamped cubic B-spline (Boehm's algorithm, P&T A5.1
//! with `r = 1`): the same curve with no knot span longer than a length
//! ([`with_spans_at_most`]), or cut at every so many knots into clamped
//! pieces ([`split_at_knots`]).
//!
//! Both change how a fitted curve is held, never its shape, so they are
//! kept apart from the fit and its bound.

use super::fit::FIT_DEGREE;
use super::{Nurbs, Vec3};
use alloc::vec;
use alloc::vec::Vec;

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
