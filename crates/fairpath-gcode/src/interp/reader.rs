//! The `Reader`: a program read in place (one line per source line) or
//! expanded (the lines its o-word control flow executes), line by line.

use super::facts::FactsAcc;
use super::line::interpret_line;
use super::motion_sink::{MotionReader, MotionSink};
use super::runs::group_runs;
use super::{FeedMode, State};
use crate::error::{ErrorKind, GcodeError};
use crate::lang::{
    self,
    error::LangError,
    params::{Params, SystemView},
};
use crate::lexer::{line_slices, scan_line, split_lines, ItemKind, SourceLine};
use crate::program::{Expansion, MotionMode, MotionOutline, Move, Program, ProgramLine, Units};
use crate::spline::ParseOptions;
use fairpath::controller::Plane;
use fairpath::path::Run;

/// Reads a program with the default [`ParseOptions`]. See the crate
/// documentation for what is accepted.
pub fn parse(text: &[u8]) -> Result<Program, GcodeError> {
    parse_with(text, &ParseOptions::default())
}

/// Reads a program for its motion only: the moves, runs and modal facts
/// of [`parse`], without what only writing the program again needs: the
/// lines' texts and words, the path-control words and the moves' written
/// end coordinates (on a long program most of its memory: a written
/// program read back to be checked and timed holds half as much). Such a
/// [`Program`] must not be given to a writer.
pub fn parse_motion(text: &[u8]) -> Result<Program, GcodeError> {
    read(text, &ParseOptions::default(), true)
}

/// Reads a program. See the crate documentation for what is accepted.
///
/// A program without o-word statements is read in place, one
/// [`ProgramLine`] per source line. A program with o-words is expanded: its
/// lines are the executed lines in execution order ([`crate::lang::flow`]),
/// each written out with literal values ([`Program::expansion`]).
pub fn parse_with(text: &[u8], opts: &ParseOptions) -> Result<Program, GcodeError> {
    read(text, opts, false)
}

/// Reads a program for what planning and checking it needs, and nothing
/// else: its motions in order and its runs' pieces, as
/// [`crate::program::into_outline_and_runs`] makes them of
/// [`parse_motion`]'s program. A program read in place is streamed: each
/// line is interpreted, its moves go to their run or the outline, and the
/// line is dropped, so the memory held grows with the pieces alone (a
/// written program read back to be checked can be many times its input).
/// A program with o-words is expanded as [`parse_motion`] reads it.
pub fn read_motion(text: &[u8]) -> Result<(Vec<MotionOutline>, Vec<Run>), GcodeError> {
    let mut oword = false;
    for l in line_slices(text) {
        oword |= lang::flow::looks_like_oword(l?.0);
    }
    if oword {
        return Ok(crate::program::into_outline_and_runs(parse_motion(text)?));
    }
    let (_, outline, runs) = MotionReader::new().read_part(text)?;
    Ok((outline, runs))
}

/// [`parse_with`], or with `motion_only` [`parse_motion`].
fn read(text: &[u8], opts: &ParseOptions, motion_only: bool) -> Result<Program, GcodeError> {
    // One pass to validate the text and look for o-words, then the lines
    // are read from the text itself: each is copied once, into its
    // `ProgramLine`.
    let mut oword = false;
    let mut count = 0;
    for l in line_slices(text) {
        oword |= lang::flow::looks_like_oword(l?.0);
        count += 1;
    }
    let mut r = Reader::new(opts);
    r.motion_only = motion_only;
    // A line read in place is one `ProgramLine` and holds at most one move
    // in most programs: room for that many at once (the program's largest
    // allocations, grown once rather than by copies).
    if !oword {
        r.lines.reserve_exact(count);
        r.moves.reserve_exact(count);
    }
    if oword {
        r.expand(split_lines(text)?)?;
    } else {
        r.in_place(line_slices(text).map_while(Result::ok))?;
    }
    r.finish()
}

/// The state of reading one program.
#[derive(Clone)]
pub(super) struct Reader {
    pub(super) st: State,
    params: Params,
    pub(super) lines: Vec<ProgramLine>,
    pub(super) moves: Vec<Move>,
    pub(super) start_units: Option<Units>,
    expansion: Option<Expansion>,
    /// Keep no texts, words or written coordinates ([`parse_motion`]).
    pub(super) motion_only: bool,
    /// Keep no lines or moves at all: each line's moves go here
    /// ([`read_motion`]).
    pub(super) sink: Option<MotionSink>,
    /// Keep no lines or moves at all: each line only adds to these
    /// ([`super::read_facts`]).
    pub(super) facts: Option<Box<FactsAcc>>,
    /// [`ProgramLine::number`] of `lines[0]`: lines before it were handed
    /// out as parts ([`super::PartReader`]).
    pub(super) first_number: usize,
}

