//! The look-ahead (step 3 of the planner, [`super::plan`]): the speed at
//! every boundary between a run's segments, by a backward pass (what can
//! still be braked to the next boundary within the segment,
//! [`max_entry_velocity`]) and a forward pass (what can be reached from
//! the previous one, [`max_reachable_velocity`]), over the whole run or
//! within a real-time controller's bounded window.
//!
//! It sees only the segments' lengths, the caps at their boundaries and
//! their tangential limits, not the path: the passes are the same whatever
//! set the caps.

use super::{max_entry_velocity, max_reachable_velocity, FeedError};
use alloc::vec::Vec;

/// Relative margin of the bounded look-ahead's braking test: a committed
/// speed within this share of the highest one that still brakes to a new
/// window's target is taken as not braking in time, so that a speed equal
/// to it up to rounding does not commit a profile that overshoots the
/// target by that rounding.
const BRAKING_ROUNDING_SHARE: f64 = 1e-9;

/// Boundary speeds of segments of `lengths` with boundary caps `caps`
/// (`caps.len() == lengths.len() + 1`, both ends at rest): the full
/// bidirectional scan, or the bounded look-ahead of `window` segments.
pub(super) fn boundary_speeds(
    lengths: &[f64],
    caps: &[f64],
    window: Option<usize>,
    tl: &[(f64, f64)],
) -> Result<Vec<f64>, FeedError> {
    let n = lengths.len();
    let mut v = caps.to_vec();
    match window {
        None => {
            for i in (0..n).rev() {
                let e = max_entry_velocity(v[i + 1], lengths[i], tl[i].0, tl[i].1)?;
                v[i] = v[i].min(e);
            }
            for i in 0..n {
                let r = max_reachable_velocity(v[i], lengths[i], tl[i].0, tl[i].1)?;
                v[i + 1] = v[i + 1].min(r);
            }
        }
        Some(w) => {
            // Sliding window: at segment i the planner sees segments
            // i..i+w, assumes a stop at the end of them, and commits the
            // speed at the end of segment i. With jerk limits, braking to a
            // higher speed can take longer than braking to rest (a
            // zero-acceleration-to-zero-acceleration change of dv at mean
            // speed vm takes vm sqrt(dv/J)), so a new window's target is
            // taken only when it is reachable from the committed speed;
            // otherwise the previous window's plan, which was, goes on.
            let w = w.max(1);
            let mut plan_b = alloc::vec![0.0f64; n + 1];
            for i in 0..n {
                let end = (i + w).min(n);
                let mut nb = alloc::vec![0.0f64; end - i + 1]; // boundaries i..=end
                for k in (i + 1..end).rev() {
                    nb[k - i] = caps[k].min(max_entry_velocity(
                        nb[k + 1 - i],
                        lengths[k],
                        tl[k].0,
                        tl[k].1,
                    )?);
                }
                let reach = max_reachable_velocity(v[i], lengths[i], tl[i].0, tl[i].1)?;
                let candidate = nb[1].min(reach).min(caps[i + 1]);
                let feasible = candidate >= v[i]
                    || v[i]
                        <= max_entry_velocity(candidate, lengths[i], tl[i].0, tl[i].1)?
                            * (1.0 - BRAKING_ROUNDING_SHARE);
                if feasible || i == 0 {
                    plan_b[i + 1..=end].copy_from_slice(&nb[1..]);
                    v[i + 1] = candidate;
                } else {
                    v[i + 1] = plan_b[i + 1].min(reach);
                }
            }
        }
    }
    Ok(v)
}
