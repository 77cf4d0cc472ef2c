//! Arcs so flat that a controller cannot tell them from a full circle,
//! rendered as their chords.

use super::RenderStats;
use crate::geom::{Curve, Line};
use crate::path::Piece;

/// LinuxCNC's `CIRCLE_FUZZ` (rad, posemath.h): up to 2.8 its
/// `pmCircleInit` ran an arc whose angle between start and end is below
/// it as a full circle (LinuxCNC's issue #1528, fixed in 2022: "short arcs
/// of very large radius were being interpreted as full circles").
pub const CONTROLLER_CIRCLE_FUZZ: f64 = 1e-6;

/// The largest sweep (rad) of an arc rendered as its chord: twice
/// [`CONTROLLER_CIRCLE_FUZZ`], for the rounding of the written words. The
/// chord turns from such an arc by at most half its sweep at each end,
/// within the joint classes' tangent threshold
/// ([`crate::geom::continuity::TANGENT_ANGLE`]), and lies within
/// `r sweep^2 / 8` of it (0.5 um on a radius of 1000 km).
pub const FLAT_ARC_SWEEP: f64 = 2.0 * CONTROLLER_CIRCLE_FUZZ;

// The chord leaves every joint in its class.
const _: () = assert!(0.5 * FLAT_ARC_SWEEP <= crate::geom::continuity::TANGENT_ANGLE);

/// Replaces every arc of `pieces` of a sweep up to [`FLAT_ARC_SWEEP`] with
/// its chord, counted in `stats` as a line; returns how many. Before the
/// short lines are merged ([`super::absorb`]): such an arc on a radius of
/// kilometres may be a micrometre long.
pub(crate) fn flat_arcs_as_lines(pieces: &mut [Piece], stats: &mut RenderStats) -> usize {
    let mut n = 0;
    for p in pieces.iter_mut() {
        let Curve::Arc(a) = &p.curve else { continue };
        if a.sweep > FLAT_ARC_SWEEP {
            continue;
        }
        if a.rise != 0.0 {
            stats.helical -= 1;
        }
        p.curve = Curve::Line(Line::new(a.p0, a.p1));
        stats.arcs -= 1;
        stats.lines += 1;
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Arc, ParamCurve, Vec3};
    use alloc::vec;

    fn arc_piece(r: f64, sweep: f64) -> Piece {
        let a = Arc::from_center(
            Vec3::new(r, 0.0, 0.0),
            Vec3::new(r * sweep.cos(), r * sweep.sin(), 0.0),
            Vec3::ZERO,
            Vec3::Z,
            false,
            1,
            0.0,
        )
        .unwrap();
        Piece {
            curve: Curve::from(a),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        }
    }

    #[test]
    fn only_arcs_of_a_sweep_a_controller_cannot_see_become_chords() {
        // A 2 nm move on a radius of 4 km (`r004_mixed.ngc` at 0.2 mm), a
        // 1 mm move on a radius of 1 km (1e-6 rad), and a 0.1 mm move on
        // a radius of 10 mm (0.01 rad).
        let mut pieces = vec![
            arc_piece(4.05e6, 2e-6 / 4.05e6),
            arc_piece(1e6, 1e-6),
            arc_piece(10.0, 0.01),
        ];
        let mut stats = RenderStats {
            arcs: 3,
            ..RenderStats::default()
        };
        assert_eq!(flat_arcs_as_lines(&mut pieces, &mut stats), 2);
        assert!(matches!(pieces[0].curve, Curve::Line(_)));
        assert!(matches!(pieces[1].curve, Curve::Line(_)));
        assert!(matches!(pieces[2].curve, Curve::Arc(_)));
        assert_eq!((stats.arcs, stats.lines), (1, 2));
        // The chords keep the arcs' ends.
        let end = Vec3::new(1e6 * 1e-6f64.cos(), 1e6 * 1e-6f64.sin(), 0.0);
        assert!(pieces[1].curve.end().dist(end) < 1e-9);
    }
}
