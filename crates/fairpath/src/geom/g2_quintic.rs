//! The quintic Bezier curve that joins two curve ends with G2 continuity:
//! the same point, unit tangent and curvature vector as each end.
//!
//! A Bezier curve `B(t) = sum_i P_i B_i^5(t)` has `B'(0) = 5 (P1 - P0)` and
//! `B''(0) = 20 (P2 - 2 P1 + P0)`, and the mirror images at `t = 1` (Farin,
//! *Curves and Surfaces for CAGD*, 5th ed., section 5.3). Asking for
//! `B'(0) = d0 T0` and `B''(0) = d0^2 K0` (unit tangent `T0`, curvature
//! vector `K0 = kappa0 N0`, perpendicular to `T0`) gives
//!
//! `P1 = P0 + d0 T0 / 5`, `P2 = P0 + 2 d0 T0 / 5 + d0^2 K0 / 20`,
//!
//! and at the other end `P4 = P5 - d1 T1 / 5`,
//! `P3 = P5 - 2 d1 T1 / 5 + d1^2 K1 / 20`. The curvature vector of `B` at
//! `t = 0` is the part of `B''` normal to `B'` over `|B'|^2`, which is
//! `K0`: the joint is G2 whatever the speeds `d0`, `d1 > 0` (the two free
//! parameters of G2 Hermite interpolation; the tangential part of `B''`
//! is set to zero, which only reparametrises). With curvature vectors of
//! zero (a line's end), `P0, P1, P2` lie on the tangent line.

use super::{Nurbs, Vec3};
use alloc::vec::Vec;

/// What a curve is at one end of a joint: its point, unit tangent (in the
/// direction of travel) and curvature vector `kappa N` (1/mm; zero on a
/// line).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndState {
    pub point: Vec3,
    pub tangent: Vec3,
    pub curvature: Vec3,
}

/// The six control points of the quintic from `a` to `b` that meets each
/// with G2 continuity, leaving `a` at speed `d0` and reaching `b` at speed
/// `d1` (mm per unit parameter; the module documentation gives the
/// formulas).
pub fn g2_quintic_points(a: &EndState, b: &EndState, d0: f64, d1: f64) -> [Vec3; 6] {
    let p0 = a.point;
    let p5 = b.point;
    [
        p0,
        p0 + a.tangent * (d0 / 5.0),
        p0 + a.tangent * (2.0 * d0 / 5.0) + a.curvature * (d0 * d0 / 20.0),
        p5 - b.tangent * (2.0 * d1 / 5.0) + b.curvature * (d1 * d1 / 20.0),
        p5 - b.tangent * (d1 / 5.0),
        p5,
    ]
}

/// The Bezier curve with control points `points` (2 to
/// [`Nurbs::MAX_DEGREE`]` + 1` of them) as a clamped, non-rational NURBS
/// on `[0, 1]`.
pub fn bezier_nurbs(points: &[Vec3]) -> Nurbs {
    let degree = points.len() - 1;
    let mut knots: Vec<f64> = alloc::vec![0.0; degree + 1];
    knots.extend(core::iter::repeat_n(1.0, degree + 1));
    Nurbs {
        degree,
        knots,
        points: points.to_vec(),
        weights: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;

    fn state(point: Vec3, tangent: Vec3, curvature: Vec3) -> EndState {
        EndState {
            point,
            tangent,
            curvature,
        }
    }

    /// Seeded random end states: the quintic meets each end's point, unit
    /// tangent and curvature vector.
    #[test]
    fn seeded_random_ends_are_met_with_g2_continuity() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut r = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let mut v = || Vec3::new(r(), r(), r());
            let (p0, p5) = (v() * 3.0, v() * 3.0);
            let t0 = v().normalized(0.0).unwrap();
            let t1 = v().normalized(0.0).unwrap();
            // Curvature vectors perpendicular to the tangents.
            let k0 = {
                let w = v() * 2.0;
                w - t0 * w.dot(t0)
            };
            let k1 = {
                let w = v() * 2.0;
                w - t1 * w.dot(t1)
            };
            let (d0, d1) = (0.5 + r().abs() * 4.0, 0.5 + r().abs() * 4.0);
            let c = bezier_nurbs(&g2_quintic_points(
                &state(p0, t0, k0),
                &state(p5, t1, k1),
                d0,
                d1,
            ));
            c.validate().unwrap();
            assert!(c.eval(0.0).dist(p0) < 1e-12 && c.eval(1.0).dist(p5) < 1e-12);
            assert!(c.unit_tangent(0.0).unwrap().dist(t0) < 1e-12);
            assert!(c.unit_tangent(1.0).unwrap().dist(t1) < 1e-12);
            assert!(c.curvature_vector(0.0).dist(k0) < 1e-9, "start curvature");
            assert!(c.curvature_vector(1.0).dist(k1) < 1e-9, "end curvature");
            assert!((c.deriv1(0.0).norm() - d0).abs() < 1e-12);
        }
    }
}
