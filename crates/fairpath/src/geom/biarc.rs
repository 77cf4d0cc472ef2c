//! Biarcs: two tangent circular arcs that join two points with given
//! tangents, the building block of arc-spline approximation of curves.
//!
//! Construction (the equal-tangent-length biarc of Bolton 1975, in the form
//! of Ryan Juckett, "Biarc interpolation", 2010, and Meek & Walton,
//! "Approximating smooth planar curves by arc splines", J. Comput. Appl.
//! Math. 59, 1995): with `v = p1 - p0` and unit tangents `t0`, `t1`, the
//! two control points `p0 + d t0` and `p1 - d t1` are `2d` apart, which
//! gives
//!
//! `2 (1 - t0.t1) d^2 - 2 (v.(t0 + t1)) d - v.v = 0`,
//!
//! whose positive root is taken; the joint is the midpoint of the two
//! control points and the tangent there points from the first to the
//! second. Each arc is the circle through its ends tangent to the given
//! direction at its start: signed curvature `k = 2 (t x c) / |c|^2` for
//! the chord `c`.
//!
//! Arcs are built in a principal [`Plane`] (G17, G18, G19): the in-plane
//! coordinates form the biarc, and the coordinate along the plane's normal
//! rises linearly with in-plane arc length over the whole biarc, so both
//! arcs are helical with the same pitch and meet tangent in 3D too.

use super::{Arc, Curve, Line, Plane, Vec3};
use crate::math;

/// Two arcs (or lines, where a turn vanishes) from `p0` to `p1`.
#[derive(Clone, Debug, PartialEq)]
pub struct Biarc {
    pub first: Curve,
    pub second: Curve,
    /// Where they meet.
    pub joint: Vec3,
}

/// 2D helpers on `[a, b]`.
fn cross2(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}
fn dot2(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[0] + u[1] * v[1]
}
fn norm2(u: [f64; 2]) -> f64 {
    math::sqrt(dot2(u, u))
}

/// In-plane unit direction of a 3D tangent, if its projection on `plane`
/// has at least `min_share` of its length.
pub fn in_plane_direction(plane: Plane, t: Vec3, min_share: f64) -> Option<[f64; 2]> {
    let l = plane.local(t);
    let p = [l[0], l[1]];
    let n = norm2(p);
    let full = t.norm();
    if !(n > 0.0 && n >= min_share * full) {
        return None;
    }
    Some([p[0] / n, p[1] / n])
}

/// Below this half turn `phi` (rad), [`arc_length_2d`] takes the chord's
/// length: `phi / sin(phi) = 1 + phi^2 / 6 + ...` differs from 1 by less
/// than f64's rounding there (and the quotient is 0/0 at 0).
const CHORD_LENGTH_BELOW: f64 = 1e-8;

/// Length in the plane of the arc that leaves `p` with unit direction `t`
/// and ends at `q` (both in-plane): `|c| (phi / sin phi)` with `phi` the
/// angle from `t` to the chord `c` (half the arc's turn); the chord itself
/// as `phi` vanishes. `None` for a turn of half a circle or more.
fn arc_length_2d(t: [f64; 2], c: [f64; 2]) -> Option<f64> {
    let len = norm2(c);
    let phi = math::atan2(cross2(t, c), dot2(t, c));
    if math::abs(phi) >= core::f64::consts::FRAC_PI_2 {
        return None;
    }
    let s = math::sin(phi);
    Some(if math::abs(phi) < CHORD_LENGTH_BELOW {
        len
    } else {
        len * phi / s
    })
}

/// The piece from `p` leaving with in-plane unit direction `t` to `q`, in
/// `plane`: an arc, or a line when the arc's curvature is at most
/// `straight` (1/mm; a line then kinks against the tangent by half the
/// arc's turn, `straight * length / 2`). `None` when the chord is empty or
/// the arc would turn by half a circle or more.
pub fn arc_from_tangent(
    plane: Plane,
    p: Vec3,
    t: [f64; 2],
    q: Vec3,
    straight: f64,
) -> Option<Curve> {
    let (lp, lq) = (plane.local(p), plane.local(q));
    let c = [lq[0] - lp[0], lq[1] - lp[1]];
    let c2 = dot2(c, c);
    if c2.is_nan() || c2 <= 0.0 {
        return None;
    }
    arc_length_2d(t, c)?;
    let k = 2.0 * cross2(t, c) / c2;
    if math::abs(k) <= straight {
        return Some(Curve::Line(Line::new(p, q)));
    }
    // Centre: left of the tangent for a left turn (k > 0).
    let center = plane.point([lp[0] - t[1] / k, lp[1] + t[0] / k, lp[2]]);
    let arc = Arc::from_center(p, q, center, plane.normal(), k < 0.0, 1, 0.0).ok()?;
    Some(Curve::from(arc))
}

