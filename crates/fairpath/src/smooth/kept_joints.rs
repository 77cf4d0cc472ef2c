//! Joints a method leaves as they are, reported as kept corners: `arc-fit`
//! blends nothing between the blocks it fits, and `none` nothing between
//! the program's moves, so each of their joints that is not G2 is
//! reported ([`report_corners`]), as the corner methods report the corners
//! they keep.

use super::chains::{CornerReason, KeptCorner};
use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{Curve, ParamCurve, Vec3};
use crate::path::Piece;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// The direction in which `c` ends.
pub(super) fn end_tangent(c: &Curve) -> Vec3 {
    match c {
        Curve::Line(l) => l.p1 - l.p0,
        c => c.deriv1(c.domain().1),
    }
}

/// Reports the joints inside `pieces[first..]` that are not G2 as kept
/// corners (the joint into them is `smooth_by_chains`' to report): this
/// method blends nothing, so a joint between blocks keeps whatever
/// continuity the fit gave it, and every one that is not G2 is reported,
/// as the other methods report the corners they leave (`none` reports its
/// joints with it too).
pub(crate) fn report_corners(
    pieces: &[Piece],
    first: usize,
    jt: &JointTolerances,
    kept: &mut Vec<KeptCorner>,
) {
    for k in first + 1..pieces.len() {
        let (a, b) = (&pieces[k - 1], &pieces[k]);
        if classify_joint(&a.curve, &b.curve, jt) != Continuity::G2 {
            let ta = end_tangent(&a.curve);
            let tb = b.curve.deriv1(b.curve.domain().0);
            let reason = if ta.angle_to(tb) >= PI - 2.0 * jt.angle {
                CornerReason::Reversal
            } else {
                CornerReason::NoRoom
            };
            kept.push(KeptCorner {
                at: b.start(),
                source_line: a.source_lines.1,
                reason,
            });
        }
    }
}
