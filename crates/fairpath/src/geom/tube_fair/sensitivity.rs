//! Sensitivities and move distances (thesis sections 3.7 and 3.9, "3.5"
//! and "3.7" in the checklist).
//!
//! The sensitivity of a control point is how far the curve moved at the
//! point's parameter for each mm the point moved in the previous iteration
//! (eq. 3-38: `S_i = |D(t_i)| / MD_i`), `D` the difference spline of the
//! move (eq. 3-32: the control points `P_new - P_old` on the same knots).
//! Before the first iteration a mock iteration with `D_max = R` gives the
//! starting values, and the polygon is put back.
//!
//! The parameter of each control point (eqs. 3-33 to 3-37, the thesis'
//! distinct knots `k_0..k_(n-1)` for `m` control points): `t_0 = k_0`,
//! `t_1 = (k_0 + k_1) / 2`, `t_i = k_(i-1)`, `t_(m-2) = (k_(n-2) +
//! k_(n-1)) / 2`, `t_(m-1) = k_(n-1)`. On the full clamped knot vector `u`
//! (`u_3 = k_0`, `u_(j+3) = k_j`) that is `t_0 = u_3`,
//! `t_1 = (u_3 + u_4) / 2`, `t_i = u_(i+2)`, `t_(m-2) = (u_(m-1) + u_m) / 2`,
//! `t_(m-1) = u_m`, which is also what is used for repeated interior knots.
//! The thesis fairs cubics; a curve of another degree `p` (ours) takes its
//! control points' Greville abscissae `(u_(i+1) + ... + u_(i+p)) / p`
//! (de Boor, A Practical Guide to Splines, rev. ed., chapter XI), the
//! parameters where each control point pulls the curve most, which the
//! thesis' choice approximates at degree 3.
//!
//! Move distances (eqs. 3-40, 3-41): `S_inv_i = (1 / S_i) / max_j (1 / S_j)`
//! in `(0, 1]`, `MD_i = D_max S_inv_i`, so the least sensitive point moves
//! `D_max` and the curve moves about `D_max min_j S_j` everywhere (the
//! thesis' worked example, tested below).
//!
//! Choices where the thesis is silent or loose:
//! * A sensitivity that is 0 or undefined (the point did not move, or the
//!   curve did not move at its parameter) is 1.0: the thesis sets its
//!   zero sensitivities to 1.0 "so that it does not cause a division
//!   error".
//! * The maximum in eq. 3-40 is taken over the points that move this
//!   iteration (non-zero direction, not pinned): a point that stays where
//!   it is would otherwise scale every other move down for nothing.

use super::spans::{self, Basis};
use crate::geom::Vec3;
use alloc::vec::Vec;

