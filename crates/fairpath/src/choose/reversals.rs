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
    let exact = core::f64::consts::PI - 2.0 * BsplineCornerOptions::default().min_half_angle;
    (1..run.pieces.len())
        .filter(|&k| {
            let (before, after) = (&run.pieces[k - 1], &run.pieces[k]);
            let a = tangent(before, true);
            let b = tangent(after, false);
            let angle = a.angle_to(b);
            if !(angle.is_finite() && angle >= turn && angle < exact) {
                return false;
            }
            let at = before.curve.end();
            let (Some(back), Some(on)) = (
                far_point(run, at, k - 1, false, min_leg),
                far_point(run, at, k, true, min_leg),
            ) else {
                return false;
            };
            let far = (at - back).angle_to(on - at);
            far.is_finite() && far >= turn
        })
        .collect()
}

/// [`reversal_cuts`] of `run`, or none where the run has more than
/// [`REVERSAL_PIECES_PER_CUT`] pieces per cut (the work of smoothing it
/// again between them is not offered).
pub fn reversal_cuts_bounded(run: &Run, turn: f64, min_leg: f64) -> alloc::vec::Vec<usize> {
    let cuts = reversal_cuts(run, turn, min_leg);
    if run.pieces.len() > cuts.len() * REVERSAL_PIECES_PER_CUT {
        return alloc::vec::Vec::new();
    }
    cuts
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
        assert!(reversal_cuts_bounded(&one, REVERSAL_TURN, 0.05).is_empty());
        // Two tips: three near-reversals (each tip's turn back, and the
        // turn into the next tip).
        let two = run_with(3 * REVERSAL_PIECES_PER_CUT, 2);
        assert_eq!(reversal_cuts(&two, REVERSAL_TURN, 0.05).len(), 3);
        assert_eq!(
            reversal_cuts_bounded(&two, REVERSAL_TURN, 0.05),
            reversal_cuts(&two, REVERSAL_TURN, 0.05)
        );
        let longer = run_with(3 * REVERSAL_PIECES_PER_CUT + 1, 2);
        assert!(reversal_cuts_bounded(&longer, REVERSAL_TURN, 0.05).is_empty());
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
}
