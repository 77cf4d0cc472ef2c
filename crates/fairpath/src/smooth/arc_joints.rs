//! G2 transitions at the joints next to arcs that the corner methods keep.
//!
//! The corner methods (seeds 000 and 001) blend corners between lines and
//! keep arcs as they are, so a joint between a line and an arc, or between
//! two arcs, keeps the continuity the program gave it: a corner, or a
//! tangent joint whose curvature jumps by `1/R`, which slows the machine
//! as much as a corner of small angle. The seeds leave these joints alone;
//! [`blend_arc_joints`] replaces each such joint by a quintic that meets
//! both sides G2 ([`crate::geom::g2_quintic_points`]), the arc cut back to
//! where the quintic leaves it (an exact sub-arc, [`Arc::between`]) and
//! the line likewise, so the arc keeps its constant curvature up to the
//! transition. A CNC engineer's choices where the seeds say nothing:
//!
//! * **Reach.** The transition reaches the same arc length `s` back along
//!   both sides, at most half of each piece as it came from the method
//!   (the other half is the next joint's) and at most an eighth of a turn
//!   of an arc ([`MAX_ARC_SWEEP`]). Of the longest `s` within the band
//!   (bisection, at the widest speeds) and its halvings, the one whose
//!   transition has the lowest jerk demand (`jerk_demand`, machine-independent): at a corner the
//!   longest, the gentlest turn; between two arcs of nearly the same
//!   curvature a short one, as a long quintic follows the arcs with a
//!   wobble of its curvature.
//! * **Speeds.** `d0 = d1 =` a factor of [`SPEED_FACTORS`] times the
//!   chord between the two ends (the chord itself is the usual choice for
//!   Hermite interpolation; how the speeds spread the curvature over the
//!   transition changes its jerk demand by more than the reach does), the
//!   one whose transition has the lowest jerk demand with the reach.
//! * **Band.** The transition replaces a line piece and an arc of the
//!   method's output that lie on the original path, within what absorbing
//!   jogs spent on a line ([`crate::budget::ABSORB_SHARE`], taken out of
//!   the band by the triangle inequality); its distance to the parts it
//!   replaces is bounded from samples ([`deviation_bound`]), which bounds
//!   its distance to the original path.
//! * **Not blended**: joints with a NURBS on either side, corners sharper
//!   than [`MAX_TURN`] (kept, as the planner passes them faster than a
//!   transition inside the band), joints that are nearly G2 already
//!   ([`NEAR_G2_TURN`]), and joints where no reach of at least
//!   [`MIN_REACH_SHARE`] of the tolerance stays in the band or leaves that
//!   much of both pieces (a line shorter than that has no direction of its
//!   own).

use super::chains::{min_feed, CornerReason};
use super::SmoothedRun;
use crate::budget::{ABSORB_SHARE, BAND_USE};
use crate::geom::{
    bezier_nurbs, classify_joint, distance_to_polyline, g2_quintic_points, Arc, Continuity, Curve,
    EndState, JointTolerances, Line, ParamCurve, Vec3,
};
use crate::path::Piece;
use alloc::vec::Vec;

/// What a corner method does at the joints next to arcs that are not G2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum ArcJoints {
    /// Kept as the program has them, as the seeds do (the default; each is
    /// reported as a kept corner, [`CornerReason::ArcJoint`]).
    #[default]
    Kept,
    /// G2 transitions where they help: at tangent joints and corners up to
    /// 30 degrees ([`blend_arc_joints`]); the arcs stay arcs up to the
    /// transitions.
    Blended,
}

impl ArcJoints {
    /// Applies the choice to `out`, smoothed within `tolerance` mm.
    pub(crate) fn apply(self, out: &mut SmoothedRun, tolerance: f64) {
        if self == ArcJoints::Blended {
            blend_arc_joints(out, tolerance);
        }
    }
}

/// Largest turn (rad) at a joint that gets a transition (30 degrees). A
/// sharper corner next to an arc is kept: inside the band a G2 transition
/// turns it on a small radius that the machine must follow slowly over
/// the transition's whole length, while the planner (and a blending
/// controller) passes the kept corner on its junction circle, a few
/// micrometres long (`docs/tuning.md` has the survey behind the value).
pub const MAX_TURN: f64 = 30.0 * core::f64::consts::PI / 180.0;

