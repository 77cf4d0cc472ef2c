//! The speed caps of a run (step 1 of the planner, [`super::plan`]): the
//! run cut into stretches, each with the lowest speed that any limit
//! allows on it, and the caps at the joints between pieces.
//!
//! * Along a piece: the caps at a point ([`speed_cap`]: curvature, the
//!   change of curvature `dkappa/ds` across the stretch, chord error,
//!   axes, feed) at the ends and middle of each chord-error interval (a
//!   spline is flattened span by span), which is halved while they
//!   differ by more than [`CAP_SPLIT_RATIO`].
//! * At a joint that is not G2, as [`Corners`] says: the blend circle of a
//!   corner and the curvature jumps where it starts and ends
//!   ([`super::junction`]), a corner followed exactly
//!   ([`followed_corner_cap`]), or a block's rest-to-rest peak speed
//!   ([`block_cap`]).
//! * At a corner inside a spline ([`crate::geom::inner_corners`]: a
//!   breakpoint where the tangent turns, as at a control point repeated
//!   `degree` times), and at a sharp turn inside a polynomial cubic span
//!   ([`crate::geom::sharp_turns_in_span`]: a cusp, where a fit through a
//!   reversal stops and turns back): the cap of a corner followed
//!   exactly, whatever [`Corners`] says of the joints between pieces (the
//!   sampled caps either side of it see little or nothing of the turn).
//!
//! This is where the machine's limits meet the geometry. The rest of the
//! planner (segments, look-ahead, profiles) sees only the stretches with
//! their caps and tangential factors, so it is kept apart from them.

