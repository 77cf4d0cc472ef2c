//! Canned cycles (G73, G74, G81, G82, G83, G84, G85, G86, G89) as LinuxCNC
//! 2.9 runs them (`convert_cycle`, `convert_cycle_xy/yz/zx` and the
//! `convert_cycle_g8x` functions of its `interp_cycles.cc`, with the
//! `CYCLE_MACRO` of `interp_internal.hh`): the reader makes every rapid and
//! feed the cycle makes, with LinuxCNC's end points, so that the position
//! after a cycle is known. The moves are pinned ([`PinReason::CannedCycle`])
//! and the line is written back verbatim.
//!
//! LinuxCNC's rules, all followed here:
//! * the first cycle after another motion mode needs R and the plane's
//!   normal axis word (Z in G17); later cycles of the same code (and modal
//!   repeats: axis words without a G word) reuse them; G82/G86/G89 need P
//!   and G73/G83 need Q in the same way;
//! * in G90 X Y R Z are absolute; in G91 X Y are increments per repeat, R
//!   is relative to the *initial level* (the normal-axis position before
//!   the first cycle since the last non-cycle motion) and Z relative to R;
//! * `L` repeats the cycle (moving by the X Y increments each time in G91);
//! * G98 retracts to the initial level, G99 (the default) to R; a cycle
//!   starting below R first rises to R;
//! * G73/G83 back off 0.010 in (0.254 mm) above the last depth;
//! * G84 needs the spindle turning clockwise, G74 counter-clockwise, G86
//!   turning; no cycle runs without a feed rate, in G93, or with cutter
//!   compensation.
//!
//! Not supported (errors): G76 (threading), G87 (back boring), G88
//! (manual retract), G74/G84 outside G17 (LinuxCNC's argument order there
//! moves the wrong axes). Rotary and UVW words on a cycle line are errors,
//! as in LinuxCNC.

use crate::axes::{axis, set_axis, AXIS_LETTERS};
use crate::error::{CycleError, ErrorKind, GcodeError};
use crate::interp::{err, finite, FeedMode, State};
use crate::lexer::{LexedLine, Word};
use crate::program::{Move, MoveKind, PinReason};
use fairpath::controller::Plane;
use fairpath::geom::{Curve, Line, Vec3};
use fairpath::path::Piece;

/// How far above the last depth G73 and G83 rapid back down to (or back up
/// to, G73), in inches: LinuxCNC 2.9's `G83_RAPID_DELTA`
/// (interp_internal.hh), scaled to mm in mm programs.
const PECK_CLEARANCE_INCH: f64 = 0.010;

/// How far an `L` word may be from an integer: LinuxCNC's
/// `read_integer_value` takes 0.0001.
const NEAR_INT: f64 = 1e-4;

/// The spindle's direction, for the cycles that check it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Spindle {
    Stopped,
    Clockwise,
    CounterClockwise,
}

/// The canned-cycle part of the modal state (LinuxCNC's `cycle_*`
/// settings), in program units.
#[derive(Clone)]
pub(crate) struct CycleState {
    /// G99 (retract to R, LinuxCNC's default) rather than G98.
    pub(crate) retract_to_r: bool,
    pub(crate) spindle: Spindle,
    r: f64,
    /// The normal-axis word of the last cycle (LinuxCNC's `cycle_cc`).
    z: f64,
    p: f64,
    q: f64,
    /// The initial level and whether it is known, from the first cycle
    /// since the last non-cycle motion (LinuxCNC's `cycle_il`).
    initial: Option<(f64, bool)>,
}

impl CycleState {
    pub(crate) fn new() -> CycleState {
        CycleState {
            retract_to_r: true,
            spindle: Spindle::Stopped,
            r: 0.0,
            z: 0.0,
            p: 0.0,
            q: 0.0,
            initial: None,
        }
    }

    /// A motion that is not a cycle ran: the next cycle takes a new
    /// initial level (LinuxCNC's `convert_motion` clears `cycle_il_flag`).
    pub(crate) fn other_motion(&mut self) {
        self.initial = None;
    }
}

/// Whether `code` (G code times 10) is a canned cycle this reader runs.
pub(crate) fn is_cycle(code: u16) -> bool {
    matches!(code, 730 | 740 | 810..=860 | 890)
}

fn name(code: u16) -> &'static str {
    match code {
        730 => "G73",
        740 => "G74",
        810 => "G81",
        820 => "G82",
        830 => "G83",
        840 => "G84",
        850 => "G85",
        860 => "G86",
        _ => "G89",
    }
}

/// One cycle line.
pub(crate) struct CycleLine<'a> {
    pub lx: &'a LexedLine,
    pub ln: usize,
    /// The cycle's G code times 10.
    pub code: u16,
    /// The motion mode before the line was this same cycle.
    pub same_mode: bool,
    /// Column errors about the whole line point at.
    pub column: usize,
}

