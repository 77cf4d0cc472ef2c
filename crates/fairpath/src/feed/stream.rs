//! A servo-rate stream: the planned motion of a whole program as one
//! position per servo period, which a controller plays directly (LinuxCNC's
//! `halstreamer`), checked as the controller samples it.
//!
//! The stream follows the path exactly, so it has no blends: corners are
//! passed at the speed [`Corners::Followed`] allows. Every feed run is
//! planned by [`plan_run_shaped`], sampled on the program's clock (sample
//! `k` at `k Ts` from the start), and measured as the controller sees it
//! ([`super::sampled`]: velocity, acceleration and 5-period jerk, as 3D
//! magnitudes and per axis). The planner's caps bound each term of the
//! acceleration and jerk vectors on its own; the samples check their sum
//! (see [`super::shaping`] for the terms, among them the cross term
//! `3 k v a_t` that no cap holds). Where a run's samples exceed a limit, it
//! is planned again with its speed cap and its tangential acceleration and
//! jerk lowered (`stream_run` says how), until every sample is within every
//! limit.
//!
//! Rapids are rest-to-rest jerk-limited lines at the fastest speed,
//! acceleration and jerk the path and every axis allow along them; a dwell
//! holds the position for its time.

use super::plan::{plan_run_shaped, Corners, PlanOptions, RunPlan};
use super::sampled::{accelerations, measure, Excess, Peaks, Quantity, SampleLimits};
use super::shaping::{Reduction, Shaping};
use super::{DoubleS, FeedError, Limits, State};
use crate::geom::{arc_length_between, Curve, ParamCurve, Vec3};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// Factor by which every reduction undershoots what the measurement asks
/// for, so that a round rarely needs a second pass at the same place.
pub const REDUCTION_MARGIN: f64 = 0.98;

/// Factor on the whole run per round once local rounds are used up.
pub const GLOBAL_STEP: f64 = 0.8;

/// Samples of rest put before and after a run when it is measured on its
/// own (the motions before and after it are at rest where it starts and
/// ends): enough for the 5-period jerk.
const REST_PAD: usize = 6;

/// One motion of a program, in order.
#[derive(Clone, Copy, Debug)]
pub enum Motion<'a> {
    /// Continuous feed pieces, from rest to rest.
    Run(&'a [Piece]),
    /// A rapid (a line).
    Rapid(&'a Piece),
    /// A dwell of this many seconds.
    Dwell(f64),
}

/// How to stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StreamOptions {
    /// The machine (path and axis limits, servo period) and the feeds.
    pub plan: PlanOptions,
    /// Jerk limit of each axis (X, Y, Z), mm/s^3, held averaged over
    /// [`super::sampled::JERK_AVERAGE_PERIODS`] periods as the path jerk.
    pub axis_jerk: [f64; 3],
    /// Rounds of local reductions per run before the whole run is slowed.
    pub local_rounds: usize,
    /// Rounds per run in all; a run still above a limit then is an error.
    pub max_rounds: usize,
    /// Relative excess of a limit tolerated by the check: the rounding of
    /// the written positions (9 decimals of a mm move a 5 ms jerk by less
    /// than 1 mm/s^3).
    pub slack: f64,
}

impl StreamOptions {
    /// Streams for `plan`'s machine with axis jerks equal to its path jerk.
    pub fn new(plan: PlanOptions) -> StreamOptions {
        StreamOptions {
            axis_jerk: [plan.limits.jerk; 3],
            plan,
            local_rounds: 60,
            max_rounds: 120,
            slack: 1e-3,
        }
    }

    fn sample_limits(&self) -> SampleLimits {
        let m = &self.plan.limits;
        SampleLimits {
            period: m.period,
            vel: m.max_feed,
            acc: m.acc,
            jerk: m.jerk,
            axis_vel: m.axis_vel,
            axis_acc: m.axis_acc,
            axis_jerk: self.axis_jerk,
        }
    }
}

