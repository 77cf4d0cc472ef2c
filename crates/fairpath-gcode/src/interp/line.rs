//! One line interpreted: what its words ask for ([`Words`]), its state
//! changes ([`super::modal`], [`super::nonmodal`]), then its moves: a
//! spline line ([`crate::spline`]), a canned cycle ([`crate::cycles`]) or a
//! move in the modal motion mode ([`super::motion`]).

use super::codes::{LineCodes, NonModal, G};
use super::{err, modal, motion, nonmodal, State};
use crate::axes::{AXIS_LETTERS, CENTER_LETTERS};
use crate::cycles::{self, CycleLine};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::{LexedLine, Word};
use crate::program::{MotionMode, Move, MoveKind, PinReason};
use crate::spline;

/// Word letters the interpreter takes (`@` and `^` are resolved to X and
/// Y before it; `E`, the 3D-printer extruder, is passed through, see
/// [`FOREIGN_WORDS`]).
const INTERPRETED_LETTERS: &str = "ABCDEFGHIJKLMNPQRSTUVWXYZ";
pub(super) const EXTRA_AXES: &str = "ABCUVW";

/// Whether `w` is an axis word (X Y Z, or A B C U V W).
fn is_axis_word(w: &Word) -> bool {
    AXIS_LETTERS.contains(&w.letter) || EXTRA_AXES.contains(w.letter)
}

/// What the reader records of an interpreted line.
pub(super) struct LineInfo {
    pub(super) breaks_run: bool,
    pub(super) sets_motion: bool,
    pub(super) uses_modal_motion: bool,
    /// The line holds a group-0 code other than G4 (G10, G28, G92 ...).
    pub(super) group0: bool,
}

impl LineInfo {
    const NONE: LineInfo = LineInfo {
        breaks_run: false,
        sets_motion: false,
        uses_modal_motion: false,
        group0: false,
    };
}

/// Word letters that no dialect fairpath reads gives a meaning it can
/// smooth through: `E`, the extruder of 3D printers (LinuxCNC takes E
/// only in G76 threading, which is not supported). A line with one is
/// passed through verbatim ([`PinReason::ForeignWords`]) and ends runs.
const FOREIGN_WORDS: &str = "E";

/// Whether the line has [`FOREIGN_WORDS`].
pub(super) fn has_foreign_words(lx: &LexedLine) -> bool {
    lx.words.iter().any(|w| FOREIGN_WORDS.contains(w.letter))
}

/// What [`Program::passthrough`](crate::program::Program::passthrough) calls a line with [`FOREIGN_WORDS`].
const FOREIGN_NOTE: &str = "extruder word E (3D printers)";
/// What [`Program::passthrough`](crate::program::Program::passthrough) calls a canned-cycle line.
const CYCLE_NOTE: &str = "canned cycle";

/// What [`Program::passthrough`](crate::program::Program::passthrough) calls a line whose feed move is pinned
/// for what it runs in or with, not for what the line itself says (its
/// own words or state changes end runs as any program's do): the machine
/// runs it as written, and the user is told why that stretch was left as
/// it is (a program cut under G41 or in G93 would otherwise come out
/// unchanged without a word).
fn pinned_note(reason: PinReason) -> Option<&'static str> {
    match reason {
        PinReason::CutterComp => Some("cutter radius compensation G41/G42"),
        PinReason::FeedMode => Some("inverse-time or per-revolution feed G93/G95"),
        PinReason::ExtraAxes => Some("rotary or extra axes A B C U V W"),
        PinReason::SpecialMotion => Some("threading, tapping, probing or G53"),
        _ => None,
    }
}

