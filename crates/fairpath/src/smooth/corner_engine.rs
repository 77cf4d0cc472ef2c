//! The one walk over a chain of lines that the three corner methods
//! (`bspline-corner`, `ctm`, `lotm`) share: at each inner vertex it keeps
//! the corner or blends it, emits the kept part of the segment before it as
//! a line piece, then the transition curve, puts the transition's ends
//! exactly on the points they must meet, and records the corners it keeps.
//!
//! What differs between the methods is injected:
//!
//! * the *plan* ([`CornerPlan`]): how far the transition at a corner
//!   reaches along its two segments, where its ends lie on them, and its
//!   five control points (the closed forms stay with the methods, in
//!   `bspline_corner.rs` and `bezier_corner.rs`);
//! * the *rules* ([`CornerRules`]): the two loops this engine replaced
//!   (`bspline-corner`'s and the one `ctm` and `lotm` shared) did not agree
//!   on what counts as a kept corner, where a transition's far end is
//!   snapped, and what a vertex without a direction becomes; each method
//!   keeps its own behaviour, byte for byte, through these parameters
//!   ([`Room`], [`CornerRules::keep_exact_reversal`], [`Undirected`]).
//!
//! The plans differ in one more place, kept in them: when the engine moves
//! a transition's ends, `bspline-corner` puts `P1`, `P3` halfway to the
//! moved ends (its polygon stays uniform), the Bezier corners leave them
//! where the length put them (`d` unchanged).

use super::absorb::{absorb_jogs, JogTolerances};
use super::bspline_corner::transition_curve;
use super::chains::{
    absorb_limit, merge_collinear, min_feed, CleanTolerances, CornerReason, KeptCorner, LineChain,
};
use super::SmoothedRun;
use crate::geom::{Curve, Line, Vec3};
use crate::path::Piece;
use alloc::vec;
use alloc::vec::Vec;

/// How the room a transition may use on its incoming segment is measured,
/// and so when the transitions are planned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Room {
    /// The whole segment from the previous vertex (`ctm`, `lotm`). The
    /// plan sees every corner of the chain before the walk
    /// ([`CornerPlan::plan_chain`]) and splits each segment shared by two
    /// transitions between them itself, so no room is left over to track.
    /// A transition's far end is put exactly on the next vertex when it
    /// comes within the zero-length threshold of it and no transition
    /// starts there (the chain's end, or a kept corner): the line piece
    /// left between would be a zero-length move.
    WholeSegment,
    /// What the previous transition left of the segment, less the share
    /// `lambda` of it kept straight (`bspline-corner`: paper eq. 8, overlap
    /// avoidance, section 3.4). Each corner is planned as the walk reaches
    /// it, from that room, so whether the next vertex gets a transition is
    /// not known yet: the far end is put on the next vertex (when within
    /// the zero-length threshold) only at the chain's last corner, where
    /// the chain's end vertex must be kept exactly. Elsewhere a line piece
    /// of at most that threshold can remain before the next vertex, whose
    /// corner then has no more room than the threshold and is kept.
    LeftByPrevious { lambda: f64 },
}

/// What a vertex without a direction on one side (a zero-length segment;
/// cleaning leaves none, see `chains.rs`) becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Undirected {
    /// Passed over: no piece ends there, the next piece runs through it
    /// (`bspline-corner`, as its own loop did).
    Skip,
    /// A line piece ends there, as at a kept corner, but nothing is
    /// reported (`ctm`, `lotm`).
    LineTo,
}

/// The per-method parameters of the walk (see [`Room`], [`Undirected`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CornerRules {
    /// Corners whose half-angle `theta` (radians) is below this are
    /// reversals and kept.
    pub min_half_angle: f64,
    /// Keep an exact reversal (`theta = 0`) even when `min_half_angle` is
    /// 0 (`ctm`, `lotm`: a transition there would turn on the spot, a cusp
    /// at its joint). `bspline-corner` applies its threshold alone (its
    /// default, 1e-6 rad, keeps exact reversals all the same).
    pub keep_exact_reversal: bool,
    pub room: Room,
    pub undirected: Undirected,
}