use super::junction::{
    blend_cap, corner_blend, corner_jump, follow_neighbours, jump_cap, step_cap, Blend, MEET_REL,
};
use super::limits::{speed_cap, Constraint, MachineLimits, PathPoint};
use super::plan::{Corners, Part, PlanOptions};
use super::shaping::Shaping;
use super::{max_reachable_velocity, FeedError};
use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{flatten_params, flatten_params_between, CubicBezier, Curve, ParamCurve, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;

/// A stretch of curve is cut in two while the speed caps at its ends and
/// middle differ by more than this ratio (and it is longer than one period
/// of travel): its cap, the lowest of the three, is then close to the cap
/// everywhere in it.
pub const CAP_SPLIT_RATIO: f64 = 1.25;

/// Largest change of radius along an arc, as a share of its smaller
/// radius, for which the planner takes the arc as one stretch: its caps
/// then differ along it by less than that share (the curvature caps go as
/// `k^(-1/2)` and `k^(-2/3)`), and the least of them, at its ends and
/// middle, holds for all of it. Arcs read back from rounded coordinates
/// are such spirals; one that changes more is sampled at the chord error
/// as curves are.
pub const ARC_ONE_STRETCH_SPREAD: f64 = 1e-4;

/// Most halvings of a stretch for [`CAP_SPLIT_RATIO`].
const MAX_CAP_SPLITS: u32 = 24;

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

/// Whether the cubic Bezier span with control points `b` is accepted
/// whole by [`crate::geom::flatten_params`] at `chord`, on sure bounds: the
/// span lies in the hull of its control points, so no point of it is
/// farther from its chord than the inner points are; and its second
/// derivative (in the span's own parameter) is at most six times the
/// larger second difference of the points, so the flattening's estimate
/// `|C''| dt^2 / 8` is at most 0.75 times it. Where both are within
/// `chord`, the flattening's first test passes and it takes the span as one
/// interval: the same cut, without its samples.
fn flat_span(b: &[Vec3], chord: f64) -> bool {
    let [p0, p1, p2, p3] = match b {
        [p0, p1, p2, p3] => [*p0, *p1, *p2, *p3],
        _ => return false,
    };
    let hull = crate::geom::point_segment_distance(p1, p0, p3)
        .max(crate::geom::point_segment_distance(p2, p0, p3));
    let second = (p2 - p1 * 2.0 + p0).norm().max((p3 - p2 * 2.0 + p1).norm());
    hull <= chord && 0.75 * second <= chord
}

fn point<C: ParamCurve + ?Sized>(c: &C, t: f64) -> (PathPoint, f64) {
    let (d1, d2) = c.derivs12(t);
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

/// A stretch with a constant cap, before segmentation: what the planner
/// needs of it to make and check profiles. Where it lies on the run and
/// what sets its cap ([`Located`]) are kept apart, and only when the plan
/// keeps its segments: a plan for its time alone holds 32 bytes a
/// stretch, not 64 (on a rendering of millions of pieces read back, two
/// such plans side by side held hundreds of megabytes of stretch vectors,
/// grown by doubling; the vector is now sized for one stretch per piece;
/// measurements: docs/tuning.md, `Stretch`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Stretch {
    /// Arc length, mm.
    pub(super) length: f64,
    /// Speed cap on the stretch, mm/s.
    pub(super) cap: f64,
    /// Speed cap at its start from the joint before it (mm/s; INFINITY
    /// inside pieces and at G2 joints).
    pub(super) entry_cap: f64,
    /// Factor on the tangential acceleration and jerk ([`Shaping`]).
    pub(super) tangential: f64,
}

/// Where a [`Stretch`] lies and what sets its cap.
#[derive(Clone, Copy, Debug)]
pub(super) struct Located {
    /// Index of the piece in the run.
    pub(super) piece: usize,
    /// Parameter interval on the piece's curve.
    pub(super) t0: f64,
    pub(super) t1: f64,
    pub(super) constraint: Constraint,
}

impl Located {
    /// The [`Part`] of the planned segment: `st` located here.
    pub(super) fn part(&self, st: &Stretch) -> Part {
        Part {
            piece: self.piece,
            t0: self.t0,
            t1: self.t1,
            length: st.length,
            cap: st.cap,
            entry_cap: st.entry_cap,
        }
    }
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

/// How a joint between two consecutive pieces is passed, before its
/// neighbours are known.
#[derive(Clone, Copy)]
enum Joint {
    Smooth,
    Tangent(f64),
    Corner(Blend, Vec3, Vec3),
}

/// How each joint between consecutive pieces of `valid` (indices of
/// pieces with positive length, and their lengths) is passed, joint after
/// joint: G2 joints freely, tangent joints at the cap of their curvature
/// jump, corners on blend circles that may meet each other on short moves
/// (see [`super::junction`]). A joint's cap depends on its neighbours
/// only, so three joints are held at a time, not one per piece: on a
/// rendering of millions of pieces the table of joints was the largest
/// thing a plan held.
struct JointCaps<'a> {
    pieces: &'a [Piece],
    valid: &'a [(usize, f64)],
    m: &'a MachineLimits,
    corners: Corners,
    jt: JointTolerances,
    /// Index of the joint [`JointCaps::next_cap`] returns next.
    next: usize,
    /// Joints `next - 1`, `next` and `next + 1` (`None` outside the run).
    window: [Option<Joint>; 3],
}

impl<'a> JointCaps<'a> {
    fn new(
        pieces: &'a [Piece],
        valid: &'a [(usize, f64)],
        m: &'a MachineLimits,
        corners: Corners,
    ) -> JointCaps<'a> {
        let mut caps = JointCaps {
            pieces,
            valid,
            m,
            corners,
            jt: JointTolerances::from_tolerance(m.chord_error),
            next: 0,
            window: [None; 3],
        };
        caps.window = [None, caps.joint(0), caps.joint(1)];
        caps
    }

    /// Number of joints.
    fn len(&self) -> usize {
        self.valid.len().saturating_sub(1)
    }

    fn is_line(&self, k: usize) -> bool {
        matches!(self.pieces[self.valid[k].0].curve, Curve::Line(_))
    }

    /// Joint `j` on its own (`None` past the last joint).
    fn joint(&self, j: usize) -> Option<Joint> {
        if j >= self.len() {
            return None;
        }
        let (m, corners) = (self.m, self.corners);
        let ((qa, la), (qb, lb)) = (self.valid[j], self.valid[j + 1]);
        let (a, c) = (&self.pieces[qa].curve, &self.pieces[qb].curve);
        let class = classify_joint(a, c, &self.jt);
        let (pa, _) = point(a, a.domain().1);
        let (pb, _) = point(c, c.domain().0);
        // The cap of the joint's curvature jump (`step_cap`: on a chain of
        // short pieces the jumps add up).
        let step = || step_cap(m, (pb.curvature - pa.curvature).norm(), la.min(lb));
        if class == Continuity::G2 {
            // A jump below the class threshold still steps the normal
            // acceleration.
            let cap = step();
            return Some(if cap.is_finite() {
                Joint::Tangent(cap)
            } else {
                Joint::Smooth
            });
        }
        // Tangent within the joint tolerances (and rounding): a
        // curvature jump, not a corner of a microradian.
        Some(
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
                Joint::Tangent(step())
            },
        )
    }

    /// The cap of the next joint (in order from the first), or `None`
    /// after the last.
    fn next_cap(&mut self) -> Option<JointCap> {
        let j = self.next;
        if j >= self.len() {
            return None;
        }
        let cap = self.cap(j);
        self.next += 1;
        self.window = [self.window[1], self.window[2], self.joint(j + 2)];
        if self.corners == Corners::BlockCapped {
            let m = self.m;
            let block = block_cap(m, self.valid[j].1).min(block_cap(m, self.valid[j + 1].1));
            return Some(JointCap {
                point: cap.point.min(block),
                arc: cap.arc.min(block),
                entry: cap.entry.min(block),
                exit: cap.exit.min(block),
                ..cap
            });
        }
        Some(cap)
    }

    /// The blend circle of joint `j`, one of the window's.
    fn blend_of(&self, j: usize) -> Option<Blend> {
        let slot = (j + 1).checked_sub(self.next)?;
        match self.window.get(slot).copied().flatten() {
            Some(Joint::Corner(b, _, _)) => Some(b),
            _ => None,
        }
    }

    /// Whether the circles of joints `j` and `j + 1` fill the line between.
    fn meet(&self, j: usize) -> bool {
        let (Some(a), Some(b)) = (self.blend_of(j), self.blend_of(j + 1)) else {
            return false;
        };
        let len = self.valid[j + 1].1;
        let rest = len - a.tangent_length - b.tangent_length;
        self.is_line(j + 1) && rest <= self.m.chord_error.max(len * MEET_REL)
    }

    /// The cap of joint `j` = `self.next`, from the window.
    fn cap(&self, j: usize) -> JointCap {
        let m = self.m;
        match self.window[1] {
            None | Some(Joint::Smooth) => SMOOTH_JOINT,
            Some(Joint::Tangent(cap)) => JointCap {
                point: cap,
                ..SMOOTH_JOINT
            },
            Some(Joint::Corner(bl, k_in, k_out)) => {
                // What the circle meets: the neighbouring circle when both
                // fill the line between them, else the piece itself.
                let before = if j > 0 && self.meet(j - 1) {
                    self.blend_of(j - 1)
                } else {
                    None
                };
                let meets_next = self.meet(j);
                let after = if meets_next {
                    self.blend_of(j + 1)
                } else {
                    None
                };
                let arc = blend_cap(m, &bl, 0.0);
                // The jump to what the circle meets. Circles that meet (a
                // chain of short moves sampling a curve) step the
                // curvature every circle, the shorter one's length apart;
                // a lone circle's two jumps have opposite signs and do not
                // add up.
                let jump = |next: Option<Blend>, k_piece: Vec3| match next {
                    Some(b) => step_cap(
                        m,
                        (bl.curvature - b.curvature).norm(),
                        b.arc_length.min(bl.arc_length),
                    ),
                    None => step_cap(m, (bl.curvature - k_piece).norm(), f64::INFINITY),
                };
                let entry = jump(before, k_in);
                let exit = jump(after, k_out);
                // Next to an arc or curve the circle's ends are not
                // modelled as stretches: all of its caps at the joint, the
                // curvature change across it as one jump, from what comes
                // before the circle to what comes after it. A line that
                // this circle and the next one's fill is not what comes
                // after: the curvature goes on to the next circle's (an arc
                // that goes on as short moves sampling the same curve
                // keeps its curvature; taken as a jump to a line's, its
                // joint was capped at a tenth of the curve's speed).
                let lines = self.is_line(j) && self.is_line(j + 1);
                let k_in = before.map_or(k_in, |b| b.curvature);
                let k_out = after.map_or(k_out, |b| b.curvature);
                let circle = bl.curvature - (k_in + k_out) * 0.5;
                let across = jump_cap(m, corner_jump(circle, k_in, k_out));
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
        }
    }
}

