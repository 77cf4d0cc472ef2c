//! `auto`'s near-reversals: where a run turns back on itself by more than
//! [`REVERSAL_TURN`], it is also smoothed as the runs between those
//! vertices, each vertex kept as a corner, and that is kept where it plans
//! faster than the best smoothing of the whole run (see
//! [`super::auto`]).
//!
//! Any path inside the band that turns through such a vertex G2 needs a
//! curvature of the order of `1 / tolerance` or more there (a turn of
//! `phi` inside a band of half-width `d` has a radius of at most about
//! `d / (1 - sin(phi / 2))` for a circular fillet, and a G2 ramp needs
//! more), so the machine all but stops on it anyway, and the ramps of
//! curvature on either side (the cap `|dk/ds| v^3 <= J`) slow it over a
//! longer stretch than a stop at the vertex itself (LinuxCNC's
//! `parabolic_split1.ngc`, a line then an arc starting back along it at
//! 165 degrees; measurements: docs/methods.md, "Near-reversals", and
//! docs/tuning.md, `REVERSAL_TURN`). Issue 21 lets `auto` keep reversals
//! as corners ("no kept corners but reversals"); where a near-reversal
//! counts as one is chosen here, and it is kept only where that plans
//! faster.

use crate::geom::{ParamCurve, Vec3};
use crate::path::{Piece, Run};
use crate::smooth::BsplineCornerOptions;

/// Sharpest turn (rad, about 160 degrees) below which `auto` keeps every
/// joint G2: a turn at or above it is a near-reversal, where keeping a
/// corner is also tried ([`reversal_cuts`]). The through-corners fits stop
/// at [`crate::smooth::THROUGH_MAX_TURN`] (143 degrees) already; this is
/// sharper, so that only turns where a G2 path through the band is a
/// near-cusp are cut.
pub const REVERSAL_TURN: f64 = 2.8;

/// Most pieces of a run per near-reversal in it for which the run is
/// also smoothed between them: the runs between are smoothed anew in
/// full, which doubles `auto`'s work on the run, so a long run with one
/// near-reversal is not cut (LinuxCNC-style plotter output such as
/// `makerblock_tinycnc.gcode`, one near-reversal in a run of thousands
/// of moves; measurements: docs/tuning.md, `REVERSAL_TURN`).
pub const REVERSAL_PIECES_PER_CUT: usize = 1000;

/// The direction in which `p` leaves (`at_end` false) or reaches its end.
fn tangent(p: &Piece, at_end: bool) -> crate::geom::Vec3 {
    let (t0, t1) = p.curve.domain();
    p.curve.deriv1(if at_end { t1 } else { t0 })
}

/// Most pieces [`reversal_cuts`] walks from a vertex, either way, to find
/// a point `min_leg` away from it: a vertex with more pieces than that
/// within `min_leg` on one side sits in a cluster of moves far inside the
/// band (jitter, not a turn of the path), and is not cut.
pub const REVERSAL_WALK_PIECES: usize = 32;

/// The first point `min_leg` or more from `at`, walking from piece `k`
/// backward (`forward` false: the pieces' starts, `k` down to 0) or
/// forward (their ends, `k` up), at most [`REVERSAL_WALK_PIECES`]
/// pieces; the run's end point where the run ends nearer, unless that is
/// `at` itself; `None` in a cluster.
fn far_point(run: &Run, at: Vec3, k: usize, forward: bool, min_leg: f64) -> Option<Vec3> {
    for i in 0..REVERSAL_WALK_PIECES {
        let piece = if forward {
            run.pieces.get(k + i)?
        } else {
            run.pieces.get(k.checked_sub(i)?)?
        };
        let p = if forward {
            piece.curve.end()
        } else {
            piece.curve.start()
        };
        if p.dist(at) >= min_leg {
            return Some(p);
        }
        let at_run_end = if forward {
            k + i + 1 == run.pieces.len()
        } else {
            k == i
        };
        if at_run_end {
            return (p != at).then_some(p);
        }
    }
    None
}

