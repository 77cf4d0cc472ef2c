//! A program without o-words read part after part, so that a long one is
//! smoothed, written and checked a part at a time and the memory held
//! grows with the largest part, not with the file.
//!
//! A part ends where no run and no spline block goes on, before a line
//! outside any spline block and not deleted by the block-delete switch
//! that either
//!
//! * holds a rapid programmed with its own `G0`: it ends every run (a
//!   rapid always does, whatever the state before it), is copied as it is
//!   by the writer, and sets the motion mode itself, so that neither the
//!   writer's look-ahead after a run (for `/` lines before the next motion
//!   word) nor the motion mode the written text leaves before it changes
//!   how it, or anything after it, is read or written; or
//! * starts a run at a feed other than the move before it (a feed change
//!   starts a run, and the written text keeps each run's feed, so the
//!   written run before it ends there too), in a program without `/`
//!   lines (so the writer's look-ahead after a run finds none).
//!
//! With [`RunWindows`] ([`PartReader::windowed`]), a run that holds a
//! window's lines is also cut, at the middle of one of its lines: the
//! part ends with a line the reader puts in, to that midpoint, and the
//! next starts with the cut line ([`super::window_cut`]).
//!
//! The reader's state goes on from one part to the next: each part is read
//! exactly as it is read within the whole program; what the writer needs
//! of the line before a part (the arc plane and distance mode a run
//! starting there is written in, the feed before it) goes with the part,
//! and what it carries from part to part is [`crate::write_gcode::WriterCarry`].

use super::reader::Reader;
use super::runs::group_runs;
use super::window_cut::{cut_before, RunWindows};
use crate::error::GcodeError;
use crate::lexer::line_slices;
use crate::program::{Feed, MoveKind, Program, ProgramLine};
use crate::spline::ParseOptions;
use fairpath::geom::Plane;

/// Reads a program without o-words in parts of at least `min_lines`
/// lines (the last part may be shorter), each a [`Program`] whose lines
/// keep their numbers in the whole program ([`Program::first_number`]).
pub struct PartReader<'t> {
    r: Reader,
    lines: Box<dyn Iterator<Item = Result<(&'t str, &'static str), GcodeError>> + Send + 't>,
    next: usize,
    min_lines: usize,
    /// The feed, and the arc plane and distance mode, in force before the
    /// first line held.
    feed_before: Option<Feed>,
    before: Option<(Plane, bool)>,
    /// Parts may start at a feed change (the program has no `/` lines).
    feed_cuts: bool,
    /// Long runs are cut into windows (the program has no `/` lines).
    windows: Option<RunWindows>,
    /// The line read before a window's cut, read first for the next part.
    pending: Option<(&'t str, &'static str)>,
    /// The last part ended in a window's cut.
    continued: bool,
    done: bool,
}

