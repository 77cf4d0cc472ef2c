//! The modal interpreter: turns lexed lines into moves (pieces in mm), tracks
//! the modal state, decides which moves are pinned and which lines end runs,
//! and groups the runs. Spline lines (G5, G5.1, G5.2 ... G5.3, G6.2) go to
//! [`crate::spline`] once the line's state changes are applied.

// Axis loops index several parallel arrays by axis number.
#![allow(clippy::needless_range_loop)]

use crate::block_delete::{Dependence, Modal, Snapshot};
use crate::cycles::{self, CycleLine, CycleState, Spindle};
use crate::error::{ErrorKind, GcodeError};
use crate::lang::{
    self,
    error::LangError,
    params::{Params, SystemView},
};
use crate::lexer::{line_slices, scan_line, split_lines, ItemKind, LexedLine, SourceLine, Word};
use crate::program::{
    Expansion, Feed, MotionMode, Move, MoveKind, Passthrough, PinReason, Program, ProgramLine,
    RunSpan, Units,
};
use crate::spline::{self, ParseOptions, SplineState};
use fairpath::controller::Plane;
use fairpath::geom::{Arc, ArcError, Curve, Line, ParamCurve, Vec3};
use fairpath::path::Piece;

/// Distance (mm) below which an arc's start and end coincide in the plane
/// (a full circle) or a point coincides with the centre: below G-code
/// resolution (1e-4 mm or 1e-5 in are the finest programs write).
pub const COINCIDENT_MM: f64 = 1e-7;

/// Largest difference between an IJK arc's start and end radius accepted
/// (a spiral arc within it is kept as a spiral, like LinuxCNC does); larger
/// is an error. LinuxCNC's defaults: 0.0005 in for inch programs, 0.01 mm for
/// mm programs (absolute, in program units). The same tolerance bounds how
/// much an R-form arc's radius may fall short of half the chord.
pub const ARC_RADIUS_TOLERANCE_INCH: f64 = 0.0005;
/// See [`ARC_RADIUS_TOLERANCE_INCH`].
pub const ARC_RADIUS_TOLERANCE_MM: f64 = 0.01;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FeedMode {
    InverseTime,
    PerMinute,
    PerRev,
}

/// In-plane axes (first, second), normal axis, and the centre-word letters
/// for the in-plane axes and the off-plane one.
pub(crate) fn plane_axes(plane: Plane) -> (usize, usize, usize, char, char, char) {
    match plane {
        Plane::Xy => (0, 1, 2, 'I', 'J', 'K'),
        Plane::Zx => (2, 0, 1, 'K', 'I', 'J'),
        Plane::Yz => (1, 2, 0, 'J', 'K', 'I'),
    }
}

/// Group-0 (non-modal) codes that matter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NonModal {
    Dwell,
    G10,
    G28,
    G28_1,
    G30,
    G30_1,
    G52,
    G53,
    G92,
    G92_1,
    G92_2,
    G92_3,
}

impl NonModal {
    fn uses_axes(self) -> bool {
        matches!(
            self,
            NonModal::G10 | NonModal::G28 | NonModal::G30 | NonModal::G52 | NonModal::G92
        )
    }
}

/// A classified G code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum G {
    Motion(MotionMode),
    Plane(Plane),
    Units(Units),
    Incremental(bool),
    ArcIncremental(bool),
    FeedMode(FeedMode),
    CutterComp(bool),
    ToolLength(bool),
    CoordSystem(u16),
    PathControl(u16),
    /// G98 (false) or G99 (true: retract to R).
    ReturnMode(bool),
    SpindleMode(u16),
    LatheRadius,
    Cancel(u16),
    NonModal(NonModal),
    /// G5.3: closes a G5.2 block (LinuxCNC modal group 0).
    SplineEnd,
}

