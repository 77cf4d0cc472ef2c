//! Corners inside a B-spline: breakpoints where the curve's tangent turns
//! at a point, as a corner between two moves does.
//!
//! A B-spline is tangent continuous where its parameter is, except at a
//! breakpoint whose one-sided derivatives differ in direction: a knot of
//! multiplicity `degree` with control points that bend there, or a
//! derivative that vanishes there, as at a control point repeated
//! `degree` times (a CAM system's way of putting a sharp corner into one
//! spline block). The curvature is not defined at such a point, and a
//! planner that samples it sees the straight stretches either side only:
//! it would run through the corner at the feed.
//!
//! The one-sided tangents come from the Bezier spans either side of the
//! breakpoint, exactly: near the end of a span with control points `q0 ..
//! qp`, `C(t) - qp` is led by the first non-zero `qp - q(p-k)`, `k = 1 ..
//! p` (times a positive power of `1 - t`; for a rational span, times a
//! positive weight too), so the tangent there points along it; likewise
//! `q(k) - q0` at the start.
//!
//! Inside a span, a polynomial cubic turns sharply only where its
//! derivative, the quadratic hodograph `H(u) = 3 ((1-u)^2 D0 + 2u(1-u) D1 +
//! u^2 D2)` (`Di = q(i+1) - q(i)`), nearly vanishes: a cusp where it
//! stops and turns back, as a least-squares fit through a reversal of the
//! program has one. [`sharp_turns_in_span`] finds the points where the
//! span turns on a radius below a given one; a span whose hodograph stays
//! away from zero along the chord is passed over on a sure bound.

use super::{JointTolerances, Nurbs, Vec3};
use alloc::vec::Vec;

/// A corner inside a curve: where the tangent turns, and the unit tangents
/// arriving at it and leaving it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InnerCorner {
    /// The breakpoint (curve parameter).
    pub t: f64,
    pub tangent_in: Vec3,
    pub tangent_out: Vec3,
}

/// Unit tangent at the end of the Bezier span with control points `q`
/// (leaving along it): the first difference `q[p] - q[p - k]` longer than
/// `zero` mm, normalised.
fn end_tangent(q: &[Vec3], zero: f64) -> Option<Vec3> {
    let last = *q.last()?;
    q.iter()
        .rev()
        .skip(1)
        .map(|&p| last - p)
        .find(|d| d.norm() > zero)
        .and_then(|d| d.normalized(0.0))
}

/// Unit tangent at the start of the Bezier span with control points `q`.
fn start_tangent(q: &[Vec3], zero: f64) -> Option<Vec3> {
    let first = *q.first()?;
    q.iter()
        .skip(1)
        .map(|&p| p - first)
        .find(|d| d.norm() > zero)
        .and_then(|d| d.normalized(0.0))
}

/// The corners at the breakpoints between consecutive Bezier spans: span
/// `i` (control points `spans[i]`) covers `breaks[i] .. breaks[i + 1]`.
/// A corner is a turn of the one-sided tangents by more than `jt.angle`
/// (plus the rounding of control points `|d|` apart, as
/// [`super::classify_joint`] allows for); a control point difference no
/// longer than `jt.position` counts as none. A span of coincident control
/// points (no tangent) is passed over: the tangents either side of it are
/// compared, at its start.
pub fn corners_between_spans<S: AsRef<[Vec3]>>(
    breaks: &[f64],
    spans: &[S],
    jt: &JointTolerances,
) -> Vec<InnerCorner> {
    let mut out = Vec::new();
    // The tangent leaving the last span that had one, with the length of
    // its leading difference.
    let mut before: Option<Vec3> = None;
    for (i, s) in spans.iter().enumerate() {
        let q = s.as_ref();
        let Some(start) = start_tangent(q, jt.position) else {
            continue;
        };
        if let (Some(tin), Some(&t)) = (before, breaks.get(i)) {
            let scale = q.iter().fold(1.0f64, |m, p| {
                m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs())
            });
            let lead = q
                .iter()
                .skip(1)
                .map(|&p| (p - q[0]).norm())
                .fold(0.0f64, f64::max);
            let round = 1e3 * f64::EPSILON * scale / lead.max(jt.position);
            if tin.angle_to(start) > jt.angle + round {
                out.push(InnerCorner {
                    t,
                    tangent_in: tin,
                    tangent_out: start,
                });
            }
        }
        before = end_tangent(q, jt.position);
    }
    out
}

