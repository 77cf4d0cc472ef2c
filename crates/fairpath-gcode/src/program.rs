//! The result of reading a program: its original lines, every move as a
//! [`Piece`] in mm, and the runs of smoothable feed moves.

use crate::lexer::Word;
use fairpath::path::{Piece, Run};
use std::ops::{Range, RangeInclusive};
use std::sync::Arc;

/// Length units of the program (G20 inch, G21 mm).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    Mm,
    Inch,
}

impl Units {
    /// Millimetres per program unit.
    pub fn mm_per_unit(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }
}

/// Modal motion mode (G-code modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    /// No motion mode: program start (as LinuxCNC) or after G80. Axis words
    /// without a motion G word are then an error.
    None,
    /// G0
    Rapid,
    /// G1
    Linear,
    /// G2
    ArcCw,
    /// G3
    ArcCcw,
    /// G33 spindle-synchronised motion.
    Thread,
    /// G33.1 rigid tapping.
    RigidTap,
    /// G38.2 .. G38.5 probing, or G31 (Mach3, Fanuc): the code times 10.
    Probe(u16),
    /// G5: cubic spline (LinuxCNC), modal.
    CubicSpline,
    /// G5.1: quadratic spline (LinuxCNC), modal.
    QuadSpline,
    /// G5.2: inside a LinuxCNC NURBS block (until G5.3).
    Nurbs,
    /// G6.2: inside a NURBS block (Fanuc, LinuxCNC master), until its
    /// knot vector is complete.
    NurbsG6,
    /// A canned cycle (G73, G74, G81 .. G86, G89): the code times 10.
    /// Axis words on later lines repeat it at the new position.
    Cycle(u16),
}

impl MotionMode {
    /// The G word selecting this mode (`None` for [`MotionMode::None`]).
    pub fn gword(self) -> Option<String> {
        Some(match self {
            MotionMode::None => return None,
            MotionMode::Rapid => "G0".into(),
            MotionMode::Linear => "G1".into(),
            MotionMode::ArcCw => "G2".into(),
            MotionMode::ArcCcw => "G3".into(),
            MotionMode::Thread => "G33".into(),
            MotionMode::RigidTap => "G33.1".into(),
            MotionMode::Probe(310) => "G31".into(),
            MotionMode::CubicSpline => "G5".into(),
            MotionMode::QuadSpline => "G5.1".into(),
            MotionMode::Nurbs => "G5.2".into(),
            MotionMode::NurbsG6 => "G6.2".into(),
            MotionMode::Probe(c) => format!("G{}.{}", c / 10, c % 10),
            MotionMode::Cycle(c) => format!("G{}", c / 10),
        })
    }
}

/// Why a move is pinned: written back verbatim, never smoothed, and ends the
/// run before it and starts a new one after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinReason {
    /// The line starts with the block-delete `/`.
    BlockDelete,
    /// The move's start (absolute mode), its feed, its motion mode or the
    /// modal state it runs in depends on whether an earlier `/` line ran
    /// (see [`crate::ParseOptions::block_delete`]): written verbatim so that
    /// the program runs as written with the switch on or off.
    AfterBlockDelete,
    /// One of the moves a canned cycle (G73, G74, G81 .. G86, G89) makes.
    CannedCycle,
    /// The line has words fairpath does not interpret (another dialect's,
    /// such as the 3D-printer extruder word `E`): passed through verbatim.
    ForeignWords,
    /// The line carries non-motion words (M, S, T, H, D, P on G1, ...).
    ExtraWords,
    /// The line changes modal state (units, distance mode, offsets, ...).
    StateChange,
    /// Cutter radius compensation (G41/G42) is active.
    CutterComp,
    /// Inverse-time (G93) or per-revolution (G95) feed mode.
    FeedMode,
    /// The move has rotary or secondary linear axis words (A B C U V W).
    ExtraAxes,
    /// The start position is unknown (after G28/G30, offset or tool-length
    /// changes, probing, machine-coordinate moves).
    UnknownStart,
    /// G33, G33.1, G38.x or G53: special motion.
    SpecialMotion,
}

