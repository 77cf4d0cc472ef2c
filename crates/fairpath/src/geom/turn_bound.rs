//! The curvature a turn needs inside a tolerance band: what the smoothing of
//! a corner can be held against.
//!
//! A path turning by the angle `phi` (its deflection, 0 for straight on,
//! `pi` for a reversal) at a corner between two straight legs, that stays
//! within `band` of them and leaves them along each leg no further than
//! `leg` from the corner, can do no better than the circular arc tangent
//! to both legs that uses the whole band, or the whole legs if those are
//! shorter. Elementary geometry of the inscribed circle, the one a
//! junction-deviation planner blends with (`feed/junction.rs`: `R = e
//! sin(a) / (1 - sin(a))`, `a = (pi - phi) / 2`, with `e` measured from the
//! corner; S. Jeon, "Improving Grbl: cornering algorithm", 2011), measured
//! here from the legs, as the tolerance is:
//!
//! * the arc of radius `R` tangent to both legs has its centre on the
//!   bisector at `R / cos(phi/2)` from the corner, so its middle is
//!   `R (1/cos(phi/2) - 1)` from the corner along the bisector, which is
//!   `R (1 - cos(phi/2))` from each leg; within `band`:
//!   `1/R >= (1 - cos(phi/2)) / band = 2 sin^2(phi/4) / band`;
//! * it touches each leg `R tan(phi/2)` from the corner; within `leg`:
//!   `1/R >= tan(phi/2) / leg`.
//!
//! [`turn_curvature`] is the larger of the two. A curvature-continuous
//! transition (zero curvature where it meets its legs) must peak above
//! the arc's constant curvature; the corner transitions of seeds 000 and
//! 001 peak at about 1.6 times it on long legs (`crates/fairpath-gcode/tests/tiny_jogs.rs`).

use crate::math;

/// The curvature (1/mm) of the circular arc that turns by `deflection`
/// radians between two legs inside a band of `band` mm, touching each leg
/// no further than `leg` mm from the corner (module docs): the least
/// curvature any tangent-continuous turn there can keep to. Infinite for a
/// reversal (`deflection >= pi`) and for `band` or `leg` not positive.
pub fn turn_curvature(deflection: f64, band: f64, leg: f64) -> f64 {
    let phi = deflection.abs();
    if phi == 0.0 {
        return 0.0;
    }
    if phi >= core::f64::consts::PI || band <= 0.0 || leg <= 0.0 {
        return f64::INFINITY;
    }
    let s = math::sin(0.25 * phi);
    let by_band = 2.0 * s * s / band;
    let by_leg = math::tan(0.5 * phi) / leg;
    by_band.max(by_leg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    /// A right angle on long legs: the arc's middle is `band` from the
    /// legs, `R (1 - cos 45)` = band.
    #[test]
    fn a_right_angle_on_long_legs_uses_the_band() {
        let k = turn_curvature(PI / 2.0, 0.05, 100.0);
        let r = 1.0 / k;
        assert!((r * (1.0 - (PI / 4.0).cos()) - 0.05).abs() < 1e-12);
        // On short legs the arc touches them at their ends.
        let k = turn_curvature(PI / 2.0, 0.05, 0.01);
        assert!((1.0 / k * (PI / 4.0).tan() - 0.01).abs() < 1e-12);
    }

    #[test]
    fn straight_on_needs_none_and_a_reversal_cannot_be_turned() {
        assert_eq!(turn_curvature(0.0, 0.05, 1.0), 0.0);
        assert_eq!(turn_curvature(PI, 0.05, 1.0), f64::INFINITY);
        assert_eq!(turn_curvature(1.0, 0.0, 1.0), f64::INFINITY);
        assert!(turn_curvature(1.0, 0.05, 1.0) < turn_curvature(2.0, 0.05, 1.0));
    }
}