impl CornerRules {
    /// Why the corner at half-angle `theta` is kept, with `room_in` and
    /// `len_out` mm on its two sides (see [`Room`]), or `None` when it is
    /// blended: a reversal, or no room on one side (no longer than the
    /// zero-length threshold `min_seg`). A corner whose band `delta`,
    /// narrowed to the reach, is no wider than `min_seg` is a reversal too
    /// (the tip of a spike: a transition there would turn on the spot).
    fn keep(
        &self,
        theta: f64,
        room_in: f64,
        len_out: f64,
        min_seg: f64,
        delta: f64,
    ) -> Option<CornerReason> {
        if theta < self.min_half_angle
            || (self.keep_exact_reversal && theta == 0.0)
            || delta <= min_seg
        {
            Some(CornerReason::Reversal)
        } else if room_in <= min_seg || len_out <= min_seg {
            Some(CornerReason::NoRoom)
        } else {
            None
        }
    }
}

/// The band one chain is smoothed in, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Band {
    /// Deviation the transitions may use from the original moves: a
    /// transition on segments that absorbed jogs uses this less what they
    /// spent ([`LineChain::absorbed`]).
    pub delta: f64,
    /// Moves no longer than this are zero-length (the cleaning's
    /// threshold, `CleanTolerances::min_segment`).
    pub min_seg: f64,
    /// The jogs absorbed before the walk (`absorb.rs`).
    pub jogs: JogTolerances,
    /// How far from its corner point a transition's apex may lie.
    pub reach: Reach,
}

/// How far a transition's apex may lie from its corner point: the band at
/// a corner of half-angle `theta` is narrowed to `radius sin(theta)` (a
/// transition within `delta` of both moves crosses the bisector within
/// `delta / sin(theta)` of the corner, [`crate::budget::CORNER_REACH_SHARE`]),
/// less what absorbed jogs moved the corner.
///
/// On the outer-edge guide (`outer_guide.rs`) a moved corner lies
/// `shift / sin(theta)` outside the original one on its bisector (each
/// move's line moved out by `shift`), so its band may be `shift` wider for
/// the apex to keep the same reach of the original corner: `shift +
/// radius sin(theta)`. The guide moves no corner of half-angle below
/// `moved_from` (turns sharper than its largest), which keep `radius
/// sin(theta)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Reach {
    /// The apex's largest distance from the (original) corner point, mm.
    pub radius: f64,
    /// How far the guide moved the lines of the corners of half-angle at
    /// least `moved_from`, mm (0 off the guide).
    pub shift: f64,
    /// The least half-angle of a moved corner (0 off the guide).
    pub moved_from: f64,
}

impl Reach {
    /// The band `delta` at a corner of half-angle `theta`, less `spent` mm
    /// that absorbing jogs moved it, narrowed to this reach.
    fn narrowed(&self, delta: f64, theta: f64, spent: f64) -> f64 {
        let reach = (self.radius - spent).max(0.0) * crate::math::sin(theta);
        let moved = if theta >= self.moved_from {
            self.shift
        } else {
            0.0
        };
        delta.min(moved + reach)
    }
}

impl Band {
    /// The band of transitions that may use `delta` mm of the tolerance
    /// `tolerance`: zero-length moves as the cleaning's, jogs absorbed
    /// within [`absorb_limit`], short moves up to
    /// [`crate::budget::SHORT_MOVE_SHARE`] tolerances considered, every
    /// apex within [`crate::budget::CORNER_REACH_SHARE`] `delta` of its
    /// corner.
    pub fn new(tolerance: f64, delta: f64) -> Band {
        let min_seg = CleanTolerances::from_tolerance(tolerance).min_segment;
        let short = tolerance * crate::budget::SHORT_MOVE_SHARE;
        Band {
            delta,
            min_seg,
            jogs: JogTolerances::new(absorb_limit(tolerance, delta), short, min_seg)
                .merging(CleanTolerances::from_tolerance(tolerance).collinear),
            reach: Reach {
                radius: crate::budget::CORNER_REACH_SHARE * delta,
                shift: 0.0,
                moved_from: 0.0,
            },
        }
    }

    /// This band with its apexes held to `reach`.
    pub fn with_reach(self, reach: Reach) -> Band {
        Band { reach, ..self }
    }
}