/// Interprets one lexed line, appending its moves: skips a `/` line when
/// the block-delete switch is on, records what a `/` line changes when it
/// is off ([`crate::block_delete`]), and notes passed-through lines.
pub(super) fn interpret_line(
    lx: &LexedLine,
    ln: usize,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    if lx.block_delete && st.skip_block_delete {
        return Ok(LineInfo::NONE);
    }
    let first = moves.len();
    let before = lx.block_delete.then(|| st.snapshot());
    let info = interpret_words(lx, ln, st, moves)?;
    if let Some(before) = before {
        let after = st.snapshot();
        let moved = info.sets_motion || moves.len() > first;
        st.after_delete
            .after_deleted_line(&before, &after, info.group0, moved);
    }
    let cycle = moves[first..]
        .iter()
        .any(|m| m.pinned == Some(PinReason::CannedCycle));
    if cycle {
        st.note_passthrough(ln, CYCLE_NOTE);
    } else if has_foreign_words(lx) {
        st.note_passthrough(ln, FOREIGN_NOTE);
    } else if let Some(what) = moves[first..]
        .iter()
        .filter(|m| m.kind != MoveKind::Rapid)
        .find_map(|m| m.pinned.and_then(pinned_note))
    {
        st.note_passthrough(ln, what);
    } else if moves.len() > first {
        st.last_plain_move_line = ln;
    }
    Ok(info)
}

/// Interprets the words of one line, appending its moves.
fn interpret_words(
    lx: &LexedLine,
    ln: usize,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    if lx.percent {
        st.percent_line();
        return Ok(LineInfo::NONE);
    }
    if lx.words.is_empty() {
        return Ok(LineInfo::NONE);
    }
    let w = Words::read(lx, ln, st)?;
    let changes = modal::apply(&w, st)?;
    nonmodal::apply(&w, st, moves)?;
    let info = if w.spline {
        spline_line(&w, &changes, st, moves)?
    } else if let Some(MotionMode::Cycle(code)) = w.runs_motion() {
        cycle_line(&w, code, &changes, st, moves)?
    } else {
        motion::line_move(&w, &changes, st, moves)?
    };
    if w.codes.ends_program() {
        st.ended = true;
    }
    Ok(info)
}