/// A joint whose tangent turns by at most this (rad) and whose curvature
/// vector changes by at most [`NEAR_G2_CURVATURE_STEP`] of its size is
/// nearly G2 (two helices of different pitch, an arc split in two and
/// rounded) and is not blended: the planner passes it at the cap of its
/// small curvature jump, while a quintic must follow the arcs' curvature
/// over its whole reach and wobbles about it (`docs/tuning.md`).
pub const NEAR_G2_TURN: f64 = 0.01;

/// See [`NEAR_G2_TURN`].
pub const NEAR_G2_CURVATURE_STEP: f64 = 0.25;

/// Shortest reach, as a share of the tolerance, worth a transition: a
/// shorter one would turn the corner with a curvature the machine passes
/// no faster than the corner itself.
pub const MIN_REACH_SHARE: f64 = 0.01;

/// The end speeds `d0 = d1` of a transition tried at each reach, in
/// chords between its ends, the widest first (see the module
/// documentation; the survey behind them is in `docs/tuning.md`).
pub const SPEED_FACTORS: [f64; 4] = [1.3, 1.15, 1.0, 0.85];

/// Samples of a transition at which its distance to the path is measured
/// ([`deviation_bound`]).
const SAMPLES: usize = 48;

/// Bisection steps on the reach.
const REACH_STEPS: usize = 40;

/// Reaches tried below the longest within the band, each half the one
/// before ([`blend_joint`]).
const REACH_LADDER: usize = 8;

/// Share of the band the chords of an arc may take where the distance to
/// the arc is measured on them.
const ARC_CHORD_SHARE: f64 = 0.01;

/// Largest sweep (rad) of an arc that a transition replaces: an eighth of
/// a turn, so that the arc keeps most of its constant curvature.
pub const MAX_ARC_SWEEP: f64 = 0.5 * core::f64::consts::FRAC_PI_2;

/// Replaces the joints of `out`'s pieces between a line and an arc, or two
/// arcs, that are not G2 by G2 transitions within the band of `tolerance`
/// mm, where the module documentation says; the kept corners reported there
/// ([`CornerReason::ArcJoint`]) go, and `out.transitions` counts the new
/// transitions. Bounds: each transition lies within `tolerance * (BAND_USE
/// - ABSORB_SHARE)` of the pieces it replaces.
pub fn blend_arc_joints(out: &mut SmoothedRun, tolerance: f64) {
    let band = tolerance * (BAND_USE - ABSORB_SHARE);
    let jt = JointTolerances::from_tolerance(tolerance);
    let min_reach = MIN_REACH_SHARE * tolerance;
    let pieces = core::mem::take(&mut out.pieces);
    let mut result: Vec<Piece> = Vec::with_capacity(pieces.len());
    let mut blended: Vec<Vec3> = Vec::new();
    let mut iter = pieces.into_iter();
    let Some(mut cur) = iter.next() else {
        return;
    };
    // Half the length of `cur` as the method made it: the room each of its
    // joints may use (a transition at its start took no more than that).
    let mut cur_room = 0.5 * length(&cur.curve);
    for next in iter {
        let next_room = 0.5 * length(&next.curve);
        let joint = next.start();
        let room = (cur_room, next_room);
        match blend_joint(&cur, &next, room, band, min_reach, &jt) {
            Some([a, t, b]) => {
                result.push(a);
                result.push(t);
                blended.push(joint);
                cur = b;
            }
            None => {
                result.push(cur);
                cur = next;
            }
        }
        cur_room = next_room;
    }
    result.push(cur);
    out.pieces = result;
    out.transitions += blended.len();
    out.kept_corners
        .retain(|k| k.reason != CornerReason::ArcJoint || !blended.contains(&k.at));
}

/// The length of a line or arc (for a spiral, of the arc of its mean
/// radius: only the reach is measured by it); 0 for anything else.
fn length(c: &Curve) -> f64 {
    match c {
        Curve::Line(l) => l.length(),
        Curve::Arc(a) => a.approx_length(),
        Curve::Nurbs(_) => 0.0,
    }
}

/// Which end of a piece a transition leaves or reaches.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    /// The piece ends at the joint: the transition starts on it.
    End,
    /// The piece starts at the joint: the transition ends on it.
    Start,
}