/// One chain of lines as a whole-chain plan sees it ([`Room::WholeSegment`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ChainCorners {
    /// Length of segment `j` (from vertex `j` to `j + 1`).
    pub seg_len: Vec<f64>,
    /// Half-angle at vertex `k` (0 at the two ends).
    pub theta: Vec<f64>,
    /// Whether vertex `k` gets a transition (false at the ends and at kept
    /// corners).
    pub blend: Vec<bool>,
    /// Deviation the transition at vertex `k` may use from the chain (mm):
    /// the band less what absorbing jogs spent on its two segments.
    pub delta: Vec<f64>,
}

impl ChainCorners {
    /// Whether segment `j` has transitions at both ends.
    pub fn shared(&self, j: usize) -> bool {
        self.blend[j] && self.blend[j + 1]
    }
}

/// One corner to blend, as the walk reaches it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Corner {
    /// Index of the vertex in the chain.
    pub k: usize,
    /// The vertex.
    pub at: Vec3,
    /// Unit directions from the vertex towards the previous and next ones.
    pub a: Vec3,
    pub b: Vec3,
    /// Half the angle between `a` and `b`.
    pub theta: f64,
    /// Room on the incoming segment (see [`Room`]), mm.
    pub room_in: f64,
    /// The outgoing segment, from the vertex to the next one, and its length.
    pub out: Vec3,
    pub len_out: f64,
    /// Whether this is the chain's last inner vertex.
    pub last: bool,
    /// Deviation the transition may use, mm.
    pub delta: f64,
}

/// The per-method part of a corner transition.
pub(crate) trait CornerPlan {
    /// Sees every corner of the chain before the walk, with
    /// [`Room::WholeSegment`] only (`ctm` and `lotm` plan all lengths here).
    fn plan_chain(&mut self, _corners: &ChainCorners) {}
    /// How far the transition at `c` reaches along each segment from the
    /// corner, mm. When it reaches the whole room on a side, the engine
    /// puts the end there exactly.
    fn reach(&mut self, c: &Corner) -> f64;
    /// Where the ends of the transition of `reach` lie, on the incoming and
    /// the outgoing segment.
    fn ends(&self, c: &Corner, reach: f64) -> (Vec3, Vec3);
    /// The five control points of the transition of `reach`, with its ends
    /// `p0` and `p4` where the engine put them (at most the zero-length
    /// threshold from [`CornerPlan::ends`], or on the room's ends).
    fn control_points(&self, c: &Corner, reach: f64, p0: Vec3, p4: Vec3) -> [Vec3; 5];
}