/// A line's words and what they ask for, read before the line changes
/// the state.
pub(super) struct Words<'a> {
    pub(super) lx: &'a LexedLine,
    /// The program line number.
    pub(super) ln: usize,
    pub(super) codes: LineCodes<'a>,
    /// The motion G word (group 1).
    pub(super) motion: Option<(MotionMode, &'a Word)>,
    /// The group-0 G word.
    pub(super) nonmodal: Option<(NonModal, &'a Word)>,
    /// The group-0 code takes the axis words (G10, G28, G30, G52, G92): the
    /// line does not move in the motion mode. (G53 is non-modal but
    /// modifies the motion on its line.)
    pub(super) axes_for_nonmodal: bool,
    /// The line has axis words, or is a centre-only arc.
    pub(super) has_axes: bool,
    /// The spline reader takes the line ([`spline::claims`]).
    pub(super) spline: bool,
    /// The motion mode before the line.
    pub(super) motion_before: MotionMode,
}

impl<'a> Words<'a> {
    /// Reads line `ln`: every letter must be one the interpreter takes, its
    /// codes are classified ([`LineCodes::of`]), and a motion code may not
    /// share the axis words with a group-0 code.
    fn read(lx: &'a LexedLine, ln: usize, st: &State) -> Result<Words<'a>, GcodeError> {
        // The lexer reads every letter; these are the ones interpreted here.
        if let Some(w) = lx
            .words
            .iter()
            .find(|w| !INTERPRETED_LETTERS.contains(w.letter))
        {
            return Err(err(ln, w.column, ErrorKind::UnsupportedWord(w.letter)));
        }
        let codes = LineCodes::of(lx, ln)?;
        let motion = codes.motion();
        let nonmodal = codes.nonmodal();
        let axis_user_nonmodal = nonmodal.filter(|(n, _)| n.uses_axes());
        let has_axes = lx.words.iter().any(is_axis_word);
        // `G2 J-1` (centre words, no axis words): a full circle back to the
        // current point, as LinuxCNC runs it (quick-tests/tangent_arcs.ngc).
        let center_only_arc = !has_axes
            && matches!(motion, Some((MotionMode::ArcCw | MotionMode::ArcCcw, _)))
            && CENTER_LETTERS.iter().any(|&l| lx.word(l).is_some())
            && lx.word('R').is_none()
            && axis_user_nonmodal.is_none();
        let has_axes = has_axes || center_only_arc;
        if let (Some((_, w)), Some((m, _))) = (axis_user_nonmodal, motion) {
            if m != MotionMode::None && has_axes {
                return Err(err(ln, w.column, ErrorKind::ConflictingAxisUsers));
            }
        }
        let spline = spline::claims(
            st,
            motion.map(|(m, _)| m),
            codes.spline_end().is_some(),
            has_axes && axis_user_nonmodal.is_none(),
        );
        Ok(Words {
            lx,
            ln,
            codes,
            motion,
            nonmodal,
            axes_for_nonmodal: axis_user_nonmodal.is_some(),
            has_axes,
            spline,
            motion_before: st.motion,
        })
    }

    /// The line moves the axes in a motion mode.
    pub(super) fn moves_axes(&self) -> bool {
        self.has_axes && !self.axes_for_nonmodal
    }

    /// The motion the line runs: its motion code, or the modal motion when
    /// it moves the axes without one.
    pub(super) fn runs_motion(&self) -> Option<MotionMode> {
        self.motion
            .map(|(m, _)| m)
            .or_else(|| self.moves_axes().then_some(self.motion_before))
    }

    /// The line holds a group-0 code other than G4.
    pub(super) fn group0(&self) -> bool {
        self.nonmodal.is_some_and(|(n, _)| n != NonModal::Dwell)
    }

    /// The X, Y and Z words.
    pub(super) fn axis_words(&self) -> [Option<&'a Word>; 3] {
        [self.lx.word('X'), self.lx.word('Y'), self.lx.word('Z')]
    }

    /// The column of the first axis word (1 without one).
    pub(super) fn first_axis_column(&self) -> usize {
        self.lx
            .words
            .iter()
            .find(|w| is_axis_word(w))
            .map_or(1, |w| w.column)
    }
}

/// A line the spline reader takes ([`spline::line`]); its moves are
/// pinned when they depend on an earlier `/` line.
fn spline_line(
    w: &Words,
    changes: &modal::Changes,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    let other_g = w
        .codes
        .gs
        .iter()
        .find(|(g, _)| !matches!(g, G::Motion(m) if spline::is_spline(*m)) && *g != G::SplineEnd)
        .map(|(_, w)| *w);
    let ctx = spline::LineCtx {
        lx: w.lx,
        ln: w.ln,
        code: w.motion.filter(|(m, _)| spline::is_spline(*m)),
        end: w.codes.spline_end(),
        other_g,
        state_change: changes.state || changes.plane,
    };
    let first = moves.len();
    let mut pinned_moves = spline::line(&ctx, st, moves)?;
    if moves.len() > first
        && !w.lx.block_delete
        && st.depends_on_deleted_line(MoveKind::Spline, w.motion.is_none())
    {
        for m in &mut moves[first..] {
            m.pinned.get_or_insert(PinReason::AfterBlockDelete);
        }
        pinned_moves = true;
    }
    Ok(LineInfo {
        breaks_run: changes.state || pinned_moves,
        sets_motion: changes.sets_motion,
        uses_modal_motion: w.has_axes && w.motion.is_none(),
        group0: w.group0(),
    })
}

/// A canned-cycle line ([`cycles::run`]): its moves, all pinned.
fn cycle_line(
    w: &Words,
    code: u16,
    changes: &modal::Changes,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    let lx = w.lx;
    let column = w.motion.map_or_else(
        || {
            lx.words
                .iter()
                .find(|w| w.letter != 'N')
                .map_or(1, |w| w.column)
        },
        |(_, w)| w.column,
    );
    let cycle = CycleLine {
        lx,
        ln: w.ln,
        code,
        same_mode: w.motion_before == MotionMode::Cycle(code),
        column,
    };
    cycles::run(&cycle, st, moves)?;
    // Where a cycle ends depends on its initial level and retract
    // plane: after anything a `/` line changed, on everything.
    if !lx.block_delete && !st.after_delete.is_clear() {
        st.after_delete.axes = [true; 3];
    }
    Ok(LineInfo {
        breaks_run: true,
        sets_motion: changes.sets_motion,
        uses_modal_motion: w.motion.is_none(),
        group0: w.group0(),
    })
}