/// The moves of one cycle line, as LinuxCNC makes them.
struct Emitter<'a> {
    ln: usize,
    st: &'a mut State,
    moves: &'a mut Vec<Move>,
    /// In-plane axes and the normal axis.
    axes: (usize, usize, usize),
    mm: f64,
    feed: Option<f64>,
}

impl Emitter<'_> {
    /// A move to (in-plane a, b, normal c) in program units.
    fn go(&mut self, rapid: bool, a: f64, b: f64, c: f64) {
        let start = self.st.pos;
        let mut end = start;
        set_axis(&mut end, self.axes.0, a * self.mm);
        set_axis(&mut end, self.axes.1, b * self.mm);
        set_axis(&mut end, self.axes.2, c * self.mm);
        self.push(rapid, start, end);
    }

    fn push(&mut self, rapid: bool, start: Vec3, end: Vec3) {
        self.moves.push(Move {
            piece: Piece {
                curve: Curve::Line(Line::new(start, end)),
                rapid,
                source_lines: (self.ln, self.ln),
                feed: if rapid { None } else { self.feed },
            },
            line: self.ln,
            kind: if rapid {
                MoveKind::Rapid
            } else {
                MoveKind::Linear
            },
            pinned: Some(PinReason::CannedCycle),
            end_text: [None, None, None],
        });
        self.st.pos = end;
    }
}

fn cycle_err(c: &CycleLine, column: usize, e: CycleError) -> GcodeError {
    err(c.ln, column, ErrorKind::Cycle(e))
}