/// The parameter of each of the `m` control points (eqs. 3-33 to 3-37 on
/// the full clamped knot vector, see the module documentation; Greville's
/// at degrees other than 3).
pub fn point_parameters(basis: &Basis, m: usize) -> Vec<f64> {
    let (u, p) = (basis.knots, basis.degree);
    if p != spans::DEGREE {
        return (0..m)
            .map(|i| u[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect();
    }
    (0..m)
        .map(|i| {
            if i == 0 {
                u[3]
            } else if i == m - 1 {
                u[m]
            } else if i == 1 {
                0.5 * (u[3] + u[4])
            } else if i == m - 2 {
                0.5 * (u[m - 1] + u[m])
            } else {
                u[i + 2]
            }
        })
        .collect()
}

/// Eq. 3-38: `S_i = |D(t_i)| / |step_i|` for the move `step` (the control
/// points of the difference spline, eq. 3-32), 1.0 where either is zero.
pub fn sensitivities(step: &[Vec3], basis: &Basis, params: &[f64]) -> Vec<f64> {
    step.iter()
        .zip(params)
        .map(|(s, &t)| {
            let moved = s.norm();
            if moved == 0.0 {
                return 1.0;
            }
            let curve = spans::eval(basis, step, t).norm();
            if curve > 0.0 && curve.is_finite() {
                curve / moved
            } else {
                1.0
            }
        })
        .collect()
}

/// Eq. 3-40: the scaled inverse sensitivities `(1 / S_i) / max (1 / S_j)`,
/// the maximum over the points with `moving[j]`; 0 for the others (and
/// all 0 when none moves).
pub fn scaled_inverse(s: &[f64], moving: &[bool]) -> Vec<f64> {
    let s_min = s
        .iter()
        .zip(moving)
        .filter(|(_, &m)| m)
        .map(|(&x, _)| x)
        .fold(f64::INFINITY, f64::min);
    s.iter()
        .zip(moving)
        .map(|(&x, &m)| {
            if m && s_min.is_finite() {
                s_min / x
            } else {
                0.0
            }
        })
        .collect()
}

/// Eq. 3-41: `MD_i = D_max S_inv_i`.
pub fn move_distances(s_inv: &[f64], d_max: f64) -> Vec<f64> {
    s_inv.iter().map(|&x| d_max * x).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    /// The thesis' worked example (section 3.9, eqs. 3-42 to 3-46):
    /// sensitivities [1/5, 2/5, 1/2, 4/5, 1] scale to [1, 1/2, 2/5, 1/4,
    /// 1/5], with `D_max = 10` the move distances are [10, 5, 4, 5/2, 2],
    /// and the curve moves 2 at every point.
    #[test]
    fn the_thesis_worked_example() {
        let s = [0.2, 0.4, 0.5, 0.8, 1.0];
        let inv = scaled_inverse(&s, &[true; 5]);
        let want = [1.0, 0.5, 0.4, 0.25, 0.2];
        for (a, b) in inv.iter().zip(want) {
            assert!((a - b).abs() < 1e-15, "{inv:?}");
        }
        let md = move_distances(&inv, 10.0);
        let want = [10.0, 5.0, 4.0, 2.5, 2.0];
        for (a, b) in md.iter().zip(want) {
            assert!((a - b).abs() < 1e-14, "{md:?}");
        }
        for (m, s) in md.iter().zip(s) {
            assert!((m * s - 2.0).abs() < 1e-14);
        }
    }

    #[test]
    fn points_that_stay_do_not_scale_the_others() {
        let inv = scaled_inverse(&[0.01, 0.5, 1.0], &[false, true, true]);
        assert_eq!(inv, vec![0.0, 1.0, 0.5]);
        assert_eq!(scaled_inverse(&[1.0], &[false]), vec![0.0]);
    }

    /// The thesis' parameters on a clamped knot vector with distinct knots
    /// 0, 1, 2, 3 (six control points): 0, 1/2, 1, 2, 5/2, 3.
    #[test]
    fn parameters_per_control_point() {
        let u = [0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0];
        let b = Basis::cubic(&u);
        assert_eq!(point_parameters(&b, 6), vec![0.0, 0.5, 1.0, 2.0, 2.5, 3.0]);
        let u4 = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let b4 = Basis::cubic(&u4);
        assert_eq!(point_parameters(&b4, 4), vec![0.0, 0.5, 0.5, 1.0]);
        // Another degree: Greville's abscissae.
        let u5 = [0.0; 6]
            .into_iter()
            .chain([1.0, 2.0])
            .chain([3.0; 6])
            .collect::<Vec<f64>>();
        let b5 = Basis {
            knots: &u5,
            degree: 5,
            weights: None,
        };
        let g = point_parameters(&b5, 8);
        assert_eq!((g[0], g[7]), (0.0, 3.0));
        assert!((g[3] - 6.0 / 5.0).abs() < 1e-15, "{g:?}");
    }

    /// A lone move of an interior point on uniform knots: the curve moves
    /// 2/3 of it at the point's knot (the cubic B-spline's peak).
    #[test]
    fn sensitivity_of_a_lone_move() {
        let u = [0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0];
        let mut step = vec![Vec3::ZERO; 7];
        step[3] = Vec3::new(0.0, 0.3, 0.0);
        let u = Basis::cubic(&u);
        let t = point_parameters(&u, 7);
        let s = sensitivities(&step, &u, &t);
        assert!((s[3] - 2.0 / 3.0).abs() < 1e-12, "{s:?}");
        assert_eq!(s[0], 1.0);
    }
}
