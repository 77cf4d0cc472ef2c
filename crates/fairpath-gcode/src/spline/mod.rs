//! Spline codes: G5, G5.1, G5.2/G5.3 (LinuxCNC) and G6.2 (Fanuc NURBS
//! interpolation, also in LinuxCNC master), read with LinuxCNC's rules.
//!
//! Sources: LinuxCNC master 5c41560eb, `src/emc/rs274ngc/interp_convert.cc`
//! (`convert_spline`, `convert_nurbs`), `interp_check.cc` (which words each
//! code takes), `interp_internal.cc`, `src/emc/task/emccanon.cc`
//! (`NURBS_G5_FEED`, `NURBS_G6_FEED`); LinuxCNC 2.9 (Debian's 2.9.0~pre1 and
//! every 2.9.x: the same spline code as each other).
//!
//! ## The codes as LinuxCNC reads them
//! * **G5** `X Y I J P Q` (cubic; modal): control points: the current
//!   position, start + (I, J), end + (P, Q), the end. I and J both or
//!   neither; neither takes (-P, -Q) of the previous G5 (an error when the
//!   previous move was not a G5). P and Q are required.
//! * **G5.1** `X Y I J` (quadratic; modal): the current position,
//!   start + (I, J), the end. I and J are both required.
//! * **G5.2** `X Y P L` ... **G5.3**: a NURBS block. The current position is
//!   the first control point (its weight from `P` on a first line without
//!   X Y, else 1); every other line gives a point with both in-plane axes
//!   and a positive weight `P` (LinuxCNC reads a missing P on a first line
//!   with X Y as weight -1, and P <= 0 on a first line without X Y as 1:
//!   both are errors here); `L` (an integer, any line) sets the order
//!   when above 3 (the order is 3 otherwise). G5.3 (alone) runs it; at
//!   least `order` points are required. The knot vector is LinuxCNC's
//!   clamped uniform one ([`fairpath::controller::linuxcnc::g5_2_knots`]).
//!   Between G5.2 and G5.3 only control points (and comments, F, M codes)
//!   may come.
//! * **G6.2** `P K X Y Z R Q F` (NURBS, Fanuc syntax): the first line has
//!   the order `P` (2 to 8 here; Fanuc takes 2 to 4) and the first control
//!   point; every control-point line has both in-plane axes, a knot `K` and
//!   a weight `R > 0`; then `P` lines with a knot only close the knot
//!   vector (`number of knots = points + P`). The block ends, as LinuxCNC
//!   decides, on the line whose knot is the `P`th equal one in a row. The
//!   knot vector must be clamped (the first and last knot each `P` times).
//!   LinuxCNC master requires `Q1`..`Q3` on the first line (its execution
//!   method) and `G6.2` on knot-only lines, and integer knots; Fanuc knows
//!   no Q and writes knot-only lines as bare `K`: both forms are read, and
//!   real knots too. LinuxCNC's checks let `L` pass on G6.2 lines but it
//!   means nothing there: an error here, as are `P` on a later line with
//!   another order and a missing `R` (LinuxCNC would reuse the previous
//!   line's R).
//!
//! Planes: LinuxCNC master takes all codes in G17, G18 and G19 (the
//! control-point words are the plane's axes, in-plane pair `(Z, X)` in
//! G18); 2.9 takes G5/G5.1 only in G17 and reads G5.2's X and Y in every
//! plane, so programs for other planes are master programs. In G18 master
//! maps I to X and J to Z for the first control point of G5/G5.1 but P to
//! Z and Q to X for the second: replicated. The off-plane axis (which
//! LinuxCNC ignores on G5/G5.1/G5.2 lines) and A B C U V W are errors here;
//! on G6.2 lines the off-plane axis makes the curve 3D (Fanuc).
//!
//! Units and G91: coordinates are in the program's units; in G91 every
//! control point of a block is relative to the position *before the block*
//! (LinuxCNC's `find_ends` during the block), I J relative to the start and
//! P Q relative to the end in both modes. Weights and knots have no units.
//! The feed is the one in force when the block runs (its last line).
//!
//! ## What LinuxCNC runs
//! G5, G5.1 and G5.2 become `NURBS_G5_FEED`: biarcs, 4 samples per control
//! point ([`fairpath::controller::linuxcnc`] replicates its arithmetic bit
//! for bit). G6.2 becomes `NURBS_G6_FEED` in master: in the plane only (it
//! ignores the off-plane axis), by the method Q (1: biarcs at constant
//! parameter steps, 15 per point; 2: biarcs at arc-length steps; 3:
//! straight feeds every `feed * 0.1 s / 60` mm, a step that grows with the
//! feed), split in pieces when it has more than `3 P` points. Its
//! interpreter then takes as its position the in-plane coordinates of the
//! block's last line, stored as X and Y whatever the plane: a knot-only
//! line, so the position before the block (in G17; garbled in G18/G19). A
//! following move that omits an axis or is incremental starts from there
//! in LinuxCNC, a bug that fairpath does not replicate (it continues from
//! the curve's end, as the machine is; the G6.2 writer adds a `G1` to the
//! end point for LinuxCNC). Fanuc controls interpolate the exact NURBS.
//!
//! ## How fairpath reads them
//! G6.2 is always the exact NURBS it describes (one [`Curve::Nurbs`] piece,
//! preceded by a straight line when its first control point is not the
//! current position, as LinuxCNC moves there first). G5, G5.1 and G5.2 are
//! read by default as LinuxCNC runs them ([`SplineReading::AsLinuxcnc`]:
//! its arcs and straight feeds), or as the exact cubic Bezier, quadratic
//! Bezier and NURBS ([`SplineReading::Exact`]). All pieces of a block are
//! moves of kind [`MoveKind::Spline`] on the block's last line, with
//! `source_lines` (first line, last line); the other lines of a multi-line
//! block are marked [`crate::ProgramLine::in_block`]. A block is pinned as a
//! move line is (`/`, extra words such as M8, a state change, cutter
//! compensation (an error for G5/G5.1, as in LinuxCNC), G93/G95, an unknown
//! start) when any of its lines gives a reason.
//!
//! ## Files
//! * This file: the reading options, the spline state with its open block,
//!   and a line dispatched to its code's reader.
//! * `curves.rs`: the curves of a G5, G5.1 or G5.2 block as LinuxCNC
//!   runs them (its end snapped) or exactly, and the moves a block's
//!   curves become.
//! * `g5.rs`: G5 and G5.1, one line and one curve each.
//! * `g5_2.rs`: G5.2 ... G5.3 blocks, their control points read and the
//!   block run at G5.3.
//! * `g6_2.rs`: G6.2 blocks, their control points and knots read and the
//!   block run when its knot vector is complete.
//! * `words.rs`: the words of a line (which letters a code takes,
//!   coordinates, weights, integer words, the in-plane pair) and the pin
//!   reasons a line or its state gives a block.
//!
//! [`Curve::Nurbs`]: fairpath::geom::Curve::Nurbs
//! [`MoveKind::Spline`]: crate::MoveKind::Spline

