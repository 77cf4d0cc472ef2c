//! The modal interpreter: turns lexed lines into moves (pieces in mm), tracks
//! the modal state, decides which moves are pinned and which lines end runs,
//! and groups the runs. Spline lines (G5, G5.1, G5.2 ... G5.3, G6.2) go to
//! [`crate::spline`] once the line's state changes are applied.
//!
//! * `reader.rs`: the reader of a program, in place or expanded, line by
//!   line ([`parse`], [`parse_with`]; for motion only, [`parse_motion`]).
//! * `state.rs`: the modal state.
//! * `codes.rs`: G and M codes classified by modal group.
//! * `line.rs`: one line interpreted: what its words ask for, then a
//!   short dispatch over the files below, `crate::spline` and
//!   `crate::cycles`.
//! * `modal.rs`: the line's state changes in LinuxCNC's order (M codes,
//!   feed mode, F, plane, units, distance modes, ..., motion mode).
//! * `nonmodal.rs`: the group-0 codes that use axis words (G92, G52, G10,
//!   G28/G30).
//! * `motion.rs`: a move in the modal motion mode (G0/G1, G2/G3, G53 and
//!   the pinned special motions): its end, pin reason and feed.
//! * `arc.rs`: G2/G3 arcs (centre and radius forms, helices, turns).
//! * `runs.rs`: the moves grouped into runs of feed moves.
//!
//! This file: the helpers the interpreter shares with the canned cycles
//! (`cycles.rs`) and the spline reader ([`crate::spline`]).

// Axis loops index several parallel arrays by axis number.
#![allow(clippy::needless_range_loop)]

mod arc;
mod codes;
mod facts;
mod line;
mod modal;
mod motion;
mod motion_sink;
mod nonmodal;
mod parts;
mod reader;
mod runs;
mod state;
mod window_cut;

pub use arc::{ARC_RADIUS_TOLERANCE_INCH, ARC_RADIUS_TOLERANCE_MM, COINCIDENT_MM};
pub use facts::read_facts;
pub use motion_sink::{MotionReader, PartRead, ReadBackError, RunStream, READ_BACK_BYTES};
pub use parts::PartReader;
pub use reader::{parse, parse_motion, parse_with, read_motion};
pub(crate) use state::{FeedMode, State};
pub use window_cut::RunWindows;

use crate::error::{ErrorKind, GcodeError};
use crate::lexer::Word;

pub(crate) fn err(line: usize, column: usize, kind: ErrorKind) -> GcodeError {
    GcodeError::new(line, column, kind)
}

pub(crate) fn finite(v: f64, ln: usize, w: &Word) -> Result<f64, GcodeError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(ln, w.column, ErrorKind::NumberOutOfRange(w.letter)))
    }
}
