//! The chain around the fitted sections of `bspline-fit`: the walk along
//! one chain that fits its dense sections and leaves the rest to the
//! corner method ([`BsplineFit::smooth_chain`]), which vertices a
//! section takes ([`extend_sections`]), how far its fit leads into the kept
//! segments at its ends ([`lead_point`]), the parts of the chain left to
//! the corner method between fits ([`sub_chain`]), and the fit's output
//! pieces with the input lines they replace ([`push_fit`]).
//!
//! Not in seed 002 (its joins are "future work"). A fit that starts at a
//! section's end vertex along the kept segment must make the whole turn at
//! that vertex on the section's first chords; leading in along the kept
//! segment lets it round that corner within the band. On the issue-5
//! survey (0.05 mm) the leads and the widening planned the programs of
//! dense lines faster (measurements: docs/tuning.md, `lead_point` and
//! `extend_sections`).

use super::bspline_corner::{BsplineCorner, BAND_USE};
use super::bspline_fit::{fit_polyline_faired, BsplineFit, RunMemo};
use super::chains::{min_feed, LineChain};
use super::corner_engine::Band;
use super::fit_sections::dense_sections;
use super::SmoothedRun;
use crate::geom::fit::{chord_params, split_at_knots, EndCondition};
use crate::geom::{Curve, Nurbs, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// Largest turn at the vertex next to a section that [`extend_sections`]
/// takes into it (30 degrees). On the issue-5 survey it planned sampled
/// curves faster; smaller limits lost a sampled parabola's gain, larger
/// ones lost on `LHchips4.ngc`, and no limit lost on most programs (raster
/// step-overs are real corners; measurements: docs/tuning.md,
/// `EXTEND_MAX_TURN`).
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
/// it, in tolerances (10 mm at 0.05 mm). A corner of angle `theta` rounded
/// by a circle within the band `e` needs `4 e / theta` of each leg (radius
/// `8 e / theta^2`, from the deviation `R (1 / cos(theta / 2) - 1) ~ R
/// theta^2 / 8` at its bisector), so 200 tolerances let the fit round
/// corners down to about 1.1 degrees with all the band; a curvature ramp
/// shorter than the corner asks is what slowed the shallow corners of
/// `test_12mmflat.ngc` at 80 (measurements: docs/tuning.md,
/// `LEAD_PER_TOLERANCE`).
const LEAD_PER_TOLERANCE: f64 = 200.0;
/// Largest share of a kept segment a lead-in (lead-out) takes: the corner
/// at the segment's other end keeps the rest (a segment between two fits
/// keeps a fifth as a line). Chosen on the issue-5 survey, where a larger
/// share did no better (measurements: docs/tuning.md, `LEAD_SHARE`).
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
    let mut absorbed: Vec<f64> = if chain.absorbed.is_empty() {
        Vec::new()
    } else {
        chain.absorbed[a..b].to_vec()
    };
    if to.1 != chain.pts[b] {
        // `to.1` lies on segment `b`.
        pts.push(to.1);
        lines.push(chain.lines[b]);
        feed.push(chain.feed[b]);
        if !chain.absorbed.is_empty() {
            absorbed.push(chain.absorbed[b]);
        }
    }
    LineChain {
        pts,
        lines,
        feed,
        absorbed,
    }
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
            curve: Curve::from(piece),
            rapid: false,
            source_lines: lines,
            feed,
        });
        seg = last;
    }
}

