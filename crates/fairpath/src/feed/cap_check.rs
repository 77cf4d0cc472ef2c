//! The check of a planned profile against the caps inside its segment
//! (step 2 of the planner, [`super::plan`]). A segment gets one double-S
//! profile under its highest cap; where the cap inside rises more slowly
//! than the machine accelerates, that profile passes a lower cap of a
//! stretch or of a joint, and the check names the stretch boundary to
//! split the segment at, the worst first. The exact speed at an arc length
//! is looked up only where it passes the cap (a cheap bound, then the arc
//! length at which the profile reaches the cap, in closed form, settle the
//! rest) and could pass it by more than the worst found so far: when
//! `auto` costs its candidates, most stretches checked pass their cap
//! (the first profile of a long segment passes many), and only the worst
//! of them names the split.
//!
//! The planner runs it on every profile it makes, so it is kept apart from
//! how the caps and the profiles are made.

use super::caps::Stretch;
use super::DoubleS;

/// Relative slack of the check of a profile against the caps inside its
/// segment: rounding of the profile's closed forms, far below any speed
/// that matters.
pub const CAP_SLACK: f64 = 1e-9;

/// Relative rounding (of the segment's length) of the arc length at which
/// a profile's speed crosses a cap, computed in closed form
/// ([`DoubleS::time_at_speed`]): arc lengths this close to the crossing
/// get the exact lookup of the speed, so the closed form never hides a
/// cap passed.
const CROSSING_ROUNDING: f64 = 1e-12;

/// The speed of `profile` at arc length `q`, on its rising side (`rising`)
/// or its falling side.
fn speed_at(profile: &DoubleS, q: f64, rising: bool) -> f64 {
    let ph = profile.phases();
    let (mut lo, mut hi) = if rising {
        (0.0, ph.ta)
    } else {
        (ph.ta + ph.tv, profile.duration())
    };
    // Safeguarded Newton on time: q(t) is increasing with slope v(t), so
    // a Newton step converges in a few iterations where bisection took
    // about 55 (this lookup was a large share of planning a long run of
    // arcs; measurements: docs/tuning.md, `speed_at`);
    // a step that leaves the bracket, or a point at rest, bisects
    // instead. 64 steps reach f64 resolution of any duration either way.
    let mut t = 0.5 * (lo + hi);
    for _ in 0..64 {
        let st = profile.eval(t);
        if st.q < q {
            lo = t;
        } else {
            hi = t;
        }
        let newton = t - (st.q - q) / st.v;
        let next = if st.v > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next <= lo || next >= hi || crate::math::abs(next - t) <= f64::EPSILON * t {
            return profile.eval(next.clamp(lo, hi)).v;
        }
        t = next;
    }
    profile.eval(hi).v
}

/// Checks `profile` against the caps of `parts`. Returns the stretch
/// boundary (index into `parts`, 0..=len) at which to split where the
/// profile passes a cap, the worst first, or `None`.
pub(super) fn violation(
    profile: &DoubleS,
    parts: &[Stretch],
    lower_boundary: &[f64],
) -> Option<usize> {
    let ph = profile.phases();
    let peak_lo = profile.eval(ph.ta).q;
    let peak_hi = profile.eval(ph.ta + ph.tv).q;
    let vpeak = profile.vlim().max(profile.v0()).max(profile.v1());
    // Cheap upper bounds of the speed at arc length q (dv^2/dq = 2a and
    // |a| is at most the profile's peak): the exact speed is looked up
    // only where a bound passes the cap.
    let total: f64 = parts.iter().map(|st| st.length).sum();
    let (a_up, a_down) = (
        crate::math::abs(profile.alim_a()),
        crate::math::abs(profile.alim_d()),
    );
    // Whether the speed at q on the rising (or falling) side passes `cap`
    // (the cap `reference` with its slack) by a larger ratio to
    // `reference` than `beat`: `None` where it does not, else `Some` of
    // the speed there. Only such a speed can change the worst violation,
    // and only it is looked up exactly: the others are settled by the
    // cheap bound, or by the arc length at which the speed equals the cap
    // (the closed-form inverse of the speed, monotone on either side).
    let exceeds = |q: f64, cap: f64, reference: f64, beat: f64, rising: bool| {
        let (v_end, a_max, dist) = if rising {
            (profile.v0(), a_up, q)
        } else {
            (profile.v1(), a_down, total - q)
        };
        let bound = crate::math::sqrt(v_end * v_end + 2.0 * a_max * dist.max(0.0)).min(vpeak);
        if bound <= cap || bound / reference <= beat {
            return None;
        }
        // Arc lengths within rounding of the crossing are looked up too.
        let q_cap = profile.eval(profile.time_at_speed(cap, rising)).q;
        let near = CROSSING_ROUNDING * total;
        let over = if rising {
            q > q_cap - near
        } else {
            q < q_cap + near
        };
        if !over {
            return None;
        }
        let v = speed_at(profile, q, rising);
        (v > cap && v / reference > beat).then_some(v)
    };
    let mut worst: Option<(f64, usize)> = None;
    let mut s0 = 0.0;
    for (k, st) in parts.iter().enumerate() {
        let s1 = s0 + st.length;
        let cap = st.cap * (1.0 + CAP_SLACK);
        // The ratio a violation must pass to be the worst so far.
        let beat = worst.map_or(0.0, |(r, _)| r);
        // v(q) rises to the peak plateau, then falls: the largest speed on
        // [s0, s1] is at the end nearer the plateau.
        let (over, at) = if s1 < peak_lo {
            (
                if vpeak <= cap {
                    None
                } else {
                    exceeds(s1, cap, st.cap, beat, true)
                },
                k + 1,
            )
        } else if s0 > peak_hi {
            (
                if vpeak <= cap {
                    None
                } else {
                    exceeds(s0, cap, st.cap, beat, false)
                },
                k,
            )
        } else {
            // The plateau is inside: split at the inner end with the
            // lower cap.
            let inner = |i: usize| i != 0 && i != parts.len();
            let at = match (inner(k), inner(k + 1)) {
                (true, true) if lower_boundary[k + 1] < lower_boundary[k] => k + 1,
                (true, _) => k,
                (false, _) => k + 1,
            };
            ((vpeak > cap).then_some(vpeak), at)
        };
        // A split at the segment's own ends is no split: the speed there is
        // already within the cap, and only rounding can exceed it.
        if let Some(vmax) = over {
            if at != 0 && at != parts.len() {
                let ratio = vmax / st.cap;
                if worst.is_none_or(|(r, _)| ratio > r) {
                    worst = Some((ratio, at));
                }
            }
        }
        // The junction cap at the inner boundary at the end of this
        // stretch.
        let jb = lower_boundary[k + 1] * (1.0 + CAP_SLACK);
        if k + 1 < parts.len() && vpeak > jb {
            let beat = worst.map_or(0.0, |(r, _)| r);
            let over = if s1 < peak_lo {
                exceeds(s1, jb, lower_boundary[k + 1], beat, true)
            } else if s1 > peak_hi {
                exceeds(s1, jb, lower_boundary[k + 1], beat, false)
            } else {
                Some(vpeak)
            };
            if let Some(v) = over {
                let ratio = v / lower_boundary[k + 1];
                if worst.is_none_or(|(r, _)| ratio > r) {
                    worst = Some((ratio, k + 1));
                }
            }
        }
        s0 = s1;
    }
    worst.map(|(_, at)| at)
}