/// The indices `k` of the joints (between pieces `k - 1` and `k`) where
/// `run` turns by `turn` radians or more but is no exact reversal. An
/// exact reversal (half the turn's supplement below the corner methods'
/// `min_half_angle`, [`BsplineCornerOptions`]' default) is kept as a
/// corner by every candidate already: cut there, the runs between would
/// only get other section mixes, which the objective may rank cheaper by
/// less than the rounding of the written coordinates moves
/// (`reprap_cnc.gcode`: docs/tuning.md, `REVERSAL_TURN`). Joints with a
/// piece of zero length (no direction) are not cut.
///
/// Nor are jogs the band absorbs: the chords from the vertex back to the
/// first point `min_leg` (mm; `auto` passes its tolerance) or more
/// before it, and on to the first such point after it (`far_point`),
/// must turn by `turn` too. A spike out and back on moves shorter than
/// `min_leg` between two collinear long moves turns by nearly 180 degrees
/// at its tip but not at all over those chords: a G2 path inside the
/// band need not turn there, and absorbing it is what issue 21 asks (a
/// 0.3 um spike: `tiny_jogs::near_reversal_spike_between_long_moves` in
/// fairpath-gcode). A short move in line with the long one before a
/// reversal keeps it; a short hook before a turn of about 90 degrees over
/// the chords is no reversal and is not cut (`line-contouring-xz.ngc`:
/// docs/tuning.md, `REVERSAL_WALK_PIECES`).
pub fn reversal_cuts(run: &Run, turn: f64, min_leg: f64) -> alloc::vec::Vec<usize> {
    (1..run.pieces.len())
        .filter(|&k| sharp_joint(run, k, turn, min_leg).is_some())
        .collect()
}

/// Where joint `k` of `run` (between pieces `k - 1` and `k`) turns by
/// `turn` or more both at the joint and over the chords to the first
/// points `min_leg` away on either side (`far_point`), and is no exact
/// reversal: its turn at the joint, its point, and the chords into and
/// out of it; `None` otherwise (or where a piece has no direction).
fn sharp_joint(run: &Run, k: usize, turn: f64, min_leg: f64) -> Option<(f64, Vec3, Vec3, Vec3)> {
    let exact = core::f64::consts::PI - 2.0 * BsplineCornerOptions::default().min_half_angle;
    let (before, after) = (&run.pieces[k - 1], &run.pieces[k]);
    let local = tangent(before, true).angle_to(tangent(after, false));
    if !(local.is_finite() && local >= turn && local < exact) {
        return None;
    }
    let at = before.curve.end();
    let back = far_point(run, at, k - 1, false, min_leg)?;
    let on = far_point(run, at, k, true, min_leg)?;
    let (din, dout) = (at - back, on - at);
    let far = din.angle_to(dout);
    (far.is_finite() && far >= turn).then_some((local, at, din, dout))
}

/// Least turn (rad, about 69 degrees) of each corner of a narrow U-turn
/// ([`u_turn_cuts`]), at the joint and over the chords a tolerance away.
pub const U_TURN_CORNER: f64 = 1.2;

/// Default widest U-turn (mm) whose corners `auto` also tries to keep
/// ([`u_turn_cuts`], `AutoOptions::u_turn_width`): the step-over between
/// passes of a zigzag or raster, which is up to a few millimetres (1.2 mm
/// on LinuxCNC's `line-contouring-xz.ngc`, 1.5 mm on
/// `surface-raster.ngc`). Wider, the corners are corners of the path, and
/// stay G2 as every joint but reversals does (issue 5).
pub const U_TURN_WIDTH: f64 = 3.0;