/// The modal feed rate: mm/min and the F word's text as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Feed {
    pub mm_per_min: f64,
    /// Shared: every line's [`ProgramLine::feed_after`] holds the modal
    /// feed, and a copy of its text per line would cost more than a
    /// comment line's own text.
    pub text: Arc<str>,
    /// Units in force when the F word was written.
    pub units: Units,
}

/// One line of the input, with its interpretation.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramLine {
    /// 1-based line number in the program as read (in an expanded program,
    /// the position among the executed lines).
    pub number: usize,
    /// 1-based line number in the source file: equal to `number` for a
    /// program read in place; for an expanded program, the source line this
    /// executed line comes from.
    pub source_line: usize,
    /// The exact text, without the line ending. In an expanded program,
    /// the source line with every computed value written as a literal and
    /// its parameter assignments removed.
    pub text: String,
    /// `"\n"`, `"\r\n"` or `""` (last line without newline).
    pub ending: &'static str,
    /// Units in force after this line.
    pub units: Units,
    /// Incremental distance mode (G91) in force after this line.
    pub incremental: bool,
    /// The words of the line (empty for lines after the program end).
    pub words: Vec<Word>,
    /// The line ends the current run (it affects motion, or holds a rapid or
    /// pinned move).
    pub breaks_run: bool,
    /// Indices of this line's moves in [`Program::moves`].
    pub moves: Range<usize>,
    /// False for lines after the program end (M2/M30 or a closing `%`),
    /// which are passed through unread.
    pub interpreted: bool,
    /// Modal motion mode before this line.
    pub motion_before: MotionMode,
    /// Modal motion mode after this line (the next line's
    /// [`ProgramLine::motion_before`]).
    pub motion_after: MotionMode,
    /// The line has an explicit motion G word (group 1).
    pub sets_motion: bool,
    /// The line has axis words that move in the modal motion mode (no G word
    /// of group 1 and no G10/G28/G30/G52/G92 on the line).
    pub uses_modal_motion: bool,
    /// Modal feed after this line.
    pub feed_after: Option<Feed>,
    /// Column (1-based) before which a motion word can be inserted: the
    /// first word that is not N, or the end of the words.
    pub insert_column: usize,
    /// Arc plane (G17/G18/G19) in force after this line.
    pub plane_after: fairpath::geom::Plane,
    /// Incremental arc centres (G91.1, the default) in force after this
    /// line; false after G90.1.
    pub arc_incremental_after: bool,
    /// The path-control command in force after this line as the program
    /// wrote it (`G64 P0.01 Q0`, `G61`), or `None` if it never set one.
    pub path_control_after: Option<String>,
    /// The line belongs to a multi-line spline block (G5.2 ... G5.3, or a
    /// G6.2 block) and is not its last line: it carries part of a move that
    /// executes on the block's last line (which holds the block's moves).
    /// Comment and blank lines inside the block count too. A writer that
    /// replaces a run must not emit these lines as if they held no motion.
    pub in_block: bool,
}

/// What kind of move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKind {
    Rapid,
    Linear,
    Arc,
    /// One piece of a spline block (G5, G5.1, G5.2/G5.3, G6.2): a NURBS
    /// (exact reading), or one of the arcs and lines LinuxCNC runs for it.
    /// All pieces of a block belong to its last line and have
    /// `source_lines` = (first line of the block, last line).
    Spline,
}

/// One move of the program.
#[derive(Clone, Debug, PartialEq)]
pub struct Move {
    pub piece: Piece,
    /// 1-based line number.
    pub line: usize,
    pub kind: MoveKind,
    /// Why the move may not be smoothed (rapids are never smoothed either).
    pub pinned: Option<PinReason>,
    /// Text of the absolute coordinate of each axis at the end of the move as
    /// last written in the program (in the line's units), when known: lets
    /// writers reproduce run endpoints exactly.
    pub end_text: [Option<crate::short_text::ShortText>; 3],
}

