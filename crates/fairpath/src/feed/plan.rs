//! Planning the feed along a run: a cap on the speed at every point, a
//! bidirectional jerk-limited look-ahead over the whole run, and one
//! double-S profile from each speed minimum to the next.
//!
//! 1. **Caps.** A line is one stretch. Arcs and curves are cut where
//!    their chords deviate by the machine's chord error (the interpolator's
//!    own resolution), a spline span by span; each interval is a stretch whose cap is the smallest
//!    [`speed_cap`](super::limits::speed_cap) at its ends and middle, with `dkappa/ds` from the change
//!    of curvature across it. At a joint between pieces that is not G2 the
//!    speed is also capped as in [`super::junction`]. The run starts and
//!    ends at rest.
//! 2. **Segments.** The profile of a segment starts and ends at zero
//!    acceleration, so segment boundaries cost time where the machine
//!    would rather keep accelerating. Boundaries are therefore put only
//!    where the cap has a local minimum (the "critical points" of feed
//!    scheduling, where the optimal speed touches the cap with zero
//!    acceleration), and each segment gets one profile under the highest
//!    cap inside it. Where that profile would pass a lower cap inside the
//!    segment (the cap rises more slowly than the machine accelerates),
//!    the segment is split at the worst stretch boundary and the run is
//!    planned again, until every profile stays under every cap. A
//!    minimum that the planned speed stays more than [`UNREACHED_CAP`]
//!    below is dropped first: the machine passes it accelerating or
//!    braking, and a boundary there would stop the acceleration for
//!    nothing (a fitted curve's cap ripples by fractions of a percent;
//!    with a boundary at every ripple the machine took far longer over a
//!    270-degree helical arc of `tort.ngc`; measurements: docs/tuning.md,
//!    `UNREACHED_CAP`).
//! 3. **Look-ahead.** A backward pass lowers every boundary speed to what
//!    can still be braked to the next one within the segment
//!    ([`max_entry_velocity`]), a forward pass to what can be reached from
//!    the previous one ([`max_reachable_velocity`]); both are exact for
//!    jerk-limited motion starting and ending at zero acceleration.
//!    With [`PlanOptions::window`] the look-ahead is bounded as on a
//!    real-time controller: it sees `n` segments ahead and must be able to
//!    stop at the end of them.
//! 4. **Profiles.** Each segment gets the fastest seven-phase double-S
//!    profile ([`DoubleS`]) between its boundary speeds.
//!
//! Zero acceleration at the (few) boundaries is conservative: a little
//! slower than a planner that lets acceleration run across them, but every
//! limit holds exactly.
//!
//! This file holds the plan's types and [`plan_run_shaped`], which ties the
//! steps together. The steps that stand on their own are in files private
//! to `feed` (what they make public is re-exported here): the caps of
//! step 1 in `caps.rs`, the check of a profile against the caps inside its
//! segment of step 2 in `cap_check.rs`, and the passes of step 3 in
//! `lookahead.rs`.

pub use super::cap_check::CAP_SLACK;
pub use super::caps::{block_cap, followed_corner_cap, CAP_SPLIT_RATIO};

use super::cap_check::violation;
use super::caps::stretches;
use super::limits::{Constraint, MachineLimits};
use super::lookahead::boundary_speeds;
use super::shaping::Shaping;
use super::{max_entry_velocity, max_reachable_velocity, DoubleS, FeedError, Limits};
use crate::path::Piece;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;

/// A minimum of the cap counts as reached (a segment boundary is kept
/// there) when the planned speed comes within this share of it.
pub const UNREACHED_CAP: f64 = 0.02;

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
    /// The speed a run starts and ends at.
    pub ends: RunEnds,
}

/// The speed at a run's two ends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RunEnds {
    /// At rest: a run between rapids, or at a program's start and end.
    #[default]
    AtRest,
    /// At the speed cap there (the feed, or less on a curve): the thesis'
    /// simulation (seed 003, section 4.5: "the trajectory generator assumed
    /// that the feedrate was capable of maximum velocity at the beginning
    /// and end of the tool paths"), for comparing its tables like for like.
    AtCap,
}