impl G {
    fn group(self) -> &'static str {
        match self {
            G::Motion(_) => "motion",
            G::Plane(_) => "plane",
            G::Units(_) => "units",
            G::Incremental(_) => "distance mode",
            G::ArcIncremental(_) => "arc distance mode",
            G::FeedMode(_) => "feed mode",
            G::CutterComp(_) => "cutter compensation",
            G::ToolLength(_) => "tool length offset",
            G::CoordSystem(_) => "coordinate system",
            G::PathControl(_) => "path control",
            G::ReturnMode(_) => "canned cycle return",
            G::SpindleMode(_) => "spindle speed mode",
            G::LatheRadius => "lathe diameter mode",
            G::Cancel(10) => "polar coordinates",
            G::Cancel(_) => "rotation",
            G::NonModal(_) | G::SplineEnd => "non-modal",
        }
    }
}

/// Classifies `G<code/10>`.
fn classify_g(code: u16, text: &str) -> Result<G, ErrorKind> {
    let unsupported = |what: &'static str| Err(ErrorKind::Unsupported(what));
    Ok(match code {
        0 => G::Motion(MotionMode::Rapid),
        10 => G::Motion(MotionMode::Linear),
        20 => G::Motion(MotionMode::ArcCw),
        30 => G::Motion(MotionMode::ArcCcw),
        40 => G::NonModal(NonModal::Dwell),
        50 => G::Motion(MotionMode::CubicSpline),
        51 => G::Motion(MotionMode::QuadSpline),
        52 => G::Motion(MotionMode::Nurbs),
        53 => G::SplineEnd,
        62 => G::Motion(MotionMode::NurbsG6),
        60 | 61 | 63 => return unsupported("LinuxCNC master's G6, G6.1 and G6.3"),
        70 => return unsupported("lathe diameter mode G7"),
        80 => G::LatheRadius,
        100 => G::NonModal(NonModal::G10),
        150 => G::Cancel(10),
        160 => return unsupported("polar coordinates G16"),
        170 => G::Plane(Plane::Xy),
        180 => G::Plane(Plane::Zx),
        190 => G::Plane(Plane::Yz),
        171 | 181 | 191 => return unsupported("UVW planes (G17.1, G18.1, G19.1)"),
        200 => G::Units(Units::Inch),
        210 => G::Units(Units::Mm),
        280 => G::NonModal(NonModal::G28),
        281 => G::NonModal(NonModal::G28_1),
        300 => G::NonModal(NonModal::G30),
        301 => G::NonModal(NonModal::G30_1),
        330 => G::Motion(MotionMode::Thread),
        331 => G::Motion(MotionMode::RigidTap),
        382..=385 | 310 => G::Motion(MotionMode::Probe(code)),
        400 => G::CutterComp(false),
        410 | 411 | 420 | 421 => G::CutterComp(true),
        430..=432 => G::ToolLength(true),
        490 => G::ToolLength(false),
        520 => G::NonModal(NonModal::G52),
        530 => G::NonModal(NonModal::G53),
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => G::CoordSystem(code),
        610 | 611 | 640 => G::PathControl(code),
        680 => return unsupported("coordinate rotation G68"),
        690 => G::Cancel(69),
        510 => return unsupported("scaling G51"),
        700 | 710 | 720 => return unsupported("G70/G71/G72 (lathe cycles or legacy units)"),
        c if cycles::is_cycle(c) => G::Motion(MotionMode::Cycle(c)),
        760 => return unsupported("the G76 threading cycle"),
        870 | 880 => {
            return unsupported("canned cycles G87 (back boring) and G88 (manual retract)")
        }
        800 => G::Motion(MotionMode::None),
        900 => G::Incremental(false),
        910 => G::Incremental(true),
        901 => G::ArcIncremental(false),
        911 => G::ArcIncremental(true),
        930 => G::FeedMode(FeedMode::InverseTime),
        940 => G::FeedMode(FeedMode::PerMinute),
        950 => G::FeedMode(FeedMode::PerRev),
        920 => G::NonModal(NonModal::G92),
        921 => G::NonModal(NonModal::G92_1),
        922 => G::NonModal(NonModal::G92_2),
        923 => G::NonModal(NonModal::G92_3),
        960 | 970 => G::SpindleMode(code),
        980 | 990 => G::ReturnMode(code == 990),
        _ => return Err(ErrorKind::UnknownGCode(text.to_string())),
    })
}