/// Where a run sits in the program.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpan {
    /// Indices of the run's moves in [`Program::moves`].
    pub moves: Range<usize>,
    /// First and last line (1-based) holding the run's moves.
    pub first_line: usize,
    pub last_line: usize,
    pub units: Units,
    pub incremental: bool,
    /// Modal feed before the run's first line and after its last line.
    pub feed_before: Option<Feed>,
    pub feed_after: Option<Feed>,
}

/// Lines passed through verbatim because fairpath does not smooth what
/// they do (canned cycles, another dialect's words): callers warn about
/// them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Passthrough {
    /// First and last line (1-based). Lines in between that hold no move
    /// (comments, blank lines, modal words) count as part of the range.
    pub lines: RangeInclusive<usize>,
    /// What they hold, e.g. "canned cycle".
    pub what: &'static str,
}

/// A read program.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    pub(crate) lines: Vec<ProgramLine>,
    pub(crate) moves: Vec<Move>,
    pub(crate) runs: Vec<RunSpan>,
    pub(crate) start_units: Units,
    pub(crate) expansion: Option<Expansion>,
    pub(crate) passthrough: Vec<Passthrough>,
    /// [`ProgramLine::number`] of the first line: 1 for a whole program,
    /// more for a part of one read by [`crate::interp::PartReader`] (its
    /// lines keep their numbers in the whole program).
    pub(crate) first_number: usize,
    /// For a part of a program: the arc plane and arc distance mode in
    /// force before its first line (what a run starting there is written
    /// in); `None` for a whole program.
    pub(crate) before: Option<(fairpath::geom::Plane, bool)>,
    /// For a part of a program: its last line is not the program's but
    /// the one [`crate::interp::PartReader`] put in to cut a long run at
    /// the middle of the line after it ([`crate::interp::RunWindows`]).
    pub(crate) window_cut: bool,
    /// For a part of a program: its first run goes on from the part
    /// before, which ended in a window's cut.
    pub(crate) window_continued: bool,
}

/// How an expanded program (one with LinuxCNC o-word control flow) was
/// read: its lines are the executed lines in execution order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Expansion {
    /// Source lines executed, o-word lines included (a line run twice
    /// counts twice).
    pub executed_lines: usize,
    /// Lines in the source file.
    pub source_lines: usize,
}

impl Program {
    /// Every move in order (rapids included) as pieces in mm.
    pub fn pieces(&self) -> Vec<Piece> {
        self.moves.iter().map(|m| m.piece.clone()).collect()
    }

    /// The feed runs: maximal sequences of consecutive non-pinned feed moves
    /// not separated by a run-breaking line or a rapid. Each run's pieces are
    /// exactly continuous.
    pub fn runs(&self) -> Vec<Run> {
        self.runs
            .iter()
            .map(|r| {
                Run::new(
                    self.moves[r.moves.clone()]
                        .iter()
                        .map(|m| m.piece.clone())
                        .collect(),
                )
            })
            .collect()
    }

    /// Where each run of [`Program::runs`] sits (same order).
    pub fn run_spans(&self) -> &[RunSpan] {
        &self.runs
    }

    /// The program's units: those in force at its first move (the default
    /// mm, changed by a G20 before the first move), or at its end when it has
    /// no move. Internally everything is mm; writers use each line's units.
    pub fn units(&self) -> Units {
        self.start_units
    }

    /// The lines of the program with their interpretation.
    pub fn lines(&self) -> &[ProgramLine] {
        &self.lines
    }

    /// The line numbered `number` ([`ProgramLine::number`]). Panics when the
    /// program (or this part of one) has no such line.
    pub fn line(&self, number: usize) -> &ProgramLine {
        &self.lines[number - self.first_number]
    }

    /// The lines numbered `first` to `last`, both included.
    pub fn lines_between(&self, first: usize, last: usize) -> &[ProgramLine] {
        &self.lines[first - self.first_number..=last - self.first_number]
    }

