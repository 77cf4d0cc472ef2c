//! A line's move in the modal motion mode: G0 rapids, G1 feeds, G2/G3 arcs
//! ([`super::arc`]), and the moves that are always pinned (G53, G33,
//! G33.1, G38.x, G31); absolute or incremental (G90/G91), in the program's
//! units; whether it is pinned, and where it leaves the tool.

use super::arc::build_arc;
use super::codes::NonModal;
use super::line::{has_foreign_words, LineInfo, Words, EXTRA_AXES};
use super::modal::Changes;
use super::{err, finite, FeedMode, State};
use crate::axes::{axis, set_axis};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::Word;
use crate::program::{MotionMode, Move, MoveKind, PinReason};
use fairpath::geom::{Curve, Line, ParamCurve, Vec3};
use fairpath::path::Piece;

/// Interprets what is left of a line that is neither a spline line nor a
/// canned cycle: its move, if it moves the axes, appended to `moves`.
pub(super) fn line_move(
    w: &Words,
    changes: &Changes,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    let mut state_change = changes.state;
    if !w.has_axes {
        if let Some((MotionMode::ArcCw | MotionMode::ArcCcw, gw)) = w.motion {
            if ['I', 'J', 'K', 'R', 'P']
                .iter()
                .any(|&l| w.lx.word(l).is_some())
            {
                return Err(err(w.ln, gw.column, ErrorKind::ArcWithoutAxes));
            }
        }
        // Words that do nothing without a move: keep the line out of runs.
        if ['I', 'J', 'K', 'R', 'P']
            .iter()
            .any(|&l| w.lx.word(l).is_some())
        {
            state_change = true;
        }
    }
    let uses_modal_motion = w.moves_axes() && w.motion.is_none();
    let mut breaks_run = state_change;
    if w.moves_axes() {
        let changed = state_change || changes.plane;
        let m = axis_move(w, changed, uses_modal_motion, st)?;
        breaks_run |= m.pinned.is_some() || m.kind == MoveKind::Rapid;
        moves.push(m);
    }
    Ok(LineInfo {
        breaks_run,
        sets_motion: changes.sets_motion,
        uses_modal_motion,
        group0: w.group0(),
    })
}

/// The move of a line with axis words in the motion mode in force, and the
/// state after it. `state_change`: the line changes state (or the plane);
/// `uses_modal_motion`: the line has no motion G word.
fn axis_move(
    w: &Words,
    state_change: bool,
    uses_modal_motion: bool,
    st: &mut State,
) -> Result<Move, GcodeError> {
    let (lx, ln) = (w.lx, w.ln);
    let mm = st.units.mm_per_unit();
    let given = w.axis_words();
    let mode = st.motion;
    let first_axis = w.first_axis_column();
    if mode == MotionMode::None {
        return Err(err(ln, first_axis, ErrorKind::NoMotionMode));
    }
    let g53 = matches!(w.nonmodal, Some((NonModal::G53, _)));
    let start = st.pos;
    let target = if g53 {
        let mut t = st.pos;
        for a in 0..3 {
            if let Some(w) = given[a] {
                set_axis(&mut t, a, finite(w.value * mm, ln, w)?);
            }
        }
        t
    } else {
        target_point(st, &given, ln)?
    };
    st.spline.moved_otherwise();
    let (curve, kind) = match mode {
        MotionMode::ArcCw | MotionMode::ArcCcw => {
            let arc = build_arc(
                lx,
                ln,
                st,
                start,
                target,
                mode == MotionMode::ArcCw,
                first_axis,
            )?;
            // `Arc` keeps the programmed start and end exactly.
            (Curve::from(arc), MoveKind::Arc)
        }
        MotionMode::Rapid => (Curve::Line(Line::new(start, target)), MoveKind::Rapid),
        _ => (Curve::Line(Line::new(start, target)), MoveKind::Linear),
    };
    let pinned = pin_reason(w, st, kind, g53, state_change, uses_modal_motion);
    // Where the move ends with the switch on: as with it off for the
    // axes an absolute word sets (after a motion mode that may differ,
    // nowhere known).
    if !lx.block_delete {
        let dep = &mut st.after_delete;
        if dep.motion && uses_modal_motion {
            dep.axes = [true; 3];
        } else if !st.incremental && !g53 {
            for a in 0..3 {
                dep.axes[a] &= given[a].is_none();
            }
        }
    }
    let end = match &curve {
        Curve::Arc(a) => a.end(),
        _ => target,
    };
    // Update the position and what is known of it.
    st.pos = end;
    for a in 0..3 {
        if let Some(w) = given[a] {
            if g53 {
                st.known[a] = false;
                st.axis_text[a] = None;
            } else if st.incremental {
                st.axis_text[a] = None;
            } else {
                st.known[a] = true;
                st.axis_text[a] = Some(w.text.clone());
            }
        }
    }
    match mode {
        MotionMode::Probe(_) => st.forget(given.map(|g| g.is_some())),
        MotionMode::RigidTap => st.pos = start,
        _ => {}
    }
    let feed = if kind == MoveKind::Rapid || st.feed_mode != FeedMode::PerMinute {
        None
    } else {
        st.feed.as_ref().map(|f| f.mm_per_min)
    };
    Ok(Move {
        piece: Piece {
            curve,
            rapid: kind == MoveKind::Rapid,
            source_lines: (ln, ln),
            feed,
        },
        line: ln,
        kind,
        pinned,
        end_text: st.axis_text.clone(),
    })
}

