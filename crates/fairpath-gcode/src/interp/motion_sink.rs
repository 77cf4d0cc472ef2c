//! A program read for its motion only, as a stream: each line's moves go
//! to the run being read or to the outline, and the line is dropped
//! ([`crate::read_motion`]); and the same reading continued part after
//! part ([`MotionReader`]), which is how the writer's check reads a
//! program written part by part.

use super::reader::Reader;
use crate::error::GcodeError;
use crate::lexer::{line_slices, line_slices_of};
use crate::program::{MotionOutline, Move, MoveKind};
use crate::spline::ParseOptions;
use fairpath::path::{Piece, Run};
use std::io::Read;

/// Where [`crate::read_motion`] puts each line's moves: the run being
/// read, or the outline (rapids and pinned moves, and each run where it
/// starts).
#[derive(Clone, Default)]
pub(super) struct MotionSink {
    pub(super) outline: Vec<MotionOutline>,
    pub(super) runs: Vec<Run>,
    current: Vec<Piece>,
    /// The feed of the run being read (of its last piece: a feed change
    /// ends it), `None` before its first piece.
    #[allow(clippy::option_option)]
    feed: Option<Option<f64>>,
    /// The run being read is handed out part by part
    /// ([`MotionReader::read_part_streaming`]); it has moved.
    streamed: bool,
    moved: bool,
    /// The stream did not want the run being read: it is held.
    declined: bool,
    /// Runs closed that move (not empty, not all zero-length lines), as
    /// `pair_runs` pairs them: the pairing index of the run being read.
    moving: usize,
    /// Runs handed out part by part that the last line closed, with the
    /// pieces left of them, not yet handed out.
    ended: Vec<(usize, Vec<Piece>)>,
}

/// Whether a piece moves: not a line from a point to itself (what
/// `pair_runs` leaves out of a run that does not move).
fn moves(p: &Piece) -> bool {
    !matches!(&p.curve, fairpath::geom::Curve::Line(l) if l.p0 == l.p1)
}

impl MotionSink {
    pub(super) fn close_run(&mut self) {
        if !self.current.is_empty() || self.streamed {
            let k = self.runs.len();
            self.outline.push(MotionOutline::Run(k));
            // The run's pieces at their own size: grown by doubling, a
            // long run's vector holds up to twice its pieces, and a
            // written text read back is among the largest things held.
            let mut pieces = core::mem::take(&mut self.current);
            if self.moved || pieces.iter().any(moves) {
                self.moving += 1;
            }
            if self.streamed {
                // Handed out: the run holds no pieces.
                self.ended.push((k, pieces));
                self.runs.push(Run::new(Vec::new()));
            } else {
                pieces.shrink_to_fit();
                self.runs.push(Run::new(pieces));
            }
        }
        self.feed = None;
        self.streamed = false;
        self.moved = false;
        self.declined = false;
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
            if self.feed.is_some_and(|f| f != m.piece.feed) {
                self.close_run();
            }
            self.feed = Some(m.piece.feed);
            self.current.push(m.piece);
        }
    }

    /// Hands out what the last line ended of runs read part by part and,
    /// where the run being read holds `chunk` pieces and `stream` wants
    /// it, those pieces.
    fn hand_out(&mut self, chunk: usize, stream: &mut dyn RunStream) {
        for (k, rest) in self.ended.drain(..) {
            stream.pieces(k, &rest, true);
        }
        while chunk > 0 && !self.declined && self.current.len() >= chunk {
            let k = self.runs.len();
            if !self.streamed && !stream.wants(k, self.moving) {
                self.declined = true;
                return;
            }
            self.streamed = true;
            let rest = self.current.split_off(chunk);
            let part = core::mem::replace(&mut self.current, rest);
            self.moved |= part.iter().any(moves);
            stream.pieces(k, &part, false);
        }
    }
}

/// A reading that holds every run ([`MotionReader::read_part`]).
struct HoldAll;

impl RunStream for HoldAll {
    fn wants(&mut self, _: usize, _: usize) -> bool {
        false
    }
    fn pieces(&mut self, _: usize, _: &[Piece], _: bool) {}
}

/// What takes a run of a written text as it is read, part by part,
/// instead of the reading holding it ([`MotionReader::read_part_streaming`]).
pub trait RunStream {
    /// Whether the part's run `run` (its index among the part's runs;
    /// `moving`, its index among those that move, which is how
    /// `pair_runs` pairs them with the original's, if it moves) is handed
    /// out: asked once it holds the chunk's pieces.
    fn wants(&mut self, run: usize, moving: usize) -> bool;
    /// The next pieces of run `run`, in order; `end` with its last ones
    /// (possibly none).
    fn pieces(&mut self, run: usize, pieces: &[Piece], end: bool);
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
    pub fn read_part(&self, text: &[u8]) -> Result<PartRead, GcodeError> {
        self.read_part_streaming(text, 0, &mut HoldAll)
    }

