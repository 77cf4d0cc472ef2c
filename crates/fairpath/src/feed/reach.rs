//! Jerk-limited reachability along a segment.
//!
//! A velocity change from `v_from` to `v_to` that starts and ends with zero
//! acceleration, under an acceleration limit `A` and a jerk limit `J`, is
//! fastest (and shortest) when the jerk is `±J` with an optional constant
//! acceleration phase in between (Biagiotti and Melchiorri 2008, eqs. 3.19
//! and 3.20). With `dv = |v_to - v_from|`:
//!
//! * the acceleration does not saturate when `dv <= A²/J`: two jerk phases of
//!   `Tj = sqrt(dv/J)` each, duration `2 Tj`, peak acceleration `sqrt(J dv)`;
//! * it saturates when `dv > A²/J`: `Tj = A/J`, duration `Tj + dv/A`.
//!
//! The velocity is point-symmetric about the middle of the change, so the
//! distance is always `(v_from + v_to)/2 * duration` (book eq. 3.21 uses the
//! same fact).
//!
//! Reachability inverts this distance. Accelerating from `v0` over a length
//! `L`, the largest final velocity `v1 = v0 + dv` satisfies:
//!
//! * without saturation, `(v0 + v1) sqrt(dv/J) = L`, i.e.
//!   `(v1 - v0)(v1 + v0)² = J L²`, a cubic in `dv`:
//!   `g(dv) = dv (2 v0 + dv)² - J L² = 0`. `g` is increasing and convex on
//!   `dv >= 0` (`g'' = 8 v0 + 6 dv > 0`) with `g(0) < 0`, so Newton's method
//!   started from an upper bound decreases monotonically onto the unique root.
//!   Upper bounds: `cbrt(J L²)` (since `(2 v0 + dv)² >= dv²`) and
//!   `J L² / (4 v0²)` (since `(2 v0 + dv)² >= 4 v0²`); we take the smaller.
//!   Solving for `dv` rather than `v1` keeps `dv` accurate when it is tiny
//!   compared with `v0`.
//! * with saturation, which happens exactly when
//!   `L > L_sat = (2 v0 + A²/J) A / J` (the distance of the unsaturated change
//!   with `dv = A²/J`), `(2 v0 + dv)/2 (A/J + dv/A) = L`, i.e. the quadratic
//!   `J dv² + (A² + 2 v0 J) dv + 2 v0 A² - 2 L A J = 0`, whose positive root
//!   we take in the cancellation-free form
//!   `dv = 4 A (L J - v0 A) / (b + sqrt(b² + 8 A J (L J - v0 A)))`,
//!   `b = A² + 2 v0 J`.
//!
//! Deceleration is the time reverse of acceleration, so the largest entry
//! velocity from which `v1` can be reached within `L` is the same function of
//! `v1` ([`max_entry_velocity`]). Neither function applies a velocity limit;
//! the caller takes the minimum with `vmax`.

use super::{check_limit, check_value, FeedError};
use crate::math::{abs, cbrt, cbrt_at_least, sqrt};

/// The fastest jerk-limited velocity change between two velocities, starting
/// and ending with zero acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityChange {
    /// Duration of each of the two jerk phases, s (`Tj1` or `Tj2`).
    pub tj: f64,
    /// Total duration, s (`Ta` or `Td`).
    pub duration: f64,
    /// Peak acceleration magnitude, mm/s² (`J * tj`, at most `A`).
    pub peak_acceleration: f64,
    /// Distance travelled, mm: `(v_from + v_to)/2 * duration`.
    pub distance: f64,
}

/// The fastest change from `v_from` to `v_to` (either direction) under the
/// acceleration limit `amax` and the jerk limit `jmax` (eqs. 3.19, 3.20).
pub fn velocity_change(
    v_from: f64,
    v_to: f64,
    amax: f64,
    jmax: f64,
) -> Result<VelocityChange, FeedError> {
    check_value("v_from", v_from)?;
    check_value("v_to", v_to)?;
    check_limit("amax", amax)?;
    check_limit("jmax", jmax)?;
    Ok(change_unchecked(v_from, v_to, amax, jmax))
}

/// [`velocity_change`] for inputs already checked.
pub(crate) fn change_unchecked(v_from: f64, v_to: f64, amax: f64, jmax: f64) -> VelocityChange {
    let (tj, duration, peak) = change_by(abs(v_to - v_from), amax, jmax);
    VelocityChange {
        tj,
        duration,
        peak_acceleration: peak,
        distance: 0.5 * (v_from + v_to) * duration,
    }
}

/// `(tj, duration, peak acceleration)` of the fastest change by `dv >= 0`
/// (eqs. 3.19, 3.20).
pub(crate) fn change_by(dv: f64, amax: f64, jmax: f64) -> (f64, f64, f64) {
    if dv * jmax < amax * amax {
        let tj = sqrt(dv / jmax);
        (tj, 2.0 * tj, jmax * tj)
    } else {
        let tj = amax / jmax;
        (tj, tj + dv / amax, amax)
    }
}