    /// Lines of the program's text this program (or part) holds: its
    /// lines, less the one a window's cut put in ([`Program::window_cut`]).
    pub fn source_lines(&self) -> usize {
        self.lines.len() - usize::from(self.window_cut)
    }

    /// Whether the last line was put in to cut a long run into windows
    /// (see [`crate::interp::RunWindows`]): the run that ends there goes
    /// on in the next part.
    pub fn window_cut(&self) -> bool {
        self.window_cut
    }

    /// Whether the first run goes on from the part before, which ended in
    /// a window's cut ([`Program::window_cut`]).
    pub fn window_continued(&self) -> bool {
        self.window_continued
    }

    /// [`ProgramLine::number`] of the first line: 1, but for a part of a
    /// program ([`crate::interp::PartReader`]).
    pub fn first_number(&self) -> usize {
        self.first_number
    }

    /// The arc plane and arc distance mode (incremental centres) in force
    /// before line `number`: after the line before it, or as a part of a
    /// program starts, or the program's defaults (XY, incremental).
    pub(crate) fn arc_modes_before(&self, number: usize) -> (fairpath::geom::Plane, bool) {
        if number > self.first_number {
            let l = self.line(number - 1);
            (l.plane_after, l.arc_incremental_after)
        } else {
            self.before.unwrap_or((fairpath::geom::Plane::Xy, true))
        }
    }

    /// Every move with its line and pinning.
    pub fn moves(&self) -> &[Move] {
        &self.moves
    }

    /// `Some` when the program was expanded from o-word control flow: its
    /// lines are then the executed lines ([`ProgramLine::source_line`] says
    /// where each comes from), not the source file's.
    pub fn expansion(&self) -> Option<&Expansion> {
        self.expansion.as_ref()
    }

    /// True when the program was expanded from o-word control flow.
    pub fn expanded(&self) -> bool {
        self.expansion.is_some()
    }

    /// The lines passed through verbatim because fairpath does not
    /// interpret or smooth them, in order.
    pub fn passthrough(&self) -> &[Passthrough] {
        &self.passthrough
    }

    /// True when the program has no move at all.
    pub fn is_empty(&self) -> bool {
        self.moves.is_empty()
    }
}

/// One motion of a program as `simulate` plans it, without the program.
#[derive(Clone, Debug, PartialEq)]
pub enum MotionOutline {
    /// Run `k` (in the order of [`Program::runs`]).
    Run(usize),
    Rapid(Piece),
    /// A feed move that is a motion of its own (pinned).
    Pinned(Piece),
}

/// [`crate::pipeline::outline`] and [`Program::runs`] of `program`, which is consumed: its
/// lines are dropped first and its pieces moved, not copied (on a long
/// written program the copies would double the largest thing held).
pub fn into_outline_and_runs(program: Program) -> (Vec<MotionOutline>, Vec<Run>) {
    let Program {
        lines,
        moves,
        runs: spans,
        ..
    } = program;
    drop(lines);
    let mut outline = Vec::with_capacity(2 * spans.len() + 1);
    let mut runs = Vec::with_capacity(spans.len());
    let mut next_run = 0;
    let mut current: Option<(usize, Vec<Piece>)> = None;
    for (mi, m) in moves.into_iter().enumerate() {
        if let Some((end, pieces)) = &mut current {
            pieces.push(m.piece);
            if mi + 1 == *end {
                runs.push(Run::new(core::mem::take(pieces)));
                current = None;
            }
            continue;
        }
        if next_run < spans.len() && spans[next_run].moves.start == mi {
            let span = &spans[next_run];
            outline.push(MotionOutline::Run(next_run));
            next_run += 1;
            let mut pieces = Vec::with_capacity(span.moves.len());
            pieces.push(m.piece);
            if span.moves.len() == 1 {
                runs.push(Run::new(pieces));
            } else {
                current = Some((span.moves.end, pieces));
            }
            continue;
        }
        outline.push(if m.piece.rapid {
            MotionOutline::Rapid(m.piece)
        } else {
            MotionOutline::Pinned(m.piece)
        });
    }
    (outline, runs)
}