/// Number of samples of `|H|^2` per span in [`sharp_turns_in_span`]; each
/// local minimum among them is refined in the two sample intervals around
/// it (`|H|^2` is a quartic: at most two local minima).
const TURN_SAMPLES: usize = 32;

/// Width, as a share of the two sample intervals it starts from, to which
/// that refinement narrows the bracket of a minimum.
const TURN_ACCURACY: f64 = 1e-9;

/// The points strictly inside the cubic Bezier span `q` (local parameter
/// `u` in `(0, 1)`) where its speed `|H|` has a local minimum and it turns
/// there on a radius below `radius` mm (or stops: `H(u) = 0`), each with the unit tangents a sample interval
/// (`1 / TURN_SAMPLES` of the span) before and after it, which the turn
/// lies between. Bounds: a span whose control-point differences `Di` all
/// lead along its chord by at least `m` has `|H| >= 3 m` everywhere and
/// `|H'| <= 6 M` (`M` the larger of `|D1 - D0|`, `|D2 - D1|`), so its
/// curvature `|H x H'| / |H|^3 <= 2 M / (3 m^2)`; where that is at most
/// `1 / radius` nothing is sampled. Otherwise the minima of `|H|^2` are
/// found by `TURN_SAMPLES` (32) samples and golden-section refinement, and a
/// minimum whose curvature exceeds `1 / radius` is reported (two minima
/// closer than a sample interval may show as one). A curvature peak where
/// the speed has no minimum is a bend the planner's sampling sees; the
/// turn at a minimum of the speed is concentrated where the speed is
/// least, and can fall between samples.
pub fn sharp_turns_in_span(q: &[Vec3; 4], radius: f64) -> Vec<(f64, Vec3, Vec3)> {
    let d = [q[1] - q[0], q[2] - q[1], q[3] - q[2]];
    let chord = q[3] - q[0];
    let big_m = (d[1] - d[0]).norm().max((d[2] - d[1]).norm());
    if let Some(c) = chord.normalized(0.0) {
        let m = d.iter().map(|x| x.dot(c)).fold(f64::INFINITY, f64::min);
        if m > 0.0 && 2.0 * big_m * radius <= 3.0 * m * m {
            return Vec::new();
        }
    }
    let h = |u: f64| {
        (d[0] * ((1.0 - u) * (1.0 - u)) + d[1] * (2.0 * u * (1.0 - u)) + d[2] * (u * u)) * 3.0
    };
    let dh = |u: f64| ((d[1] - d[0]) * (1.0 - u) + (d[2] - d[1]) * u) * 6.0;
    let f = |u: f64| h(u).norm_sq();
    let step = 1.0 / TURN_SAMPLES as f64;
    let fs: Vec<f64> = (0..=TURN_SAMPLES).map(|k| f(k as f64 * step)).collect();
    let mut out = Vec::new();
    for k in 0..=TURN_SAMPLES {
        let left = k == 0 || fs[k] <= fs[k - 1];
        let right = k == TURN_SAMPLES || fs[k] < fs[k + 1];
        if !(left && right) {
            continue;
        }
        // Golden-section search for the minimum in [u(k-1), u(k+1)]
        // (within the span): `golden_max` of `-|H|^2`.
        let a0 = k.saturating_sub(1) as f64 * step;
        let b0 = ((k + 1) as f64 * step).min(1.0);
        let (_, u) = super::sampled_peak::golden_max(|u| -f(u), a0, b0, (b0 - a0) * TURN_ACCURACY);
        // A minimum at an end of the span is the breakpoint's
        // ([`corners_between_spans`]).
        if u - a0 <= (b0 - a0) * 1e-6 && k == 0 || b0 - u <= (b0 - a0) * 1e-6 && k == TURN_SAMPLES {
            continue;
        }
        let (d1, d2) = (h(u), dh(u));
        let sharp = d1.norm_sq() == 0.0 || super::curvature_from(d1, d2) * radius > 1.0;
        if !sharp {
            continue;
        }
        let before = h((u - step).max(0.0))
            .normalized(0.0)
            .or_else(|| start_tangent(q, 0.0));
        let after = h((u + step).min(1.0))
            .normalized(0.0)
            .or_else(|| end_tangent(q, 0.0));
        if let (Some(tin), Some(tout)) = (before, after) {
            out.push((u, tin, tout));
        }
    }
    out
}