mod curves;
mod g5;
mod g5_2;
mod g6_2;
mod words;

use crate::error::{ErrorKind, GcodeError, SplineError};
use crate::interp::{err, State};
use crate::lexer::{LexedLine, Word};
use crate::program::{MotionMode, Move, PinReason};
use fairpath::geom::{Nurbs, Vec3};
use g5::g5;
use g5_2::{close_g5_2, g5_2_point};
use g6_2::g6_2_line;

/// How G5, G5.1 and G5.2/G5.3 are read (G6.2 is always read exactly).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SplineReading {
    /// The arcs and straight feeds LinuxCNC's canon layer makes of them.
    #[default]
    AsLinuxcnc,
    /// The curves they describe: G5 a cubic Bezier, G5.1 a quadratic
    /// Bezier, G5.2 the NURBS with LinuxCNC's knot vector (order up to 8).
    Exact,
}

/// How the reader reads what admits more than one reading
/// ([`crate::parse_with`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ParseOptions {
    /// G5, G5.1 and G5.2/G5.3 as LinuxCNC runs them (the default) or as
    /// the exact curves they describe.
    pub splines: SplineReading,
    /// The block-delete switch: `true` skips the lines that start with `/`,
    /// as LinuxCNC does with block delete on; `false` (the default) runs
    /// them, and pins the moves whose meaning would change with the switch
    /// on (see [`crate::PinReason::AfterBlockDelete`]).
    pub block_delete: bool,
}

/// Highest G6.2 order (and exact G5.2 order): degree [`Nurbs::MAX_DEGREE`].
const MAX_ORDER: usize = Nurbs::MAX_DEGREE + 1;

/// Spline reading state: the open multi-line block, and the tangent a G5
/// without I J continues.
#[derive(Clone)]
pub(crate) struct SplineState {
    reading: SplineReading,
    open: Option<Block>,
    /// (-P, -Q) of the previous move when it was a G5 (program units).
    g5_tangent: Option<[f64; 2]>,
}