/// Why the move of `kind` on line `w` is written back verbatim, if it is
/// (the first reason that applies), from the state before the move: `g53`
/// whether it is a G53 move, `state_change` whether the line changes state
/// (or the plane), `uses_modal_motion` whether it moves in the modal
/// motion mode.
fn pin_reason(
    w: &Words,
    st: &State,
    kind: MoveKind,
    g53: bool,
    state_change: bool,
    uses_modal_motion: bool,
) -> Option<PinReason> {
    let lx = w.lx;
    // Words that are part of a plain move.
    let extra_words = lx.words.iter().any(|w| {
        let plain = matches!(w.letter, 'N' | 'F' | 'X' | 'Y' | 'Z' | 'G')
            || EXTRA_AXES.contains(w.letter)
            || (kind == MoveKind::Arc && matches!(w.letter, 'I' | 'J' | 'K' | 'R' | 'P'));
        !plain
    });
    let extra_axes = lx.words.iter().any(|w| EXTRA_AXES.contains(w.letter));
    let start_known = st.known.iter().all(|&k| k);
    let after_delete = !lx.block_delete && st.depends_on_deleted_line(kind, uses_modal_motion);
    if lx.block_delete {
        Some(PinReason::BlockDelete)
    } else if has_foreign_words(lx) {
        Some(PinReason::ForeignWords)
    } else if g53
        || matches!(
            st.motion,
            MotionMode::Thread | MotionMode::RigidTap | MotionMode::Probe(_)
        )
    {
        Some(PinReason::SpecialMotion)
    } else if extra_axes {
        Some(PinReason::ExtraAxes)
    } else if extra_words {
        Some(PinReason::ExtraWords)
    } else if state_change {
        Some(PinReason::StateChange)
    } else if st.comp {
        Some(PinReason::CutterComp)
    } else if st.feed_mode != FeedMode::PerMinute && kind != MoveKind::Rapid {
        Some(PinReason::FeedMode)
    } else if !start_known {
        Some(PinReason::UnknownStart)
    } else if after_delete {
        Some(PinReason::AfterBlockDelete)
    } else {
        None
    }
}

/// The end point of a move from the axis words, in mm.
pub(super) fn target_point(
    st: &State,
    given: &[Option<&Word>; 3],
    ln: usize,
) -> Result<Vec3, GcodeError> {
    let mm = st.units.mm_per_unit();
    let mut t = st.pos;
    for a in 0..3 {
        if let Some(w) = given[a] {
            let v = if st.incremental {
                axis(st.pos, a) + w.value * mm
            } else {
                w.value * mm
            };
            set_axis(&mut t, a, finite(v, ln, w)?);
        }
    }
    Ok(t)
}