/// M-code modal group (LinuxCNC), or 0 for codes without a group.
fn m_group(code: i64) -> u8 {
    match code {
        0 | 1 | 2 | 30 | 60 => 4,
        6 | 61 => 6,
        3..=5 => 7,
        7..=9 => 8,
        48..=53 => 9,
        _ => 0,
    }
}

/// The modal state of the interpreter.
pub(crate) struct State {
    /// Current position, mm, program coordinates.
    pub(crate) pos: Vec3,
    /// Whether each axis of `pos` is known (see the crate docs).
    pub(crate) known: [bool; 3],
    /// Text of the absolute coordinate last written for each axis.
    pub(crate) axis_text: [Option<String>; 3],
    pub(crate) units: Units,
    pub(crate) incremental: bool,
    arc_incremental: bool,
    pub(crate) plane: Plane,
    pub(crate) motion: MotionMode,
    pub(crate) feed: Option<Feed>,
    pub(crate) feed_mode: FeedMode,
    pub(crate) comp: bool,
    tlo: bool,
    /// Canned cycle settings and the spindle direction they check.
    pub(crate) cycle: CycleState,
    /// Skip `/` lines (the block-delete switch on).
    skip_block_delete: bool,
    /// What later lines depend on of `/` lines (switch off).
    after_delete: Dependence,
    /// Lines passed through, and the last line holding a move that was
    /// not passed through (ranges of passed-through lines merge across
    /// lines without such moves).
    passthrough: Vec<Passthrough>,
    last_plain_move_line: usize,
    coord: u16,
    path: u16,
    /// The words of the path-control command in force (`G64 P0.01 Q0`),
    /// if the program set one.
    path_words: Option<String>,
    spindle_mode: u16,
    ended: bool,
    percent_lines: usize,
    /// Spline blocks being read, and how splines are read.
    pub(crate) spline: SplineState,
}

impl State {
    fn new(opts: &ParseOptions) -> State {
        State {
            pos: Vec3::ZERO,
            known: [true; 3],
            axis_text: [None, None, None],
            units: Units::Mm,
            incremental: false,
            arc_incremental: true,
            plane: Plane::Xy,
            motion: MotionMode::None,
            feed: None,
            feed_mode: FeedMode::PerMinute,
            comp: false,
            tlo: false,
            coord: 540,
            path: 640,
            path_words: None,
            spindle_mode: 970,
            ended: false,
            percent_lines: 0,
            spline: SplineState::new(opts.splines),
            cycle: CycleState::new(),
            skip_block_delete: opts.block_delete,
            after_delete: Dependence::default(),
            passthrough: Vec::new(),
            last_plain_move_line: 0,
        }
    }

    /// What a `/` line may change ([`crate::block_delete`]).
    fn snapshot(&self) -> Snapshot {
        Snapshot {
            pos: self.pos,
            known: self.known,
            feed: self.feed.as_ref().map(|f| f.mm_per_min),
            motion: self.motion,
            modal: Modal {
                units: self.units,
                incremental: self.incremental,
                arc_incremental: self.arc_incremental,
                plane: self.plane,
                feed_mode: self.feed_mode,
                comp: self.comp,
                tool_length: self.tlo,
                coord: self.coord,
                path_control: self.path_words.clone(),
                retract_to_r: self.cycle.retract_to_r,
            },
        }
    }

    /// Records that line `ln` is passed through because of `what`.
    fn note_passthrough(&mut self, ln: usize, what: &'static str) {
        if let Some(last) = self.passthrough.last_mut() {
            if last.what == what && *last.lines.end() >= self.last_plain_move_line {
                last.lines = *last.lines.start()..=ln;
                return;
            }
        }
        self.passthrough.push(Passthrough {
            lines: ln..=ln,
            what,
        });
    }
    fn forget(&mut self, axes: [bool; 3]) {
        for a in 0..3 {
            if axes[a] {
                self.known[a] = false;
                self.axis_text[a] = None;
            }
        }
    }
}

