//! A program read for its motion only, as a stream: each line's moves go
//! to the run being read or to the outline, and the line is dropped
//! ([`crate::read_motion`]); and the same reading continued part after
//! part ([`MotionReader`]), which is how the writer's check reads a
//! program written part by part.

use super::reader::Reader;
use crate::error::GcodeError;
use crate::lexer::line_slices;
use crate::program::{MotionOutline, Move, MoveKind};
use crate::spline::ParseOptions;
use fairpath::path::{Piece, Run};

/// Where [`crate::read_motion`] puts each line's moves: the run being
/// read, or the outline (rapids and pinned moves, and each run where it
/// starts).
#[derive(Clone, Default)]
pub(super) struct MotionSink {
    pub(super) outline: Vec<MotionOutline>,
    pub(super) runs: Vec<Run>,
    current: Vec<Piece>,
}

impl MotionSink {
    pub(super) fn close_run(&mut self) {
        if !self.current.is_empty() {
            self.outline.push(MotionOutline::Run(self.runs.len()));
            // The run's pieces at their own size: grown by doubling, a
            // long run's vector holds up to twice its pieces, and a
            // written text read back is among the largest things held.
            let mut pieces = core::mem::take(&mut self.current);
            pieces.shrink_to_fit();
            self.runs.push(Run::new(pieces));
        }
    }

    /// The moves of one line, as `group_runs` groups them: a line that
    /// breaks the run (or is not interpreted) ends it and its moves are
    /// motions of their own; a feed change ends it too.
    pub(super) fn line(&mut self, breaks_run: bool, moves: impl Iterator<Item = Move>) {
        if breaks_run {
            self.close_run();
            for m in moves {
                self.outline.push(if m.piece.rapid {
                    MotionOutline::Rapid(m.piece)
                } else {
                    MotionOutline::Pinned(m.piece)
                });
            }
            return;
        }
        for m in moves {
            debug_assert!(m.pinned.is_none() && m.kind != MoveKind::Rapid);
            if self.current.last().is_some_and(|l| l.feed != m.piece.feed) {
                self.close_run();
            }
            self.current.push(m.piece);
        }
    }
}

/// A program without o-words read for its motion part after part: the
/// interpreter's state at the end of one part is where the next is read
/// from, so the parts read as the whole text would
/// ([`MotionReader::read_part`]). Each part must end where no run or
/// spline block is open in the text (the writer's parts end before a line
/// that holds a rapid, [`super::PartReader`]).
#[derive(Clone)]
pub struct MotionReader {
    r: Reader,
    /// Number of the next line read.
    next: usize,
}

impl Default for MotionReader {
    fn default() -> Self {
        MotionReader::new()
    }
}

impl MotionReader {
    /// At the start of a program.
    pub fn new() -> MotionReader {
        let mut r = Reader::new(&ParseOptions::default());
        r.motion_only = true;
        MotionReader { r, next: 1 }
    }

    /// Reads `text` (whole lines) from where this reading stands: its
    /// motions in order and its runs, as [`crate::read_motion`] reads a
    /// whole text, and the reading that continues after it. The run open
    /// at the end of `text` ends there, and a spline block open there is
    /// an error (as at the end of a program).
    pub fn read_part(
        &self,
        text: &[u8],
    ) -> Result<(MotionReader, Vec<crate::program::MotionOutline>, Vec<Run>), GcodeError> {
        let mut r = self.r.clone();
        r.sink = Some(MotionSink::default());
        let mut next = self.next;
        for line in line_slices(text) {
            let (t, ending) = line?;
            r.step_in_place(next, t, ending)?;
            next += 1;
        }
        r.first_number = next;
        r.check_closed()?;
        let mut sink = r.sink.take().unwrap_or_default();
        sink.close_run();
        Ok((MotionReader { r, next }, sink.outline, sink.runs))
    }
}
