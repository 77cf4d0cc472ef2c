//! # fairpath-gcode
//!
//! G-code reader (lexer with spans, modal interpreter) and writers (G-code,
//! JSON) for fairpath. Everything inside is mm and f64.
//!
//! ```text
//! parse(&[u8]) -> Program --runs()--> Vec<Run> --smoother--> Vec<Vec<Piece>>
//!     --> write_gcode(&Program, &smoothed, &GcodeWriteOptions) -> String
//!     --> write_json(&Program, &smoothed) -> String;  read_json(&str) -> Vec<Piece>
//! ```
//! A smoothed G-code file is read back with [`parse`] (it is plain G-code).
//! [`parse_with`] takes [`ParseOptions`] (how splines are read);
//! [`write_spline`] formats NURBS pieces as G6.2 or G5.2/G5.3 blocks.
//!
//! ## What is read
//! Programs as LinuxCNC, Fanuc, Mach3, grbl and CAM post-processors write
//! them (see [`lexer`] for the syntax; UTF-8, LF, CR LF or CR line
//! endings, an optional byte-order mark). G0/G1/G2/G3 (IJK and R forms, negative
//! R = the long arc, G17/G18/G19, helical moves, full circles, P turns),
//! G20/G21, G90/G91, G90.1/G91.1 (default incremental IJK), F (program units
//! per minute, stored as mm/min), axis words without a G word (the modal
//! motion mode). LinuxCNC's execution order within a line applies: F is read
//! before a G20/G21 on the same line (`G21 F100` in an inch program is
//! 100 in/min), the units change before the move.
//!
//! Splines ([`spline`] has the details and LinuxCNC's rules): G5 (cubic),
//! G5.1 (quadratic) and G5.2 ... G5.3 (NURBS blocks) are read by default as
//! LinuxCNC runs them (the biarcs and straight feeds of its canon layer,
//! [`fairpath::controller::linuxcnc`]), or as the exact curves with
//! [`SplineReading::Exact`]; G6.2 (Fanuc NURBS: P order, K knots, R
//! weights; also LinuxCNC master) is read as the exact NURBS. Their moves
//! are [`MoveKind::Spline`] on the block's last line; the other lines of a
//! multi-line block are marked [`ProgramLine::in_block`]. Spline moves take
//! part in runs like arcs; a block is pinned when any of its lines would
//! pin a move.
//!
//! * The position before any move is (0,0,0) in program coordinates.
//! * Work offsets are not known: coordinates are program coordinates. After
//!   a change of coordinate system (G54..G59.3), G10, G92.1/G92.2/G92.3,
//!   G28/G30 (home), tool-length changes (G43/G49: Z), G52 (the axes given),
//!   G53 and probe moves (the axes moved), the affected axes are *unknown*;
//!   a move that starts with any unknown axis is pinned (its piece starts at
//!   the last tracked value). G92 sets the position of the axes it names.
//! * The motion mode at program start is none (as LinuxCNC): axis words
//!   before any G0/G1/G2/G3 are an error. `G80` beside another motion code on
//!   the same line (`G0 G80`, common in headers) is ignored.
//! * IJK arcs whose end radius differs from the start radius by more than
//!   [`interp::ARC_RADIUS_TOLERANCE_MM`] (mm programs) or
//!   [`interp::ARC_RADIUS_TOLERANCE_INCH`] (inch programs) are errors;
//!   smaller differences make spiral arcs, as LinuxCNC runs them. An R arc
//!   whose radius is shorter than half the chord by more than the same
//!   tolerance is an error. `P` must be a positive integer. A centre word of
//!   the axis normal to the plane (K in G17, ...) must be 0 if present.
//! * Lines after `M2`/`M30` or after a closing `%` are passed through
//!   unread.
//! * Canned cycles G73, G74, G81 .. G86, G89 (G98/G99, modal repeats, `L`
//!   repeats, G17/G18/G19; G74/G84 in G17 only) make the moves LinuxCNC
//!   2.9 makes of them (see the `cycles` module's source), all pinned
//!   ([`PinReason::CannedCycle`]): the position after a cycle is known.
//! * A line with the 3D-printer extruder word `E` is passed through
//!   verbatim ([`PinReason::ForeignWords`]). Canned-cycle and `E` lines are
//!   listed by [`Program::passthrough`].
//! * Block delete: with [`ParseOptions::block_delete`] set, `/` lines are
//!   skipped (the switch on); by default they run, and the moves that
//!   would mean something else with the switch on are pinned
//!   ([`PinReason::AfterBlockDelete`]; the rules are in the
//!   `block_delete` module's source).
//!
//! ## LinuxCNC's language ([`lang`])
//! Parameters (`#1`, `#<name>`, `#<_global>`, `##1`, `#[expr]`),
//! assignments (`#1 = value`, applied after the line's values are read, as
//! LinuxCNC does), expressions in brackets with LinuxCNC's operators,
//! precedence and functions (degrees), polar words `@` and `^` (XY plane),
//! and o-word control flow (`sub`/`endsub`/`call`/`return`, `while`, `do`,
//! `repeat`, `if`/`elseif`/`else`, `break`, `continue`), numbered and
//! named, case-insensitive, blanks ignored anywhere outside comments.
//! System parameters the reader knows: the position (`#5420`..`#5422`,
//! `#<_x>`..`#<_z>`, program units) and modal state (`#<_metric>`,
//! `#<_absolute>`, `#<_feed>`, `#<_motion_mode>`, `#<_plane>`, `#<_value>`,
//! `#<_call_level>`, ...); those of the machine (work offsets, tool table,
//! probe results, `#<_current_tool>`, ...) are unsupported-feature errors.
//! Comments are kept verbatim (`(debug, ...)` included).
//!
//! * A program without o-words is read **in place**: one [`ProgramLine`]
//!   per source line, its text kept, its [`ProgramLine::words`] holding the
//!   evaluated values (a computed word's text is its value's round-trip
//!   literal). A line that assigns a parameter ends runs (it is written
//!   back verbatim, in place).
//! * A program with o-words is **expanded** ([`Program::expansion`]): its
//!   lines are the lines executed, in execution order, each with its
//!   computed values written as literals and its assignments removed
//!   (a line left empty by that is dropped); o-word lines and subroutines
//!   not called do not appear; [`ProgramLine::source_line`] names the
//!   source line, and errors always name source lines and columns.
//!   [`write_gcode()`] writes such a program with
//!   [`write_gcode::EXPANDED_HEADER`] as its first line (after a leading
//!   `%`). Calls of subroutines not defined in the program (LinuxCNC's
//!   subroutine files) are unsupported-feature errors; recursion deeper than
//!   [`lang::flow::MAX_CALL_LEVEL`] and more than
//!   [`lang::flow::MAX_EXECUTED_LINES`] executed lines are errors.
//!
//! ## Runs, pinned moves
//! A *run* ([`Program::runs`]) is a maximal sequence of consecutive
//! non-pinned feed moves (G1, G2, G3) at one feed with no run-breaking line
//! between them: a move whose feed differs from the one before starts a new
//! run, so each programmed feed keeps its stretch of path.
//! A line *breaks runs* when it holds a rapid or a pinned move, or changes
//! state: any M code, S, T, H, D, L, Q, E words, G4 dwell, G10, G28/G30, G52,
//! G53, G92/G92.x, a change of coordinate system, tool length offset
//! (G43*/G49 when active), cutter compensation (G41/G42, G40 when active),
//! feed mode (G93/G94/G95), path control (G61/G61.1/G64, or G64 with P/Q),
//! units, distance mode, arc distance mode, plane, spindle mode, G15/G69,
//! a motion G word alone that changes the mode, and block-delete (`/`)
//! lines. Lines holding only comments, blank, `%`, N, F, an O program
//! number, or modal words restating the current state do not break runs.
//!
//! A move is *pinned* (written back verbatim, never smoothed) when its line
//! starts with `/`, carries words other than N, F, X, Y, Z, G (and I, J, K,
//! R, P for arcs; the spline words for splines) such as M8 or S1000,
//! changes state, has A/B/C/U/V/W words,
//! runs with cutter compensation active or in G93/G95 feed mode, starts at
//! an unknown position, is G33/G33.1/G38.x/G31 or G53 motion, is part of
//! a canned cycle, has an `E` word, or depends on an earlier `/` line.
//!
//! Each run's pieces join exactly as f64 values (arcs keep their programmed
//! start and end points exactly). Zero-length moves are kept.
//!
//! ## Errors
//! Every reader error is a [`GcodeError`] with 1-based line and column
//! (`Display`: `line:column: message`); [`GcodeError::is_unsupported`] tells
//! unsupported features from malformed input. Unsupported: the machine's
//! parameters and subroutine files (above), Fanuc `M98`/`M99`
//! subprograms (a Fanuc `O1234` program number alone on a line is passed
//! through), LinuxCNC master's G6/G6.1 (aliases of G5/G5.1) and G6.3, the
//! canned cycles G76 (threading), G87 and G88, G7 diameter mode, G16 polar
//! coordinates, G51 scaling, G68 rotation, G70/G71/G72, G17.1/G18.1/G19.1.
//! Canned cycles LinuxCNC refuses (no R or Z on the first cycle, R below
//! the bottom, no feed, G84 without M3, ...) are [`CycleError`]s. Word
//! values beyond [`lexer::MAX_WORD_MAGNITUDE`] are errors. Unknown G codes
//! are errors; unknown M codes are
//! passed through (they break runs). An empty program is an empty
//! [`Program`] (no moves, no runs), not an error.