impl<'t> PartReader<'t> {
    /// Parts of `text` (which must have no o-word statements: see
    /// [`super::read_facts`]) of at least `min_lines` lines; `block_delete`:
    /// the program has `/` lines ([`crate::ProgramFacts::block_delete`]),
    /// then parts start before rapids only.
    pub fn new(
        text: &'t [u8],
        opts: &ParseOptions,
        min_lines: usize,
        block_delete: bool,
    ) -> PartReader<'t> {
        PartReader {
            r: Reader::new(opts),
            lines: Box::new(line_slices(text)),
            next: 1,
            min_lines: min_lines.max(1),
            feed_before: None,
            before: None,
            feed_cuts: !block_delete,
            windows: None,
            pending: None,
            continued: false,
            done: false,
        }
    }

    /// Cuts long runs into windows too ([`RunWindows`]); not in a program
    /// with `/` lines.
    pub fn windowed(mut self, windows: RunWindows) -> PartReader<'t> {
        self.windows = self.feed_cuts.then_some(windows);
        self
    }

    /// The next part, or `None` after the last.
    pub fn next_part(&mut self) -> Result<Option<Program>, GcodeError> {
        if self.done {
            return Ok(None);
        }
        loop {
            let (t, ending) = match self.pending.take() {
                Some(l) => l,
                None => match self.lines.next() {
                    Some(l) => l?,
                    None => break,
                },
            };
            if let Some(cut) = self.window_cut(t) {
                // The cut line is read first for the next part, and the
                // line put in before it keeps its number.
                let cut_ending = if ending.is_empty() { "\n" } else { ending };
                self.r.step_in_place(self.next, &cut, cut_ending)?;
                self.pending = Some((t, ending));
                let n = self.r.lines.len();
                let mut part = self.cut(n);
                part.window_cut = true;
                self.continued = true;
                self.r.first_number -= 1;
                return Ok(Some(part));
            }
            self.r.step_in_place(self.next, t, ending)?;
            self.next += 1;
            let n = self.r.lines.len();
            if n > self.min_lines && self.starts_part(&self.r.lines[n - 2], &self.r.lines[n - 1]) {
                return Ok(Some(self.cut(n - 1)));
            }
        }
        self.done = true;
        self.r.check_closed()?;
        let n = self.r.lines.len();
        Ok((n > 0).then(|| self.cut(n)))
    }

    /// The line that cuts a window before the line `text`, where one is
    /// due ([`RunWindows`]).
    fn window_cut(&self, text: &str) -> Option<String> {
        let w = self.windows?;
        let held = self.r.lines.len();
        let prev = self.r.lines.last()?;
        if held < w.lines.max(1) || prev.moves.is_empty() {
            return None;
        }
        let prev_move = &self.r.moves[prev.moves.end - 1];
        cut_before(&self.r.st, prev, prev_move, text, self.next, w.min_cut_mm)
    }

    /// The first `k` lines held, as a part; the lines after them stay.
    fn cut(&mut self, k: usize) -> Program {
        let r = &mut self.r;
        let m = r.lines.get(k).map_or(r.moves.len(), |l| l.moves.start);
        // The vectors themselves, not a copy of them beside them: the held
        // lines after the part (the one that starts the next, at most a
        // few) are split off instead. A part is cut when the line after it
        // is read, so a program of one long run (a raster) and the rapid
        // after it was copied whole here, beside itself, at its peak.
        let (mut lines, mut moves): (Vec<ProgramLine>, Vec<_>) = {
            let (rest_lines, rest_moves) = (r.lines.split_off(k), r.moves.split_off(m));
            (
                core::mem::replace(&mut r.lines, rest_lines),
                core::mem::replace(&mut r.moves, rest_moves),
            )
        };
        for l in &mut r.lines {
            l.moves = l.moves.start - m..l.moves.end - m;
        }
        let first_number = r.first_number;
        r.first_number += k;
        let last = lines.last();
        let feed_before = core::mem::replace(
            &mut self.feed_before,
            last.and_then(|l| l.feed_after.clone()),
        );
        let before = core::mem::replace(
            &mut self.before,
            last.map(|l| (l.plane_after, l.arc_incremental_after)),
        );
        let runs = group_runs(&lines, &moves, first_number, feed_before);
        lines.shrink_to_fit();
        moves.shrink_to_fit();
        Program {
            lines,
            moves,
            runs,
            start_units: r.start_units.unwrap_or(r.st.units),
            expansion: None,
            passthrough: Vec::new(),
            first_number,
            before,
            window_cut: false,
            window_continued: core::mem::take(&mut self.continued),
        }
    }

    /// Whether a part may start at `line` (`prev` the line before it): see
    /// the module docs.
    fn starts_part(&self, prev: &ProgramLine, line: &ProgramLine) -> bool {
        let moves = &self.r.moves[line.moves.clone()];
        let plain = line.interpreted
            && !line.in_block
            && !prev.in_block
            && !crate::facts::is_block_delete(&line.text)
            && !moves.is_empty();
        if !plain {
            return false;
        }
        let rapid =
            line.breaks_run && line.sets_motion && moves.iter().all(|m| m.kind == MoveKind::Rapid);
        let feed_change = self.feed_cuts
            && !line.breaks_run
            && moves
                .iter()
                .all(|m| m.pinned.is_none() && m.kind != MoveKind::Rapid)
            && line.moves.start > 0
            && self.r.moves[line.moves.start - 1].piece.feed != moves[0].piece.feed;
        rapid || feed_change
    }
}
