//! Planning the feed along a run: a cap on the speed at every point, a
//! bidirectional jerk-limited look-ahead over the whole run, and one
//! double-S profile from each speed minimum to the next.
//!
//! 1. **Caps.** A line is one stretch. Arcs and curves are cut where
//!    their chords deviate by the machine's chord error (the interpolator's
//!    own resolution); each interval is a stretch whose cap is the smallest
//!    [`speed_cap`] at its ends and middle, with `dkappa/ds` from the change
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
//!    with a boundary at every ripple the machine took 1.06 s instead of
//!    0.76 s over a 270-degree helical arc of `tort.ngc`).
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

use super::junction::{
    blend_cap, corner_blend, corner_jump, follow_neighbours, jump_cap, Blend, MEET_REL,
};
use super::limits::{speed_cap, Constraint, MachineLimits, PathPoint};
use super::shaping::Shaping;
use super::{max_entry_velocity, max_reachable_velocity, DoubleS, FeedError, Limits};
use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{flatten_params, Curve, ParamCurve, Vec3};
use crate::path::Piece;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;

/// Relative slack of the check of a profile against the caps inside its
/// segment: rounding of the profile's closed forms, far below any speed
/// that matters.
pub const CAP_SLACK: f64 = 1e-9;

/// A stretch of curve is cut in two while the speed caps at its ends and
/// middle differ by more than this ratio (and it is longer than one period
/// of travel): its cap, the lowest of the three, is then close to the cap
/// everywhere in it.
pub const CAP_SPLIT_RATIO: f64 = 1.25;

/// A minimum of the cap counts as reached (a segment boundary is kept
/// there) when the planned speed comes within this share of it.
pub const UNREACHED_CAP: f64 = 0.02;

/// Most halvings of a stretch for [`CAP_SPLIT_RATIO`].
const MAX_CAP_SPLITS: u32 = 24;

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

/// The rest-to-rest peak speed (mm/s) over a block of `length` mm: the
/// speed reached from rest over half of it (see [`Corners::BlockCapped`]).
pub fn block_cap(m: &MachineLimits, length: f64) -> f64 {
    max_reachable_velocity(0.0, 0.5 * length, m.acc, m.jerk)
        .unwrap_or(0.0)
        .min(m.max_feed)
}