/// The biarc from `p0` (unit tangent `t0`) to `p1` (unit tangent `t1`) in
/// `plane`, helical along its normal (see the module docs). Tangents whose
/// projection on the plane is shorter than `min_share` of them, biarcs that
/// do not exist (parallel tangents across the chord, a root that is not
/// positive) or whose arcs turn by half a circle or more give `None`.
/// Arcs whose curvature is at most `straight` (1/mm) are lines.
pub fn biarc(
    plane: Plane,
    p0: Vec3,
    t0: Vec3,
    p1: Vec3,
    t1: Vec3,
    min_share: f64,
    straight: f64,
) -> Option<Biarc> {
    let d0 = in_plane_direction(plane, t0, min_share)?;
    let d1 = in_plane_direction(plane, t1, min_share)?;
    let (l0, l1) = (plane.local(p0), plane.local(p1));
    let v = [l1[0] - l0[0], l1[1] - l0[1]];
    let vv = dot2(v, v);
    if vv.is_nan() || vv <= 0.0 {
        return None;
    }
    let t = [d0[0] + d1[0], d0[1] + d1[1]];
    let vt = dot2(v, t);
    // |v - d t|^2 = (2 d)^2 gives a d^2 + 2 (v.t) d - v.v = 0 with
    // a = 2 (1 - t0.t1) >= 0. Its positive root, in the form without
    // cancellation: vv / (vt + root) when vt > 0 (also right for a = 0,
    // equal tangents), (root - vt) / a otherwise.
    let a = 2.0 * (1.0 - dot2(d0, d1));
    let root = math::sqrt(vt * vt + a * vv);
    let d = if vt > 0.0 {
        vv / (vt + root)
    } else if a > 0.0 {
        (root - vt) / a
    } else {
        return None;
    };
    if !(d.is_finite() && d > 0.0) {
        return None;
    }
    // Control points and the joint, in the plane.
    let c0 = [l0[0] + d * d0[0], l0[1] + d * d0[1]];
    let c1 = [l1[0] - d * d1[0], l1[1] - d * d1[1]];
    let m = [0.5 * (c0[0] + c1[0]), 0.5 * (c0[1] + c1[1])];
    let tm_raw = [c1[0] - c0[0], c1[1] - c0[1]];
    let tn = norm2(tm_raw);
    let tm = if tn > 0.0 {
        [tm_raw[0] / tn, tm_raw[1] / tn]
    } else {
        d0
    };
    // In-plane lengths, for the helical rise.
    let la = arc_length_2d(d0, [m[0] - l0[0], m[1] - l0[1]])?;
    let lb = arc_length_2d(tm, [l1[0] - m[0], l1[1] - m[1]])?;
    let h = if la + lb > 0.0 {
        l0[2] + (l1[2] - l0[2]) * la / (la + lb)
    } else {
        l0[2]
    };
    let joint = plane.point([m[0], m[1], h]);
    let first = arc_from_tangent(plane, p0, d0, joint, straight)?;
    let second = arc_from_tangent(plane, joint, tm, p1, straight)?;
    Some(Biarc {
        first,
        second,
        joint,
    })
}

/// An upper bound of the distance (mm) from `q` to the arc: the distance
/// to the arc's point at `q`'s angle about its centre (clamped to the
/// arc's sweep, the nearer end otherwise). Exact for circular arcs in the
/// plane of `q`; for helical and spiral arcs a point of the arc, so never
/// below the true distance.
pub fn arc_distance_bound(arc: &Arc, q: Vec3) -> f64 {
    let w = q - arc.center;
    let v = arc.normal.cross(arc.u);
    let mut ang = math::atan2(w.dot(v), w.dot(arc.u));
    if ang < 0.0 {
        ang += 2.0 * core::f64::consts::PI;
    }
    if ang <= arc.sweep {
        q.dist(arc.eval_formula(ang / arc.sweep))
    } else {
        q.dist(arc.p0).min(q.dist(arc.p1))
    }
}

