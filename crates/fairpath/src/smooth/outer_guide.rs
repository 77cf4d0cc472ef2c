//! A guide polyline for corner transitions that use both sides of the
//! band: every sparse corner of a run of lines moved outward, so that a
//! transition built on the guide starts on the outer edge of the band and
//! cuts across to its inner edge at the corner (issue 21, item 1).
//!
//! Why: a corner method builds its transition on the two moves with its
//! apex within the tolerance `e` of the vertex, on the inner side. The
//! band also lies on the outer side of each move: a path that runs along
//! the outer edge before the corner and turns onto the outer edge after it
//! has a cut depth of about `2 e` instead of `e`, and for a turn `theta`
//! the transition's curvature scales as `1 / depth` (a circle tangent to
//! both moves whose apex is `h` from their meeting point has radius `h /
//! (1 / cos(theta / 2) - 1)`), so its speed under `k^2 v^3 <= J` rises by
//! `2^(2/3)`. Moving the vertex outward along its bisector by `s /
//! cos(theta / 2)` moves each of its moves' lines outward by exactly `s`
//! (the bisector makes the angle `theta / 2` with each move's normal); a
//! transition of depth `s + e'` on the guide then has its apex `e' + s -
//! s / cos(theta / 2) <= e'` inside the original vertex. The moves
//! between two moved corners stay within `s` of the original's (both
//! their ends are, and distance to a line is convex along a segment),
//! except next to a vertex, where the transition replaces the guide.
//! That is an argument, not a proof for every shape (a transition may
//! bulge beyond the guide's moves where they leave the original's strip
//! near the vertex), so the candidate that uses the guide is verified
//! against the run it smooths and falls back where it leaves the band
//! (`choose::candidates`, `Candidate::OuterCorner`).

use super::chains::{merge_collinear, LineChain};
use crate::geom::{Curve, Line, Vec3};
use crate::path::{Piece, Run};
use alloc::vec::Vec;

/// Which corners [`outer_guide`] moves, and how far.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OuterGuide {
    /// How far each move's line is moved outward at a corner (mm): the
    /// vertex moves `shift / cos(theta / 2)` along its bisector.
    pub shift: f64,
    /// Largest turn (rad) of a corner that is moved: at sharper turns the
    /// vertex moves far (`1 / cos(theta / 2)`) for little gain, as the
    /// machine nearly stops there whatever the transition.
    pub max_turn: f64,
    /// The cut depth (mm) a transition on the guide takes at a corner
    /// (the corner method's tolerance there). A corner is moved only
    /// where a circle of that depth fits in half of each of its moves:
    /// its tangent length, `depth / tan(theta / 4)` (a circle tangent to
    /// both moves whose middle lies `h` from their vertex has radius `h
    /// cos(theta / 2) / (1 - cos(theta / 2))` and tangent length that
    /// times `tan(theta / 2)`, which is `h / tan(theta / 4)`), at most
    /// half the shorter move. Elsewhere the moves, not the band, limit
    /// the transition, and a deeper cut gains nothing: vertices that turn
    /// by a little (a straight edge whose rounded coordinates wobble, a
    /// sampled arc) stay where they are instead of zigzagging by the
    /// shift.
    pub depth: f64,
    /// Moves that run straight on within this distance (mm) are one move
    /// for the guide: a straight edge written as many short moves (an
    /// engraving's, its coordinates rounded so that its vertices wobble
    /// by the last decimal) gives its corners the room of the whole edge.
    /// Merged only where the feed is the same and the direction does not
    /// reverse; the merged move keeps the input lines of those it
    /// replaces.
    pub straight: f64,
}

/// `run` with every corner between two line moves that turns by at most
/// `g.max_turn` and whose transition of `g.depth` fits in its moves moved
/// outward (module docs), or `None` where the run has a piece that is not a line or no
/// corner moves. The run's ends stay where they are; every other field
/// of each piece (feed, source lines) is kept.
pub fn outer_guide(run: &Run, g: &OuterGuide) -> Option<Run> {
    if run.pieces.len() < 2 || g.shift.is_nan() || g.shift <= 0.0 {
        return None;
    }
    if run
        .pieces
        .iter()
        .any(|p| !matches!(p.curve, Curve::Line(_)))
    {
        return None;
    }
    let pieces = merged_straight(&run.pieces, g.straight);
    let mut pts: Vec<Vec3> = Vec::with_capacity(pieces.len() + 1);
    pts.push(pieces[0].start());
    pts.extend(pieces.iter().map(|p| p.end()));
    let mut moved = pts.clone();
    let mut any = false;
    for i in 1..pts.len() - 1 {
        let (a, b) = (pts[i] - pts[i - 1], pts[i + 1] - pts[i]);
        let (Some(u1), Some(u2)) = (a.normalized(0.0), b.normalized(0.0)) else {
            continue;
        };
        let theta = u1.angle_to(u2);
        if !(theta > 0.0 && theta <= g.max_turn) {
            continue;
        }
        let tangent = g.depth / crate::math::tan(0.25 * theta);
        // (NaN: a move of no length.)
        if tangent.is_nan() || tangent > 0.5 * a.norm().min(b.norm()) {
            continue;
        }
        // The inner bisector (towards the inside of the turn).
        let Some(inner) = (u2 - u1).normalized(0.0) else {
            continue;
        };
        let out = g.shift / crate::math::cos(0.5 * theta);
        moved[i] = pts[i] - inner * out;
        any = true;
    }
    if !any {
        return None;
    }
    let pieces = pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut q = p.clone();
            q.curve = Curve::Line(Line::new(moved[i], moved[i + 1]));
            q
        })
        .collect();
    Some(Run::new(pieces))
}