/// Why a stream could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StreamError {
    #[error("motion {index}: {source}")]
    Plan { index: usize, source: FeedError },
    #[error("motion {index} starts {gap} mm away from where the one before it ends: a stream cannot jump")]
    Gap { index: usize, gap: f64 },
    #[error("motion {index} still exceeds a limit after {rounds} rounds of planning")]
    NotWithinLimits { index: usize, rounds: usize },
    #[error(
        "the stream would have {samples:.0} samples (more than {max:.0}); use a longer period"
    )]
    TooLong { samples: f64, max: f64 },
    #[error("a limit of the stream is not a positive number: {0}")]
    BadLimit(&'static str),
}

/// Most samples a stream may hold (1e8 periods of 1 ms: more than a day).
pub const MAX_SAMPLES: f64 = 1e8;

/// What a streamed motion was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StreamedKind {
    Feed,
    Rapid,
    Dwell,
}

/// How one motion was streamed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StreamedMotion {
    pub kind: StreamedKind,
    /// Start time and duration, s.
    pub start: f64,
    pub duration: f64,
    /// Plans made (1: the first plan was within every limit).
    pub plans: usize,
}

/// A stream and what it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Stream {
    /// One position per period, from the start (time 0) to the first
    /// period at or after the end.
    pub positions: Vec<Vec3>,
    /// Planned duration, s: the sum of the motions' durations.
    pub time: f64,
    pub motions: Vec<StreamedMotion>,
    /// The stream measured as the controller samples it.
    pub peaks: Peaks,
    /// Samples of the whole stream that exceed a limit (beyond `slack`).
    pub excess: usize,
}

/// A planned feed run with what it takes to evaluate it at any time.
struct Track<'a> {
    pieces: &'a [Piece],
    plan: RunPlan,
    /// Start time and arc length of each segment; part prefix lengths.
    seg_t: Vec<f64>,
    seg_s: Vec<f64>,
    part_s: Vec<Vec<f64>>,
    /// Accuracy (mm) of the arc-length inversion: the planner's own
    /// accuracy of the part lengths.
    accuracy: f64,
}

/// A run sampled: per sample the position, the profile state and the arc
/// length along the run.
struct RunSamples {
    p: Vec<Vec3>,
    state: Vec<State>,
    s: Vec<f64>,
}