/// The corners inside `n` ([`corners_between_spans`] of its Bezier spans).
pub fn inner_corners(n: &Nurbs, jt: &JointTolerances) -> Vec<InnerCorner> {
    if let Some((breaks, spans)) = n.cubic_bezier_points() {
        return corners_between_spans(&breaks, &spans, jt);
    }
    let breaks = n.breakpoints();
    let spans: Vec<Vec<Vec3>> = n.bezier_spans().into_iter().map(|s| s.points).collect();
    if spans.len() + 1 != breaks.len() {
        return Vec::new();
    }
    corners_between_spans(&breaks, &spans, jt)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;
    use alloc::vec;

    fn jt() -> JointTolerances {
        JointTolerances::from_tolerance(0.05)
    }

    /// A uniform cubic whose middle control point is repeated three times
    /// turns there by the angle of its polygon, at the knot 0.5.
    #[test]
    fn a_triple_control_point_is_a_corner_at_its_knot() {
        let q = Vec3::new(10.0, 0.0, 0.0);
        let pts = vec![
            Vec3::new(9.0, 0.0, 0.0),
            Vec3::new(9.5, 0.0, 0.0),
            q,
            q,
            q,
            Vec3::new(10.0, 0.5, 0.0),
            Vec3::new(10.0, 1.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0];
        let n = Nurbs::new(3, knots, pts, None).expect("valid");
        let c = inner_corners(&n, &jt());
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].t, 0.5);
        assert!(n.eval(0.5).dist(q) < 1e-12);
        assert!(c[0].tangent_in.dist(Vec3::X) < 1e-12, "{c:?}");
        assert!(c[0].tangent_out.dist(Vec3::Y) < 1e-12, "{c:?}");
    }

    /// A knot of full multiplicity with a bent polygon is a corner; with
    /// its neighbours in line with it, none.
    #[test]
    fn a_full_knot_is_a_corner_only_where_the_polygon_bends() {
        let knots = vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0];
        let bent = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
        ];
        let n = Nurbs::new(2, knots.clone(), bent, None).expect("valid");
        let c = inner_corners(&n, &jt());
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].t, 1.0);
        let straight = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(4.0, 2.0, 0.0),
        ];
        let n = Nurbs::new(2, knots, straight, None).expect("valid");
        assert!(inner_corners(&n, &jt()).is_empty());
    }

    /// A span whose hodograph passes through zero (control points (0,0),
    /// (1,1), (0,1), (1,0)) stops at `u = 1/2` and turns back; a nearly
    /// straight span and a circle-like bend have no sharp turn.
    #[test]
    fn a_cusp_inside_a_span_is_a_sharp_turn_and_a_bend_is_not() {
        let v = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let cusp = [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0), v(1.0, 0.0)];
        let t = sharp_turns_in_span(&cusp, 1e-3);
        assert_eq!(t.len(), 1, "{t:?}");
        assert!((t[0].0 - 0.5).abs() < 1e-6, "{t:?}");
        assert!(t[0].1.dot(t[0].2) < -0.9, "turns back: {t:?}");
        let straight = [v(0.0, 0.0), v(1.0, 0.01), v(2.0, -0.01), v(3.0, 0.0)];
        assert!(sharp_turns_in_span(&straight, 1e-3).is_empty());
        // A quarter turn of radius about 1: sharp only for a radius above 1.
        let bend = [v(1.0, 0.0), v(1.0, 0.552), v(0.552, 1.0), v(0.0, 1.0)];
        assert!(sharp_turns_in_span(&bend, 0.5).is_empty());
        assert_eq!(sharp_turns_in_span(&bend, 2.0).len(), 1);
    }

    /// Seeded random cubic spans: wherever the speed `|H|` of a span has
    /// a local minimum inside it (found by dense sampling) where the span
    /// turns on a radius below half of `radius`, a sharp turn is reported
    /// there; none is reported where the curvature stays below
    /// `1 / radius` everywhere.
    #[test]
    fn seeded_random_spans_report_their_sharp_turns() {
        let mut rng = crate::seeded::Rng(22);
        let (mut found, mut smooth) = (0, 0);
        for case in 0..1200 {
            let q: [Vec3; 4] = core::array::from_fn(|_| {
                Vec3::new(
                    2.0 * rng.next(),
                    2.0 * rng.next(),
                    (case % 2) as f64 * rng.next(),
                )
            });
            let radius = [1e-3, 1e-2, 0.1][case % 3];
            let span = Nurbs::new(
                3,
                vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                q.to_vec(),
                None,
            )
            .expect("a span");
            let n = 20_000;
            let at = |k: usize| span.derivs12(k as f64 / n as f64);
            let speed = |k: usize| at(k).0.norm();
            let mut peak = 0.0f64;
            let mut sharp_min: Option<f64> = None;
            for k in 1..n {
                let (d1, d2) = at(k);
                let kappa = crate::geom::curvature_from(d1, d2);
                peak = peak.max(kappa);
                if speed(k) <= speed(k - 1) && speed(k) < speed(k + 1) && kappa * radius > 2.0 {
                    sharp_min = Some(k as f64 / n as f64);
                }
            }
            let turns = sharp_turns_in_span(&q, radius);
            if let Some(u) = sharp_min {
                found += 1;
                assert!(
                    turns
                        .iter()
                        .any(|t| (t.0 - u).abs() < 2.0 / TURN_SAMPLES as f64),
                    "case {case}: sharp at {u}, found {turns:?}"
                );
            } else if peak * radius < 1.0 {
                smooth += 1;
                assert!(turns.is_empty(), "case {case}: {turns:?}, peak {peak}");
            }
        }
        assert!(
            found > 100 && smooth > 400,
            "{found} sharp, {smooth} smooth"
        );
    }

    /// Seeded random smooth cubics (simple knots, control points apart)
    /// have no corner, rational or not; the same with one control point
    /// tripled have one, at the knot the triple point's curve point is.
    #[test]
    fn seeded_random_cubics_have_corners_only_at_tripled_points() {
        let mut rng = crate::seeded::Rng(21);
        for case in 0..200 {
            let count = 7 + case % 5;
            let mut pts: Vec<Vec3> = (0..count)
                .map(|i| {
                    Vec3::new(
                        i as f64 + 0.5 * rng.next(),
                        3.0 * rng.next(),
                        rng.next() - 0.5,
                    )
                })
                .collect();
            let inner = count - 4;
            let mut knots = vec![0.0; 4];
            knots.extend((1..=inner).map(|i| i as f64 / (inner + 1) as f64));
            knots.extend([1.0; 4]);
            let weights = (case % 2 == 1).then(|| (0..count).map(|_| 0.5 + rng.next()).collect());
            let n = Nurbs::new(3, knots.clone(), pts.clone(), weights.clone()).expect("valid");
            assert!(inner_corners(&n, &jt()).is_empty(), "case {case}");
            // Control points j - 1, j, j + 1 made one: the curve passes
            // through it at knot `knots[j + 2]` and turns there.
            let j = 2 + case % (count - 4);
            let (a, b) = (pts[j - 2], pts[j + 2]);
            let q = pts[j];
            pts[j - 1] = q;
            pts[j + 1] = q;
            let turned = (q - a)
                .normalized(0.0)
                .unwrap()
                .angle_to((b - q).normalized(0.0).unwrap());
            let n = Nurbs::new(3, knots.clone(), pts, weights).expect("valid");
            let c = inner_corners(&n, &jt());
            assert_eq!(c.len(), 1, "case {case}: {c:?}");
            assert_eq!(c[0].t, knots[j + 2], "case {case}");
            assert!(n.eval(c[0].t).dist(q) < 1e-9, "case {case}");
            assert!(
                (c[0].tangent_in.angle_to(c[0].tangent_out) - turned).abs() < 1e-9,
                "case {case}"
            );
        }
    }
}