/// The corners of the narrow U-turns of `run`: two joints no more than
/// `width` mm of path apart, each turning by [`U_TURN_CORNER`] or more
/// (at the joint and over the chords to the first points `min_leg` away,
/// as [`reversal_cuts`] judges them), with the path turning by `turn` or
/// more from the chord into the first to the chord out of the second; of
/// joints less than `min_leg` apart that pass, the sharper stands for
/// them (a 4 um hook at a corner is the corner). Sorted joint indices (see
/// [`reversal_cuts`]).
///
/// At the scale of the step-over such a turn is a reversal, and a G2
/// path through it is a crawl: inside the band each of its right angles
/// needs a curvature of the order of `1 / tolerance`, ramped within a
/// tolerance, so that `|dk/ds| v^3 <= J` holds the machine to a few mm/s
/// over the ramps, while a kept corner costs the braking alone. Each such
/// corner between two step-overs of `line-contouring-xz.ngc` had planned
/// faster kept (docs/methods.md, "Near-reversals"); `auto` keeps them only
/// where the whole run plans faster so.
pub fn u_turn_cuts(run: &Run, turn: f64, min_leg: f64, width: f64) -> alloc::vec::Vec<usize> {
    if !(turn.is_finite() && width > 0.0) {
        return alloc::vec::Vec::new();
    }
    // Corners: (joint, local turn, chord in, chord out).
    let mut corners: alloc::vec::Vec<(usize, f64, Vec3, Vec3)> = alloc::vec::Vec::new();
    for k in 1..run.pieces.len() {
        let Some((local, at, din, dout)) = sharp_joint(run, k, U_TURN_CORNER, min_leg) else {
            continue;
        };
        match corners.last_mut() {
            // (The chord into the first of them, out of the last.)
            Some(last) if run.pieces[last.0 - 1].curve.end().dist(at) < min_leg => {
                if local > last.1 {
                    (last.0, last.1) = (k, local);
                }
                last.3 = dout;
            }
            _ => corners.push((k, local, din, dout)),
        }
    }
    let mut cuts = alloc::vec::Vec::new();
    for pair in corners.windows(2) {
        let ((a, _, din, _), (b, _, _, dout)) = (pair[0], pair[1]);
        let between: f64 = run.pieces[a..b]
            .iter()
            .map(|p| p.curve.length(min_leg))
            .sum();
        let back = din.angle_to(dout);
        if between <= width && back.is_finite() && back >= turn {
            if cuts.last() != Some(&a) {
                cuts.push(a);
            }
            cuts.push(b);
        }
    }
    cuts
}

/// Most pieces of a run on which `cut_sets_bounded` offers the U-turns'
/// corners: the runs between them are smoothed anew, which doubles
/// `auto`'s work on the run, and on a long run of many U-turns (a plot's
/// pixel steps) that did not pay (measurements: docs/tuning.md,
/// `U_TURN_MAX_PIECES`).
pub const U_TURN_MAX_PIECES: usize = 4000;

/// The sets of joints where `auto` tries cutting `run`: its
/// near-reversals ([`reversal_cuts`]), and those with the corners of its
/// U-turns up to `u_turn_width` mm wide ([`u_turn_cuts`]), each where it
/// is not empty, differs from the set before and leaves at most
/// [`REVERSAL_PIECES_PER_CUT`] pieces per cut (the work of smoothing the
/// run again between them is not offered otherwise); the U-turns only on
/// runs of at most [`U_TURN_MAX_PIECES`] pieces. Both are tried
/// because a run is cut at every joint of a set or at none: the corners
/// of a U-turn may plan faster kept on one run and slower on another
/// (LinuxCNC's `adjustment.ngc` at 0.01 mm; measurements: docs/tuning.md,
/// `U_TURN_CORNER`).
pub fn cut_sets_bounded(
    run: &Run,
    turn: f64,
    min_leg: f64,
    u_turn_width: f64,
) -> alloc::vec::Vec<alloc::vec::Vec<usize>> {
    let reversals = reversal_cuts(run, turn, min_leg);
    let mut with_u_turns = reversals.clone();
    if run.pieces.len() <= U_TURN_MAX_PIECES {
        with_u_turns.extend(u_turn_cuts(run, turn, min_leg, u_turn_width));
    }
    with_u_turns.sort_unstable();
    with_u_turns.dedup();
    let mut sets: alloc::vec::Vec<alloc::vec::Vec<usize>> = alloc::vec::Vec::new();
    for cuts in [reversals, with_u_turns] {
        let bounded = run.pieces.len() <= cuts.len() * REVERSAL_PIECES_PER_CUT;
        if !cuts.is_empty() && bounded && sets.last() != Some(&cuts) {
            sets.push(cuts);
        }
    }
    sets
}