impl<'a> Track<'a> {
    fn new(pieces: &'a [Piece], plan: RunPlan, accuracy: f64) -> Track<'a> {
        let (mut t, mut s) = (0.0, 0.0);
        let mut seg_t = Vec::with_capacity(plan.segments.len());
        let mut seg_s = Vec::with_capacity(plan.segments.len());
        let mut part_s = Vec::with_capacity(plan.segments.len());
        for sg in &plan.segments {
            seg_t.push(t);
            seg_s.push(s);
            t += sg.profile.duration();
            s += sg.length;
            let mut pre = Vec::with_capacity(sg.parts.len() + 1);
            let mut acc = 0.0;
            pre.push(0.0);
            for p in &sg.parts {
                acc += p.length;
                pre.push(acc);
            }
            part_s.push(pre);
        }
        Track {
            pieces,
            plan,
            seg_t,
            seg_s,
            part_s,
            accuracy,
        }
    }

    fn duration(&self) -> f64 {
        self.plan.time
    }

    /// Segment, profile state and run arc length at time `tau`.
    fn state(&self, tau: f64) -> (usize, State, f64) {
        let i = self.seg_t.partition_point(|&t| t <= tau).max(1) - 1;
        let sg = &self.plan.segments[i];
        let st = sg
            .profile
            .eval((tau - self.seg_t[i]).min(sg.profile.duration()));
        (i, st, self.seg_s[i] + st.q)
    }

    /// The point at arc length `q` into segment `seg`: exact in arc length
    /// (Newton on the arc length within the part), so that the sampled
    /// speed is the planned one.
    fn position(&self, seg: usize, q: f64) -> Vec3 {
        let sg = &self.plan.segments[seg];
        let pre = &self.part_s[seg];
        let k = (pre.partition_point(|&x| x <= q).max(1) - 1).min(sg.parts.len() - 1);
        let part = &sg.parts[k];
        let c = &self.pieces[part.piece].curve;
        let q_in = (q - pre[k]).clamp(0.0, part.length);
        let f = if part.length > 0.0 {
            q_in / part.length
        } else {
            0.0
        };
        let mut u = part.t0 + (part.t1 - part.t0) * f;
        if matches!(c, Curve::Line(_)) {
            return c.eval(u);
        }
        let (lo, hi) = (part.t0.min(part.t1), part.t0.max(part.t1));
        for _ in 0..16 {
            let err = arc_length_between(c, part.t0, u, self.accuracy) - q_in;
            if math::abs(err) <= 10.0 * self.accuracy {
                break;
            }
            let speed = c.deriv1(u).norm();
            if speed == 0.0 || speed.is_nan() {
                break;
            }
            u = (u - err / speed).clamp(lo, hi);
        }
        c.eval(u)
    }

    /// Samples at `phase + k period` while before the end.
    fn sample(&self, phase: f64, period: f64) -> RunSamples {
        let mut out = RunSamples {
            p: Vec::new(),
            state: Vec::new(),
            s: Vec::new(),
        };
        let d = self.duration();
        let mut k = 0usize;
        loop {
            let tau = phase + k as f64 * period;
            if tau >= d {
                break;
            }
            let (seg, st, s) = self.state(tau);
            out.p.push(self.position(seg, st.q));
            out.state.push(st);
            out.s.push(s);
            k += 1;
        }
        out
    }

    fn end(&self) -> Vec3 {
        match self.plan.segments.last() {
            Some(sg) => self.position(self.plan.segments.len() - 1, sg.length),
            None => self.pieces.last().map_or(Vec3::ZERO, |p| p.end()),
        }
    }
}

/// The reductions that answer `excess` on a run sampled as `rs` (whose
/// positions were measured with `REST_PAD` rest samples before them).
///
/// The measured vector is split into the part the tangential profile makes
/// (`a_t T` for the acceleration; `j_t T + 3 a_t a_n / v` for the jerk,
/// `a_n` the measured normal acceleration vector, both averaged as the
/// measurement averages) and the rest, which scales with the speed (`v^2`
/// for the acceleration, `v^3` for the jerk). Both parts shrink by the
/// same factor until their sum is within the limit: the rest through the
/// cap (the square or cube root of the factor), the tangential part
/// through the tangential limits.
fn reductions(rs: &RunSamples, padded: &[Vec3], excess: &[Excess], period: f64) -> Vec<Reduction> {
    let acc = accelerations(padded, period);
    let n = rs.p.len();
    let np = padded.len();
    // Planned tangential acceleration at a padded index (rest outside).
    let a_plan = |k: usize| -> f64 {
        if k < REST_PAD || k >= REST_PAD + n {
            0.0
        } else {
            rs.state[k - REST_PAD].a
        }
    };
    let v_plan = |k: usize| -> f64 {
        if k < REST_PAD || k >= REST_PAD + n {
            0.0
        } else {
            rs.state[k - REST_PAD].v
        }
    };
    let tangent = |k: usize| -> Vec3 {
        let (lo, hi) = (k.saturating_sub(1), (k + 1).min(np - 1));
        (padded[hi] - padded[lo])
            .normalized(0.0)
            .unwrap_or(Vec3::ZERO)
    };
    let split = |k: usize| -> (Vec3, Vec3) {
        // Measured acceleration: (tangential part of the profile, rest).
        let t = tangent(k);
        let at = t * a_plan(k);
        (at, acc[k] - at)
    };
    let nj = super::sampled::JERK_AVERAGE_PERIODS;
    let mut out = Vec::with_capacity(excess.len());
    for e in excess {
        let c = e.index.min(np - 1);
        let i = c.saturating_sub(REST_PAD).min(n - 1);
        let lo = rs.s[i.saturating_sub(REST_PAD)];
        let hi = rs.s[(i + REST_PAD).min(n - 1)];
        let (s0, s1) = if hi > lo {
            (lo, hi)
        } else {
            (lo - 1e-3, hi + 1e-3)
        };
        let r = e.ratio * REDUCTION_MARGIN;
        let (tangential_part, rest, measured, power) = match e.what {
            Quantity::Velocity => (0.0, 1.0, 1.0, 1.0),
            Quantity::Acceleration => {
                let (at, rest) = split(c);
                (at.norm(), rest.norm(), acc[c].norm(), 2.0)
            }
            Quantity::Jerk => {
                // The averaged jerk at centre c spans accelerations
                // c - 2 .. c + 3 (see `measure`).
                let (k0, k1) = (c.saturating_sub(nj / 2), (c + nj - nj / 2).min(np - 1));
                let dt = (k1 - k0).max(1) as f64 * period;
                let measured = (acc[k1] - acc[k0]) / dt;
                let profile = (tangent(k1) * a_plan(k1) - tangent(k0) * a_plan(k0)) / dt;
                let (_, an) = split(c);
                let v = v_plan(c);
                let cross = if v > 0.0 {
                    an * (3.0 * a_plan(c) / v)
                } else {
                    Vec3::ZERO
                };
                let tp = profile + cross;
                (tp.norm(), (measured - tp).norm(), measured.norm(), 3.0)
            }
        };
        // The two parts are bounded in sum (the triangle inequality): the
        // measured vector then is too.
        let limit = measured * r;
        // Both parts shrink in proportion to their size.
        let sum = tangential_part + rest;
        let f = if sum > limit { limit / sum } else { r };
        let cap = if rest > 0.0 {
            math::powf(f, 1.0 / power)
        } else {
            1.0
        };
        let tangential = if tangential_part > 0.0 {
            f.max(0.05)
        } else {
            1.0
        };
        out.push(Reduction {
            s0,
            s1,
            cap,
            tangential,
        });
    }
    out
}

/// A rest-to-rest profile along a rapid: the fastest the path and every
/// axis allow along its direction.
fn rapid_profile(p: &Piece, o: &StreamOptions) -> Result<(DoubleS, Vec3, Vec3), FeedError> {
    let m = &o.plan.limits;
    let (a, b) = (p.start(), p.end());
    let len = a.dist(b);
    let dir = (b - a) / len;
    let comp = [math::abs(dir.x), math::abs(dir.y), math::abs(dir.z)];
    let (mut v, mut acc, mut jerk) = (m.max_feed, m.acc, m.jerk);
    for (i, &c) in comp.iter().enumerate() {
        if c > 0.0 {
            v = v.min(m.axis_vel[i] / c);
            acc = acc.min(m.axis_acc[i] / c);
            jerk = jerk.min(o.axis_jerk[i] / c);
        }
    }
    let prof = DoubleS::plan(len, 0.0, 0.0, &Limits::new(v, acc, jerk)?)?;
    Ok((prof, a, dir))
}

/// One sample of a planned run: time from the run's start (s), arc length
/// along it (mm), the profile's state and the position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSample {
    pub t: f64,
    pub s: f64,
    pub state: State,
    pub p: Vec3,
}