/// Cuts the run into stretches with caps; the `entry_cap` of each caps the
/// speed at its start (INFINITY inside pieces and at G2 joints).
/// `shaping` lowers caps and tangential limits by arc length along the run.
pub(super) fn stretches(
    pieces: &[Piece],
    opts: &PlanOptions,
    shaping: &Shaping,
    corners: Corners,
    locate: bool,
) -> Result<(Vec<Stretch>, Vec<Located>), FeedError> {
    let m = &opts.limits;
    let mut valid: Vec<(usize, f64)> = Vec::with_capacity(pieces.len());
    for (pi, p) in pieces.iter().enumerate() {
        let len = p.curve.length(m.chord_error * 1e-3);
        if !len.is_nan() && len > 0.0 {
            valid.push((pi, len));
        }
    }
    let mut jcaps = JointCaps::new(pieces, &valid, m, corners);
    // The caps of the joints before and after the current piece.
    let mut jout = SMOOTH_JOINT;
    // At least one stretch per piece; where more, the vector grows.
    let mut out: Vec<Stretch> = Vec::with_capacity(valid.len());
    let mut located: Vec<Located> = Vec::with_capacity(if locate { valid.len() } else { 0 });
    // The piece of the last stretch pushed.
    let mut last_piece = usize::MAX;
    // Arc length of the run before the current stretch.
    let mut s_run = 0.0f64;
    // Per piece: the parameters it is cut at, the blend caps of a line's
    // stretches (cap, length or 0 for the line's own, entry cap), and the
    // intervals to do with their end points where known.
    let mut ts: Vec<f64> = Vec::new();
    let mut caps: Vec<(f64, f64, f64)> = Vec::new();
    // A cubic spline's Bezier spans, and the span each interval of `ts`
    // lies in (that of `ts[k - 1]..ts[k]` at `k`): a stretch of a span is
    // measured and sampled on its Bezier form (`CubicBezier`).
    let mut beziers: Vec<CubicBezier> = Vec::new();
    let mut span_of: Vec<usize> = Vec::new();
    // A spline's corners inside it (`inner_corners`): where, and the cap
    // of each, in order.
    let mut inner: Vec<(f64, f64)> = Vec::new();
    type Known = Option<(PathPoint, f64)>;
    let mut todo: Vec<(f64, f64, u32, Known, Known, usize)> = Vec::new();
    for (vi, &(pi, len_total)) in valid.iter().enumerate() {
        let p = &pieces[pi];
        let feed = if opts.override_feed {
            m.max_feed
        } else {
            p.feed.map(|f| f / 60.0).unwrap_or(m.max_feed)
        };
        // The block's least time caps its speed (`MachineLimits::block_time`).
        let block_cap = if m.block_time > 0.0 {
            len_total / m.block_time
        } else {
            f64::INFINITY
        };
        if !(feed > 0.0 && feed.is_finite()) {
            return Err(FeedError::BadValue {
                name: "feed",
                value: feed,
            });
        }
        let c = &p.curve;
        // The joint's cap goes to the first stretch of the piece.
        let jin = if vi > 0 { jout } else { SMOOTH_JOINT };
        jout = jcaps.next_cap().unwrap_or(SMOOTH_JOINT);
        // The cap at the start of the piece.
        let mut jcap = jin.point;
        // A line with a corner at an end: the end stretch of the line that
        // the blend circle replaces is passed at the circle's cap, over
        // half the circle's arc length (the machine follows the circle
        // there, not just its middle), with the curvature jumps where the
        // circle starts and ends. Arcs and curves next to a corner take
        // the caps at the joint only.
        // (The buffers are the loop's: a plan of a long rendering made
        // three small vectors per piece.)
        ts.clear();
        caps.clear();
        beziers.clear();
        span_of.clear();
        inner.clear();
        // The next of `inner` not yet applied.
        let mut next_inner = 0usize;
        match c {
            Curve::Line(_) => {
                let (tin, tout) = (jin.tangent_length, jout.tangent_length);
                ts.push(0.0);
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
            }
            // A circular or helical arc's caps are the same all along it
            // (one curvature, no change of it), so its flattened spans
            // would merge into one stretch again; unless a shaping cuts it
            // where its factors change. A spiral (an arc read back from
            // rounded coordinates) is one stretch only while its radius
            // changes by at most ARC_ONE_STRETCH_SPREAD, else its caps
            // differ along it and it is flattened as curves are.
            Curve::Arc(a)
                if shaping.is_none()
                    && crate::math::abs(a.r1 - a.r0) <= ARC_ONE_STRETCH_SPREAD * a.r0.min(a.r1) =>
            {
                ts.extend([0.0, 1.0]);
            }
            // A spline is flattened span by span. Where the stretches fall
            // moves the plan (a segment boundary, where the acceleration
            // stops, falls between stretches), and at a knot the third
            // derivative, and so `dkappa/ds`, jumps: flattened span by
            // span, a B-spline has the stretches of its own Bezier spans and
            // plans their time (the thesis' square of ripples planned
            // slower as one B-spline before, `tests/feed_form.rs`; adding
            // the knots to the whole curve's cuts did not do it;
            // measurements: docs/tuning.md, `stretches`).
            // A span that its Bezier control points show flat is taken
            // whole without sampling it (`flat_span`: what the flattening
            // would decide at its first test), which on a long fit of short,
            // nearly straight spans is most of them.
            //
            // Each span of a polynomial cubic is flattened, measured and
            // sampled as the Bezier curve it is there (the same curve but
            // for rounding, at a fraction of the B-spline's evaluation:
            // `plan curves` of `surface-raster.ngc`'s fits in the stages
            // benchmark; measurements: docs/performance.md, "Fits
            // evaluated span by span").
            Curve::Nurbs(n) => {
                // (Span `i`'s points, where the spline is a polynomial
                // cubic: one per interval of `breaks`, none left out.)
                let breaks = n.breakpoints();
                let points = n.cubic_bezier_points().map(|(_, p)| p);
                let points = points.as_deref().unwrap_or(&[]);
                beziers.extend(
                    breaks
                        .windows(2)
                        .zip(points)
                        .filter_map(|(w, p)| CubicBezier::new(*p, w[0], w[1])),
                );
                if beziers.len() + 1 != breaks.len() {
                    beziers.clear();
                }
                // A corner inside the spline (a repeated control point, a
                // full knot where the polygon bends) is passed as a path
                // followed exactly passes a corner, whatever `corners`
                // says of the joints between pieces: the program asked
                // for the curve itself, corner included, and a controller
                // blends the joints between its blocks, not the inside of
                // one. Its curvature is not defined there, and the
                // sampled caps either side see no turn.
                let found = if points.is_empty() {
                    crate::geom::inner_corners(n, &jcaps.jt)
                } else {
                    crate::geom::corners_between_spans(&breaks, points, &jcaps.jt)
                };
                inner.extend(
                    found
                        .iter()
                        .map(|k| (k.t, followed_corner_cap(m, k.tangent_in, k.tangent_out))),
                );
                ts.push(breaks[0]);
                span_of.push(usize::MAX);
                for (i, w) in breaks.windows(2).enumerate() {
                    let first = ts.len();
                    if points.get(i).is_some_and(|b| flat_span(b, m.chord_error)) {
                        ts.push(w[1]);
                        span_of.push(i);
                    } else {
                        let span = match beziers.get(i) {
                            Some(b) => flatten_params_between(b, w[0], w[1], m.chord_error),
                            None => flatten_params_between(c, w[0], w[1], m.chord_error),
                        };
                        ts.extend_from_slice(&span[1..]);
                        span_of.extend(core::iter::repeat_n(i, span.len() - 1));
                    }
                    // A sharp turn inside a span (a cusp where a fit runs
                    // through a reversal: the curve stops and turns back)
                    // is passed as a corner followed exactly, at a cut of
                    // its own: its curvature is not defined where the
                    // curve stops, and the samples either side of it may
                    // see little of the turn. Turns on radii below the
                    // chord error are what the flattening does not resolve.
                    let Some(q) = points.get(i) else { continue };
                    for (u, tin, tout) in crate::geom::sharp_turns_in_span(q, m.chord_error) {
                        let t = w[0] + u * (w[1] - w[0]);
                        if !(t > w[0] && t < w[1]) {
                            continue;
                        }
                        let at = first + ts[first..].partition_point(|&x| x < t);
                        if ts.get(at) != Some(&t) {
                            ts.insert(at, t);
                            span_of.insert(at, i);
                        }
                        inner.push((t, followed_corner_cap(m, tin, tout)));
                    }
                }
                inner.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            _ => ts.extend(flatten_params(c, m.chord_error)),
        }
        let mut blend_caps = caps.iter().copied();
        // Intervals to do, last first; each is cut in two while the caps
        // at its ends and middle differ by more than CAP_SPLIT_RATIO and it
        // is longer than one period of travel at its cap.
        // Each with its end points where they are known (a split's halves
        // share its ends and middle; an interval starts where the one
        // before it ended): each point is evaluated once.
        todo.clear();
        todo.extend(ts.windows(2).enumerate().rev().map(|(k, w)| {
            let span = span_of.get(k + 1).copied().unwrap_or(usize::MAX);
            (w[0], w[1], 0, None, None, span)
        }));
        let mut last_end: Option<(f64, (PathPoint, f64))> = None;
        while let Some((t0, t1, depth, known0, known1, span)) = todo.pop() {
            // The curve the stretch is measured and sampled on.
            let on: &dyn ParamCurve = match beziers.get(span) {
                Some(b) => b,
                None => c,
            };
            let (blend_cap, blend_len, entry) =
                blend_caps
                    .next()
                    .unwrap_or((f64::INFINITY, 0.0, f64::INFINITY));
            if matches!(c, Curve::Line(_)) {
                jcap = jcap.min(entry);
            }
            while let Some(&(_, cap)) = inner.get(next_inner).filter(|k| k.0 <= t0) {
                jcap = jcap.min(cap);
                next_inner += 1;
            }
            let len = match c {
                Curve::Line(_) if blend_len > 0.0 => blend_len,
                Curve::Line(_) => len_total * (t1 - t0),
                _ => crate::geom::arc_length_between(on, t0, t1, m.chord_error * 1e-4),
            };
            if len.is_nan() || len <= 0.0 {
                continue;
            }
            let (p0, k0) = known0
                .or_else(|| last_end.filter(|l| l.0 == t0).map(|l| l.1))
                .unwrap_or_else(|| point(on, t0));
            let (pm, km) = point(on, 0.5 * (t0 + t1));
            let (p1, k1) = known1.unwrap_or_else(|| point(on, t1));
            last_end = Some((t1, (p1, k1)));
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
            if block_cap < cap.0 {
                cap = (block_cap, Constraint::BlockTime);
            }
            let (cap_factor, tangential) = shaping.factors(s_run, s_run + len);
            if high > CAP_SPLIT_RATIO * cap.0
                && len > cap.0 * m.period
                && depth < MAX_CAP_SPLITS
                && !matches!(c, Curve::Line(_))
            {
                let tm = 0.5 * (t0 + t1);
                todo.push((tm, t1, depth + 1, Some((pm, km)), Some((p1, k1)), span));
                todo.push((t0, tm, depth + 1, Some((p0, k0)), Some((pm, km)), span));
                continue;
            }
            let j = core::mem::replace(&mut jcap, f64::INFINITY) * cap_factor;
            cap.0 *= cap_factor;
            s_run += len;
            // Neighbouring stretches with the same cap and nothing between
            // them are one stretch.
            if let Some(last) = out.last_mut() {
                if last.cap == cap.0
                    && j >= cap.0
                    && last_piece == pi
                    && last.tangential == tangential
                {
                    last.length += len;
                    if let Some(l) = located.last_mut() {
                        l.t1 = t1;
                    }
                    continue;
                }
            }
            out.push(Stretch {
                length: len,
                cap: cap.0,
                entry_cap: j,
                tangential,
            });
            if locate {
                located.push(Located {
                    piece: pi,
                    t0,
                    t1,
                    constraint: cap.1,
                });
            }
            last_piece = pi;
        }
    }
    Ok((out, located))
}

#[cfg(test)]
mod tests {
    use super::flat_span;
    use crate::geom::{flatten_params, Curve, Nurbs, Vec3};
    use crate::seeded::Rng;

    /// Wherever `flat_span` takes a span whole, the flattening it stands in
    /// for takes it whole too: the shortcut never changes the cut. Random
    /// cubic spans from nearly straight to bent, at several chord errors,
    /// some of them taken whole.
    #[test]
    fn seeded_random_spans_taken_whole_are_what_the_flattening_takes_whole() {
        let mut rng = Rng(5);
        let mut taken = 0;
        for case in 0..2000 {
            let len = 0.05 + 3.0 * rng.next();
            let bend = [1e-6, 1e-4, 1e-3, 1e-2][case % 4] * len;
            // Control points unevenly spaced along the chord too.
            let uneven = [0.0, 1e-5, 1e-3, 0.1][(case / 4) % 4] * len;
            let mut pts = Vec::new();
            for i in 0..4 {
                let x = len * i as f64 / 3.0 + uneven * (rng.next() - 0.5);
                let y = bend * (rng.next() - 0.5);
                let z = bend * (rng.next() - 0.5);
                pts.push(Vec3::new(x, y, z));
            }
            let (a, b) = (10.0 * rng.next(), 10.0 + 10.0 * rng.next());
            let knots = vec![a, a, a, a, b, b, b, b];
            let span = Nurbs::new(3, knots, pts.clone(), None).expect("a valid span");
            let chord = [1e-4, 1e-3, 1e-2][case % 3];
            if flat_span(&pts, chord) {
                taken += 1;
                let cut = flatten_params(&Curve::from(span), chord);
                assert_eq!(cut, vec![a, b], "case {case}: {pts:?} at {chord}");
            }
        }
        assert!(taken > 300, "only {taken} spans taken whole");
    }
}