/// Distance bound from `q` to a line or arc (see [`arc_distance_bound`]);
/// `None` for other curves.
pub fn piece_distance_bound(c: &Curve, q: Vec3) -> Option<f64> {
    match c {
        Curve::Line(l) => Some(super::point_segment_distance(q, l.p0, l.p1)),
        Curve::Arc(a) => Some(arc_distance_bound(a, q)),
        Curve::Nurbs(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;

    fn on_circle(r: f64, a: f64) -> (Vec3, Vec3) {
        let (s, c) = (math::sin(a), math::cos(a));
        (Vec3::new(r * c, r * s, 0.0), Vec3::new(-s, c, 0.0))
    }

    #[test]
    fn a_biarc_between_two_points_of_a_circle_is_that_circle() {
        let (p0, t0) = on_circle(5.0, 0.1);
        let (p1, t1) = on_circle(5.0, 0.9);
        let b = biarc(Plane::Xy, p0, t0, p1, t1, 0.1, 1e-12).unwrap();
        for c in [&b.first, &b.second] {
            let Curve::Arc(a) = c else {
                panic!("not an arc")
            };
            assert!((a.r0 - 5.0).abs() < 1e-9 && (a.r1 - 5.0).abs() < 1e-9);
            assert!(a.center.norm() < 1e-9);
            assert!(a.normal == Vec3::Z, "counter-clockwise");
        }
        assert_eq!(b.first.start(), p0);
        assert_eq!(b.second.end(), p1);
        assert!((b.joint.norm() - 5.0).abs() < 1e-9);
    }

    #[test]
    fn a_biarc_is_tangent_at_its_ends_and_its_joint() {
        // An S: tangents turning both ways.
        let p0 = Vec3::new(0.0, 0.0, 0.0);
        let p1 = Vec3::new(3.0, 1.0, 0.0);
        let t0 = Vec3::new(1.0, 0.4, 0.0).normalized(0.0).unwrap();
        let t1 = Vec3::new(1.0, 0.6, 0.0).normalized(0.0).unwrap();
        let b = biarc(Plane::Xy, p0, t0, p1, t1, 0.1, 1e-12).unwrap();
        let ut = |c: &Curve, t: f64| c.unit_tangent(t).unwrap();
        assert!(ut(&b.first, 0.0).angle_to(t0) < 1e-9);
        assert!(ut(&b.second, 1.0).angle_to(t1) < 1e-9);
        assert!(ut(&b.first, 1.0).angle_to(ut(&b.second, 0.0)) < 1e-9);
        assert_eq!(b.first.end(), b.joint);
        assert_eq!(b.second.start(), b.joint);
    }

    #[test]
    fn a_helix_is_rebuilt_with_helical_arcs_in_every_plane() {
        // Radius 4, pitch 2 per turn, about each axis.
        for plane in Plane::ALL {
            let at = |a: f64| {
                let (s, c) = (math::sin(a), math::cos(a));
                let p = plane.point([4.0 * c, 4.0 * s, a / core::f64::consts::TAU * 2.0]);
                let t = plane.point([-4.0 * s, 4.0 * c, 2.0 / core::f64::consts::TAU]);
                (p, t.normalized(0.0).unwrap())
            };
            let (p0, t0) = at(0.3);
            let (p1, t1) = at(1.1);
            let b = biarc(plane, p0, t0, p1, t1, 0.1, 1e-12).unwrap();
            for c in [&b.first, &b.second] {
                for k in 0..=10 {
                    let q = c.eval(k as f64 / 10.0);
                    let l = plane.local(q);
                    assert!((l[0].hypot(l[1]) - 4.0).abs() < 1e-9, "{plane:?}");
                    let a = l[1].atan2(l[0]);
                    assert!((l[2] - a / core::f64::consts::TAU * 2.0).abs() < 1e-9);
                }
            }
            assert!(b.first.unit_tangent(0.0).unwrap().angle_to(t0) < 1e-9);
            assert!(b.second.unit_tangent(1.0).unwrap().angle_to(t1) < 1e-9);
        }
    }

    #[test]
    fn straight_data_gives_lines_and_bad_data_gives_none() {
        let x = Vec3::X;
        let b = biarc(
            Plane::Xy,
            Vec3::ZERO,
            x,
            Vec3::new(2.0, 0.0, 0.0),
            x,
            0.1,
            1e-9,
        )
        .unwrap();
        assert!(matches!(b.first, Curve::Line(_)) && matches!(b.second, Curve::Line(_)));
        // Same point.
        assert!(biarc(Plane::Xy, Vec3::ZERO, x, Vec3::ZERO, x, 0.1, 1e-9).is_none());
        // A tangent along the plane's normal.
        assert!(biarc(Plane::Xy, Vec3::ZERO, Vec3::Z, Vec3::X, x, 0.1, 1e-9).is_none());
        // Reversed tangents across the chord: no biarc of small turn.
        assert!(biarc(Plane::Xy, Vec3::ZERO, -x, Vec3::X, -x, 0.1, 1e-9).is_none());
    }

    #[test]
    fn distance_bound_is_exact_in_the_plane_and_never_below_the_truth() {
        let a = Arc::from_center(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            false,
            1,
            0.0,
        )
        .unwrap();
        let q = Vec3::new(2.0, 2.0, 0.0);
        assert!((arc_distance_bound(&a, q) - (8f64.sqrt() - 1.0)).abs() < 1e-12);
        // Outside the sweep: the nearer end.
        let q = Vec3::new(0.0, -3.0, 0.0);
        assert!((arc_distance_bound(&a, q) - 10f64.sqrt()).abs() < 1e-12);
        // Brute force on a helical arc.
        let h = Arc::from_center(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.5),
            Vec3::ZERO,
            Vec3::Z,
            false,
            1,
            0.0,
        )
        .unwrap();
        let q = Vec3::new(0.3, 0.8, 0.9);
        let brute = (0..=100_000)
            .map(|k| q.dist(h.eval(k as f64 / 100_000.0)))
            .fold(f64::INFINITY, f64::min);
        assert!(arc_distance_bound(&h, q) >= brute - 1e-12);
    }
}