/// How the machine passes a corner (a joint where the tangent turns).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Corners {
    /// On a blend circle within the junction deviation, as a blending
    /// controller does ([`super::junction`]): the plan of a G-code program
    /// that a controller runs.
    #[default]
    Blended,
    /// Through the corner point itself, as a stream of positions that
    /// follows the path exactly does: the direction changes within one
    /// period, a velocity step of `dv = 2 v sin(phi / 2)`, which the
    /// sampled motion shows as an acceleration `dv / Ts` in one period and
    /// a jerk `dv / (5 Ts^2)` averaged over five
    /// ([`super::sampled`]). The speed at the corner is capped so that
    /// both stay within the limits: `v <= min(A Ts, 5 J Ts^2) / (2 sin(phi/2))`.
    Followed,
    /// As [`Corners::Blended`], and every joint between two pieces is also
    /// capped at the speed the shorter of them reaches from rest over half
    /// its length under the acceleration and jerk limits: the model of
    /// LinuxCNC master's S-curve planner, which caps the speed at the end
    /// of every block at its rest-to-rest peak speed (`tp.c`:
    /// `tpComputeOptimalVelocity` -> `findSCurveVPeak`; about
    /// `(L sqrt(J) / 2)^(2/3)` for a block of length `L`). Each piece is
    /// one block.
    BlockCapped,
}
/// A stretch of path inside a segment, with its own speed cap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    /// Index of the piece in the run.
    pub piece: usize,
    /// Parameter interval on the piece's curve.
    pub t0: f64,
    pub t1: f64,
    /// Arc length, mm.
    pub length: f64,
    /// Speed cap on this stretch, mm/s.
    pub cap: f64,
    /// Speed cap at its start from the joint before it (mm/s; INFINITY
    /// inside pieces and at G2 joints).
    pub entry_cap: f64,
}

/// One planned segment of a run: from one speed minimum to the next.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedSegment {
    /// The stretches of path it covers, in order.
    pub parts: Vec<Part>,
    /// Arc length, mm.
    pub length: f64,
    /// Highest cap inside the segment (the profile's speed limit), mm/s;
    /// the profile stays under every part's own cap.
    pub cap: f64,
    /// The tightest constraint in the segment: what sets the lowest cap at
    /// its ends or inside it.
    pub constraint: Constraint,
    pub profile: DoubleS,
}

impl PlannedSegment {
    /// The piece and curve parameter at arc length `q` into the segment
    /// (linear in the parameter within each part: parts of curves are
    /// chord-error short).
    pub fn locate(&self, q: f64) -> (usize, f64) {
        let mut rest = q.max(0.0);
        for p in &self.parts {
            if rest <= p.length {
                let f = if p.length > 0.0 { rest / p.length } else { 0.0 };
                return (p.piece, p.t0 + (p.t1 - p.t0) * f);
            }
            rest -= p.length;
        }
        let p = self.parts.last().expect("a segment has parts");
        (p.piece, p.t1)
    }

