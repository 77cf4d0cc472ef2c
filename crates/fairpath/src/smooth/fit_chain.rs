//! The chain around the fitted sections of `bspline-fit`: which vertices a
//! section takes ([`extend_sections`]), how far its fit leads into the kept
//! segments at its ends ([`lead_point`]), the parts of the chain left to
//! the corner method between fits ([`sub_chain`]), and the fit's output
//! pieces with the input lines they replace ([`push_fit`]).
//!
//! Not in seed 002 (its joins are "future work"). A fit that starts at a
//! section's end vertex along the kept segment must make the whole turn at
//! that vertex on the section's first chords; leading in along the kept
//! segment lets it round that corner within the band. On the issue-5
//! survey (0.05 mm) the leads and the widening planned
//! `line-contouring-xz.ngc` 0.33 -> 0.25 of the original,
//! `spiral_lines.ngc` 0.43 -> 0.37, `LHchips4.ngc` 0.61 -> 0.57,
//! `test_12mmflat.ngc` 0.71 -> 0.67 and `Cereal.ngc` 0.68 -> 0.65.

use super::chains::{min_feed, LineChain};
use super::SmoothedRun;
use crate::geom::fit::{chord_params, split_at_knots};
use crate::geom::{Curve, Nurbs, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// Largest turn at the vertex next to a section that [`extend_sections`]
/// takes into it (30 degrees). On the issue-5 survey: `arc_parabolic.ngc`
/// 1.01 -> 0.97 of the original, `line-contouring-xz.ngc` 0.26 -> 0.25,
/// `blur_torus.ngc` 0.65 -> 0.64; 10 and 20 degrees did the same but for
/// `arc_parabolic`, 45 lost on LHchips4, and no limit lost on most programs
/// (raster step-overs are real corners).
pub(super) const EXTEND_MAX_TURN: f64 = PI / 6.0;

/// Widens every section by the vertex before and after it, when that
/// vertex turns by at most `max_turn` and a kept segment stays between the
/// section and its neighbours: that vertex, where a long segment meets the
/// dense ones at a shallow corner (a pass meeting a sampled arc), is then
/// rounded by the fit with its lead into the long segment, instead of by a
/// corner transition squeezed into half of the short segment next to it.
pub(super) fn extend_sections(sections: &mut [(usize, usize)], q: &[Vec3], max_turn: f64) {
    let nseg = q.len() - 1;
    let turn = |i: usize| (q[i] - q[i - 1]).angle_to(q[i + 1] - q[i]);
    for i in 0..sections.len() {
        let prev_end = if i > 0 { Some(sections[i - 1].1) } else { None };
        let (k, m) = sections[i];
        if k > 0 && prev_end.is_none_or(|p| k - 1 > p) && (k == 1 || turn(k - 1) <= max_turn) {
            sections[i].0 = k - 1;
        }
        let next_start = sections.get(i + 1).map(|s| s.0);
        if m < nseg
            && next_start.is_none_or(|n| m + 1 < n - 1)
            && (m + 1 == nseg || turn(m + 1) <= max_turn)
        {
            sections[i].1 = m + 1;
        }
    }
}

/// Longest lead-in (lead-out) of a fit into the kept segment before (after)
/// it, in tolerances (4 mm at 0.05 mm). On the issue-5 survey 20, 40, 80
/// and 160 planned within 1% of each other except `test_12mmflat.ngc`
/// (0.69 of the original at 20 and 40, 0.67 at 80).
const LEAD_PER_TOLERANCE: f64 = 80.0;
/// Largest share of a kept segment a lead-in (lead-out) takes: the corner
/// at the segment's other end keeps the rest (a segment between two fits
/// keeps a fifth as a line). 0.4 planned `line-contouring-xz.ngc` 0.28 ->
/// 0.26 of the original against 0.25; 0.45 did no better.
const LEAD_SHARE: f64 = 0.4;
/// Shortest lead, in shortest kept segments ([`super::chains::CleanTolerances::min_segment`]).
const LEAD_MIN_SEGMENTS: f64 = 4.0;

/// The point where a fit ending at vertex `at` leads into the kept segment
/// from `at` to `to` (its lead-in or lead-out): at most [`LEAD_SHARE`] of
/// the segment and [`LEAD_PER_TOLERANCE`] tolerances from `at`; `None` when
/// that is shorter than [`LEAD_MIN_SEGMENTS`] shortest kept segments
/// (`min_segment`, mm).
pub(super) fn lead_point(at: Vec3, to: Vec3, tolerance: f64, min_segment: f64) -> Option<Vec3> {
    let len = at.dist(to);
    let l = (LEAD_SHARE * len).min(LEAD_PER_TOLERANCE * tolerance);
    (l >= min_segment * LEAD_MIN_SEGMENTS).then(|| at.lerp(to, l / len))
}

/// The part of `chain` from `from.1` to `to.1`, where each is given as
/// `(i, p)`: vertex `i` itself or a point `p` on the segment after it (a
/// fit's lead point). Both a fitted section with its leads and the corner
/// part between two fits are such parts.
pub(super) fn sub_chain(chain: &LineChain, from: (usize, Vec3), to: (usize, Vec3)) -> LineChain {
    let (a, b) = (from.0, to.0);
    let mut pts = Vec::with_capacity(b + 2 - a);
    pts.push(from.1);
    pts.extend_from_slice(&chain.pts[a + 1..=b]);
    let mut lines = chain.lines[a..b].to_vec();
    let mut feed = chain.feed[a..b].to_vec();
    if to.1 != chain.pts[b] {
        // `to.1` lies on segment `b`.
        pts.push(to.1);
        lines.push(chain.lines[b]);
        feed.push(chain.feed[b]);
    }
    LineChain { pts, lines, feed }
}

/// Pushes the fit of the whole of `section` as pieces of at most
/// `max_spans` knot spans, each with the input lines and lowest feed of
/// the segments its parameter range covers.
pub(super) fn push_fit(
    section: &LineChain,
    curve: &Nurbs,
    max_spans: usize,
    out: &mut SmoothedRun,
) {
    let params = chord_params(&section.pts);
    let nseg = section.segments();
    let mut seg = 0;
    for piece in split_at_knots(curve, max_spans) {
        let (ua, ub) = (piece.knots[0], *piece.knots.last().unwrap());
        while seg + 1 < nseg && params[seg + 1] <= ua {
            seg += 1;
        }
        let first = seg;
        let mut last = seg;
        while last + 1 < nseg && params[last + 1] < ub {
            last += 1;
        }
        let lines = (section.lines[first].0, section.lines[last].1);
        let feed = (first..=last).fold(None, |f, i| min_feed(f, section.feed[i]));
        out.pieces.push(Piece {
            curve: Curve::Nurbs(piece),
            rapid: false,
            source_lines: lines,
            feed,
        });
        seg = last;
    }
}