/// `run` cut at `cuts` (sorted joint indices, see [`reversal_cuts`]) into
/// the runs between them.
pub fn split_at(run: &Run, cuts: &[usize]) -> alloc::vec::Vec<Run> {
    let mut out = alloc::vec::Vec::with_capacity(cuts.len() + 1);
    let mut start = 0;
    for &k in cuts.iter().chain(core::iter::once(&run.pieces.len())) {
        out.push(Run::new(run.pieces[start..k].to_vec()));
        start = k;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;

    fn v(x: f64, y: f64) -> Vec3 {
        Vec3::new(x, y, 0.0)
    }

    /// A zigzag turning back by 170 degrees is cut at its tips; a right
    /// angle is not.
    #[test]
    fn near_reversals_are_cut_and_right_angles_are_not() {
        let tip = (10f64.to_radians() / 2.0).tan() * 10.0;
        let run = Run::polyline(
            &[
                v(0.0, 0.0),
                v(10.0, 0.0),
                v(0.0, tip * 2.0),
                v(0.0, 10.0),
                v(10.0, 10.0),
            ],
            Some(1000.0),
        );
        let cuts = reversal_cuts(&run, REVERSAL_TURN, 0.05);
        assert_eq!(cuts, [1]);
        let parts = split_at(&run, &cuts);
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].pieces.len(), 1);
        assert_eq!(parts[1].pieces.len(), 3);
        assert_eq!(
            parts[0].pieces[0].curve.end(),
            parts[1].pieces[0].curve.start()
        );
    }

    /// A run is cut only where it has at most [`REVERSAL_PIECES_PER_CUT`]
    /// pieces per near-reversal.
    #[test]
    fn a_long_run_is_cut_only_with_near_reversals_enough() {
        let tip = (10f64.to_radians() / 2.0).tan() * 10.0;
        let run_with = |n: usize, tips: usize| {
            let mut pts = vec![v(0.0, 0.0)];
            for _ in 0..tips {
                let last = *pts.last().unwrap();
                pts.push(last + v(10.0, 0.0));
                pts.push(last + v(0.0, tip * 2.0));
            }
            while pts.len() <= n {
                let last = *pts.last().unwrap();
                pts.push(last + v(0.0, 1.0));
            }
            Run::polyline(&pts, Some(1000.0))
        };
        let one = run_with(REVERSAL_PIECES_PER_CUT + 1, 1);
        assert_eq!(reversal_cuts(&one, REVERSAL_TURN, 0.05).len(), 1);
        assert!(cut_sets_bounded(&one, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
        // Two tips: three near-reversals (each tip's turn back, and the
        // turn into the next tip).
        let two = run_with(3 * REVERSAL_PIECES_PER_CUT, 2);
        assert_eq!(reversal_cuts(&two, REVERSAL_TURN, 0.05).len(), 3);
        assert_eq!(
            cut_sets_bounded(&two, REVERSAL_TURN, 0.05, U_TURN_WIDTH),
            [reversal_cuts(&two, REVERSAL_TURN, 0.05)]
        );
        let longer = run_with(3 * REVERSAL_PIECES_PER_CUT + 1, 2);
        assert!(cut_sets_bounded(&longer, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
    }

    /// An exact reversal is kept by every candidate: not cut.
    #[test]
    fn an_exact_reversal_is_not_cut() {
        let run = Run::polyline(
            &[v(0.0, 0.0), v(10.0, 0.0), v(0.0, 0.0), v(0.0, 5.0)],
            Some(1000.0),
        );
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN, 0.05), [] as [usize; 0]);
    }

    /// A zero-length move has no direction and cuts nothing.
    #[test]
    fn a_zero_length_move_is_not_a_reversal() {
        let run = Run::polyline(
            &[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 0.0), v(0.0, 0.0)],
            Some(1000.0),
        );
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN, 0.05), [] as [usize; 0]);
    }

    /// A spike out and nearly back on moves shorter than `min_leg` is
    /// absorbed, not cut; the same spike on longer moves is cut
    /// (`tiny_jogs::near_reversal_spike_between_long_moves` in
    /// fairpath-gcode).
    #[test]
    fn a_near_reversal_on_a_move_shorter_than_min_leg_is_not_cut() {
        let spike = |s: f64| {
            Run::polyline(
                &[
                    v(0.0, 0.0),
                    v(10.0, 0.0),
                    v(10.0 + 3.0 * s, s),
                    v(10.0 + 0.1 * s, 2.0 * s),
                    v(20.0, 2.0 * s),
                ],
                Some(1000.0),
            )
        };
        assert!(reversal_cuts(&spike(1e-4), REVERSAL_TURN, 0.05).is_empty());
        assert_eq!(reversal_cuts(&spike(1.0), REVERSAL_TURN, 0.05), [3]);
    }

    /// A 4 um move in line with the long move before a reversal of 175
    /// degrees onto a long move is still cut: over the chords the path
    /// turns back as much.
    #[test]
    fn a_short_move_before_a_near_reversal_keeps_it() {
        let back = 175f64.to_radians();
        let run = Run::polyline(
            &[
                v(0.0, 0.0),
                v(1.0, 0.0),
                v(1.004, 0.0),
                v(1.004 + 1.3 * back.cos(), 1.3 * back.sin()),
            ],
            Some(1000.0),
        );
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN, 0.05), [2]);
    }

    /// A zigzag of more than [`REVERSAL_WALK_PIECES`] moves of 1 um, all
    /// within `min_leg` of each other, is jitter: not cut.
    #[test]
    fn a_cluster_of_tiny_zigzags_is_not_cut() {
        let mut pts = vec![v(0.0, 0.0), v(10.0, 0.0)];
        for i in 0..2 * REVERSAL_WALK_PIECES {
            let y = if i % 2 == 0 { 1e-3 } else { 0.0 };
            pts.push(v(10.0 + 1e-4 * i as f64, y));
        }
        let last = *pts.last().unwrap();
        pts.push(last + v(10.0, 0.0));
        let run = Run::polyline(&pts, Some(1000.0));
        assert!(reversal_cuts(&run, REVERSAL_TURN, 0.05).is_empty());
        // The same zigzag judged with no band at all is all near-reversals.
        assert!(!reversal_cuts(&run, REVERSAL_TURN, 0.0).is_empty());
    }

    /// A 4 um hook at the end of a move, turning back by 175 degrees onto
    /// a long move at right angles to the first (as in
    /// `line-contouring-xz.ngc`): over the chords a right angle, not cut.
    #[test]
    fn a_hook_before_a_right_angle_is_not_cut() {
        let back = 175f64.to_radians();
        let hook = v(0.004 * back.cos(), 0.004 * back.sin());
        let run = Run::polyline(
            &[v(0.0, 10.0), v(0.0, 0.0), hook, hook + v(1.3, 0.0)],
            Some(1000.0),
        );
        assert!(reversal_cuts(&run, REVERSAL_TURN, 0.05).is_empty());
        // Judged joint by joint, the hook's end is a near-reversal.
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN, 0.0), [2]);
    }

    /// The step-over of `line-contouring-xz.ngc` at its line 52: down the
    /// end of an arch in XZ, 1.21 mm across in Y, a 4 um move down, and up
    /// the next arch.
    fn step_over() -> Run {
        let p = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        Run::polyline(
            &[
                p(17.155, -16.967, -1.253),
                p(17.26, -16.967, -2.525),
                p(17.477, -15.773, -2.525),
                p(17.477, -15.773, -2.529),
                p(17.37, -15.773, -1.226),
                p(17.146, -15.773, 0.113),
            ],
            Some(1000.0),
        )
    }

    /// Its two right angles make a narrow U-turn: cut at the first and at
    /// the hook's end (the sharper of the two joints 4 um apart), which
    /// [`reversal_cuts`] leaves (over the chords the hook is a right
    /// angle).
    #[test]
    fn line_contouring_xz_step_over_is_a_narrow_u_turn() {
        let run = step_over();
        assert!(reversal_cuts(&run, REVERSAL_TURN, 0.05).is_empty());
        assert_eq!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, U_TURN_WIDTH), [1, 3]);
        assert_eq!(
            cut_sets_bounded(&run, REVERSAL_TURN, 0.05, U_TURN_WIDTH),
            [[1, 3]]
        );
        // No U-turns of any width, or no reversals at all: no cut.
        assert!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, 0.0).is_empty());
        assert!(u_turn_cuts(&run, f64::INFINITY, 0.05, U_TURN_WIDTH).is_empty());
        // The step-over is 1.21 mm: narrower U-turns only, none.
        assert!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, 1.0).is_empty());
    }

    /// A run with a near-reversal and a narrow U-turn is tried cut at the
    /// near-reversal alone and at both; a run with a U-turn alone, at its
    /// corners; a run with neither, not at all.
    #[test]
    fn near_reversals_are_tried_with_and_without_the_u_turns() {
        let tip = (10f64.to_radians() / 2.0).tan() * 10.0;
        let run = Run::polyline(
            &[
                v(0.0, 0.0),
                v(10.0, 0.0),
                v(0.0, tip * 2.0),
                v(0.0, 10.0),
                v(1.2, 10.0),
                v(1.2, 0.0),
            ],
            Some(1000.0),
        );
        assert_eq!(
            cut_sets_bounded(&run, REVERSAL_TURN, 0.05, U_TURN_WIDTH),
            [vec![1], vec![1, 3, 4]]
        );
        assert_eq!(cut_sets_bounded(&run, REVERSAL_TURN, 0.05, 0.0), [vec![1]]);
        let u = Run::polyline(
            &[v(0.0, 10.0), v(0.0, 0.0), v(1.2, 0.0), v(1.2, 10.0)],
            Some(1000.0),
        );
        assert_eq!(
            cut_sets_bounded(&u, REVERSAL_TURN, 0.05, U_TURN_WIDTH),
            [vec![1, 2]]
        );
        let corner = Run::polyline(&[v(0.0, 10.0), v(0.0, 0.0), v(10.0, 0.0)], Some(1000.0));
        assert!(cut_sets_bounded(&corner, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
        // The same U-turn at the end of a run longer than
        // U_TURN_MAX_PIECES: not offered.
        let mut pts: alloc::vec::Vec<Vec3> = (0..=U_TURN_MAX_PIECES)
            .map(|i| v(0.0, 10.0 + (U_TURN_MAX_PIECES - i) as f64))
            .collect();
        pts.extend([v(0.0, 0.0), v(1.2, 0.0), v(1.2, 10.0)]);
        let long = Run::polyline(&pts, Some(1000.0));
        assert!(cut_sets_bounded(&long, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
    }

    /// A U-turn wider than the width is two corners of the path, not cut;
    /// within it, cut at both.
    #[test]
    fn a_wide_u_turn_is_not_cut() {
        let run = Run::polyline(
            &[v(0.0, 10.0), v(0.0, 0.0), v(5.0, 0.0), v(5.0, 10.0)],
            Some(1000.0),
        );
        assert!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, 3.0).is_empty());
        assert_eq!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, 6.0), [1, 2]);
    }

    /// A single right angle, and a step of two right angles turning
    /// opposite ways (the path goes on), are no U-turns.
    #[test]
    fn a_right_angle_or_a_step_is_not_a_u_turn() {
        let corner = Run::polyline(&[v(0.0, 10.0), v(0.0, 0.0), v(10.0, 0.0)], Some(1000.0));
        assert!(u_turn_cuts(&corner, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
        let step = Run::polyline(
            &[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 1.0), v(20.0, 1.0)],
            Some(1000.0),
        );
        assert!(u_turn_cuts(&step, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
    }

    /// A U-turn already rounded by the program (a half circle of 0.6 mm
    /// in 30 moves) has no sharp corner: not cut.
    #[test]
    fn a_rounded_u_turn_is_not_cut() {
        let mut pts = vec![v(0.0, 10.0)];
        for i in 0..=30 {
            let a = core::f64::consts::PI * (1.0 - i as f64 / 30.0);
            pts.push(v(0.6 + 0.6 * a.cos(), -0.6 * a.sin()));
        }
        pts.push(v(1.2, 10.0));
        let run = Run::polyline(&pts, Some(1000.0));
        assert!(u_turn_cuts(&run, REVERSAL_TURN, 0.05, U_TURN_WIDTH).is_empty());
    }

    /// Seeded random U-turns (each corner 70 to 110 degrees, the whole
    /// turn from [`REVERSAL_TURN`] to 179 degrees, 0.2 to 2.5 mm across, in a random
    /// orientation in 3D) are cut at both corners, and the cuts are joints
    /// of the run, sorted.
    #[test]
    fn seeded_random_narrow_u_turns_are_cut_at_both_corners() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move |lo: f64, hi: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            let whole = uniform(REVERSAL_TURN + 1e-3, 179f64.to_radians());
            let first = uniform(70.0, 110.0)
                .to_radians()
                .min(whole - 70f64.to_radians());
            let width = uniform(0.2, 2.5);
            // In the plane: down the y axis, turn by `first`, go `width`,
            // turn by the rest.
            let d0 = v(0.0, -1.0);
            let rot =
                |d: Vec3, a: f64| v(d.x * a.cos() - d.y * a.sin(), d.x * a.sin() + d.y * a.cos());
            let d1 = rot(d0, first);
            let d2 = rot(d0, whole);
            let a = v(0.0, 0.0);
            let b = a + d1 * width;
            let pts2 = [a - d0 * 5.0, a, b, b + d2 * 5.0];
            // A random orientation: rotate about x, then z.
            let tau = core::f64::consts::TAU;
            let (ax, az) = (uniform(0.0, tau), uniform(0.0, tau));
            let orient = |p: Vec3| {
                let q = Vec3::new(
                    p.x,
                    p.y * ax.cos() - p.z * ax.sin(),
                    p.y * ax.sin() + p.z * ax.cos(),
                );
                Vec3::new(
                    q.x * az.cos() - q.y * az.sin(),
                    q.x * az.sin() + q.y * az.cos(),
                    q.z,
                )
            };
            let pts: alloc::vec::Vec<Vec3> = pts2.iter().map(|&p| orient(p)).collect();
            let run = Run::polyline(&pts, Some(1000.0));
            assert_eq!(
                u_turn_cuts(&run, REVERSAL_TURN, 0.05, U_TURN_WIDTH),
                [1, 2],
                "case {case}: corners {first} rad and {} rad, {width} mm apart",
                whole - first
            );
        }
    }
}