/// Runs one cycle line: appends its moves and updates the position and the
/// cycle state.
pub(crate) fn run(c: &CycleLine, st: &mut State, moves: &mut Vec<Move>) -> Result<(), GcodeError> {
    let word = |l: char| c.lx.word(l);
    let missing = |letter: char| {
        cycle_err(
            c,
            c.column,
            CycleError::MissingWord {
                code: name(c.code),
                letter,
            },
        )
    };
    // ---- convert_cycle ----
    let feed = st.feed.as_ref().map_or(0.0, |f| f.mm_per_min);
    if feed == 0.0 {
        return Err(cycle_err(c, c.column, CycleError::ZeroFeed));
    }
    if st.feed_mode == FeedMode::InverseTime {
        return Err(cycle_err(c, c.column, CycleError::InverseTime));
    }
    if st.comp {
        return Err(cycle_err(c, c.column, CycleError::CutterComp));
    }
    if let Some(w) = c.lx.words.iter().find(|w| "ABCUVW".contains(w.letter)) {
        return Err(cycle_err(c, w.column, CycleError::AxisWord(w.letter)));
    }
    let r_number = match word('R') {
        Some(w) => finite(w.value, c.ln, w)?,
        None if c.same_mode => st.cycle.r,
        None => return Err(missing('R')),
    };
    let repeats = match word('L') {
        None => 1,
        Some(w) => {
            let n = w.value.round();
            if (w.value - n).abs() > NEAR_INT || n < 1.0 || n > u32::MAX as f64 {
                return Err(cycle_err(c, w.column, CycleError::BadRepeats(w.value)));
            }
            n as u32
        }
    };
    if let Some(w) = word('P').filter(|w| w.value < 0.0) {
        return Err(err(c.ln, w.column, ErrorKind::BadValue('P')));
    }
    // ---- convert_cycle_xy / _yz / _zx ----
    let (a1, a2, an) = st.plane.axes();
    let letters = AXIS_LETTERS;
    let given = |a: usize| -> Option<&Word> { word(letters[a]) };
    if matches!(c.code, 740 | 840) && st.plane != Plane::Xy {
        return Err(err(
            c.ln,
            c.column,
            ErrorKind::Unsupported("G74/G84 tapping outside the XY plane (G17)"),
        ));
    }
    if !c.same_mode && given(an).is_none() {
        return Err(missing(letters[an]));
    }
    let z_number = match given(an) {
        Some(w) => finite(w.value, c.ln, w)?,
        None => st.cycle.z,
    };
    let mm = st.units.mm_per_unit();
    let start = st.pos;
    let current = |a: usize| axis(start, a) / mm;
    let mut current_cc = current(an);
    let (mut old_cc, initial_known) = match st.cycle.initial {
        Some(il) => il,
        None => {
            let il = (current_cc, st.known[an]);
            st.cycle.initial = Some(il);
            il
        }
    };
    let value = |a: usize| -> Result<Option<f64>, GcodeError> {
        given(a).map(|w| finite(w.value, c.ln, w)).transpose()
    };
    let (mut aa, mut bb, inc_a, inc_b, r, cc, r_known);
    if st.incremental {
        inc_a = value(a1)?.unwrap_or(0.0);
        inc_b = value(a2)?.unwrap_or(0.0);
        r = r_number + old_cc;
        cc = r + z_number;
        aa = current(a1);
        bb = current(a2);
        r_known = initial_known;
    } else {
        inc_a = 0.0;
        inc_b = 0.0;
        r = r_number;
        cc = z_number;
        aa = value(a1)?.unwrap_or_else(|| current(a1));
        bb = value(a2)?.unwrap_or_else(|| current(a2));
        r_known = true;
    }
    if r < cc {
        return Err(cycle_err(
            c,
            c.column,
            CycleError::RBelowBottom { r, bottom: cc },
        ));
    }
    // The per-code words, checked before any move as LinuxCNC does.
    let p = match word('P') {
        Some(w) => w.value,
        None if matches!(c.code, 820 | 860 | 890) && !c.same_mode => return Err(missing('P')),
        None => st.cycle.p,
    };
    let q = match word('Q') {
        Some(w) => w.value,
        None if matches!(c.code, 730 | 830) && !c.same_mode => return Err(missing('Q')),
        None => st.cycle.q,
    };
    if matches!(c.code, 730 | 830) && q <= 0.0 {
        let col = word('Q').map_or(c.column, |w| w.column);
        return Err(cycle_err(c, col, CycleError::BadPeck(q)));
    }
    let spindle_ok = match c.code {
        840 => st.cycle.spindle == Spindle::Clockwise,
        740 => st.cycle.spindle == Spindle::CounterClockwise,
        860 => st.cycle.spindle != Spindle::Stopped,
        _ => true,
    };
    if !spindle_ok {
        let turning = match c.code {
            840 => "clockwise (M3)",
            740 => "counter-clockwise (M4)",
            _ => "(M3 or M4)",
        };
        return Err(cycle_err(
            c,
            c.column,
            CycleError::Spindle {
                code: name(c.code),
                turning,
            },
        ));
    }
    st.spline.moved_otherwise();
    let feed_mm = (st.feed_mode == FeedMode::PerMinute).then_some(feed);
    let retract_to_r = st.cycle.retract_to_r;
    let known_before = st.known;
    let peck_clearance = PECK_CLEARANCE_INCH * 25.4 / mm;
    let mut e = Emitter {
        ln: c.ln,
        st,
        moves,
        axes: (a1, a2, an),
        mm,
        feed: feed_mm,
    };
    let mut old_known = initial_known;
    // Below the R plane: straight up to it first.
    if old_cc < r {
        let (x, y) = (current(a1), current(a2));
        e.go(true, x, y, r);
        old_cc = r;
        current_cc = old_cc;
        old_known = r_known;
    }
    let clear_cc = if retract_to_r { r } else { old_cc };
    for repeat in (1..=repeats).rev() {
        aa += inc_a;
        bb += inc_b;
        if repeat == repeats && current_cc > r {
            e.go(true, aa, bb, current_cc);
            e.go(true, aa, bb, r);
        } else {
            e.go(true, aa, bb, clear_cc);
            if clear_cc > r {
                e.go(true, aa, bb, r);
            }
        }
        match c.code {
            // G81, G82 (dwell), G86 (dwell, spindle stop): down, rapid out.
            810 | 820 | 860 => {
                e.go(false, aa, bb, cc);
                e.go(true, aa, bb, clear_cc);
            }
            // G73 (chip break) and G83 (peck): down by Q at a time.
            730 | 830 => {
                let mut depth = r - q;
                while depth > cc {
                    e.go(false, aa, bb, depth);
                    if c.code == 830 {
                        e.go(true, aa, bb, r);
                    }
                    e.go(true, aa, bb, depth + peck_clearance);
                    depth -= q;
                }
                e.go(false, aa, bb, cc);
                e.go(true, aa, bb, clear_cc);
            }
            // G74/G84 (tapping: reverse the spindle, feed out) and G89
            // (dwell, feed out).
            740 | 840 | 890 => {
                e.go(false, aa, bb, cc);
                e.go(false, aa, bb, clear_cc);
            }
            // G85: feed in, feed out to R, rapid to the clearance.
            _ => {
                e.go(false, aa, bb, cc);
                e.go(false, aa, bb, r);
                e.go(true, aa, bb, clear_cc);
            }
        }
    }
    let st = e.st;
    st.cycle.r = r_number;
    st.cycle.z = z_number;
    if matches!(c.code, 820 | 860 | 890 | 740 | 840) {
        st.cycle.p = p;
    }
    if matches!(c.code, 730 | 830) {
        st.cycle.q = q;
    }
    // What is known of the position afterwards.
    if !st.incremental {
        for a in [a1, a2] {
            if given(a).is_some() {
                st.known[a] = true;
            }
        }
    } else {
        st.known[a1] = known_before[a1];
        st.known[a2] = known_before[a2];
    }
    st.known[an] = if retract_to_r { r_known } else { old_known };
    st.axis_text = [None, None, None];
    Ok(())
}