/// A line or arc cut back by arc length `s` from the joint at `side`: its
/// state where the transition meets it, the piece that is left (at least
/// `min_keep` mm long), and the part cut off (for the distance bound), as
/// points within `chord` mm of it.
fn cut(
    p: &Piece,
    side: Side,
    s: f64,
    (chord, min_keep): (f64, f64),
) -> Option<(EndState, Piece, Vec<Vec3>)> {
    let len = length(&p.curve);
    // What is left must keep a direction of its own.
    if !(s > 0.0 && len - s >= min_keep) {
        return None;
    }
    let t = match side {
        Side::End => 1.0 - s / len,
        Side::Start => s / len,
    };
    let (kept, removed): (Curve, Vec<Vec3>) = match &p.curve {
        Curve::Line(l) => {
            let q = l.eval(t);
            match side {
                Side::End => (Curve::Line(Line::new(l.p0, q)), alloc::vec![q, l.p1]),
                Side::Start => (Curve::Line(Line::new(q, l.p1)), alloc::vec![l.p0, q]),
            }
        }
        Curve::Arc(a) => {
            let (kept, gone) = match side {
                Side::End => (a.between(0.0, t), a.between(t, 1.0)),
                Side::Start => (a.between(t, 1.0), a.between(0.0, t)),
            };
            (Curve::from(kept), arc_points(&gone, chord)?)
        }
        Curve::Nurbs(_) => return None,
    };
    let state = EndState {
        point: p.curve.eval(t),
        tangent: p.curve.unit_tangent(t)?,
        curvature: p.curve.curvature_vector(t),
    };
    let piece = Piece {
        curve: kept,
        ..p.clone()
    };
    Some((state, piece, removed))
}

/// Points of `a` whose chords lie within `chord` mm of it
/// ([`Arc::chord_params`]).
fn arc_points(a: &Arc, chord: f64) -> Option<Vec<Vec3>> {
    let ts = a.chord_params(chord, 4096)?;
    Some(ts.into_iter().map(|t| a.eval(t)).collect())
}

