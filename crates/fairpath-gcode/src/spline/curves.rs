//! The curves of a G5, G5.1 or G5.2 block as the reading asks (the arcs
//! and straight feeds LinuxCNC runs, the last one snapped to the block's
//! end, or the exact curve), and the moves a spline block's curves become.

use super::{spline_err, SplineReading, MAX_ORDER};
use crate::error::{ErrorKind, GcodeError, SplineError};
use crate::interp::{err, FeedMode, State};
use crate::program::{Move, MoveKind, PinReason};
use fairpath::controller::linuxcnc::{g5_2_curve, g5_2_motion, G5Error};
use fairpath::geom::{Curve, Line, Vec3};
use fairpath::path::Piece;

/// Units in the last place within which the end of LinuxCNC's last move is
/// the block's end point (`(a + b) * mm` against `a * mm + b * mm`).
const END_ULPS: f64 = 64.0;

/// The pieces of a G5/G5.1/G5.2 spline as the reading asks: `prog` the
/// control points in the plane (program units), `pts` the same in mm
/// (the first is the current position, the last the end).
pub(super) fn curves(
    st: &State,
    prog: &[[f64; 2]],
    pts: &[Vec3],
    weights: &[f64],
    order: usize,
    ln: usize,
    col: usize,
) -> Result<Vec<Curve>, GcodeError> {
    let g5err = |e: G5Error| {
        let kind = match e {
            G5Error::TooFewPoints { points, order } => SplineError::TooFewPoints { points, order },
            G5Error::BadOrder(o) | G5Error::OrderTooHigh(o) => SplineError::BadOrder {
                value: o as f64,
                min: 3,
                max: MAX_ORDER,
            },
            G5Error::BadWeights => SplineError::BadWeight(0.0),
            G5Error::NotFinite | G5Error::BadScale => {
                return err(ln, col, ErrorKind::NumberOutOfRange('X'));
            }
        };
        spline_err(ln, col, kind)
    };
    let (start, end) = (pts[0], pts[pts.len() - 1]);
    match st.spline.reading {
        SplineReading::Exact => Ok(vec![Curve::from(
            g5_2_curve(pts, weights, order).map_err(g5err)?,
        )]),
        SplineReading::AsLinuxcnc => {
            let mm = st.units.mm_per_unit();
            let mut cs = g5_2_motion(start, prog, weights, order, st.plane, mm).map_err(g5err)?;
            let scale = pts
                .iter()
                .flat_map(|p| p.to_array())
                .fold(0.0f64, |m, c| m.max(c.abs()));
            snap_end(&mut cs, start, end, END_ULPS * f64::EPSILON * scale);
            Ok(cs)
        }
    }
}

/// Makes the last curve end exactly at `end` when it is within `tol` of it
/// (else adds a line there).
fn snap_end(cs: &mut Vec<Curve>, start: Vec3, end: Vec3, tol: f64) {
    let last = cs.last().map_or(start, fairpath::ParamCurve::end);
    if last == end {
        return;
    }
    match cs.last_mut() {
        Some(Curve::Line(l)) if last.dist(end) <= tol => l.p1 = end,
        Some(Curve::Arc(a)) if last.dist(end) <= tol => a.p1 = end,
        _ => cs.push(Curve::Line(Line::new(last, end))),
    }
}

/// Pushes a block's curves as moves on line `ln` and moves the position to
/// `end`; `words` the axis words of the end point. Returns whether pinned.
#[allow(clippy::too_many_arguments)]
pub(super) fn emit(
    st: &mut State,
    moves: &mut Vec<Move>,
    curves: Vec<Curve>,
    first_line: usize,
    ln: usize,
    pinned: Option<PinReason>,
    end: Vec3,
    words: [Option<String>; 3],
) -> bool {
    let feed = match st.feed_mode {
        FeedMode::PerMinute => st.feed.as_ref().map(|f| f.mm_per_min),
        _ => None,
    };
    st.pos = end;
    for (a, w) in words.iter().enumerate() {
        if let Some(t) = w {
            if st.incremental {
                st.axis_text[a] = None;
            } else {
                st.known[a] = true;
                st.axis_text[a] = Some(t.into());
            }
        }
    }
    let n = curves.len();
    for (i, curve) in curves.into_iter().enumerate() {
        moves.push(Move {
            piece: Piece {
                curve,
                rapid: false,
                source_lines: (first_line, ln),
                feed,
            },
            line: ln,
            kind: MoveKind::Spline,
            pinned,
            end_text: if i + 1 == n {
                st.axis_text.clone()
            } else {
                [None, None, None]
            },
        });
    }
    pinned.is_some()
}