mod axes;
mod block_delete;
mod cycles;
pub mod emit;
pub mod entry;
pub mod error;
pub mod facts;
pub mod format;
pub mod interp;
pub mod lang;
pub mod lexer;
mod motions;
pub mod pipeline;
pub mod program;
pub mod short_text;
pub mod spline;
pub mod text_out;
pub mod write_gcode;
pub mod write_json;
pub mod write_spline;

pub use entry::{
    smooth_and_plan, smooth_in_parts, smooth_parsed, smooth_parsed_with, smooth_program,
    write_curves, Curves, Evidence, Output, PartSizes, PartsError, Prepared, Report,
    SmoothProgramError, PART_LINES, WINDOWS_UNSTITCHED,
};
pub use error::{CycleError, ErrorKind, GcodeError, JsonError, SplineError, WriteError};
pub use facts::ProgramFacts;
pub use format::{Controller, Format};
pub use interp::{parse, parse_motion, parse_with, read_motion, RunWindows};
pub use motions::{json_motions, outline_motions};
pub use pipeline::{OptionsError, SmoothOptions};
pub use program::{
    Expansion, Feed, MotionMode, Move, MoveKind, Passthrough, PinReason, Program, ProgramLine,
    RunSpan, Units,
};
pub use spline::{ParseOptions, SplineReading};
pub use write_gcode::{
    output_decimals, write_decimals, write_gcode, write_gcode_with, ArcWords, GcodeWriteOptions,
    NurbsBlocks, RenderedParts, RunOutput, ARC_ROUNDING_FACTOR, FINE_PERIODS, ROUNDING_SHARE,
};
pub use write_json::{read_json, write_json, ARC_APPROX_MM};
pub use write_spline::{g5_2_blocks, g6_2_block, G6Dialect, SplineWriteOptions};