/// The largest velocity reachable by accelerating from `v0` over `length` mm
/// with acceleration at most `amax` and jerk at most `jmax`, the acceleration
/// starting and ending at zero. No velocity limit is applied. See the module
/// documentation for the closed forms.
pub fn max_reachable_velocity(
    v0: f64,
    length: f64,
    amax: f64,
    jmax: f64,
) -> Result<f64, FeedError> {
    check_value("v0", v0)?;
    check_value("length", length)?;
    check_limit("amax", amax)?;
    check_limit("jmax", jmax)?;
    let v = v0 + reach_gain(v0, length, amax, jmax);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(FeedError::BadValue {
            name: "length",
            value: length,
        })
    }
}

/// The largest entry velocity from which `v1` can be reached by decelerating
/// over `length` mm (the time reverse of [`max_reachable_velocity`]).
pub fn max_entry_velocity(v1: f64, length: f64, amax: f64, jmax: f64) -> Result<f64, FeedError> {
    check_value("v1", v1).and_then(|_| max_reachable_velocity(v1, length, amax, jmax))
}

/// The velocity gain `dv` of the module documentation, for checked inputs.
pub(crate) fn reach_gain(v0: f64, length: f64, amax: f64, jmax: f64) -> f64 {
    if length == 0.0 {
        return 0.0;
    }
    let (a, j, l) = (amax, jmax, length);
    let l_sat = (2.0 * v0 + a * a / j) * a / j;
    if l > l_sat {
        let b = a * a + 2.0 * v0 * j;
        let m = l * j - v0 * a;
        return 4.0 * a * m / (b + sqrt(b * b + 8.0 * a * j * m));
    }
    // Cubic g(dv) = dv (2 v0 + dv)^2 - J L^2, Newton from above.
    let rhs = j * l * l;
    // The lower of the two upper bounds (the cube root taken only where it
    // may be the lower).
    let mut dv = f64::INFINITY;
    if v0 > 0.0 {
        dv = rhs / (4.0 * v0 * v0);
    }
    if !cbrt_at_least(rhs, dv) {
        dv = dv.min(cbrt(rhs));
    }
    for _ in 0..200 {
        let s = 2.0 * v0 + dv;
        let g = dv * s * s - rhs;
        let dg = s * (2.0 * v0 + 3.0 * dv);
        if g <= 0.0 || dg <= 0.0 {
            break;
        }
        let next = dv - g / dg;
        if next >= dv {
            break; // rounding floor reached
        }
        // Convexity keeps `next` at or above the root; the clamp only guards
        // against rounding when the root is tiny (dv = 0 is conservative).
        dv = next.max(0.0);
    }
    dv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seeded::Rng;

    /// [`reach_gain`] as first written: Newton from the cube root, lowered
    /// to `rhs / (4 v0^2)` where that is less.
    fn reach_gain_from_the_root(v0: f64, length: f64, amax: f64, jmax: f64) -> f64 {
        if length == 0.0 {
            return 0.0;
        }
        let (a, j, l) = (amax, jmax, length);
        let l_sat = (2.0 * v0 + a * a / j) * a / j;
        if l > l_sat {
            let b = a * a + 2.0 * v0 * j;
            let m = l * j - v0 * a;
            return 4.0 * a * m / (b + sqrt(b * b + 8.0 * a * j * m));
        }
        let rhs = j * l * l;
        let mut dv = cbrt(rhs);
        if v0 > 0.0 {
            dv = dv.min(rhs / (4.0 * v0 * v0));
        }
        for _ in 0..200 {
            let s = 2.0 * v0 + dv;
            let g = dv * s * s - rhs;
            let dg = s * (2.0 * v0 + 3.0 * dv);
            if g <= 0.0 || dg <= 0.0 {
                break;
            }
            let next = dv - g / dg;
            if next >= dv {
                break;
            }
            dv = next.max(0.0);
        }
        dv
    }

    /// Skipping the cube root where the other bound is lower changes no
    /// bit, from rest and from speeds where either bound is the lower.
    #[test]
    fn seeded_random_gains_as_from_the_root() {
        let mut rng = Rng(0x4EAC);
        for i in 0..100_000 {
            let (a, j) = (rng.decades(2.0, 5.0), rng.decades(3.0, 6.0));
            let v0 = if i % 5 == 0 {
                0.0
            } else {
                rng.decades(-3.0, 3.0)
            };
            let l = rng.decades(-5.0, 2.0);
            let want = reach_gain_from_the_root(v0, l, a, j);
            assert_eq!(
                reach_gain(v0, l, a, j).to_bits(),
                want.to_bits(),
                "{v0} {l} {a} {j}"
            );
        }
    }
}