    /// [`MotionReader::read_part`], handing each run that `stream` wants
    /// to it `chunk` pieces at a time as they are read (and the rest at
    /// its end) instead of holding it: such a run is in the runs returned
    /// with no pieces. The memory held then grows with the runs not
    /// handed out, not with a long written run.
    pub fn read_part_streaming(
        &self,
        text: &[u8],
        chunk: usize,
        stream: &mut dyn RunStream,
    ) -> Result<PartRead, GcodeError> {
        let mut part = self.start_part();
        for line in line_slices(text) {
            part.line(line?, chunk, stream)?;
        }
        part.finish(stream)
    }

    /// [`MotionReader::read_part`] of the text `source` reads to its end
    /// (taken a chunk of lines at a time).
    pub fn read_part_from(&self, source: &mut dyn Read) -> Result<PartRead, ReadBackError> {
        self.read_part_streaming_from(source, 0, &mut HoldAll)
    }

    /// [`MotionReader::read_part_streaming`] of the text `source` reads
    /// to its end, taken [`READ_BACK_BYTES`] of lines at a time: the text
    /// is never held whole.
    pub fn read_part_streaming_from(
        &self,
        source: &mut dyn Read,
        chunk: usize,
        stream: &mut dyn RunStream,
    ) -> Result<PartRead, ReadBackError> {
        self.read_part_in_slices(source, READ_BACK_BYTES, chunk, stream)
    }

    /// [`MotionReader::read_part_streaming_from`], the text taken `bytes`
    /// of lines at a time.
    fn read_part_in_slices(
        &self,
        source: &mut dyn Read,
        bytes: usize,
        chunk: usize,
        stream: &mut dyn RunStream,
    ) -> Result<PartRead, ReadBackError> {
        let mut part = self.start_part();
        crate::text_out::for_each_chunk(
            source,
            bytes,
            |bytes, first| -> Result<(), ReadBackError> {
                let lines = if first {
                    Box::new(line_slices(bytes)) as Box<dyn Iterator<Item = _>>
                } else {
                    Box::new(line_slices_of(bytes))
                };
                for line in lines {
                    part.line(line?, chunk, stream)?;
                }
                Ok(())
            },
            ReadBackError::Io,
        )?;
        Ok(part.finish(stream)?)
    }

    fn start_part(&self) -> PartReading {
        let mut r = self.r.clone();
        r.sink = Some(MotionSink::default());
        PartReading { r, next: self.next }
    }
}

/// Bytes of text [`MotionReader::read_part_streaming_from`] takes at a
/// time.
pub const READ_BACK_BYTES: usize = 1 << 20;

/// What reading a part gives: the reading that continues after it, its
/// outline and its runs ([`MotionReader::read_part`]).
pub type PartRead = (MotionReader, Vec<MotionOutline>, Vec<Run>);

/// Why a text could not be read back from its output.
#[derive(Debug, thiserror::Error)]
pub enum ReadBackError {
    #[error(transparent)]
    Gcode(#[from] GcodeError),
    #[error("reading the text back from the output")]
    Io(#[source] std::io::Error),
}

/// A part being read, line after line.
struct PartReading {
    r: Reader,
    next: usize,
}

impl PartReading {
    fn line(
        &mut self,
        (t, ending): (&str, &'static str),
        chunk: usize,
        stream: &mut dyn RunStream,
    ) -> Result<(), GcodeError> {
        self.r.step_in_place(self.next, t, ending)?;
        if let Some(sink) = &mut self.r.sink {
            sink.hand_out(chunk, stream);
        }
        self.next += 1;
        Ok(())
    }

    fn finish(self, stream: &mut dyn RunStream) -> Result<PartRead, GcodeError> {
        let PartReading { mut r, next } = self;
        r.first_number = next;
        r.check_closed()?;
        let mut sink = r.sink.take().unwrap_or_default();
        sink.close_run();
        sink.hand_out(0, stream);
        Ok((MotionReader { r, next }, sink.outline, sink.runs))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Read back from a source a few bytes of lines at a time, a part is
    /// read as from its whole text: the same outline, runs and reading
    /// after it, whatever the line endings (LF, CR LF, a lone CR), a
    /// byte-order mark at the start, arcs, and a last line without one.
    #[test]
    fn a_part_read_in_slices_is_the_part_read_whole() {
        let body = [
            "G21 G90",
            "G0 X0 Y0",
            "G1 X10 F1200",
            "G2 X20 Y0 R5",
            "G1 Y5 Z-1",
            "(a comment)",
            "G0 Z5",
            "G1 X0 Y10 F600",
            "M2",
        ];
        let mut texts: Vec<Vec<u8>> = ["\n", "\r\n", "\r"]
            .iter()
            .map(|eol| body.join(eol).into_bytes())
            .collect();
        texts.push([&b"\xEF\xBB\xBF"[..], &texts[0]].concat());
        texts.push([&texts[1][..], b"\r\n"].concat());
        let reader = MotionReader::new();
        for text in &texts {
            let (w_after, w_outline, w_runs) = reader.read_part(text).unwrap();
            for bytes in [1, 2, 3, 7, 64, 1 << 20] {
                let (after, outline, runs) = reader
                    .read_part_in_slices(&mut &text[..], bytes, 0, &mut HoldAll)
                    .unwrap();
                assert_eq!(outline, w_outline, "{bytes} bytes");
                assert_eq!(runs, w_runs, "{bytes} bytes");
                assert_eq!(after.next, w_after.next, "{bytes} bytes");
            }
        }
    }
}