/// An open G5.2 or G6.2 block.
#[derive(Clone)]
struct Block {
    g6: bool,
    first_line: usize,
    column: usize,
    start: Vec3,
    start_known: bool,
    order: usize,
    pin: Option<PinReason>,
    /// G5.2: control points in the plane, program units (the start first).
    prog: Vec<[f64; 2]>,
    /// Control points in mm (G5.2: the start first).
    pts: Vec<Vec3>,
    weights: Vec<f64>,
    /// G6.2: the knot of every line (control point or knot-only).
    knots: Vec<f64>,
    /// G6.2: number of knot-only lines so far.
    knot_only: usize,
    /// Axis words (text) of the last control point.
    last_words: [Option<String>; 3],
}

impl SplineState {
    pub(crate) fn new(reading: SplineReading) -> SplineState {
        SplineState {
            reading,
            open: None,
            g5_tangent: None,
        }
    }

    /// A multi-line block is open (the line just read is inside it).
    pub(crate) fn is_open(&self) -> bool {
        self.open.is_some()
    }

    /// A move other than a G5 happened: the next G5 needs I and J.
    pub(crate) fn moved_otherwise(&mut self) {
        self.g5_tangent = None;
    }

    /// The error for a block still open at the end of the program.
    pub(crate) fn check_closed(&self) -> Result<(), GcodeError> {
        match &self.open {
            None => Ok(()),
            Some(b) => Err(spline_err(
                b.first_line,
                b.column,
                SplineError::NotClosed(if b.g6 { "G6.2" } else { "G5.2" }),
            )),
        }
    }
}

pub(crate) fn is_spline(m: MotionMode) -> bool {
    matches!(
        m,
        MotionMode::CubicSpline | MotionMode::QuadSpline | MotionMode::Nurbs | MotionMode::NurbsG6
    )
}

/// Whether the spline reader takes the line: a block is open, or the line
/// has a spline G word or G5.3, or axis words in modal G5/G5.1.
pub(crate) fn claims(st: &State, code: Option<MotionMode>, end: bool, axes: bool) -> bool {
    st.spline.open.is_some()
        || code.is_some_and(is_spline)
        || end
        || (code.is_none()
            && axes
            && matches!(st.motion, MotionMode::CubicSpline | MotionMode::QuadSpline))
}

/// What the interpreter knows of a spline line.
pub(crate) struct LineCtx<'a> {
    pub lx: &'a LexedLine,
    pub ln: usize,
    /// The line's spline G word (group 1).
    pub code: Option<(MotionMode, &'a Word)>,
    /// The line's G5.3.
    pub end: Option<&'a Word>,
    /// The first G word that is neither a spline code nor G5.3.
    pub other_g: Option<&'a Word>,
    /// The line changes modal state (or the plane).
    pub state_change: bool,
}

fn spline_err(line: usize, column: usize, e: SplineError) -> GcodeError {
    err(line, column, ErrorKind::Spline(e))
}

/// Reads one spline line; returns whether it made pinned moves.
pub(crate) fn line(
    ctx: &LineCtx,
    st: &mut State,
    moves: &mut Vec<Move>,
) -> Result<bool, GcodeError> {
    let ln = ctx.ln;
    if let Some(open) = &st.spline.open {
        if let Some(w) = ctx.other_g {
            return Err(spline_err(
                ln,
                w.column,
                SplineError::InBlock("no other G code before the block is closed"),
            ));
        }
        let own = if open.g6 {
            MotionMode::NurbsG6
        } else {
            MotionMode::Nurbs
        };
        if let Some((m, w)) = ctx.code {
            if m != own {
                return Err(spline_err(
                    ln,
                    w.column,
                    SplineError::InBlock("another motion code before the block is closed"),
                ));
            }
        }
    }
    if let Some(w) = ctx.end {
        if let Some(o) = ctx.other_g.or(ctx.code.map(|c| c.1)) {
            return Err(spline_err(
                ln,
                o.column,
                SplineError::InBlock("G5.3 must be the only G code on its line"),
            ));
        }
        return close_g5_2(ctx, w, st, moves);
    }
    let mode = ctx.code.map_or(st.motion, |c| c.0);
    match mode {
        MotionMode::CubicSpline => g5(ctx, st, moves, false),
        MotionMode::QuadSpline => g5(ctx, st, moves, true),
        MotionMode::Nurbs => g5_2_point(ctx, st).map(|_| false),
        _ => g6_2_line(ctx, st, moves),
    }
}

fn new_block(st: &State, g6: bool, ln: usize, column: usize, order: usize) -> Block {
    Block {
        g6,
        first_line: ln,
        column,
        start: st.pos,
        start_known: st.known.iter().all(|&k| k),
        order,
        pin: None,
        prog: Vec::new(),
        pts: Vec::new(),
        weights: Vec::new(),
        knots: Vec::new(),
        knot_only: 0,
        last_words: [None, None, None],
    }
}
