//! One line interpreted: its codes classified, its state changes applied
//! in LinuxCNC's order, its moves made, pinned or not.

use super::arc::build_arc;
use super::codes::{classify_g, m_group, NonModal, G};
use super::{axis, err, finite, set_axis, FeedMode, State};
use crate::cycles::{self, CycleLine, Spindle};
use crate::error::{ErrorKind, GcodeError};
use crate::lexer::{LexedLine, Word};
use crate::program::{Feed, MotionMode, Move, MoveKind, PinReason};
use crate::spline;
use fairpath::geom::{Curve, Line, ParamCurve, Vec3};
use fairpath::path::Piece;

pub(super) const AXIS_LETTERS: [char; 3] = ['X', 'Y', 'Z'];
/// Word letters the interpreter takes (`@` and `^` are resolved to X and
/// Y before it; `E`, the 3D-printer extruder, is passed through, see
/// [`FOREIGN_WORDS`]).
const INTERPRETED_LETTERS: &str = "ABCDEFGHIJKLMNPQRSTUVWXYZ";
const EXTRA_AXES: &str = "ABCUVW";

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

/// What [`Program::passthrough`] calls a line with [`FOREIGN_WORDS`].
const FOREIGN_NOTE: &str = "extruder word E (3D printers)";
/// What [`Program::passthrough`] calls a canned-cycle line.
const CYCLE_NOTE: &str = "canned cycle";

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
    let foreign = lx.words.iter().any(|w| FOREIGN_WORDS.contains(w.letter));
    if cycle {
        st.note_passthrough(ln, CYCLE_NOTE);
    } else if foreign {
        st.note_passthrough(ln, FOREIGN_NOTE);
    } else if moves.len() > first {
        st.last_plain_move_line = ln;
    }
    Ok(info)
}

/// Whether a move of `kind` on a line outside block delete depends on an
/// earlier `/` line ([`crate::block_delete`]): `modal_motion` is whether
/// the line moves in the modal motion mode.
fn depends_on_deleted_line(st: &State, kind: MoveKind, modal_motion: bool) -> bool {
    let dep = &st.after_delete;
    let start = dep.axes.iter().any(|&a| a)
        && (!st.incremental || (kind == MoveKind::Arc && !st.arc_incremental));
    dep.state || (dep.feed && kind != MoveKind::Rapid) || (dep.motion && modal_motion) || start
}

