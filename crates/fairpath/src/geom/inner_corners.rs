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
//! `q(k) - q0` at the start. A corner strictly inside a span (a cusp of a
//! single cubic) is not found here.

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