/// Samples `plan` (made for `pieces`) at `phase + k period` from the run's
/// start while before its end, exact in arc length (see [`Stream`]); the
/// end point itself is the caller's next sample. `accuracy` (mm) bounds
/// the arc-length inversion (the planner's own: chord error / 10,000).
pub fn sample_run(
    pieces: &[Piece],
    plan: &RunPlan,
    accuracy: f64,
    phase: f64,
    period: f64,
) -> Vec<RunSample> {
    if plan.segments.is_empty() || period.is_nan() || period <= 0.0 {
        return Vec::new();
    }
    let track = Track::new(pieces, plan.clone(), accuracy);
    let rs = track.sample(phase, period);
    (0..rs.p.len())
        .map(|k| RunSample {
            t: phase + k as f64 * period,
            s: rs.s[k],
            state: rs.state[k],
            p: rs.p[k],
        })
        .collect()
}

/// Speed-cap factors tried in turn for a whole run, from none down (see
/// `stream_run`).
pub const CAP_LEVELS: [f64; 13] = [
    1.0, 0.97, 0.94, 0.9, 0.85, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1,
];

/// Smallest factor on the tangential acceleration and jerk of a run.
pub const MIN_TANGENTIAL: f64 = 0.02;

/// Halvings (geometric) of the search for the tangential factor.
const TANGENTIAL_STEPS: usize = 6;

/// A run planned with one shaping and measured.
struct Trial<'a> {
    track: Track<'a>,
    excess: Vec<Excess>,
    samples: RunSamples,
    padded: Vec<Vec3>,
}