const AXIS_LETTERS: [char; 3] = ['X', 'Y', 'Z'];
/// Word letters the interpreter takes (`@` and `^` are resolved to X and
/// Y before it; `E`, the 3D-printer extruder, is passed through, see
/// [`FOREIGN_WORDS`]).
const INTERPRETED_LETTERS: &str = "ABCDEFGHIJKLMNPQRSTUVWXYZ";
const EXTRA_AXES: &str = "ABCUVW";

/// Reads a program with the default [`ParseOptions`]. See the crate
/// documentation for what is accepted.
pub fn parse(text: &[u8]) -> Result<Program, GcodeError> {
    parse_with(text, &ParseOptions::default())
}

/// Reads a program. See the crate documentation for what is accepted.
///
/// A program without o-word statements is read in place, one
/// [`ProgramLine`] per source line. A program with o-words is expanded: its
/// lines are the executed lines in execution order ([`crate::lang::flow`]),
/// each written out with literal values ([`Program::expansion`]).
pub fn parse_with(text: &[u8], opts: &ParseOptions) -> Result<Program, GcodeError> {
    // One pass to validate the text and look for o-words, then the lines
    // are read from the text itself: each is copied once, into its
    // `ProgramLine`.
    let mut oword = false;
    for l in line_slices(text) {
        oword |= lang::flow::looks_like_oword(l?.0);
    }
    let mut r = Reader::new(opts);
    if oword {
        r.expand(split_lines(text)?)?;
    } else {
        r.in_place(line_slices(text).map_while(Result::ok))?;
    }
    r.finish()
}

/// The state of reading one program.
struct Reader {
    st: State,
    params: Params,
    lines: Vec<ProgramLine>,
    moves: Vec<Move>,
    start_units: Option<Units>,
    expansion: Option<Expansion>,
}

impl Reader {
    fn new(opts: &ParseOptions) -> Reader {
        Reader {
            st: State::new(opts),
            params: Params::new(),
            lines: Vec::new(),
            moves: Vec::new(),
            start_units: None,
            expansion: None,
        }
    }

    /// What expressions may read of the interpreter's state before source
    /// line `line`.
    fn view(&self, line: usize) -> SystemView {
        let st = &self.st;
        let mpu = st.units.mm_per_unit();
        let pos = [st.pos.x, st.pos.y, st.pos.z];
        SystemView {
            position: std::array::from_fn(|a| st.known[a].then(|| pos[a] / mpu)),
            mm_per_unit: mpu,
            incremental: st.incremental,
            plane: match st.plane {
                Plane::Xy => 170,
                Plane::Zx => 180,
                Plane::Yz => 190,
            },
            motion: match st.motion {
                MotionMode::None => 800,
                MotionMode::Rapid => 0,
                MotionMode::Linear => 10,
                MotionMode::ArcCw => 20,
                MotionMode::ArcCcw => 30,
                MotionMode::Thread => 330,
                MotionMode::RigidTap => 331,
                MotionMode::Probe(c) => c,
                MotionMode::CubicSpline => 50,
                MotionMode::QuadSpline => 51,
                MotionMode::Nurbs => 52,
                MotionMode::NurbsG6 => 62,
                MotionMode::Cycle(c) => c,
            },
            feed: st.feed.as_ref().map_or(0.0, |f| f.mm_per_min / mpu),
            feed_mode: match st.feed_mode {
                FeedMode::InverseTime => 930,
                FeedMode::PerMinute => 940,
                FeedMode::PerRev => 950,
            },
            cutter_comp: st.comp,
            arc_absolute: !st.arc_incremental,
            coord_system: st.coord,
            spindle_mode: st.spindle_mode,
            line,
        }
    }