impl BsplineFit {
    /// Smooths one chain: fits its dense sections, blends the corners
    /// between them. `keep_ends`: whether the chain's first (last) segment
    /// must stay out of the fits (a run end that [`BsplineFitOptions::line_at_start`]
    /// or `line_at_end` asks to keep straight).
    ///
    /// [`BsplineFitOptions::line_at_start`]: super::BsplineFitOptions::line_at_start
    pub(super) fn smooth_chain(
        &self,
        chain: &LineChain,
        tolerance: f64,
        keep_ends: (bool, bool),
        memo: Option<&RunMemo>,
        out: &mut SmoothedRun,
    ) {
        let o = &self.options;
        let corner = BsplineCorner { options: o.corner };
        let band = Band::new(tolerance, tolerance * BAND_USE);
        // The corner parts next to fits: their segments there keep their
        // direction when jogs are absorbed (the fits lead into them).
        let next_to_fits = |first: bool, last: bool| {
            let mut b = band;
            b.jogs.keep_first_direction = first;
            b.jogs.keep_last_direction = last;
            b
        };
        let mut after_fit = false;
        let min_seg = band.min_seg;
        let q = &chain.pts;
        let nseg = chain.segments();
        // Sections to fit, last first. A section whose fit fails is split
        // around its sharpest vertex (the segment after it kept as a line
        // between the two fits) and the halves are tried on their own, so
        // one corner inside a section does not send all of it to the corner
        // method.
        // Sections that would take a run end's line it must keep lose it.
        let mut sections = dense_sections(q, tolerance, &o.sections);
        extend_sections(&mut sections, q, EXTEND_MAX_TURN);
        let mut todo: Vec<(usize, usize)> = sections
            .into_iter()
            .map(|(k, m)| {
                let k = if keep_ends.0 && k == 0 { 1 } else { k };
                let m = if keep_ends.1 && m == nseg {
                    nseg - 1
                } else {
                    m
                };
                (k, m)
            })
            .filter(|&(k, m)| m > k + 1)
            .collect();
        todo.reverse();
        // Where the last fit (or the chain start) left off: a vertex, and
        // the point on the segment after it where the fit ended (its lead-out).
        let mut cursor = (0, q[0]);
        while let Some((k, m)) = todo.pop() {
            let dir = |a: usize, b: usize| (q[b] - q[a]).normalized(0.0);
            let start = if k == 0 {
                EndCondition::Free
            } else {
                match dir(k - 1, k) {
                    Some(d) => EndCondition::Tangent(d),
                    None => continue,
                }
            };
            let end = if m == nseg {
                EndCondition::Free
            } else {
                match dir(m, m + 1) {
                    Some(d) => EndCondition::Tangent(d),
                    None => continue,
                }
            };
            // Lead-in and lead-out: the fit also takes a piece of the kept
            // segment before (after) it, so it can round the corner at its
            // end vertex instead of starting tangent to the segment there.
            let lead = |a: usize, b: usize| lead_point(q[a], q[b], tolerance, min_seg);
            let lead_in = if k > 0 && k > cursor.0 {
                lead(k, k - 1)
            } else {
                None
            };
            let lead_out = if m < nseg { lead(m, m + 1) } else { None };
            // The fit's ends as (vertex, point on the segment after it).
            let from = lead_in.map_or((k, q[k]), |p| (k - 1, p));
            let to = lead_out.map_or((m, q[m]), |p| (m, p));
            let section = sub_chain(chain, from, to);
            #[cfg(test)]
            tests::POINTS_FITTED.with(|c| c.set(c.get() + section.pts.len()));
            let (target, weights) = (tolerance * o.band_use, (o.fairness, o.jerk_fairness));
            let (raises, relax) = (o.fairness_raises, o.relax.as_ref());
            let fit = match memo {
                Some(m) => m.fit(&section.pts, start, end, target, weights, raises, relax),
                None => {
                    fit_polyline_faired(&section.pts, start, end, target, weights, raises, relax)
                }
            };
            let Some(fit) = fit else {
                let min = o.sections.min_points;
                let sharpest = split_vertex(q, k, m);
                // A half too short to fit goes to the corner method; the
                // other is still tried (a sharp corner next to a section
                // end, such as a plunge, no longer sends all of it there).
                if let Some(j) = sharpest {
                    if m - j >= min {
                        todo.push((j + 1, m));
                    }
                    if j + 1 - k >= min {
                        todo.push((k, j));
                    }
                }
                continue;
            };
            if from.0 > cursor.0 || (from.0 == cursor.0 && from.1 != cursor.1) {
                corner.smooth_chain(
                    &sub_chain(chain, cursor, from),
                    next_to_fits(after_fit, true),
                    out,
                );
            }
            push_fit(&section, &fit.curve, o.max_piece_spans, out);
            after_fit = true;
            out.transitions += (m - k + 1) - usize::from(k == 0) - usize::from(m == nseg);
            cursor = to;
        }
        if cursor.0 < nseg || cursor.1 != q[nseg] {
            let sub = sub_chain(chain, cursor, (nseg, q[nseg]));
            corner.smooth_chain(&sub, next_to_fits(after_fit, false), out);
        }
    }
}

/// Inner vertices turning at least this share of the sharpest one count
/// as its equals when a section that failed to fit is split
/// ([`split_vertex`]): a corner half as sharp is still one the fit must
/// turn, and splitting near the middle bounds the work.
pub const SPLIT_TURN_TIE: f64 = 0.5;