/// Smooths one chain of lines (its end vertices kept exactly) with `plan`
/// under `rules`, appending to `out`, after absorbing its jogs into their
/// neighbours (`absorb.rs`; each transition's band less what that spent on
/// its segments). A chain without segments adds nothing.
pub(crate) fn smooth_chain(
    chain: &LineChain,
    band: Band,
    rules: &CornerRules,
    plan: &mut impl CornerPlan,
    out: &mut SmoothedRun,
) {
    let absorbed;
    let chain = if band.jogs.max_dev > 0.0 {
        let mut c = chain.clone();
        let n = absorb_jogs(&mut c, &band.jogs);
        if n > 0 {
            // A jog collapsed on a straight line leaves a straight-on vertex.
            out.merged_collinear += merge_collinear(&mut c, band.jogs.collinear);
        }
        out.absorbed_jogs += n;
        absorbed = c;
        &absorbed
    } else {
        chain
    };
    let q = &chain.pts;
    let n = chain.segments();
    if n == 0 {
        return;
    }
    let min_seg = band.min_seg;
    // Directions and half-angle at every inner vertex that has both.
    let geometry: Vec<Option<(Vec3, Vec3, f64)>> = (0..=n)
        .map(|k| {
            if k == 0 || k == n {
                return None;
            }
            let a = (q[k - 1] - q[k]).normalized(0.0)?;
            let b = (q[k + 1] - q[k]).normalized(0.0)?;
            Some((a, b, 0.5 * a.angle_to(b)))
        })
        .collect();
    // The band at vertex `k`, less what absorbing jogs spent next to it,
    // narrowed to the reach.
    let delta_at = |k: usize| {
        let spent = chain.absorbed_max(k.saturating_sub(1)..(k + 1).min(n));
        match geometry[k] {
            Some((_, _, theta)) => band.reach.narrowed(band.delta - spent, theta, spent),
            None => band.delta - spent,
        }
    };
    // Which vertices a whole-chain plan blends (the same rule as the walk's,
    // with the whole segments as room).
    let blend = if rules.room == Room::WholeSegment {
        let seg_len: Vec<f64> = (0..n).map(|j| q[j].dist(q[j + 1])).collect();
        let mut theta = vec![0.0; n + 1];
        let mut blend = vec![false; n + 1];
        for k in 1..n {
            if let Some((_, _, th)) = geometry[k] {
                theta[k] = th;
                blend[k] = rules
                    .keep(th, seg_len[k - 1], seg_len[k], min_seg, delta_at(k))
                    .is_none();
            }
        }
        let cc = ChainCorners {
            seg_len,
            theta,
            blend,
            delta: (0..=n).map(delta_at).collect(),
        };
        plan.plan_chain(&cc);
        cc.blend
    } else {
        Vec::new()
    };
    let push_line = |out: &mut SmoothedRun, a: Vec3, b: Vec3, seg: usize| {
        if a.dist(b) > 0.0 {
            out.pieces.push(Piece {
                curve: Curve::Line(Line::new(a, b)),
                rapid: false,
                source_lines: chain.lines[seg],
                feed: chain.feed[seg],
            });
        }
    };
    // The end of the last piece, and (with `Room::LeftByPrevious`) where
    // the room on the current segment starts.
    let mut cursor = q[0];
    let mut left = q[0];
    for k in 1..n {
        let qk = q[k];
        let Some((a, b, theta)) = geometry[k] else {
            if rules.undirected == Undirected::LineTo {
                push_line(out, cursor, qk, k - 1);
                cursor = qk;
            }
            continue;
        };
        let room_start = match rules.room {
            Room::WholeSegment => q[k - 1],
            Room::LeftByPrevious { .. } => left,
        };
        let out_vec = q[k + 1] - qk;
        let c = Corner {
            k,
            at: qk,
            a,
            b,
            theta,
            room_in: room_start.dist(qk),
            out: out_vec,
            len_out: out_vec.norm(),
            last: k == n - 1,
            delta: delta_at(k),
        };
        if let Some(reason) = rules.keep(theta, c.room_in, c.len_out, min_seg, c.delta) {
            push_line(out, cursor, qk, k - 1);
            out.kept_corners.push(KeptCorner {
                at: qk,
                source_line: chain.lines[k - 1].1,
                reason,
            });
            cursor = qk;
            left = qk;
            continue;
        }
        let reach = plan.reach(&c);
        let (p0, p4) = plan.ends(&c, reach);
        // The ends exactly on the room's start or the next vertex when the
        // whole room is used, and on the previous piece's end when within
        // the zero-length threshold of it, so that pieces meet exactly.
        let p0 = if reach >= c.room_in { room_start } else { p0 };
        let p0 = if p0.dist(cursor) <= min_seg {
            cursor
        } else {
            p0
        };
        let snap_far = match rules.room {
            Room::WholeSegment => !blend[k + 1],
            Room::LeftByPrevious { .. } => c.last,
        };
        let p4 = if reach >= c.len_out || (snap_far && p4.dist(q[k + 1]) <= min_seg) {
            q[k + 1]
        } else {
            p4
        };
        push_line(out, cursor, p0, k - 1);
        out.pieces.push(Piece {
            curve: Curve::from(transition_curve(plan.control_points(&c, reach, p0, p4))),
            rapid: false,
            source_lines: (chain.lines[k - 1].0, chain.lines[k].1),
            feed: min_feed(chain.feed[k - 1], chain.feed[k]),
        });
        out.transitions += 1;
        cursor = p4;
        if let Room::LeftByPrevious { lambda } = rules.room {
            left = p4 + (q[k + 1] - p4) * lambda;
        }
    }
    push_line(out, cursor, q[n], n - 1);
}