    /// A line after the program's end, passed through unread.
    fn pass_through(
        &mut self,
        number: usize,
        source_line: usize,
        text: String,
        ending: &'static str,
    ) {
        let st = &self.st;
        self.lines.push(ProgramLine {
            number,
            source_line,
            text,
            ending,
            units: st.units,
            incremental: st.incremental,
            words: Vec::new(),
            breaks_run: false,
            moves: self.moves.len()..self.moves.len(),
            interpreted: false,
            motion_before: st.motion,
            sets_motion: false,
            uses_modal_motion: false,
            feed_after: st.feed.clone(),
            insert_column: 1,
            plane_after: st.plane,
            arc_incremental_after: st.arc_incremental,
            path_control_after: st.path_words.clone(),
            in_block: false,
        });
    }

    /// Evaluates and interprets source line `source_line` (syntax `src`,
    /// text `text`) as program line `number`. Expanded lines get their text
    /// with literal values; a line that only assigned parameters is then
    /// dropped (returns false).
    fn line(
        &mut self,
        number: usize,
        source_line: usize,
        src: &SourceLine,
        text: String,
        ending: &'static str,
        expanded: bool,
    ) -> Result<bool, GcodeError> {
        let view = self.view(source_line);
        let mut ev = lang::line::evaluate(src, source_line, &mut self.params, &view)?;
        lang::polar::resolve(&mut ev, &view, source_line)?;
        let (text, insert_column) = if expanded {
            let t = ev.expanded_text(&text);
            if ev.assigns && t.trim().is_empty() {
                return Ok(false);
            }
            // The column where a motion word goes, in the written text.
            let col = scan_line(&t, source_line)
                .ok()
                .and_then(|l| {
                    l.items
                        .iter()
                        .find(|i| !matches!(i.kind, ItemKind::Word { letter: 'N', .. }))
                        .map(|i| i.column)
                })
                .unwrap_or_else(|| t.chars().count() + 1);
            (t, col)
        } else {
            let col = ev
                .lexed
                .words
                .iter()
                .find(|w| w.letter != 'N')
                .map(|w| w.column)
                .unwrap_or_else(|| text.chars().count() + 1);
            (text, col)
        };
        // Fanuc subprograms would be passed through as unknown M codes
        // and their moves silently lost.
        if let Some(w) = ev
            .lexed
            .words
            .iter()
            .find(|w| w.letter == 'M' && (w.value == 98.0 || w.value == 99.0))
        {
            return Err(GcodeError::new(
                source_line,
                w.column,
                ErrorKind::Unsupported("Fanuc subprograms (M98/M99)"),
            ));
        }
        let motion_before = self.st.motion;
        let first_move = self.moves.len();
        let lines = &self.lines;
        let info = interpret_line(&ev.lexed, number, &mut self.st, &mut self.moves)
            .map_err(|e| to_source(e, number, source_line, lines))?;
        if self.start_units.is_none() && self.moves.len() > first_move {
            self.start_units = Some(self.st.units);
        }
        let st = &self.st;
        self.lines.push(ProgramLine {
            number,
            source_line,
            text,
            ending,
            units: st.units,
            incremental: st.incremental,
            words: ev.lexed.words,
            // An assignment written back verbatim must stay where it is.
            breaks_run: info.breaks_run || (ev.assigns && !expanded),
            moves: first_move..self.moves.len(),
            interpreted: true,
            motion_before,
            sets_motion: info.sets_motion,
            uses_modal_motion: info.uses_modal_motion,
            feed_after: st.feed.clone(),
            insert_column,
            plane_after: st.plane,
            arc_incremental_after: st.arc_incremental,
            path_control_after: st.path_words.clone(),
            in_block: st.spline.is_open(),
        });
        Ok(true)
    }

