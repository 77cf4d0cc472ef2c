//! Planning the feed along a run: segments with speed caps, a
//! bidirectional jerk-limited look-ahead over the whole run, and a double-S
//! profile per segment.
//!
//! 1. **Segments.** A line is one segment. Arcs and curves are cut where
//!    their chords deviate by the machine's chord error (the interpolator's
//!    own resolution); each interval is a segment whose cap is the smallest
//!    [`speed_cap`] at its ends and middle, with `dkappa/ds` from the change
//!    of curvature across it.
//! 2. **Boundaries.** The speed at a boundary is at most the caps of both
//!    neighbours and, at a joint between pieces that is not G2, the
//!    [`junction_cap`]. The run starts and ends at rest. Consecutive
//!    segments with caps within [`MERGE_RATIO`] and a boundary that does not
//!    constrain (a G2 joint, or a junction cap at least the caps) are merged
//!    at the lower cap, so that the machine can accelerate across many
//!    short moves.
//! 3. **Look-ahead.** A backward pass lowers every boundary speed to what
//!    can still be braked to the next one within the segment
//!    ([`max_entry_velocity`]), a forward pass to what can be reached from
//!    the previous one ([`max_reachable_velocity`]); both are exact for
//!    jerk-limited motion starting and ending at zero acceleration.
//!    With [`PlanOptions::window`] the look-ahead is bounded as on a
//!    real-time controller: it sees `n` segments ahead and must be able to
//!    stop at the end of them.
//! 4. **Profiles.** Each segment gets the fastest seven-phase double-S
//!    profile ([`DoubleS`]) between its boundary speeds under its cap.
//!
//! Every segment starts and ends at zero tangential acceleration, which is
//! conservative (a little slower than a planner that lets acceleration run
//! across boundaries) but keeps every limit exactly.

use super::limits::{junction_cap, speed_cap, Constraint, MachineLimits, PathPoint};
use super::{max_entry_velocity, max_reachable_velocity, DoubleS, FeedError, Limits};
use crate::geom::{flatten_params, Curve, ParamCurve};
use crate::path::Piece;
use crate::smooth::verify::{classify_joint, Continuity, JointTolerances};
use alloc::vec::Vec;

/// Consecutive segments whose caps are within this ratio (and whose
/// boundary does not constrain) are merged at the lower cap: a little speed
/// is given up inside the merged segment to avoid bringing the acceleration
/// back to zero at every boundary.
pub const MERGE_RATIO: f64 = 0.9;

/// How to plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanOptions {
    pub limits: MachineLimits,
    /// Run every feed move at the machine's maximum feed (the seeds'
    /// simulations do), ignoring programmed feeds.
    pub override_feed: bool,
    /// `None`: look ahead over the whole run (an offline planner).
    /// `Some(n)`: a real-time controller's bounded look-ahead, which sees
    /// only the next `n` segments and must always be able to stop at the
    /// end of what it sees.
    pub window: Option<usize>,
}

/// One planned segment of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedSegment {
    /// The stretches of path it covers, in order: (piece index in the run,
    /// parameter interval on its curve, arc length in mm).
    pub parts: Vec<(usize, f64, f64, f64)>,
    /// Arc length, mm.
    pub length: f64,
    /// Speed cap, mm/s, and what sets it.
    pub cap: f64,
    pub constraint: Constraint,
    pub profile: DoubleS,
}

impl PlannedSegment {
    /// The piece and curve parameter at arc length `q` into the segment
    /// (linear in the parameter within each part: parts of curves are
    /// chord-error short).
    pub fn locate(&self, q: f64) -> (usize, f64) {
        let mut rest = q.max(0.0);
        for &(piece, t0, t1, len) in &self.parts {
            if rest <= len {
                let f = if len > 0.0 { rest / len } else { 0.0 };
                return (piece, t0 + (t1 - t0) * f);
            }
            rest -= len;
        }
        let &(piece, _, t1, _) = self.parts.last().expect("a segment has parts");
        (piece, t1)
    }
}