/// An upper bound of the distance of the Bezier curve with control points
/// `p` to the union of the polylines `refs`, each within `chord` mm of the
/// path part it stands for: the largest distance of [`SAMPLES`] points
/// evenly spaced in the parameter, plus `chord`, plus half a parameter step
/// times the largest speed `|B'| <= n max |P_{i+1} - P_i|` (the hodograph's
/// control points bound it; Farin, section 5.3), which bounds how far the
/// curve gets between samples.
fn deviation_bound(p: &[Vec3; 6], refs: [&[Vec3]; 2], chord: f64) -> f64 {
    let c = bezier_nurbs(p);
    let speed = 5.0 * p.windows(2).map(|w| w[0].dist(w[1])).fold(0.0, f64::max);
    let step = 1.0 / (SAMPLES - 1) as f64;
    let mut worst: f64 = 0.0;
    for i in 0..SAMPLES {
        let q = c.eval(i as f64 * step);
        let d = refs
            .iter()
            .filter_map(|r| distance_to_polyline(q, r).map(|(d, _)| d))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    worst + chord + 0.5 * step * speed
}

/// The joint of `a` (ending there) and `b` (starting there) replaced by a
/// G2 transition reaching at most `room` along each, within `band` mm of
/// the parts it replaces: `[a cut back, transition, b cut back]`, or
/// `None` where the joint is not blended (module documentation).
fn blend_joint(
    a: &Piece,
    b: &Piece,
    room: (f64, f64),
    band: f64,
    min_reach: f64,
    jt: &JointTolerances,
) -> Option<[Piece; 3]> {
    let arc_sweep_room = |p: &Piece| match &p.curve {
        Curve::Arc(arc) => arc.approx_length() * (MAX_ARC_SWEEP / arc.sweep).min(1.0),
        _ => f64::INFINITY,
    };
    let lines_or_arcs = |p: &Piece| matches!(p.curve, Curve::Line(_) | Curve::Arc(_));
    let has_arc = matches!(a.curve, Curve::Arc(_)) || matches!(b.curve, Curve::Arc(_));
    if !(has_arc && lines_or_arcs(a) && lines_or_arcs(b)) {
        return None;
    }
    if classify_joint(&a.curve, &b.curve, jt) == Continuity::G2 {
        return None;
    }
    let ta = a.curve.unit_tangent(1.0)?;
    let tb = b.curve.unit_tangent(0.0)?;
    if ta.dot(tb) < crate::math::cos(MAX_TURN) {
        return None;
    }
    let (ka, kb) = (a.curve.curvature_vector(1.0), b.curve.curvature_vector(0.0));
    let near_g2 = ta.dot(tb) >= crate::math::cos(NEAR_G2_TURN)
        && ka.dist(kb) <= NEAR_G2_CURVATURE_STEP * ka.norm().max(kb.norm());
    if near_g2 {
        return None;
    }
    let chord = ARC_CHORD_SHARE * band;
    let s_max = room
        .0
        .min(room.1)
        .min(arc_sweep_room(a))
        .min(arc_sweep_room(b));
    // (NaN: a degenerate piece, no room either.)
    if s_max.is_nan() || s_max < min_reach {
        return None;
    }
    // The transition with reach `s`, and whether it stays in the band.
    let build = |s: f64, factor: f64| -> Option<([Piece; 3], bool)> {
        let (sa, pa, ra) = cut(a, Side::End, s, (chord, min_reach))?;
        let (sb, pb, rb) = cut(b, Side::Start, s, (chord, min_reach))?;
        let d = sa.point.dist(sb.point);
        let pts = g2_quintic_points(&sa, &sb, factor * d, factor * d);
        let within = deviation_bound(&pts, [&ra, &rb], chord) <= band;
        let t = Piece {
            curve: Curve::from(bezier_nurbs(&pts)),
            rapid: false,
            source_lines: (a.source_lines.0, b.source_lines.1),
            feed: min_feed(a.feed, b.feed),
        };
        Some(([pa, t, pb], within))
    };
    // The longest reach within the band: `s_max`, or by bisection.
    let mut s_band = s_max;
    let widest = SPEED_FACTORS[0];
    if !matches!(build(s_max, widest), Some((_, true))) {
        let (mut lo, mut hi) = (0.0, s_max);
        for _ in 0..REACH_STEPS {
            let mid = 0.5 * (lo + hi);
            match build(mid, widest) {
                Some((_, true)) => lo = mid,
                _ => hi = mid,
            }
        }
        s_band = lo;
    }
    // Of that reach and its halvings, each with every end speed of
    // [`SPEED_FACTORS`], the transition whose jerk demand is the lowest
    // (the first on a tie: the longest, the fastest ends): longer is
    // gentler where the transition turns a corner, shorter where it joins
    // two arcs of nearly the same curvature, which a long quintic follows
    // with a wobble of its curvature.
    let mut best: Option<([Piece; 3], f64)> = None;
    let mut s = s_band;
    for _ in 0..REACH_LADDER {
        if s < min_reach {
            break;
        }
        for &factor in &SPEED_FACTORS {
            if let Some((pieces, true)) = build(s, factor) {
                let demand = jerk_demand(&pieces[1].curve);
                if best.as_ref().is_none_or(|(_, d)| demand < *d) {
                    best = Some((pieces, demand));
                }
            }
        }
        s *= 0.5;
    }
    best.map(|(pieces, _)| pieces)
}

/// The largest jerk demand `sqrt(kappa^4 + (dkappa/ds)^2)` (1/mm^3) over
/// [`SAMPLES`] points of `c`: the centripetal and curvature-change terms
/// of the jerk at unit speed, which cap the speed at
/// `v <= (J / demand)^(1/3)` ([`crate::feed`]'s caps, where they bind at
/// the small radii of transitions). `dkappa/ds` by central differences
/// over the samples' chords.
fn jerk_demand(c: &Curve) -> f64 {
    let step = 1.0 / (SAMPLES - 1) as f64;
    let pts: Vec<(Vec3, f64)> = (0..SAMPLES)
        .map(|i| {
            let t = i as f64 * step;
            (c.eval(t), c.curvature(t))
        })
        .collect();
    let mut worst: f64 = 0.0;
    for i in 1..SAMPLES - 1 {
        let ds = pts[i - 1].0.dist(pts[i].0) + pts[i].0.dist(pts[i + 1].0);
        let k = pts[i].1;
        let dk = if ds > 0.0 {
            (pts[i + 1].1 - pts[i - 1].1) / ds
        } else {
            0.0
        };
        worst = worst.max(crate::math::sqrt(k * k * k * k + dk * dk));
    }
    worst
}