    /// Reads a program without o-words: one line per source line.
    fn in_place<'t>(
        &mut self,
        raw: impl Iterator<Item = (&'t str, &'static str)>,
    ) -> Result<(), GcodeError> {
        for (i, (text, ending)) in raw.enumerate() {
            let number = i + 1;
            if self.st.ended {
                self.pass_through(number, number, text.to_string(), ending);
                continue;
            }
            let src = scan_line(text, number)?;
            if let Some(o) = &src.oword {
                // looks_like_oword chose this mode; it must see every
                // statement the scanner reads.
                return Err(GcodeError::new(
                    number,
                    o.column,
                    ErrorKind::Language(LangError::OWordSyntax(
                        "o-word statement in an unexpected form",
                    )),
                ));
            }
            self.line(number, number, &src, text.to_string(), ending, false)?;
        }
        Ok(())
    }

    /// Reads a program with o-words: the executed lines, in order.
    fn expand(&mut self, raw: Vec<(String, &'static str)>) -> Result<(), GcodeError> {
        let eol = raw
            .iter()
            .map(|(_, e)| *e)
            .find(|e| !e.is_empty())
            .unwrap_or("\n");
        let texts: Vec<String> = raw.into_iter().map(|(t, _)| t).collect();
        let scanned: Vec<_> = texts
            .iter()
            .enumerate()
            .map(|(i, t)| scan_line(t, i + 1))
            .collect();
        let mut ex = lang::flow::Executor::new(&scanned, &texts)?;
        loop {
            let view = self.view(ex.position() + 1);
            let Some(i) = ex.next(&mut self.params, &view)? else {
                break;
            };
            let src = scanned[i].as_ref().map_err(Clone::clone)?;
            let number = self.lines.len() + 1;
            self.line(number, i + 1, src, texts[i].clone(), eol, true)?;
            if self.st.ended {
                if ex.call_level() == 0 {
                    for k in ex.position()..texts.len() {
                        let n = self.lines.len() + 1;
                        // An o-word statement after the end (an `endwhile`
                        // of a loop the end left) is not run, and the
                        // expanded text has no o-words: it is kept as a
                        // `;` comment, so the output reads back (fuzz input
                        // anomaly-1718-22823).
                        let text = match &scanned[k] {
                            Ok(src) if src.oword.is_some() => {
                                format!("; {}", texts[k].trim_start())
                            }
                            _ => texts[k].clone(),
                        };
                        self.pass_through(n, k + 1, text, eol);
                    }
                }
                break;
            }
        }
        self.expansion = Some(Expansion {
            executed_lines: ex.executed(),
            source_lines: texts.len(),
        });
        Ok(())
    }

    fn finish(self) -> Result<Program, GcodeError> {
        let lines = self.lines;
        let n = lines.len() + 1;
        self.st
            .spline
            .check_closed()
            .map_err(|e| to_source(e, n, n, &lines))?;
        let runs = group_runs(&lines, &self.moves);
        Ok(Program {
            lines,
            moves: self.moves,
            runs,
            start_units: self.start_units.unwrap_or(self.st.units),
            expansion: self.expansion,
            passthrough: self.st.passthrough,
        })
    }
}

/// An error of the interpreter at program line `number` (source line
/// `source_line`), or at an earlier program line (a spline block's first
/// line), named by its source line.
fn to_source(
    mut e: GcodeError,
    number: usize,
    source_line: usize,
    lines: &[ProgramLine],
) -> GcodeError {
    if e.line == number {
        e.line = source_line;
    } else if let Some(l) = lines.get(e.line.wrapping_sub(1)) {
        e.line = l.source_line;
    }
    e
}

struct LineInfo {
    breaks_run: bool,
    sets_motion: bool,
    uses_modal_motion: bool,
    /// The line holds a group-0 code other than G4 (G10, G28, G92 ...).
    group0: bool,
}

impl LineInfo {
    const NONE: LineInfo = LineInfo {
        breaks_run: false,
        sets_motion: false,
        uses_modal_motion: false,
        group0: false,
    };
}