fn trial<'a>(
    pieces: &'a [Piece],
    o: &StreamOptions,
    shaping: &Shaping,
    phase: f64,
    index: usize,
) -> Result<Trial<'a>, StreamError> {
    let lim = o.sample_limits();
    let accuracy = o.plan.limits.chord_error * 1e-4;
    let plan = plan_run_shaped(pieces, &o.plan, shaping, Corners::Followed)
        .map_err(|source| StreamError::Plan { index, source })?;
    let track = Track::new(pieces, plan, accuracy);
    let samples = track.sample(phase, lim.period);
    if samples.p.is_empty() {
        return Ok(Trial {
            track,
            excess: Vec::new(),
            samples,
            padded: Vec::new(),
        });
    }
    let start = pieces.first().map_or(samples.p[0], |p| p.start());
    let end = track.end();
    let mut padded = Vec::with_capacity(samples.p.len() + 2 * REST_PAD);
    padded.extend(core::iter::repeat_n(start, REST_PAD));
    padded.extend_from_slice(&samples.p);
    padded.extend(core::iter::repeat_n(end, REST_PAD));
    let (_, excess) = measure(&padded, &lim, o.slack);
    Ok(Trial {
        track,
        excess,
        samples,
        padded,
    })
}

/// Plans a run so that its samples starting at `phase` (s after the run's
/// start) are within every limit; returns the track and the plans made.
///
/// 1. The plan as the planner makes it, if its samples pass.
/// 2. Else one cap factor and one tangential factor for the whole run: for
///    each cap factor of [`CAP_LEVELS`] in turn, the largest tangential
///    factor whose samples pass (a geometric bisection down to
///    [`MIN_TANGENTIAL`]); the fastest pair wins, and the search stops
///    when a cap factor passes with the full tangential limits or two
///    levels in a row are slower. Uniform factors keep the plan's shape:
///    local reductions (below) make dips in the cap that the profile must
///    brake into and speed out of, which costs more jerk than it saves
///    (butterfly-80 at 0.05 mm planned far slower with local reductions
///    only; measurements: docs/tuning.md, `stream_run`).
/// 3. Else local reductions ([`Shaping::apply`]) and then, after
///    [`StreamOptions::local_rounds`], the whole run slowed by
///    [`GLOBAL_STEP`] per round.
fn stream_run<'a>(
    pieces: &'a [Piece],
    o: &StreamOptions,
    phase: f64,
    index: usize,
) -> Result<(Track<'a>, usize), StreamError> {
    let period = o.plan.limits.period;
    let mut plans = 1usize;
    let first = trial(pieces, o, &Shaping::none(), phase, index)?;
    if first.excess.is_empty() {
        return Ok((first.track, plans));
    }
    let mut best: Option<Track<'a>> = None;
    let mut slower = 0;
    for &c in &CAP_LEVELS {
        let mut pass = |g: f64| -> Result<Option<Track<'a>>, StreamError> {
            plans += 1;
            let t = trial(pieces, o, &Shaping::uniform(c, g), phase, index)?;
            Ok(t.excess.is_empty().then_some(t.track))
        };
        let (found, full) = match pass(1.0)? {
            Some(t) => (Some(t), true),
            None => match pass(MIN_TANGENTIAL)? {
                None => (None, false),
                Some(t) => {
                    let (mut lo, mut hi, mut keep) = (MIN_TANGENTIAL, 1.0f64, t);
                    for _ in 0..TANGENTIAL_STEPS {
                        let mid = math::sqrt(lo * hi);
                        match pass(mid)? {
                            Some(t) => {
                                lo = mid;
                                keep = t;
                            }
                            None => hi = mid,
                        }
                    }
                    (Some(keep), false)
                }
            },
        };
        if let Some(t) = found {
            match &best {
                Some(b) if b.duration() <= t.duration() => {
                    slower += 1;
                }
                _ => {
                    best = Some(t);
                    slower = 0;
                }
            }
        }
        if full || slower >= 2 {
            break;
        }
    }
    if let Some(t) = best {
        return Ok((t, plans));
    }
    let mut shaping = Shaping::none();
    let mut last = first;
    for round in 1..=o.max_rounds {
        if round < o.local_rounds {
            shaping.apply(&reductions(
                &last.samples,
                &last.padded,
                &last.excess,
                period,
            ));
        } else {
            shaping.scale_all(GLOBAL_STEP);
        }
        plans += 1;
        last = trial(pieces, o, &shaping, phase, index)?;
        if last.excess.is_empty() {
            return Ok((last.track, plans));
        }
    }
    Err(StreamError::NotWithinLimits {
        index,
        rounds: o.max_rounds,
    })
}

