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

use crate::geom::ParamCurve;
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

/// The indices `k` of the joints (between pieces `k - 1` and `k`) where
/// `run` turns by `turn` radians or more but is no exact reversal. An
/// exact reversal (half the turn's supplement below the corner methods'
/// `min_half_angle`, [`BsplineCornerOptions`]' default) is kept as a
/// corner by every candidate already: cut there, the runs between would
/// only get other section mixes, which the objective may rank cheaper by
/// less than the rounding of the written coordinates moves
/// (`reprap_cnc.gcode`: docs/tuning.md, `REVERSAL_TURN`). Joints with a piece
/// of zero length (no direction) are not cut.
pub fn reversal_cuts(run: &Run, turn: f64) -> alloc::vec::Vec<usize> {
    let exact = core::f64::consts::PI - 2.0 * BsplineCornerOptions::default().min_half_angle;
    (1..run.pieces.len())
        .filter(|&k| {
            let a = tangent(&run.pieces[k - 1], true);
            let b = tangent(&run.pieces[k], false);
            let angle = a.angle_to(b);
            angle.is_finite() && angle >= turn && angle < exact
        })
        .collect()
}

/// [`reversal_cuts`] of `run`, or none where the run has more than
/// [`REVERSAL_PIECES_PER_CUT`] pieces per cut (the work of smoothing it
/// again between them is not offered).
pub fn reversal_cuts_bounded(run: &Run, turn: f64) -> alloc::vec::Vec<usize> {
    let cuts = reversal_cuts(run, turn);
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
        let cuts = reversal_cuts(&run, REVERSAL_TURN);
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
        assert_eq!(reversal_cuts(&one, REVERSAL_TURN).len(), 1);
        assert!(reversal_cuts_bounded(&one, REVERSAL_TURN).is_empty());
        // Two tips: three near-reversals (each tip's turn back, and the
        // turn into the next tip).
        let two = run_with(3 * REVERSAL_PIECES_PER_CUT, 2);
        assert_eq!(reversal_cuts(&two, REVERSAL_TURN).len(), 3);
        assert_eq!(
            reversal_cuts_bounded(&two, REVERSAL_TURN),
            reversal_cuts(&two, REVERSAL_TURN)
        );
        let longer = run_with(3 * REVERSAL_PIECES_PER_CUT + 1, 2);
        assert!(reversal_cuts_bounded(&longer, REVERSAL_TURN).is_empty());
    }

    /// An exact reversal is kept by every candidate: not cut.
    #[test]
    fn an_exact_reversal_is_not_cut() {
        let run = Run::polyline(
            &[v(0.0, 0.0), v(10.0, 0.0), v(0.0, 0.0), v(0.0, 5.0)],
            Some(1000.0),
        );
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN), [] as [usize; 0]);
    }

    /// A zero-length move has no direction and cuts nothing.
    #[test]
    fn a_zero_length_move_is_not_a_reversal() {
        let run = Run::polyline(
            &[v(0.0, 0.0), v(10.0, 0.0), v(10.0, 0.0), v(0.0, 0.0)],
            Some(1000.0),
        );
        assert_eq!(reversal_cuts(&run, REVERSAL_TURN), [] as [usize; 0]);
    }
}