impl Reader {
    pub(super) fn new(opts: &ParseOptions) -> Reader {
        Reader {
            st: State::new(opts),
            params: Params::new(),
            lines: Vec::new(),
            moves: Vec::new(),
            start_units: None,
            expansion: None,
            motion_only: false,
            sink: None,
            facts: None,
            first_number: 1,
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
        if let Some(f) = &mut self.facts {
            f.ending(ending);
            return;
        }
        if let Some(sink) = &mut self.sink {
            sink.line(true, core::iter::empty());
            return;
        }
        let text = if self.motion_only {
            String::new()
        } else {
            text
        };
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
            motion_after: st.motion,
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
        let (lines, first) = (&self.lines, self.first_number);
        let info = interpret_line(&ev.lexed, number, &mut self.st, &mut self.moves)
            .map_err(|e| to_source(e, number, source_line, lines, first))?;
        if self.start_units.is_none() && self.moves.len() > first_move {
            self.start_units = Some(self.st.units);
        }
        let breaks_run = info.breaks_run || (ev.assigns && !expanded);
        if let Some(f) = &mut self.facts {
            f.ending(ending);
            f.line(
                &text,
                &ev.lexed.words,
                &self.moves[first_move..],
                breaks_run,
                &self.st,
            );
            self.moves.truncate(first_move);
            return Ok(true);
        }
        if let Some(sink) = &mut self.sink {
            sink.line(breaks_run, self.moves.drain(first_move..));
            return Ok(true);
        }
        let (text, words, path_control) = if self.motion_only {
            for m in &mut self.moves[first_move..] {
                m.end_text = [None, None, None];
            }
            (String::new(), Vec::new(), None)
        } else {
            (text, ev.lexed.words, self.st.path_words.clone())
        };
        let st = &self.st;
        self.lines.push(ProgramLine {
            number,
            source_line,
            text,
            ending,
            units: st.units,
            incremental: st.incremental,
            words,
            // An assignment written back verbatim must stay where it is.
            breaks_run,
            moves: first_move..self.moves.len(),
            interpreted: true,
            motion_before,
            motion_after: st.motion,
            sets_motion: info.sets_motion,
            uses_modal_motion: info.uses_modal_motion,
            feed_after: st.feed.clone(),
            insert_column,
            plane_after: st.plane,
            arc_incremental_after: st.arc_incremental,
            path_control_after: path_control,
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
            self.step_in_place(i + 1, text, ending)?;
        }
        Ok(())
    }

    /// Reads source line `number` of a program without o-words.
    pub(super) fn step_in_place(
        &mut self,
        number: usize,
        text: &str,
        ending: &'static str,
    ) -> Result<(), GcodeError> {
        if self.st.ended {
            self.pass_through(number, number, text.to_string(), ending);
            return Ok(());
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
        Ok(())
    }

    /// The error for a spline block still open after the lines read.
    pub(super) fn check_closed(&self) -> Result<(), GcodeError> {
        let n = self.first_number + self.lines.len();
        self.st
            .spline
            .check_closed()
            .map_err(|e| to_source(e, n, n, &self.lines, self.first_number))
    }

    /// Reads a program with o-words: the executed lines, in order.
    ///
    /// A program that runs to [`lang::flow::MAX_EXECUTED_LINES`] (a loop
    /// whose counter runs away from its bound, which no pass repeats) is
    /// refused there; it is found first by a reading that keeps no line
    /// (as [`super::read_facts`] reads), so that a program of a few lines
    /// is not refused after holding ten million executed ones (a fuzz
    /// input of a few hundred bytes held gigabytes; measurements:
    /// docs/tuning.md, `Reader::expand`). The program is then
    /// read again, keeping its lines; any other error is the second
    /// reading's, as it was.
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
        if self.facts.is_none() && self.sink.is_none() {
            let mut dry = self.clone();
            dry.facts = Some(Box::default());
            if let Err(e) = dry.run_expanded(&scanned, &texts, eol) {
                if matches!(
                    e.kind,
                    ErrorKind::Language(lang::error::LangError::TooManyLines(_))
                ) {
                    return Err(e);
                }
            }
        }
        self.run_expanded(&scanned, &texts, eol)
    }

    /// [`Reader::expand`]'s reading of the scanned source lines.
    fn run_expanded(
        &mut self,
        scanned: &[Result<SourceLine, GcodeError>],
        texts: &[String],
        eol: &'static str,
    ) -> Result<(), GcodeError> {
        let mut ex = lang::flow::Executor::new(scanned, texts)?;
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
        self.check_closed()?;
        let runs = group_runs(&self.lines, &self.moves, 1, None);
        let mut moves = self.moves;
        moves.shrink_to_fit();
        Ok(Program {
            lines: self.lines,
            moves,
            runs,
            start_units: self.start_units.unwrap_or(self.st.units),
            expansion: self.expansion,
            passthrough: self.st.passthrough,
            first_number: 1,
            before: None,
            window_cut: false,
            window_continued: false,
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
    first_number: usize,
) -> GcodeError {
    if e.line == number {
        e.line = source_line;
    } else if let Some(l) = lines.get(e.line.wrapping_sub(first_number)) {
        e.line = l.source_line;
    }
    e
}