/// Interprets the words of one line, appending its moves.
fn interpret_words(
    lx: &LexedLine,
    ln: usize,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<LineInfo, GcodeError> {
    let none = LineInfo::NONE;
    let motion_before_line = st.motion;
    if lx.percent {
        st.percent_lines += 1;
        if st.percent_lines >= 2 {
            st.ended = true;
        }
        return Ok(none);
    }
    if lx.words.is_empty() {
        return Ok(none);
    }
    // The lexer reads every letter; these are the ones interpreted here.
    if let Some(w) = lx
        .words
        .iter()
        .find(|w| !INTERPRETED_LETTERS.contains(w.letter))
    {
        return Err(err(ln, w.column, ErrorKind::UnsupportedWord(w.letter)));
    }
    // ---- classify G and M codes ----
    let mut gs: Vec<(G, &Word)> = Vec::new();
    let mut ms: Vec<(i64, &Word)> = Vec::new();
    for w in &lx.words {
        match w.letter {
            'G' => {
                let tenths = w.value * 10.0;
                let code = tenths.round();
                if (tenths - code).abs() > 1e-6 || !(0.0..=9999.0).contains(&code) {
                    return Err(err(ln, w.column, ErrorKind::UnknownGCode(w.text.clone())));
                }
                let g = classify_g(code as u16, &w.text).map_err(|k| err(ln, w.column, k))?;
                // G80 beside another motion code (`G0 G80`, common in
                // headers): the other code wins, as on Fanuc controls.
                let cancel = G::Motion(MotionMode::None);
                if let Some(k) = gs.iter().position(|(o, _)| o.group() == g.group()) {
                    if gs[k].0 == cancel && g.group() == "motion" {
                        gs[k] = (g, w);
                        continue;
                    } else if g == cancel {
                        continue;
                    }
                    return Err(err(ln, w.column, ErrorKind::ConflictingGCodes(g.group())));
                }
                gs.push((g, w));
            }
            'M' => {
                if w.value.fract() != 0.0 || !(0.0..=1.0e6).contains(&w.value) {
                    return Err(err(ln, w.column, ErrorKind::BadValue('M')));
                }
                let code = w.value as i64;
                let grp = m_group(code);
                if grp != 0 && ms.iter().any(|(c, _)| m_group(*c) == grp) {
                    return Err(err(ln, w.column, ErrorKind::ConflictingMCodes));
                }
                ms.push((code, w));
            }
            _ => {}
        }
    }
    let word = |l: char| lx.word(l);
    let motion_g = gs.iter().find_map(|(g, w)| match g {
        G::Motion(m) => Some((*m, *w)),
        _ => None,
    });
    let nonmodal = gs.iter().find_map(|(g, w)| match g {
        G::NonModal(n) => Some((*n, *w)),
        _ => None,
    });
    // G53 is non-modal but modifies the motion on its line.
    let axis_user_nonmodal = nonmodal.filter(|(n, _)| n.uses_axes());
    let has_axes = lx
        .words
        .iter()
        .any(|w| AXIS_LETTERS.contains(&w.letter) || EXTRA_AXES.contains(w.letter));
    // `G2 J-1` (centre words, no axis words): a full circle back to the
    // current point, as LinuxCNC runs it (quick-tests/tangent_arcs.ngc).
    let center_only_arc = !has_axes
        && matches!(motion_g, Some((MotionMode::ArcCw | MotionMode::ArcCcw, _)))
        && ['I', 'J', 'K'].iter().any(|&l| lx.word(l).is_some())
        && lx.word('R').is_none()
        && axis_user_nonmodal.is_none();
    let has_axes = has_axes || center_only_arc;
    if let (Some((_, w)), Some((m, _))) = (axis_user_nonmodal, motion_g) {
        if m != MotionMode::None && has_axes {
            return Err(err(ln, w.column, ErrorKind::ConflictingAxisUsers));
        }
    }
    let spline_end = gs.iter().find(|(g, _)| *g == G::SplineEnd).map(|(_, w)| *w);
    let spline_line = spline::claims(
        st,
        motion_g.map(|(m, _)| m),
        spline_end.is_some(),
        has_axes && axis_user_nonmodal.is_none(),
    );

    // ---- state changes (LinuxCNC order of execution) ----
    let mut changes = lx.block_delete || !ms.is_empty();
    for (c, _) in &ms {
        match c {
            3 => st.cycle.spindle = Spindle::Clockwise,
            4 => st.cycle.spindle = Spindle::CounterClockwise,
            5 => st.cycle.spindle = Spindle::Stopped,
            _ => {}
        }
    }
    let group0 = nonmodal.is_some_and(|(n, _)| n != NonModal::Dwell);
    for l in ['S', 'T', 'H', 'D', 'L', 'Q', 'E'] {
        // L and Q are spline words on spline lines.
        if word(l).is_some() && !(spline_line && (l == 'L' || l == 'Q')) {
            changes = true;
        }
    }
    for (g, w) in &gs {
        if let G::FeedMode(m) = g {
            changes |= *m != st.feed_mode;
            st.feed_mode = *m;
            let _ = w;
        }
    }
    if let Some(f) = word('F') {
        if f.value < 0.0 {
            return Err(err(ln, f.column, ErrorKind::BadValue('F')));
        }
        st.feed = Some(Feed {
            mm_per_min: f.value * st.units.mm_per_unit(),
            text: f.text.clone(),
            units: st.units,
        });
    }
    // A plane change alone does not end a run: the plane shapes only arcs
    // (resolved to 3D here) and canned cycles (always pinned), so a `G18`
    // line between two feed moves is written back in place and the joint
    // across it is smoothed like any other (CAM posts emit one before every
    // XZ arc: LinuxCNC's test_12mmflat.ngc kept a 3-degree corner there on
    // every pass). On a move line it pins the move, whose text must stay.
    let mut plane_changed = false;
    let mut sets_motion = false;
    let mut restated_motion = false;
    for (g, w) in &gs {
        match *g {
            G::Plane(p) => {
                plane_changed |= p != st.plane;
                st.plane = p;
            }
            G::Units(u) => {
                if u != st.units {
                    changes = true;
                    st.units = u;
                    st.axis_text = [None, None, None];
                }
            }
            G::Incremental(inc) => {
                changes |= inc != st.incremental;
                st.incremental = inc;
            }
            G::ArcIncremental(inc) => {
                changes |= inc != st.arc_incremental;
                st.arc_incremental = inc;
            }
            G::FeedMode(_) => {}
            G::CutterComp(on) => {
                changes |= on || st.comp;
                st.comp = on;
            }
            G::ToolLength(on) => {
                if on || st.tlo {
                    changes = true;
                    st.forget([false, false, true]);
                }
                st.tlo = on;
            }
            G::CoordSystem(c) => {
                if c != st.coord {
                    changes = true;
                    st.forget([true; 3]);
                }
                st.coord = c;
            }
            G::PathControl(c) => {
                changes |= c != st.path || word('P').is_some() || word('Q').is_some();
                st.path = c;
                let mut text = format!("G{}", w.text);
                if c == 640 {
                    for l in ['P', 'Q'] {
                        if let Some(v) = word(l) {
                            text.push_str(&format!(" {l}{}", v.text));
                        }
                    }
                }
                st.path_words = Some(text);
            }
            G::ReturnMode(to_r) => st.cycle.retract_to_r = to_r,
            G::LatheRadius => {}
            G::SpindleMode(c) => {
                changes |= c != st.spindle_mode;
                st.spindle_mode = c;
            }
            G::Cancel(_) => changes = true,
            G::NonModal(_) => changes = true,
            G::SplineEnd => sets_motion = true,
            G::Motion(m) => {
                sets_motion = true;
                if m == st.motion && !has_axes {
                    restated_motion = true;
                }
                // A spline G word without axes opens or continues a block.
                if !has_axes && m != st.motion && !spline_line {
                    changes = true;
                }
                let _ = w;
            }
        }
    }
    let _ = restated_motion;
    if let Some((m, _)) = motion_g {
        st.motion = m;
    }
    // A line outside block delete that sets F or the motion mode ends
    // their dependence on `/` lines.
    if !lx.block_delete {
        if word('F').is_some() {
            st.after_delete.feed = false;
        }
        if motion_g.is_some() {
            st.after_delete.motion = false;
        }
    }
    // The motion the line runs: a canned cycle, or another motion, which
    // makes the next cycle take a new initial level (LinuxCNC's
    // convert_motion).
    let line_motion = motion_g
        .map(|(m, _)| m)
        .or_else(|| (has_axes && axis_user_nonmodal.is_none()).then_some(motion_before_line));
    match line_motion {
        Some(MotionMode::Cycle(_)) | None => {}
        Some(_) => st.cycle.other_motion(),
    }

    // ---- group-0 axis users ----
    let mm = st.units.mm_per_unit();
    let given: [Option<&Word>; 3] = [word('X'), word('Y'), word('Z')];
    let given_mask = [given[0].is_some(), given[1].is_some(), given[2].is_some()];
    if let Some((n, _)) = nonmodal {
        match n {
            NonModal::G92 => {
                for a in 0..3 {
                    if let Some(w) = given[a] {
                        let v = finite(w.value * mm, ln, w)?;
                        let c = [&mut st.pos.x, &mut st.pos.y, &mut st.pos.z];
                        *c[a] = v;
                        st.known[a] = true;
                        st.axis_text[a] = Some(w.text.clone());
                    }
                }
            }
            NonModal::G52 => st.forget(given_mask),
            NonModal::G10 | NonModal::G92_1 | NonModal::G92_2 | NonModal::G92_3 => {
                st.forget([true; 3])
            }
            NonModal::G28 | NonModal::G30 => {
                // Rapid to the intermediate point (if any), then home: the
                // position is unknown afterwards.
                if has_axes {
                    st.spline.moved_otherwise();
                    let target = target_point(st, &given, ln)?;
                    let start = st.pos;
                    moves.push(Move {
                        piece: Piece {
                            curve: Curve::Line(Line::new(start, target)),
                            rapid: true,
                            source_lines: (ln, ln),
                            feed: None,
                        },
                        line: ln,
                        kind: MoveKind::Rapid,
                        pinned: Some(PinReason::SpecialMotion),
                        end_text: [None, None, None],
                    });
                    st.pos = target;
                }
                st.forget([true; 3]);
            }
            NonModal::G28_1 | NonModal::G30_1 | NonModal::Dwell | NonModal::G53 => {}
        }
    }
    if let (Some((n, _)), false) = (nonmodal, lx.block_delete) {
        // Home and G92 set the position the same way with the switch on.
        match n {
            NonModal::G28 | NonModal::G30 => st.after_delete.axes = [false; 3],
            NonModal::G92 => {
                for a in 0..3 {
                    st.after_delete.axes[a] &= !given_mask[a];
                }
            }
            _ => {}
        }
    }
    let ended_now = ms.iter().any(|(c, _)| *c == 2 || *c == 30);

    // ---- motion ----
    if spline_line {
        let other_g = gs
            .iter()
            .find(|(g, _)| {
                !matches!(g, G::Motion(m) if spline::is_spline(*m)) && *g != G::SplineEnd
            })
            .map(|(_, w)| *w);
        let ctx = spline::LineCtx {
            lx,
            ln,
            code: motion_g.filter(|(m, _)| spline::is_spline(*m)),
            end: spline_end,
            other_g,
            state_change: changes || plane_changed,
        };
        let first = moves.len();
        let mut pinned_moves = spline::line(&ctx, st, moves)?;
        if moves.len() > first
            && !lx.block_delete
            && depends_on_deleted_line(st, MoveKind::Spline, motion_g.is_none())
        {
            for m in &mut moves[first..] {
                m.pinned.get_or_insert(PinReason::AfterBlockDelete);
            }
            pinned_moves = true;
        }
        if ended_now {
            st.ended = true;
        }
        return Ok(LineInfo {
            breaks_run: changes || pinned_moves,
            sets_motion,
            uses_modal_motion: has_axes && motion_g.is_none(),
            group0,
        });
    }
    if let Some(MotionMode::Cycle(code)) = line_motion {
        let column = motion_g.map_or_else(
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
            ln,
            code,
            same_mode: motion_before_line == MotionMode::Cycle(code),
            column,
        };
        cycles::run(&cycle, st, moves)?;
        // Where a cycle ends depends on its initial level and retract
        // plane: after anything a `/` line changed, on everything.
        if !lx.block_delete && !st.after_delete.is_clear() {
            st.after_delete.axes = [true; 3];
        }
        if ended_now {
            st.ended = true;
        }
        return Ok(LineInfo {
            breaks_run: true,
            sets_motion,
            uses_modal_motion: motion_g.is_none(),
            group0,
        });
    }
    if !has_axes {
        if let Some((MotionMode::ArcCw | MotionMode::ArcCcw, w)) = motion_g {
            if ['I', 'J', 'K', 'R', 'P'].iter().any(|&l| word(l).is_some()) {
                return Err(err(ln, w.column, ErrorKind::ArcWithoutAxes));
            }
        }
        // Words that do nothing without a move: keep the line out of runs.
        if ['I', 'J', 'K', 'R', 'P'].iter().any(|&l| word(l).is_some()) {
            changes = true;
        }
    }
    let uses_modal_motion = has_axes && motion_g.is_none() && axis_user_nonmodal.is_none();
    let mut breaks_run = changes;
    if has_axes && axis_user_nonmodal.is_none() {
        let mode = st.motion;
        let first_axis = lx
            .words
            .iter()
            .find(|w| AXIS_LETTERS.contains(&w.letter) || EXTRA_AXES.contains(w.letter))
            .map_or(1, |w| w.column);
        if mode == MotionMode::None {
            return Err(err(ln, first_axis, ErrorKind::NoMotionMode));
        }
        let g53 = matches!(nonmodal, Some((NonModal::G53, _)));
        let start = st.pos;
        let start_known = st.known.iter().all(|&k| k);
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
                (Curve::Arc(arc), MoveKind::Arc)
            }
            MotionMode::Rapid => (Curve::Line(Line::new(start, target)), MoveKind::Rapid),
            _ => (Curve::Line(Line::new(start, target)), MoveKind::Linear),
        };
        // Words that are part of a plain move.
        let extra_words = lx.words.iter().any(|w| {
            let plain = matches!(w.letter, 'N' | 'F' | 'X' | 'Y' | 'Z' | 'G')
                || EXTRA_AXES.contains(w.letter)
                || (kind == MoveKind::Arc && matches!(w.letter, 'I' | 'J' | 'K' | 'R' | 'P'));
            !plain
        });
        let extra_axes = lx.words.iter().any(|w| EXTRA_AXES.contains(w.letter));
        let foreign = lx.words.iter().any(|w| FOREIGN_WORDS.contains(w.letter));
        let after_delete = !lx.block_delete && depends_on_deleted_line(st, kind, uses_modal_motion);
        let pinned = if lx.block_delete {
            Some(PinReason::BlockDelete)
        } else if foreign {
            Some(PinReason::ForeignWords)
        } else if g53
            || matches!(
                mode,
                MotionMode::Thread | MotionMode::RigidTap | MotionMode::Probe(_)
            )
        {
            Some(PinReason::SpecialMotion)
        } else if extra_axes {
            Some(PinReason::ExtraAxes)
        } else if extra_words {
            Some(PinReason::ExtraWords)
        } else if changes || plane_changed {
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
        };
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
            MotionMode::Probe(_) => st.forget(given_mask),
            MotionMode::RigidTap => st.pos = start,
            _ => {}
        }
        let feed = if kind == MoveKind::Rapid || st.feed_mode != FeedMode::PerMinute {
            None
        } else {
            st.feed.as_ref().map(|f| f.mm_per_min)
        };
        breaks_run |= pinned.is_some() || kind == MoveKind::Rapid;
        moves.push(Move {
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
        });
    }
    if ended_now {
        st.ended = true;
    }
    Ok(LineInfo {
        breaks_run,
        sets_motion,
        uses_modal_motion,
        group0,
    })
}

/// The end point of a move from the axis words, in mm.
fn target_point(st: &State, given: &[Option<&Word>; 3], ln: usize) -> Result<Vec3, GcodeError> {
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