/// Streams `motions` (consecutive: each starts where the one before it
/// ends, within the machine's chord error) on the machine of `o`.
pub fn stream(motions: &[Motion], o: &StreamOptions) -> Result<Stream, StreamError> {
    let m = &o.plan.limits;
    m.validate().map_err(|e| StreamError::BadLimit(e.name))?;
    for (i, j) in o.axis_jerk.iter().enumerate() {
        if !(j.is_finite() && *j > 0.0) {
            return Err(StreamError::BadLimit(["X jerk", "Y jerk", "Z jerk"][i]));
        }
    }
    let period = m.period;
    let mut positions: Vec<Vec3> = Vec::new();
    let mut streamed = Vec::with_capacity(motions.len());
    let mut t = 0.0f64;
    let mut next_k = 0usize;
    let mut here: Option<Vec3> = None;
    for (index, mo) in motions.iter().enumerate() {
        let start_of = |mo: &Motion| match mo {
            Motion::Run(p) => p.first().map(|q| q.start()),
            Motion::Rapid(p) => Some(p.start()),
            Motion::Dwell(_) => None,
        };
        if let (Some(h), Some(s)) = (here, start_of(mo)) {
            let gap = h.dist(s);
            if gap > m.chord_error {
                return Err(StreamError::Gap { index, gap });
            }
        }
        // The first sample of this motion, and its time into the motion.
        let first_t = next_k as f64 * period;
        let phase = (first_t - t).max(0.0);
        let (kind, duration, plans) = match mo {
            Motion::Run(pieces) => {
                if pieces.is_empty() {
                    continue;
                }
                let (track, plans) = stream_run(pieces, o, phase, index)?;
                let d = track.duration();
                check_length(t + d, period)?;
                while (next_k as f64) * period < t + d {
                    let (seg, st, _) = track.state(next_k as f64 * period - t);
                    positions.push(track.position(seg, st.q));
                    next_k += 1;
                }
                here = Some(track.end());
                (StreamedKind::Feed, d, plans)
            }
            Motion::Rapid(p) => {
                let len = p.start().dist(p.end());
                if len.is_nan() || len <= 0.0 {
                    continue;
                }
                let (prof, a, dir) =
                    rapid_profile(p, o).map_err(|source| StreamError::Plan { index, source })?;
                let d = prof.duration();
                check_length(t + d, period)?;
                while (next_k as f64) * period < t + d {
                    let q = prof.eval(next_k as f64 * period - t).q.clamp(0.0, len);
                    positions.push(a + dir * q);
                    next_k += 1;
                }
                here = Some(p.end());
                (StreamedKind::Rapid, d, 1)
            }
            Motion::Dwell(d) => {
                // A dwell before the first move is before the stream.
                let Some(h) = here else {
                    continue;
                };
                let d = if d.is_finite() { d.max(0.0) } else { 0.0 };
                check_length(t + d, period)?;
                while (next_k as f64) * period < t + d {
                    positions.push(h);
                    next_k += 1;
                }
                (StreamedKind::Dwell, d, 1)
            }
        };
        streamed.push(StreamedMotion {
            kind,
            start: t,
            duration,
            plans,
        });
        t += duration;
    }
    if let Some(h) = here {
        positions.push(h);
    }
    let (peaks, excess) = measure(&positions, &o.sample_limits(), o.slack);
    Ok(Stream {
        positions,
        time: t,
        motions: streamed,
        peaks,
        excess: excess.len(),
    })
}

fn check_length(t: f64, period: f64) -> Result<(), StreamError> {
    let samples = t / period;
    if samples > MAX_SAMPLES || samples.is_nan() {
        return Err(StreamError::TooLong {
            samples,
            max: MAX_SAMPLES,
        });
    }
    Ok(())
}