/// The vertex of section `k..=m` of the chain `q` at which a section that
/// failed to fit is split: among its inner vertices that turn at least
/// [`SPLIT_TURN_TIE`] of the sharpest (the corners the fit likely failed
/// on), the one nearest the section's middle. Splitting at the sharpest
/// alone peeled a run of equal turns from one end: LinuxCNC's
/// `sam-circle_lines.ngc`, a spiral of 370 moves turning 4.5 degrees each,
/// failed its fits at 0.005 mm with `fair` and was fitted again on all but
/// a vertex or two, 183 times, the points fitted growing with the square
/// of the run's length; split in the middle, each level of halves fits
/// the run's points once (the same curves, in a fraction of the time;
/// measurements: docs/tuning.md, `split_vertex`).
/// Sections fit
/// independently, so where the split falls changes only which fits are
/// tried next.
fn split_vertex(q: &[Vec3], k: usize, m: usize) -> Option<usize> {
    let turn = |i: usize| (q[i] - q[i - 1]).angle_to(q[i + 1] - q[i]);
    let inner = k + 1..m.saturating_sub(1);
    let sharpest = inner.clone().map(turn).fold(f64::NEG_INFINITY, f64::max);
    if !sharpest.is_finite() {
        return inner.clone().next();
    }
    let tie = sharpest * SPLIT_TURN_TIE;
    let middle = |i: usize| (2 * i).abs_diff(k + m);
    inner.filter(|&i| turn(i) >= tie).min_by_key(|&i| middle(i))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::path::Run;
    use crate::smooth::{shallow_corner_sections, BsplineFitOptions, Smoother};
    use core::cell::Cell;

    std::thread_local! {
        /// Points of every section this thread tried to fit.
        pub(super) static POINTS_FITTED: Cell<usize> = const { Cell::new(0) };
    }

    fn v(x: f64, y: f64) -> Vec3 {
        Vec3::new(x, y, 0.0)
    }

    #[test]
    fn a_section_is_split_at_its_sharpest_vertex() {
        // Turns of 10, 40 and 10 degrees: the 40-degree vertex, though
        // not the middle one.
        let mut q = vec![v(0.0, 0.0), v(1.0, 0.0)];
        let mut dir = 0.0f64;
        for turn in [10.0f64, 40.0, 10.0, 10.0, 10.0] {
            dir += turn.to_radians();
            let last = q[q.len() - 1];
            q.push(last + Vec3::new(dir.cos(), dir.sin(), 0.0));
        }
        assert_eq!(split_vertex(&q, 0, q.len() - 1), Some(2));
    }

    #[test]
    fn equal_turns_are_split_in_the_middle() {
        let q: Vec<Vec3> = (0..21)
            .map(|i| {
                let a = (4.5f64 * i as f64).to_radians();
                v(10.0 * a.cos(), 10.0 * a.sin())
            })
            .collect();
        assert_eq!(split_vertex(&q, 0, 20), Some(10));
        assert_eq!(split_vertex(&q, 3, 9), Some(6));
        // Too short a section has no inner vertex to split at.
        assert_eq!(split_vertex(&q, 4, 5), None);
    }

    /// The points of LinuxCNC's `sam-circle_lines.ngc`: from (1, 0) in,
    /// `moves` moves of `G91 @-.0025 ^4.5` (370 in the program), in mm.
    pub(in crate::smooth) fn sam_circle_lines_points(moves: usize) -> Vec<Vec3> {
        (0..=moves)
            .map(|k| {
                let (r, a) = (
                    25.4 * (1.0 - 0.0025 * k as f64),
                    (4.5 * k as f64).to_radians(),
                );
                v(r * a.cos(), r * a.sin())
            })
            .collect()
    }

    fn sam_circle_lines() -> Run {
        Run::polyline(&sam_circle_lines_points(370), Some(999.0 * 25.4))
    }

    #[test]
    fn sam_circle_lines_fits_each_point_a_few_times_at_a_small_tolerance() {
        // Fitted through its shallow corners (as `fair` fits lines) within
        // 0.001125 mm (what `fair` at 0.005 mm leaves its fit), every fit
        // of the spiral fails and is split: 1,793 points fitted, a few
        // times the run's 371 per level of halves (log2(371 / 4) < 7),
        // where splitting at the sharpest vertex alone fitted 34,775 (the
        // section less a vertex or two, again and again).
        let run = sam_circle_lines();
        let fit = BsplineFit {
            options: BsplineFitOptions {
                sections: shallow_corner_sections(&BsplineFitOptions::default().sections),
                ..BsplineFitOptions::default()
            },
        };
        POINTS_FITTED.with(|c| c.set(0));
        let out = fit.smooth_run(&run, 0.00125).expect("smooths");
        let fitted = POINTS_FITTED.with(|c| c.get());
        assert!(!out.pieces.is_empty());
        assert!(
            fitted <= 4 * 371 * 7,
            "{fitted} points fitted for a run of 371"
        );
    }
}