pub(crate) fn err(line: usize, column: usize, kind: ErrorKind) -> GcodeError {
    GcodeError::new(line, column, kind)
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
fn interpret_line(
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
            text: f.text.as_str().into(),
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

pub(crate) fn finite(v: f64, ln: usize, w: &Word) -> Result<f64, GcodeError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(ln, w.column, ErrorKind::NumberOutOfRange(w.letter)))
    }
}

pub(crate) fn set_axis(p: &mut Vec3, a: usize, v: f64) {
    match a {
        0 => p.x = v,
        1 => p.y = v,
        _ => p.z = v,
    }
}

pub(crate) fn axis(p: Vec3, a: usize) -> f64 {
    match a {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    }
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

/// Builds a G2/G3 arc from the current state.
fn build_arc(
    lx: &LexedLine,
    ln: usize,
    st: &State,
    start: Vec3,
    end: Vec3,
    clockwise: bool,
    first_axis_col: usize,
) -> Result<Arc, GcodeError> {
    let (a1, a2, _an, l1, l2, loff) = plane_axes(st.plane);
    let mm = st.units.mm_per_unit();
    let tol = match st.units {
        Units::Inch => ARC_RADIUS_TOLERANCE_INCH,
        Units::Mm => ARC_RADIUS_TOLERANCE_MM,
    };
    let has_axis = lx.words.iter().any(|w| AXIS_LETTERS.contains(&w.letter));
    let has_center = ['I', 'J', 'K'].iter().any(|&l| lx.word(l).is_some());
    if !has_axis && (!has_center || lx.word('R').is_some()) {
        return Err(err(ln, first_axis_col, ErrorKind::ArcWithoutAxes));
    }
    let r_word = lx.word('R');
    let c1 = lx.word(l1);
    let c2 = lx.word(l2);
    if let Some(w) = lx.word(loff) {
        if w.value != 0.0 {
            return Err(err(ln, w.column, ErrorKind::ArcOffPlaneCenter(loff)));
        }
    }
    let turns = match lx.word('P') {
        None => 1,
        Some(w) => {
            if w.value.fract() != 0.0 || w.value < 1.0 || w.value > 1.0e6 {
                return Err(err(ln, w.column, ErrorKind::BadTurns(w.value)));
            }
            w.value as u32
        }
    };
    let (s1, s2) = (axis(start, a1), axis(start, a2));
    let (e1, e2) = (axis(end, a1), axis(end, a2));
    let mut center = start;
    match (r_word, c1.or(c2)) {
        (Some(r), Some(_)) => return Err(err(ln, r.column, ErrorKind::ArcRadiusAndCenter)),
        (None, None) => return Err(err(ln, first_axis_col, ErrorKind::ArcWithoutCenter)),
        (None, Some(_)) => {
            let off = |w: Option<&Word>, s: f64| -> Result<f64, GcodeError> {
                let v = w.map_or(0.0, |w| w.value) * mm;
                let c = if st.arc_incremental { s + v } else { v };
                match w {
                    Some(w) => finite(c, ln, w),
                    None => Ok(c),
                }
            };
            let cc1 = off(c1, s1)?;
            let cc2 = off(c2, s2)?;
            let r0 = (s1 - cc1).hypot(s2 - cc2) / mm;
            let r1 = (e1 - cc1).hypot(e2 - cc2) / mm;
            if (r1 - r0).abs() > tol {
                let w = c1.or(c2).map_or(first_axis_col, |w| w.column);
                return Err(err(
                    ln,
                    w,
                    ErrorKind::ArcRadiusMismatch {
                        r_start: r0,
                        r_end: r1,
                        tolerance: tol,
                    },
                ));
            }
            set_axis(&mut center, a1, cc1);
            set_axis(&mut center, a2, cc2);
        }
        (Some(rw), None) => {
            // LinuxCNC's arc_data_r.
            let radius = rw.value * mm;
            let abs_r = radius.abs();
            let (m1, m2) = (0.5 * (s1 + e1), 0.5 * (s2 + e2));
            let mut half = (m1 - e1).hypot(m2 - e2);
            if half <= COINCIDENT_MM {
                return Err(err(ln, rw.column, ErrorKind::ArcRadiusFullCircle));
            }
            if abs_r <= COINCIDENT_MM || half - abs_r > tol * mm {
                return Err(err(
                    ln,
                    rw.column,
                    ErrorKind::ArcRadiusTooSmall {
                        radius: rw.value.abs(),
                        half_chord: half / mm,
                    },
                ));
            }
            if half > abs_r {
                half = abs_r;
            }
            let chord_dir = (e2 - s2).atan2(e1 - s1);
            let theta = if clockwise == (radius > 0.0) {
                chord_dir - std::f64::consts::FRAC_PI_2
            } else {
                chord_dir + std::f64::consts::FRAC_PI_2
            };
            let offset = (abs_r * abs_r - half * half).max(0.0).sqrt();
            set_axis(&mut center, a1, m1 + offset * theta.cos());
            set_axis(&mut center, a2, m2 + offset * theta.sin());
        }
    }
    let arc = Arc::from_center(
        start,
        end,
        center,
        st.plane.normal(),
        clockwise,
        turns,
        COINCIDENT_MM,
    )
    .map_err(|e| match e {
        ArcError::ZeroRadius => err(ln, first_axis_col, ErrorKind::ArcZeroRadius),
        ArcError::NotFinite => err(ln, first_axis_col, ErrorKind::BadValue('R')),
    })?;
    Ok(arc)
}

/// Groups the runs: consecutive non-pinned feed moves on lines that do not
/// break runs, at one feed. A run that starts with a spline block's moves
/// starts at the block's first line.
///
/// A move whose feed differs from the move before it starts a new run
/// (the line that changes the feed lies between the two runs): the
/// programmed feed then changes exactly at the programmed vertex, which
/// smoothing keeps (run end points are kept exactly). Smoothing across it
/// would make one feed apply to a stretch of path programmed at the other
/// (`linuxcnc/diagnostic/feed-tracking-test.ngc`: `X2 F1000`, `X2.001
/// F10`, `X5 F1000` became one move at F10, 1.03 s -> 42 s).
fn group_runs(lines: &[ProgramLine], moves: &[Move]) -> Vec<RunSpan> {
    let mut runs = Vec::new();
    let mut cur: Option<RunSpan> = None;
    let mut feed_before: Option<Feed> = None;
    for line in lines {
        if line.breaks_run || !line.interpreted {
            if let Some(r) = cur.take() {
                runs.push(r);
            }
        } else {
            for mi in line.moves.clone() {
                let m = &moves[mi];
                debug_assert!(m.pinned.is_none() && m.kind != MoveKind::Rapid);
                if let Some(r) = &cur {
                    if moves[r.moves.end - 1].piece.feed != m.piece.feed {
                        runs.extend(cur.take());
                    }
                }
                match &mut cur {
                    Some(r) => {
                        r.moves.end = mi + 1;
                        r.last_line = line.number;
                        r.feed_after = line.feed_after.clone();
                    }
                    None => {
                        // A spline block's moves start the run at the
                        // block's first line, with the feed before it.
                        let first = m.piece.source_lines.0.min(line.number);
                        let before = if first == line.number {
                            feed_before.clone()
                        } else {
                            first
                                .checked_sub(2)
                                .and_then(|i| lines[i].feed_after.clone())
                        };
                        cur = Some(RunSpan {
                            moves: mi..mi + 1,
                            first_line: first,
                            last_line: line.number,
                            units: line.units,
                            incremental: line.incremental,
                            feed_before: before,
                            feed_after: line.feed_after.clone(),
                        })
                    }
                }
            }
            // Feed changes on interior lines after the last move count too:
            // they are emitted after the run, so feed_after is the modal
            // feed after the run's last line.
        }
        feed_before = line.feed_after.clone();
    }
    if let Some(r) = cur.take() {
        runs.push(r);
    }
    runs
}