/// A planned run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunPlan {
    pub segments: Vec<PlannedSegment>,
    /// Duration, s.
    pub time: f64,
    /// Largest tangential acceleration and jerk magnitudes used.
    pub max_acc: f64,
    pub max_jerk: f64,
}

fn point(c: &Curve, t: f64) -> (PathPoint, f64) {
    let d1 = c.deriv1(t);
    let d2 = c.deriv2(t);
    let tangent = d1.normalized(0.0).unwrap_or(crate::geom::Vec3::X);
    let k = crate::geom::curvature_vector_from(d1, d2);
    (
        PathPoint {
            tangent,
            curvature: k,
            dkappa_ds: 0.0,
        },
        k.norm(),
    )
}

/// Plans a run of feed moves (continuous pieces).
pub fn plan_run(pieces: &[Piece], opts: &PlanOptions) -> Result<RunPlan, FeedError> {
    let m = &opts.limits;
    m.validate().map_err(|e| FeedError::BadLimit {
        name: e.name,
        value: e.value,
    })?;
    let jt = JointTolerances::from_tolerance(m.chord_error);
    // Segments: (piece, t0, t1, length, cap, constraint).
    let mut segs: Vec<(usize, f64, f64, f64, f64, Constraint)> = Vec::new();
    // Junction cap at the start of each segment (INFINITY inside pieces).
    let mut junction: Vec<f64> = Vec::new();
    let mut prev: Option<usize> = None;
    for (pi, p) in pieces.iter().enumerate() {
        let feed = if opts.override_feed {
            m.max_feed
        } else {
            p.feed.map(|f| f / 60.0).unwrap_or(m.max_feed)
        };
        if !(feed > 0.0 && feed.is_finite()) {
            return Err(FeedError::BadValue {
                name: "feed",
                value: feed,
            });
        }
        let c = &p.curve;
        let len_total = c.length(m.chord_error * 1e-3);
        if len_total.is_nan() || len_total <= 0.0 {
            continue;
        }
        let jcap = match prev {
            Some(q) if classify_joint(&pieces[q].curve, c, &jt) != Continuity::G2 => {
                let a = &pieces[q].curve;
                let (_, ta) = a.domain();
                let (tb, _) = c.domain();
                let (pa, _) = point(a, ta);
                let (pb, _) = point(c, tb);
                junction_cap(m, pa.tangent, pb.tangent, pa.curvature, pb.curvature)
            }
            _ => f64::INFINITY,
        };
        prev = Some(pi);
        let ts = match c {
            Curve::Line(_) => alloc::vec![0.0, 1.0],
            _ => flatten_params(c, m.chord_error),
        };
        for (k, w) in ts.windows(2).enumerate() {
            let (t0, t1) = (w[0], w[1]);
            let len = match c {
                Curve::Line(_) => len_total,
                _ => crate::geom::arc_length_between(c, t0, t1, m.chord_error * 1e-4),
            };
            if len.is_nan() || len <= 0.0 {
                continue;
            }
            let (p0, k0) = point(c, t0);
            let (pm, km) = point(c, 0.5 * (t0 + t1));
            let (p1, k1) = point(c, t1);
            let dk = (k1 - k0) / len;
            let dk_mid = crate::math::abs(k1 - km).max(crate::math::abs(km - k0)) * 2.0 / len;
            let mut cap = (f64::INFINITY, Constraint::Feed);
            for mut pp in [p0, pm, p1] {
                pp.dkappa_ds = crate::math::abs(dk).max(dk_mid);
                let c = speed_cap(m, feed, &pp);
                if c.0 < cap.0 {
                    cap = c;
                }
            }
            segs.push((pi, t0, t1, len, cap.0, cap.1));
            junction.push(if k == 0 { jcap } else { f64::INFINITY });
        }
    }
    // Merge segments whose boundary does not constrain the speed.
    let mut merged: Vec<(usize, f64, f64, f64, f64, Constraint)> = Vec::with_capacity(segs.len());
    let mut mjunction: Vec<f64> = Vec::with_capacity(segs.len());
    let mut parts: Vec<Vec<(usize, f64, f64, f64)>> = Vec::with_capacity(segs.len());
    for (s, j) in segs.into_iter().zip(junction) {
        if let Some(last) = merged.last_mut() {
            let (lo, hi) = (last.4.min(s.4), last.4.max(s.4));
            if lo >= MERGE_RATIO * hi && j >= hi {
                if s.4 < last.4 {
                    last.4 = s.4;
                    last.5 = s.5;
                }
                last.3 += s.3;
                parts.last_mut().unwrap().push((s.0, s.1, s.2, s.3));
                continue;
            }
        }
        parts.push(alloc::vec![(s.0, s.1, s.2, s.3)]);
        merged.push(s);
        mjunction.push(j);
    }
    let (segs, junction) = (merged, mjunction);
    let n = segs.len();
    let mut plan = RunPlan::default();
    if n == 0 {
        return Ok(plan);
    }
    // Boundary caps: rest at both ends.
    let mut v = alloc::vec![0.0f64; n + 1];
    for i in 1..n {
        v[i] = segs[i - 1].4.min(segs[i].4).min(junction[i]);
    }
    match opts.window {
        None => {
            // Backward pass, then forward pass.
            for i in (0..n).rev() {
                let e = max_entry_velocity(v[i + 1], segs[i].3, m.acc, m.jerk)?;
                v[i] = v[i].min(e);
            }
            for i in 0..n {
                let r = max_reachable_velocity(v[i], segs[i].3, m.acc, m.jerk)?;
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
            let caps = v.clone();
            let w = w.max(1);
            let mut plan_b = alloc::vec![0.0f64; n + 1];
            for i in 0..n {
                let end = (i + w).min(n);
                let mut nb = alloc::vec![0.0f64; end - i + 1]; // boundaries i..=end
                for k in (i + 1..end).rev() {
                    nb[k - i] =
                        caps[k].min(max_entry_velocity(nb[k + 1 - i], segs[k].3, m.acc, m.jerk)?);
                }
                let reach = max_reachable_velocity(v[i], segs[i].3, m.acc, m.jerk)?;
                let candidate = nb[1].min(reach).min(caps[i + 1]);
                let feasible = candidate >= v[i]
                    || v[i]
                        <= max_entry_velocity(candidate, segs[i].3, m.acc, m.jerk)? * (1.0 - 1e-9);
                if feasible || i == 0 {
                    plan_b[i + 1..=end].copy_from_slice(&nb[1..]);
                    v[i + 1] = candidate;
                } else {
                    v[i + 1] = plan_b[i + 1].min(reach);
                }
            }
        }
    }
    for (i, (s, parts)) in segs.into_iter().zip(parts).enumerate() {
        let lim = Limits::new(s.4, m.acc, m.jerk)?;
        let profile = DoubleS::plan(s.3, v[i].min(s.4), v[i + 1].min(s.4), &lim)?;
        plan.time += profile.duration();
        plan.max_acc = plan.max_acc.max(profile.alim_a()).max(profile.alim_d());
        let ph = profile.phases();
        if ph.tj1 > 0.0 || ph.tj2 > 0.0 {
            plan.max_jerk = m.jerk;
        }
        plan.segments.push(PlannedSegment {
            parts,
            length: s.3,
            cap: s.4,
            constraint: s.5,
            profile,
        });
    }
    Ok(plan)
}

/// A rapid move of `length` mm from rest to rest at the machine's maximum
/// feed, acceleration and jerk.
pub fn plan_rapid(length: f64, m: &MachineLimits) -> Result<DoubleS, FeedError> {
    DoubleS::plan(length, 0.0, 0.0, &Limits::new(m.max_feed, m.acc, m.jerk)?)
}