/// The largest speed (mm/s) at which a path followed exactly may turn by
/// the angle between unit tangents `ta` and `tb` (see [`Corners::Followed`]).
pub fn followed_corner_cap(m: &MachineLimits, ta: Vec3, tb: Vec3) -> f64 {
    let dv_per_v = (tb - ta).norm();
    if dv_per_v == 0.0 {
        return f64::INFINITY;
    }
    let n = super::sampled::JERK_AVERAGE_PERIODS as f64;
    let ts = m.period;
    (m.acc * ts).min(n * m.jerk * ts * ts) / dv_per_v
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

/// A stretch with a constant cap, before segmentation.
#[derive(Clone, Copy, Debug)]
struct Stretch {
    part: Part,
    constraint: Constraint,
    /// Factor on the tangential acceleration and jerk ([`Shaping`]).
    tangential: f64,
}

/// How the machine passes the joint between two consecutive pieces.
#[derive(Clone, Copy, Debug)]
struct JointCap {
    /// Cap at the joint itself: the corner's circle, or the curvature jump
    /// of a tangent joint (INFINITY at a G2 joint).
    point: f64,
    /// A corner's circle: length it takes from each move (0: no circle),
    /// half its arc length, the cap along it, and the caps where it starts
    /// and ends (curvature jumps).
    tangent_length: f64,
    half_arc: f64,
    arc: f64,
    entry: f64,
    exit: f64,
    /// The circle meets the next joint's circle (they fill the line
    /// between).
    meets_next: bool,
}

const SMOOTH_JOINT: JointCap = JointCap {
    point: f64::INFINITY,
    tangent_length: 0.0,
    half_arc: 0.0,
    arc: f64::INFINITY,
    entry: f64::INFINITY,
    exit: f64::INFINITY,
    meets_next: false,
};

/// How each joint between consecutive pieces of `valid` (indices of
/// pieces with positive length, and their lengths) is passed: G2 joints
/// freely, tangent joints at the cap of their curvature jump, corners on
/// blend circles that may meet each other on short moves (see
/// [`super::junction`]).
fn joint_caps(
    pieces: &[Piece],
    valid: &[(usize, f64)],
    m: &MachineLimits,
    corners: Corners,
) -> Vec<JointCap> {
    let jt = JointTolerances::from_tolerance(m.chord_error);
    enum Joint {
        Smooth,
        Tangent(f64),
        Corner(Blend, Vec3, Vec3),
    }
    let is_line = |k: usize| matches!(pieces[valid[k].0].curve, Curve::Line(_));
    let joints: Vec<Joint> = valid
        .windows(2)
        .map(|w| {
            let ((qa, la), (qb, lb)) = (w[0], w[1]);
            let (a, c) = (&pieces[qa].curve, &pieces[qb].curve);
            let class = classify_joint(a, c, &jt);
            if class == Continuity::G2 {
                return Joint::Smooth;
            }
            let (pa, _) = point(a, a.domain().1);
            let (pb, _) = point(c, c.domain().0);
            // Tangent within the joint tolerances (and rounding): a
            // curvature jump, not a corner of a microradian.
            if class != Continuity::G1
                && pa.tangent.angle_to(pb.tangent) > 0.0
                && corners == Corners::Followed
            {
                let jump = jump_cap(m, (pb.curvature - pa.curvature).norm());
                Joint::Tangent(followed_corner_cap(m, pa.tangent, pb.tangent).min(jump))
            } else if class != Continuity::G1 && pa.tangent.angle_to(pb.tangent) > 0.0 {
                let room = 0.5 * la.min(lb);
                match corner_blend(m, pa.tangent, pb.tangent, room) {
                    Some(bl) => Joint::Corner(
                        follow_neighbours(bl, pa.curvature, pb.curvature),
                        pa.curvature,
                        pb.curvature,
                    ),
                    None if pa.tangent.dot(pb.tangent) > 0.0 => Joint::Smooth,
                    None => Joint::Tangent(0.0),
                }
            } else {
                Joint::Tangent(jump_cap(m, (pb.curvature - pa.curvature).norm()))
            }
        })
        .collect();
    let blend_of = |j: usize| match joints.get(j) {
        Some(Joint::Corner(b, _, _)) => Some(*b),
        _ => None,
    };
    // Whether the circles of joints j and j + 1 fill the line between.
    let meet = |j: usize| -> bool {
        let (Some(a), Some(b)) = (blend_of(j), blend_of(j + 1)) else {
            return false;
        };
        let len = valid[j + 1].1;
        let rest = len - a.tangent_length - b.tangent_length;
        is_line(j + 1) && rest <= m.chord_error.max(len * MEET_REL)
    };
    (0..joints.len())
        .map(|j| match &joints[j] {
            Joint::Smooth => SMOOTH_JOINT,
            Joint::Tangent(cap) => JointCap {
                point: *cap,
                ..SMOOTH_JOINT
            },
            Joint::Corner(bl, k_in, k_out) => {
                // What the circle meets: the neighbouring circle when both
                // fill the line between them, else the piece itself.
                let k_before = if j > 0 && meet(j - 1) {
                    blend_of(j - 1).map_or(*k_in, |b| b.curvature)
                } else {
                    *k_in
                };
                let meets_next = meet(j);
                let k_after = if meets_next {
                    blend_of(j + 1).map_or(*k_out, |b| b.curvature)
                } else {
                    *k_out
                };
                let arc = blend_cap(m, bl, 0.0);
                let entry = jump_cap(m, (bl.curvature - k_before).norm());
                let exit = jump_cap(m, (k_after - bl.curvature).norm());
                // Next to an arc or curve the circle's ends are not
                // modelled as stretches: all of its caps at the joint, the
                // curvature change across it as one jump.
                let lines = is_line(j) && is_line(j + 1);
                let circle = bl.curvature - (*k_in + *k_out) * 0.5;
                let across = jump_cap(m, corner_jump(circle, *k_in, *k_out));
                JointCap {
                    point: if lines { arc } else { arc.min(across) },
                    tangent_length: if lines { bl.tangent_length } else { 0.0 },
                    half_arc: 0.5 * bl.arc_length,
                    arc,
                    entry,
                    exit,
                    meets_next: meets_next && lines,
                }
            }
        })
        .collect()
}

/// Cuts the run into stretches with caps; `junction[k]` caps the speed at
/// the start of stretch `k` (INFINITY inside pieces and at G2 joints).
/// `shaping` lowers caps and tangential limits by arc length along the run.
fn stretches(
    pieces: &[Piece],
    opts: &PlanOptions,
    shaping: &Shaping,
    corners: Corners,
) -> Result<(Vec<Stretch>, Vec<f64>), FeedError> {
    let m = &opts.limits;
    let mut valid: Vec<(usize, f64)> = Vec::with_capacity(pieces.len());
    for (pi, p) in pieces.iter().enumerate() {
        let len = p.curve.length(m.chord_error * 1e-3);
        if !len.is_nan() && len > 0.0 {
            valid.push((pi, len));
        }
    }
    let mut jcaps = joint_caps(pieces, &valid, m, corners);
    if corners == Corners::BlockCapped {
        for (j, jc) in jcaps.iter_mut().enumerate() {
            let cap = block_cap(m, valid[j].1).min(block_cap(m, valid[j + 1].1));
            jc.point = jc.point.min(cap);
            jc.arc = jc.arc.min(cap);
            jc.entry = jc.entry.min(cap);
            jc.exit = jc.exit.min(cap);
        }
    }
    let mut out: Vec<Stretch> = Vec::new();
    let mut junction: Vec<f64> = Vec::new();
    // Arc length of the run before the current stretch.
    let mut s_run = 0.0f64;
    for (vi, &(pi, len_total)) in valid.iter().enumerate() {
        let p = &pieces[pi];
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
        // The joint's cap goes to the first stretch of the piece.
        let jin = if vi > 0 { jcaps[vi - 1] } else { SMOOTH_JOINT };
        let jout = jcaps.get(vi).copied().unwrap_or(SMOOTH_JOINT);
        // The cap at the start of the piece.
        let mut jcap = jin.point;
        // A line with a corner at an end: the end stretch of the line that
        // the blend circle replaces is passed at the circle's cap, over
        // half the circle's arc length (the machine follows the circle
        // there, not just its middle), with the curvature jumps where the
        // circle starts and ends. Arcs and curves next to a corner take
        // the caps at the joint only.
        // Each stretch: (cap, length or 0 for the line's own, entry cap).
        let (ts, blend_caps) = match c {
            Curve::Line(_) => {
                let (tin, tout) = (jin.tangent_length, jout.tangent_length);
                let mut ts = alloc::vec![0.0];
                let mut caps = Vec::new();
                if tin > 0.0 && tout > 0.0 && jin.meets_next {
                    // The two circles fill the line and meet inside it.
                    ts.push(tin / (tin + tout));
                    caps.push((jin.arc, jin.half_arc, jin.point));
                    caps.push((jout.arc, jout.half_arc, jin.exit.min(jout.entry)));
                } else {
                    let (a, b) = (tin / len_total, 1.0 - tout / len_total);
                    if tin > 0.0 {
                        ts.push(a);
                        caps.push((jin.arc, jin.half_arc, jin.point));
                    }
                    if tout > 0.0 {
                        ts.push(b);
                    }
                    let entry = if tin > 0.0 { jin.exit } else { jin.point };
                    caps.push((f64::INFINITY, 0.0, entry));
                    if tout > 0.0 {
                        caps.push((jout.arc, jout.half_arc, jout.entry));
                    }
                }
                ts.push(1.0);
                (ts, caps)
            }
            _ => (flatten_params(c, m.chord_error), Vec::new()),
        };
        let mut blend_caps = blend_caps.into_iter();
        // Intervals to do, last first; each is cut in two while the caps
        // at its ends and middle differ by more than CAP_SPLIT_RATIO and it
        // is longer than one period of travel at its cap.
        let mut todo: Vec<(f64, f64, u32)> = ts.windows(2).rev().map(|w| (w[0], w[1], 0)).collect();
        while let Some((t0, t1, depth)) = todo.pop() {
            let (blend_cap, blend_len, entry) =
                blend_caps
                    .next()
                    .unwrap_or((f64::INFINITY, 0.0, f64::INFINITY));
            if matches!(c, Curve::Line(_)) {
                jcap = jcap.min(entry);
            }
            let len = match c {
                Curve::Line(_) if blend_len > 0.0 => blend_len,
                Curve::Line(_) => len_total * (t1 - t0),
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
            let mut high = 0.0f64;
            for mut pp in [p0, pm, p1] {
                pp.dkappa_ds = crate::math::abs(dk).max(dk_mid);
                let c = speed_cap(m, feed, &pp);
                high = high.max(c.0);
                if c.0 < cap.0 {
                    cap = c;
                }
            }
            if blend_cap < cap.0 {
                cap = (blend_cap, Constraint::Junction);
            }
            let (cap_factor, tangential) = shaping.factors(s_run, s_run + len);
            if high > CAP_SPLIT_RATIO * cap.0
                && len > cap.0 * m.period
                && depth < MAX_CAP_SPLITS
                && !matches!(c, Curve::Line(_))
            {
                let tm = 0.5 * (t0 + t1);
                todo.push((tm, t1, depth + 1));
                todo.push((t0, tm, depth + 1));
                continue;
            }
            let j = core::mem::replace(&mut jcap, f64::INFINITY) * cap_factor;
            cap.0 *= cap_factor;
            s_run += len;
            // Neighbouring stretches with the same cap and nothing between
            // them are one stretch.
            if let Some(last) = out.last_mut() {
                if last.part.cap == cap.0
                    && j >= cap.0
                    && last.part.piece == pi
                    && last.tangential == tangential
                {
                    last.part.t1 = t1;
                    last.part.length += len;
                    continue;
                }
            }
            out.push(Stretch {
                part: Part {
                    piece: pi,
                    t0,
                    t1,
                    length: len,
                    cap: cap.0,
                    entry_cap: j,
                },
                constraint: cap.1,
                tangential,
            });
            junction.push(j);
        }
    }
    Ok((out, junction))
}

/// Boundary speeds of segments of `lengths` with boundary caps `caps`
/// (`caps.len() == lengths.len() + 1`, both ends at rest): the full
/// bidirectional scan, or the bounded look-ahead of `window` segments.
fn boundary_speeds(
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
                            * (1.0 - 1e-9);
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
    // about 55 (this lookup was a fifth of planning a long run of arcs);
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
fn violation(profile: &DoubleS, parts: &[Stretch], lower_boundary: &[f64]) -> Option<usize> {
    let ph = profile.phases();
    let peak_lo = profile.eval(ph.ta).q;
    let peak_hi = profile.eval(ph.ta + ph.tv).q;
    let vpeak = profile.vlim().max(profile.v0()).max(profile.v1());
    // Cheap upper bounds of the speed at arc length q (dv^2/dq = 2a and
    // |a| is at most the profile's peak): the exact speed is looked up
    // only where a bound passes the cap.
    let total: f64 = parts.iter().map(|st| st.part.length).sum();
    let (a_up, a_down) = (
        crate::math::abs(profile.alim_a()),
        crate::math::abs(profile.alim_d()),
    );
    // The speed at q on the rising (or falling) side, or a bound of it when
    // the bound is within `cap` (no violation either way).
    let speed_within = |q: f64, cap: f64, rising: bool| {
        let (v_end, a_max, dist) = if rising {
            (profile.v0(), a_up, q)
        } else {
            (profile.v1(), a_down, total - q)
        };
        let bound = crate::math::sqrt(v_end * v_end + 2.0 * a_max * dist.max(0.0));
        if bound <= cap {
            bound
        } else {
            speed_at(profile, q, rising)
        }
    };
    let mut worst: Option<(f64, usize)> = None;
    let mut s0 = 0.0;
    for (k, st) in parts.iter().enumerate() {
        let s1 = s0 + st.part.length;
        let cap = st.part.cap * (1.0 + CAP_SLACK);
        // v(q) rises to the peak plateau, then falls: the largest speed on
        // [s0, s1] is at the end nearer the plateau.
        let (vmax, at) = if s1 < peak_lo {
            (
                if vpeak <= cap {
                    vpeak
                } else {
                    speed_within(s1, cap, true)
                },
                k + 1,
            )
        } else if s0 > peak_hi {
            (
                if vpeak <= cap {
                    vpeak
                } else {
                    speed_within(s0, cap, false)
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
            (vpeak, at)
        };
        // A split at the segment's own ends is no split: the speed there is
        // already within the cap, and only rounding can exceed it.
        if vmax > cap && at != 0 && at != parts.len() {
            let ratio = vmax / st.part.cap;
            if worst.is_none_or(|(r, _)| ratio > r) {
                worst = Some((ratio, at));
            }
        }
        // The junction cap at the inner boundary at the end of this
        // stretch.
        let jb = lower_boundary[k + 1] * (1.0 + CAP_SLACK);
        if k + 1 < parts.len() && vpeak > jb {
            let v = if s1 < peak_lo {
                speed_within(s1, jb, true)
            } else if s1 > peak_hi {
                speed_within(s1, jb, false)
            } else {
                vpeak
            };
            if v > jb {
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
    let m = &opts.limits;
    m.validate().map_err(|e| FeedError::BadLimit {
        name: e.name,
        value: e.value,
    })?;
    let (st, junction) = stretches(pieces, opts, shaping, corners)?;
    let n = st.len();
    let mut plan = RunPlan::default();
    if n == 0 {
        return Ok(plan);
    }
    // Cap at each stretch boundary (rest at both ends) and what sets it.
    let mut bcap = alloc::vec![0.0f64; n + 1];
    for i in 1..n {
        bcap[i] = st[i - 1].part.cap.min(st[i].part.cap).min(junction[i]);
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
    let mut pre = alloc::vec![0.0f64; n + 1];
    for i in 0..n {
        pre[i + 1] = pre[i] + st[i].part.length;
    }
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
        let vmax = st[a..b].iter().map(|s| s.part.cap).fold(0.0f64, f64::max);
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
    // (end, v0, v1, profile). Between rounds most boundary speeds stay the
    // same, and their segments are neither planned nor checked again.
    // (A map: one entry per segment, not one per stretch, keeps this small
    // on long runs: 2 million stretches of written arcs took 265 MB.)
    let mut verified: BTreeMap<usize, (usize, f64, f64, DoubleS)> = BTreeMap::new();
    let (bounds, profiles) = loop {
        let bounds: Vec<usize> = (0..=n).filter(|&i| key[i]).collect();
        let lengths: Vec<f64> = bounds.windows(2).map(|w| pre[w[1]] - pre[w[0]]).collect();
        let caps: Vec<f64> = bounds.iter().map(|&i| bcap[i]).collect();
        let tl: Vec<(f64, f64)> = bounds.windows(2).map(|w| seg_limits(w[0], w[1])).collect();
        let v = boundary_speeds(&lengths, &caps, opts.window, &tl)?;
        let mut profiles = Vec::with_capacity(lengths.len());
        let mut split = false;
        for (j, w) in bounds.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let vmax = st[a..b].iter().map(|s| s.part.cap).fold(0.0f64, f64::max);
            let (v0, v1) = (v[j].min(vmax), v[j + 1].min(vmax));
            if let Some((end, w0, w1, p)) = verified.get(&a) {
                if (*end, *w0, *w1) == (b, v0, v1) {
                    profiles.push(*p);
                    continue;
                }
            }
            let (acc, jerk) = tl[j];
            let profile = DoubleS::plan(lengths[j], v0, v1, &Limits::new(vmax, acc, jerk)?)?;
            match violation(&profile, &st[a..b], &bcap[a..=b]) {
                Some(k) => {
                    key[a + k] = true;
                    split = true;
                }
                None => {
                    verified.insert(a, (b, v0, v1, profile));
                }
            }
            profiles.push(profile);
        }
        if !split {
            break (bounds, profiles);
        }
    };
    for (w, profile) in bounds.windows(2).zip(profiles) {
        let (a, b) = (w[0], w[1]);
        plan.time += profile.duration();
        plan.max_acc = plan.max_acc.max(profile.alim_a()).max(-profile.alim_d());
        let ph = profile.phases();
        if ph.tj1 > 0.0 || ph.tj2 > 0.0 {
            plan.max_jerk = plan.max_jerk.max(seg_limits(a, b).1);
        }
        // The tightest constraint: the lowest cap among the stretches.
        let tight = st[a..b]
            .iter()
            .min_by(|x, y| x.part.cap.total_cmp(&y.part.cap))
            .expect("a segment has stretches");
        let (mut constraint, mut low) = (tight.constraint, tight.part.cap);
        for i in [a, b] {
            if i != 0 && i != n && junction[i] < low {
                low = junction[i];
                constraint = Constraint::Junction;
            }
        }
        plan.segments.push(PlannedSegment {
            parts: st[a..b].iter().map(|s| s.part).collect(),
            length: pre[b] - pre[a],
            cap: st[a..b].iter().map(|s| s.part.cap).fold(0.0f64, f64::max),
            constraint,
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