/// `pieces` (lines) with every run of moves that goes straight on within
/// `straight` mm merged into one move, by the cleaning's own rule
/// ([`super::chains::merge_collinear`]: each removed vertex within
/// `straight` of the merged move, the same feed, no reversal).
fn merged_straight(pieces: &[Piece], straight: f64) -> Vec<Piece> {
    let mut chain = LineChain {
        pts: core::iter::once(pieces[0].start())
            .chain(pieces.iter().map(|p| p.end()))
            .collect(),
        lines: pieces.iter().map(|p| p.source_lines).collect(),
        feed: pieces.iter().map(|p| p.feed).collect(),
        absorbed: Vec::new(),
    };
    merge_collinear(&mut chain, straight);
    (0..chain.segments())
        .map(|i| Piece {
            curve: Curve::Line(Line::new(chain.pts[i], chain.pts[i + 1])),
            rapid: false,
            source_lines: chain.lines[i],
            feed: chain.feed[i],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec3 {
        Vec3::new(x, y, 0.0)
    }

    /// A right angle's vertex moves `shift * sqrt(2)` outward, so both
    /// moves' lines move by `shift`; the run's ends stay.
    #[test]
    fn a_right_angle_moves_its_lines_by_the_shift() {
        let run = Run::polyline(&[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 10.0)], None);
        let g = OuterGuide {
            shift: 0.03,
            max_turn: 2.0,
            depth: 0.1,
            straight: 0.0,
        };
        let guide = outer_guide(&run, &g).expect("a corner moves");
        let c = guide.pieces[0].end();
        assert!(
            (c.x - 10.03).abs() < 1e-12 && (c.y + 0.03).abs() < 1e-12,
            "{c:?}"
        );
        assert_eq!(guide.pieces[0].start(), v(0.0, 0.0));
        assert_eq!(guide.pieces[1].end(), v(10.0, 10.0));
        assert_eq!(guide.pieces[1].start(), c);
    }

    /// Turns sharper than `max_turn`, corners whose transition does not
    /// fit in their moves (short moves, or a turn so slight that the
    /// circle of the cut depth is longer than half a move), straight runs
    /// and runs with curves are left alone.
    #[test]
    fn sharp_turns_cramped_corners_and_curves_are_not_moved() {
        let g = OuterGuide {
            shift: 0.03,
            max_turn: 2.0,
            depth: 0.05,
            straight: 0.0,
        };
        let moved = |pts: &[Vec3]| outer_guide(&Run::polyline(pts, None), &g).is_some();
        assert!(!moved(&[v(0.0, 0.0), v(10.0, 0.0), v(0.0, 1.0)]));
        assert!(!moved(&[v(0.0, 0.0), v(10.0, 0.0), v(20.0, 0.0)]));
        // A right angle needs 0.05 / tan(pi / 8) = 0.121 mm of each move.
        assert!(moved(&[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 0.25)]));
        assert!(!moved(&[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 0.24)]));
        // A turn of 0.01 rad needs 0.05 / tan(0.0025) = 20 mm.
        let slight = v(20.0 + 20.0 * 0.01f64.cos(), 20.0 * 0.01f64.sin());
        assert!(!moved(&[v(0.0, 0.0), v(20.0, 0.0), slight]));
        let arc = Curve::from(
            crate::geom::Arc::from_center(
                v(10.0, 0.0),
                v(0.0, 10.0),
                v(0.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                false,
                0,
                1e-9,
            )
            .unwrap(),
        );
        let mut with_arc = Run::polyline(&[v(20.0, 0.0), v(10.0, 0.0)], None);
        let mut p = with_arc.pieces[0].clone();
        p.curve = arc;
        with_arc.pieces.push(p);
        assert!(outer_guide(&with_arc, &g).is_none());
    }

    /// A right angle between edges written as 0.1 mm moves that wobble
    /// by 0.1 um: as separate moves its corner has no room for a
    /// transition of 0.05 mm depth (0.121 mm of each move); merged within
    /// `straight` it has the edges' 2 mm and moves. A feed change stops
    /// the merge: with one in the moves before the corner, those after it
    /// still merge but the corner's incoming move is one 0.1 mm move.
    #[test]
    fn wobbling_straight_edges_give_their_corners_room() {
        let mut pts = Vec::new();
        for k in 0..=20 {
            let w = if k % 2 == 0 { 0.0 } else { 1e-4 };
            pts.push(v(0.1 * k as f64, w));
        }
        for k in 1..=20 {
            let w = if k % 2 == 0 { 0.0 } else { 1e-4 };
            pts.push(v(2.0 + w, 0.1 * k as f64));
        }
        let run = Run::polyline(&pts, Some(1000.0));
        let g = |straight: f64| OuterGuide {
            shift: 0.03,
            max_turn: 2.0,
            depth: 0.05,
            straight,
        };
        assert!(outer_guide(&run, &g(0.0)).is_none());
        let guide = outer_guide(&run, &g(5e-4)).expect("the corner moves");
        assert_eq!(guide.pieces.len(), 2);
        assert_eq!(guide.pieces[0].source_lines, (1, 20));
        let c = guide.pieces[0].end();
        assert!(
            (c.x - 2.03).abs() < 1e-9 && (c.y + 0.03).abs() < 1e-9,
            "{c:?}"
        );
        let mut fed = run.clone();
        fed.pieces[19].feed = Some(500.0);
        assert!(outer_guide(&fed, &g(5e-4)).is_none());
    }
}
