//! The words of a spline line, shared by the G5, G5.2 and G6.2 readers:
//! which letters a code takes, axis words as coordinates (LinuxCNC's
//! `find_ends`), weights, integer words (orders, `L`), the in-plane axis
//! pair, and the pin reasons a line or the state it runs in gives a block.

use super::{spline_err, LineCtx};
use crate::axes::AXIS_LETTERS as AXES;
use crate::error::{GcodeError, SplineError};
use crate::interp::{finite, FeedMode, State};
use crate::lexer::{LexedLine, Word};
use crate::program::PinReason;
use fairpath::controller::Plane;
use fairpath::geom::Vec3;

/// How far (in integers) an order or method word may be from an integer:
/// LinuxCNC's `is_near_int` and `read_integer_value` take 0.0001.
pub(super) const NEAR_INT: f64 = 1e-4;

/// Checks the words of a spline line: the plane's axes (and the off-plane
/// one when `off_plane`), `letters`, N F G; other axes and spline letters
/// are errors; any other word pins (returns true).
pub(super) fn check_words(
    lx: &LexedLine,
    ln: usize,
    code: &'static str,
    plane: Plane,
    letters: &str,
    off_plane: bool,
) -> Result<bool, GcodeError> {
    let normal = AXES[plane.axes().2];
    let mut extra = false;
    for w in &lx.words {
        let l = w.letter;
        let ok = match l {
            'N' | 'F' | 'G' => true,
            'X' | 'Y' | 'Z' => l != normal || off_plane,
            'A' | 'B' | 'C' | 'U' | 'V' | 'W' | 'I' | 'J' | 'K' | 'P' | 'Q' | 'R' | 'L' => {
                letters.contains(l)
            }
            _ => {
                extra = true;
                true
            }
        };
        if !ok {
            let e = SplineError::WordNotAllowed { code, letter: l };
            return Err(spline_err(ln, w.column, e));
        }
    }
    Ok(extra)
}

/// The pin reason a line gives its block.
pub(super) fn line_pin(ctx: &LineCtx, extra: bool) -> Option<PinReason> {
    if ctx.lx.block_delete {
        Some(PinReason::BlockDelete)
    } else if extra {
        Some(PinReason::ExtraWords)
    } else if ctx.state_change {
        Some(PinReason::StateChange)
    } else {
        None
    }
}

/// The pin reasons of the state a block runs in.
pub(super) fn state_pin(st: &State, start_known: bool) -> Option<PinReason> {
    if st.comp {
        Some(PinReason::CutterComp)
    } else if st.feed_mode != FeedMode::PerMinute {
        Some(PinReason::FeedMode)
    } else if !start_known {
        Some(PinReason::UnknownStart)
    } else {
        None
    }
}

/// An axis word's value in program units and mm (relative to `start` in
/// G91), LinuxCNC's `find_ends`.
pub(super) fn coord(
    st: &State,
    w: &Word,
    a: usize,
    start: Vec3,
    ln: usize,
) -> Result<(f64, f64), GcodeError> {
    let mm = st.units.mm_per_unit();
    let s = start.to_array()[a];
    let (prog, in_mm) = if st.incremental {
        (s / mm + w.value, s + w.value * mm)
    } else {
        (w.value, w.value * mm)
    };
    Ok((finite(prog, ln, w)?, finite(in_mm, ln, w)?))
}

pub(super) fn weight(w: &Word, ln: usize) -> Result<f64, GcodeError> {
    if w.value > 0.0 && w.value.is_finite() {
        Ok(w.value)
    } else {
        Err(spline_err(ln, w.column, SplineError::BadWeight(w.value)))
    }
}

/// An integer word within [`NEAR_INT`] of an integer in `min..=max`.
pub(super) fn int_word(w: &Word, ln: usize, min: usize, max: usize) -> Result<usize, GcodeError> {
    let r = w.value.round();
    if (w.value - r).abs() > NEAR_INT || r < min as f64 || r > max as f64 {
        return Err(spline_err(
            ln,
            w.column,
            SplineError::BadOrder {
                value: w.value,
                min,
                max,
            },
        ));
    }
    Ok(r as usize)
}

/// The first in-plane axis word, and an error when only one of the pair
/// is given.
pub(super) fn plane_pair<'a>(
    lx: &'a LexedLine,
    ln: usize,
    code: &'static str,
    plane: Plane,
) -> Result<Option<[&'a Word; 2]>, GcodeError> {
    let (a, b, _) = plane.axes();
    match (lx.word(AXES[a]), lx.word(AXES[b])) {
        (Some(x), Some(y)) => Ok(Some([x, y])),
        (None, None) => Ok(None),
        (Some(w), None) | (None, Some(w)) => Err(spline_err(
            ln,
            w.column,
            SplineError::AxisPair {
                code,
                first: AXES[a],
                second: AXES[b],
            },
        )),
    }
}