    /// The speed cap (mm/s) at arc length `q` into the segment: the
    /// lower cap where two parts meet, and the joint's cap there.
    pub fn cap_at(&self, q: f64) -> f64 {
        let mut s0 = 0.0;
        let mut cap = f64::INFINITY;
        for p in &self.parts {
            let s1 = s0 + p.length;
            if q >= s0 && q <= s1 {
                cap = cap.min(p.cap);
            }
            if q == s0 {
                cap = cap.min(p.entry_cap);
            }
            if s0 > q {
                break;
            }
            s0 = s1;
        }
        if cap.is_finite() {
            cap
        } else {
            self.parts.last().map_or(0.0, |p| p.cap)
        }
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
/// Plans a run of feed moves (continuous pieces).
pub fn plan_run(pieces: &[Piece], opts: &PlanOptions) -> Result<RunPlan, FeedError> {
    plan_run_shaped(pieces, opts, &Shaping::none(), Corners::Blended)
}

/// [`plan_run`] with corners passed as `corners` says, and the caps and
/// tangential limits lowered by `shaping` (by arc length along the run).
/// Where the tangential factor changes, a segment boundary is kept, so
/// that a reduction on a curve does not slow the straight after it.
pub fn plan_run_shaped(
    pieces: &[Piece],
    opts: &PlanOptions,
    shaping: &Shaping,
    corners: Corners,
) -> Result<RunPlan, FeedError> {
    plan(pieces, opts, shaping, corners, true, At::START).map(|(p, _)| p)
}

/// The time (s) of [`plan_run_shaped`]'s plan, the same to the bit,
/// without its segments (where only the time is wanted, as when
/// candidates are compared: on a long run the segments' parts are a third
/// of the plan's memory).
pub fn plan_time_shaped(
    pieces: &[Piece],
    opts: &PlanOptions,
    shaping: &Shaping,
    corners: Corners,
) -> Result<f64, FeedError> {
    plan(pieces, opts, shaping, corners, false, At::START).map(|(p, _)| p.time)
}

/// Where a run's pieces lie along the run they are a window of: the arc
/// length (mm) at the start of piece `anchor` (an index in the window), as
/// the run's plan adds the stretches' lengths up to there; and a piece
/// (`mark`) at whose start the sum is wanted.
#[derive(Clone, Copy, Debug)]
pub(super) struct At {
    pub(super) s0: f64,
    pub(super) anchor: usize,
    pub(super) mark: usize,
}

impl At {
    /// A whole run.
    const START: At = At {
        s0: 0.0,
        anchor: 0,
        mark: 0,
    };
}

/// [`plan_run_shaped`] of `pieces`, a window of a run, piece `at.anchor`
/// starting `at.s0` along it (from there on, segment lengths are
/// differences of the same sums as the run's plan makes), without
/// shaping; with the sum at the start of piece `at.mark`.
pub(super) fn plan_window(
    pieces: &[Piece],
    opts: &PlanOptions,
    corners: Corners,
    at: At,
) -> Result<(RunPlan, f64), FeedError> {
    plan(pieces, opts, &Shaping::none(), corners, true, at)
}

/// [`plan_run_shaped`], with its segments only if `keep_segments`.
fn plan(
    pieces: &[Piece],
    opts: &PlanOptions,
    shaping: &Shaping,
    corners: Corners,
    keep_segments: bool,
    at: At,
) -> Result<(RunPlan, f64), FeedError> {
    let m = &opts.limits;
    m.validate().map_err(|e| FeedError::BadLimit {
        name: e.name,
        value: e.value,
    })?;
    let (st, located) = stretches(pieces, opts, shaping, corners, keep_segments)?;
    // The cap at the start of each stretch (INFINITY inside pieces and at
    // G2 joints).
    let junction = |i: usize| st[i].entry_cap;
    let n = st.len();
    let mut plan = RunPlan::default();
    if n == 0 {
        return Ok((plan, at.s0));
    }
    // Cap at each stretch boundary (rest at both ends, or the cap of the
    // end stretch) and what sets it.
    let mut bcap = alloc::vec![0.0f64; n + 1];
    for i in 1..n {
        bcap[i] = st[i - 1].cap.min(st[i].cap).min(junction(i));
    }
    if opts.ends == RunEnds::AtCap {
        bcap[0] = st[0].cap;
        bcap[n] = st[n - 1].cap;
    }
    // Initial segment boundaries: the ends and the local minima of the cap.
    let mut key = alloc::vec![false; n + 1];
    key[0] = true;
    key[n] = true;
    // Boundaries that stay: the ends and where the tangential factor
    // changes.
    let mut fixed = alloc::vec![false; n + 1];
    fixed[0] = true;
    fixed[n] = true;
    for i in 1..n {
        let (l, c, r) = (bcap[i - 1], bcap[i], bcap[i + 1]);
        if (c <= l && c < r) || (c < l && c <= r) {
            key[i] = true;
        }
        if st[i - 1].tangential != st[i].tangential {
            key[i] = true;
            fixed[i] = true;
        }
    }
    // Tangential acceleration and jerk of a segment [a, b): the machine's,
    // times the smallest factor inside.
    let seg_limits = |a: usize, b: usize| {
        let f = st[a..b].iter().map(|s| s.tangential).fold(1.0f64, f64::min);
        (m.acc * f, m.jerk * f)
    };
    // Prefix lengths of the stretches.
    // (From the anchor's first stretch on, as the run's plan adds them;
    // before it, back from there.)
    // (A plan without segments locates no stretch: 0, the whole run's
    // anchor.)
    let first_of = |piece: usize| located.partition_point(|l| l.piece < piece);
    let anchor = first_of(at.anchor);
    let mut pre = alloc::vec![at.s0; n + 1];
    for i in anchor..n {
        pre[i + 1] = pre[i] + st[i].length;
    }
    for i in (0..anchor).rev() {
        pre[i] = pre[i + 1] - st[i].length;
    }
    // The sum at the start of piece `at.mark` (where its first stretch
    // starts; the end of the run past the last piece).
    let marked = pre[first_of(at.mark)];
    // Split each segment until its fastest profile (boundary speeds at
    // their caps, as far as the segment allows) stays under every cap
    // inside. A profile between lower boundary speeds is slower everywhere,
    // so this segmentation holds for whatever the look-ahead chooses, and
    // is the same for the full scan and a bounded window.
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let mut a = 0;
    for (b, _) in key.iter().enumerate().skip(1).filter(|(_, &k)| k) {
        stack.push((a, b));
        a = b;
    }
    while let Some((a, b)) = stack.pop() {
        let len = pre[b] - pre[a];
        let vmax = st[a..b].iter().map(|s| s.cap).fold(0.0f64, f64::max);
        let (acc, jerk) = seg_limits(a, b);
        let v1 = bcap[b].min(vmax);
        let v0 = bcap[a]
            .min(vmax)
            .min(max_entry_velocity(v1, len, acc, jerk)?);
        let v1 = v1.min(max_reachable_velocity(v0, len, acc, jerk)?);
        let profile = DoubleS::plan(len, v0, v1, &Limits::new(vmax, acc, jerk)?)?;
        if let Some(k) = violation(&profile, &st[a..b], &bcap[a..=b]) {
            key[a + k] = true;
            stack.push((a, a + k));
            stack.push((a + k, b));
        }
    }
    // A minimum of the cap that the planned speed does not reach is no
    // critical point: the machine passes it accelerating
    // or braking. Its boundary would stop the acceleration there for
    // nothing (on a fitted curve, whose cap ripples by a fraction of a
    // percent, every ripple did), so it is dropped; where the merged
    // profile then passes a cap, the loop below splits it again.
    {
        let bounds: Vec<usize> = (0..=n).filter(|&i| key[i]).collect();
        let lengths: Vec<f64> = bounds.windows(2).map(|w| pre[w[1]] - pre[w[0]]).collect();
        let caps: Vec<f64> = bounds.iter().map(|&i| bcap[i]).collect();
        let tl: Vec<(f64, f64)> = bounds.windows(2).map(|w| seg_limits(w[0], w[1])).collect();
        let v = boundary_speeds(&lengths, &caps, opts.window, &tl)?;
        for (j, &i) in bounds.iter().enumerate() {
            if !fixed[i] && v[j] < bcap[i] * (1.0 - UNREACHED_CAP) {
                key[i] = false;
            }
        }
    }
    // Then the look-ahead, with a check of every profile against the caps
    // inside its segment, split where a profile passes one.
    // Profiles verified against their segment's inner caps, by start:
    // (end, v0, v1, what the plan keeps of the profile). Between rounds
    // most boundary speeds stay the same, and their segments are neither
    // planned nor checked again. (A map: one entry per segment, not one
    // per stretch, keeps this small on long runs, where the millions of
    // stretches of written arcs took hundreds of megabytes; measurements:
    // docs/tuning.md, `plan`. It keeps a [`ProfileSummary`], 24 bytes;
    // the 96-byte profiles are kept beside it only by a plan that keeps
    // its segments.)
    let mut verified: BTreeMap<usize, (usize, f64, f64, ProfileSummary)> = BTreeMap::new();
    let mut profiles: BTreeMap<usize, DoubleS> = BTreeMap::new();
    let (bounds, summaries) = loop {
        let bounds: Vec<usize> = (0..=n).filter(|&i| key[i]).collect();
        let lengths: Vec<f64> = bounds.windows(2).map(|w| pre[w[1]] - pre[w[0]]).collect();
        let caps: Vec<f64> = bounds.iter().map(|&i| bcap[i]).collect();
        let tl: Vec<(f64, f64)> = bounds.windows(2).map(|w| seg_limits(w[0], w[1])).collect();
        let v = boundary_speeds(&lengths, &caps, opts.window, &tl)?;
        let mut summaries = Vec::with_capacity(lengths.len());
        let mut split = false;
        for (j, w) in bounds.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let vmax = st[a..b].iter().map(|s| s.cap).fold(0.0f64, f64::max);
            let (v0, v1) = (v[j].min(vmax), v[j + 1].min(vmax));
            if let Some((end, w0, w1, s)) = verified.get(&a) {
                if (*end, *w0, *w1) == (b, v0, v1) {
                    summaries.push(*s);
                    continue;
                }
            }
            let (acc, jerk) = tl[j];
            let profile = DoubleS::plan(lengths[j], v0, v1, &Limits::new(vmax, acc, jerk)?)?;
            let summary = ProfileSummary::of(&profile);
            match violation(&profile, &st[a..b], &bcap[a..=b]) {
                Some(k) => {
                    key[a + k] = true;
                    split = true;
                }
                None => {
                    verified.insert(a, (b, v0, v1, summary));
                    if keep_segments {
                        profiles.insert(a, profile);
                    }
                }
            }
            summaries.push(summary);
        }
        if !split {
            break (bounds, summaries);
        }
    };
    drop(verified);
    for (w, summary) in bounds.windows(2).zip(summaries) {
        let (a, b) = (w[0], w[1]);
        plan.time += summary.duration;
        plan.max_acc = plan.max_acc.max(summary.max_acc);
        if summary.jerk_phases {
            plan.max_jerk = plan.max_jerk.max(seg_limits(a, b).1);
        }
        if !keep_segments {
            continue;
        }
        // Every segment of the last round passed its check, so its
        // profile is the one kept for it.
        let profile = profiles
            .remove(&a)
            .expect("the last round's segments are all verified");
        // The tightest constraint: the lowest cap among the stretches.
        let tight = (a..b)
            .min_by(|&x, &y| st[x].cap.total_cmp(&st[y].cap))
            .expect("a segment has stretches");
        let (mut constraint, mut low) = (located[tight].constraint, st[tight].cap);
        for i in [a, b] {
            if i != 0 && i != n && junction(i) < low {
                low = junction(i);
                constraint = Constraint::Junction;
            }
        }
        plan.segments.push(PlannedSegment {
            parts: (a..b).map(|i| located[i].part(&st[i])).collect(),
            length: pre[b] - pre[a],
            cap: st[a..b].iter().map(|s| s.cap).fold(0.0f64, f64::max),
            constraint,
            profile,
        });
    }
    Ok((plan, marked))
}

/// What a plan's time and peaks take from a segment's profile.
#[derive(Clone, Copy, Debug)]
struct ProfileSummary {
    /// [`DoubleS::duration`], s.
    duration: f64,
    /// The largest of [`DoubleS::alim_a`] and `-`[`DoubleS::alim_d`].
    max_acc: f64,
    /// The profile has a jerk phase (the segment's jerk limit is used).
    jerk_phases: bool,
}

impl ProfileSummary {
    fn of(p: &DoubleS) -> Self {
        let ph = p.phases();
        ProfileSummary {
            duration: p.duration(),
            max_acc: p.alim_a().max(-p.alim_d()),
            jerk_phases: ph.tj1 > 0.0 || ph.tj2 > 0.0,
        }
    }
}

/// A rapid move of `length` mm from rest to rest at the machine's maximum
/// feed, acceleration and jerk.
pub fn plan_rapid(length: f64, m: &MachineLimits) -> Result<DoubleS, FeedError> {
    DoubleS::plan(length, 0.0, 0.0, &Limits::new(m.max_feed, m.acc, m.jerk)?)
}
