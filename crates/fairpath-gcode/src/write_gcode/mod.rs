//! Writes a program back as G-code with each run replaced by its smoothed
//! pieces; everything else is copied byte for byte.
//!
//! Lines are written as G1; arcs as G2/G3 in their principal plane (IJK or
//! R form) or as G1 chords; NURBS as G1 chords (the spline blocks are
//! written by [`crate::write_spline`]). Nothing of the replaced lines but
//! their moves is dropped: their N numbers, comments and the lines without
//! moves between them are written beside the blocks that replace them
//! ([`write_gcode`] says where), numbers follow the input's style
//! ([`NumberStyle`]), and a blending mode of the input that could spend more
//! than the blending share is tightened around the runs
//! ([`GcodeWriteOptions::g64_blend_mm`]).
//!
//! * `options.rs`: [`GcodeWriteOptions`], [`ArcWords`], [`NurbsBlocks`].
//! * `numbers.rs`: how many decimals ([`write_decimals`],
//!   [`output_decimals`]) and number formatting.
//! * `style.rs`: the input's number style ([`NumberStyle`]).
//! * `run.rs`: writing one run: its pieces in order with the span's other
//!   lines, then the state the program has after it.
//! * `blocks.rs`: the blocks written for the pieces (G1, G2/G3, spline
//!   blocks) and their coordinate and F words.
//! * `carry.rs`: N numbers and comments of replaced lines.
//! * `blend.rs`: G64 around runs.
//!
//! This file: the program, its lines outside runs copied through.

// Axis loops index several parallel arrays by axis number.
#![allow(clippy::needless_range_loop)]

use crate::error::WriteError;
use crate::facts::ProgramFacts;
use crate::program::{MotionMode, Program, RunSpan};
use crate::text_out::{Spill, Spiller, TextOut, SPILL_BYTES};
use fairpath::path::Piece;
use std::cell::RefCell;

mod blend;
mod blocks;
mod carry;
mod numbers;
mod options;
mod run;
mod style;

pub(crate) use blend::{before_runs, has_path_control};
pub use blend::{before_runs as path_control_before_runs, PathBlending, PathControl};
pub use blocks::FINE_PERIODS;
pub use carry::MAX_COMMENT_CHARS;
pub(crate) use numbers::fmt_fixed;
pub use numbers::{output_decimals, write_decimals, ARC_ROUNDING_FACTOR, ROUNDING_SHARE};
pub use options::{ArcWords, GcodeWriteOptions, NurbsBlocks};
pub use style::{NumberStyle, StyleCount};

use run::RunWriter;

/// Writes the program with `smoothed[k]` replacing the moves of run `k`
/// (same order as [`Program::runs`]).
///
/// * Lines outside runs are copied unchanged, in place. The lines of a
///   replaced run's span are handled in order, each before the blocks of
///   the first output piece that reaches it: a line without moves
///   (comments, blank lines, F-only lines, modal words restating the state,
///   a plane change) when the piece's `source_lines.1` is greater than its
///   number, a replaced line (one with moves, or a line of a multi-line
///   spline block) when it is at least its number. A line without moves is
///   copied verbatim. A replaced line's comments (`( ... )` and `; ...`, as
///   written) become a line of their own. Its N word goes on the first
///   block written for that piece (`N20 G1 X...`), unless another replaced
///   line reached by the same block already gave it one: such N words are
///   named in a comment just before the block, `(N30-N50 merged into the
///   next block)` for the stretch of lines numbered N30 to N50 (increasing
///   stretches as `first-last`, others one by one, lines of at most
///   [`MAX_COMMENT_CHARS`]). So the N number of the first line of a run
///   starts its first block, comments keep their order, and no N number or
///   comment of the input is lost. N words that no block took (the pieces
///   after them wrote nothing) are named in a comment after the run's
///   blocks, `(N90 merged into the blocks above)`.
/// * A line is one `G1`; an arc is one `G2`/`G3` in its principal plane
///   when [`GcodeWriteOptions::arcs`] is set (with the plane word where the
///   written plane differs, `P` for several turns), otherwise G1 chords
///   within `chord_mm` as they read back; NURBS are G1 chords. An arc whose
///   rounded ends coincide in its plane (which G-code reads as a full
///   circle) is written as a G1. Every output line carries its motion word.
/// * Numbers follow the input's style ([`NumberStyle::of`]: a decimal
///   point in every number when the input always writes one or
///   [`GcodeWriteOptions::decimal_point`] asks for it, leading zeros as the
///   input writes them; counts such as arc turns `P2` stay integers, and
///   spline blocks keep their leading zeros).
/// * Coordinates are in the run's units, with more decimals when the chord
///   tolerance needs them ([`write_decimals`]); in G91 (incremental) runs
///   they are written as increments (the program stays
///   position-independent), each computed from the position the written
///   text re-reads to, so rounding does not accumulate; arc centres are
///   offsets from that position (absolute after G90.1). Axes whose value
///   does not change are omitted. The run's end point is written with the
///   original text of each coordinate (absolute runs) so that it re-reads
///   exactly.
/// * F is written on the first move of a run and whenever the feed changes;
///   if the modal feed after the run would differ from the original's, an
///   `F` line restores it. A plane the written arcs changed is restored
///   after the run, and so is the program's path-control command when
///   [`GcodeWriteOptions::g64_blend_mm`] replaced it (see there when).
/// * A line after a run that relies on the modal motion mode (axis words
///   without G0/G1/G2/G3) gets the motion word it relied on inserted when the
///   written lines changed that mode.
pub fn write_gcode(
    program: &Program,
    smoothed: &[Vec<Piece>],
    opts: &GcodeWriteOptions,
) -> Result<String, WriteError> {
    let outputs: Vec<RunOutput> = smoothed.iter().map(|p| RunOutput::Pieces(p)).collect();
    write_gcode_with(program, &outputs, opts)
}

/// A run's rendering handed to the writer part after part
/// ([`RunOutput::Parts`]), so that a long run's rendering (millions of
/// blocks on a one-run raster) is never held whole.
pub trait RenderedParts {
    /// The run's next pieces, each with the highest speed (mm/s) it is
    /// planned to be passed at (as [`RunOutput::Rendered`]; empty where
    /// unknown), or `None` once every piece is given. A source that fails
    /// keeps its error and returns `None`: the caller, who reads it after
    /// the text is written, discards the text.
    fn next_part(&mut self) -> Option<(Vec<Piece>, Vec<f64>)>;
}

/// What [`write_gcode_with`] writes for one run.
#[derive(Clone, Copy)]
pub enum RunOutput<'a> {
    /// These pieces, as [`write_gcode`] writes them.
    Pieces(&'a [Piece]),
    /// These pieces, each with the highest speed (mm/s) it is planned to
    /// be passed at ([`fairpath::render::Rendered::speeds`]): those
    /// shorter than [`FINE_PERIODS`] periods of travel get more decimals
    /// ([`GcodeWriteOptions::period_s`]).
    Rendered(&'a [Piece], &'a [f64]),
    /// The pieces and speeds of [`RunOutput::Rendered`], taken part after
    /// part from a source as they are written.
    Parts(&'a RefCell<dyn RenderedParts + 'a>),
    /// The run's own lines, as they are (a motion word inserted where a
    /// line relies on a modal motion that the written program changed).
    Original,
}

impl core::fmt::Debug for RunOutput<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RunOutput::Pieces(p) => f.debug_tuple("Pieces").field(&p.len()).finish(),
            RunOutput::Rendered(p, _) => f.debug_tuple("Rendered").field(&p.len()).finish(),
            RunOutput::Parts(_) => f.write_str("Parts"),
            RunOutput::Original => f.write_str("Original"),
        }
    }
}

/// First line of the output of an expanded program
/// ([`Program::expanded`]): its loops and calls are written out.
pub const EXPANDED_HEADER: &str =
    "(fairpath: expanded from LinuxCNC o-word control flow; every move explicit)";

/// [`write_gcode`], with some runs kept as the program wrote them.
pub fn write_gcode_with(
    program: &Program,
    smoothed: &[RunOutput],
    opts: &GcodeWriteOptions,
) -> Result<String, WriteError> {
    let facts = ProgramFacts::of(program);
    let mut out: Vec<u8> = Vec::new();
    write_part(
        program,
        smoothed,
        opts,
        &facts,
        &mut WriterCarry::new(),
        &mut out,
    )?;
    // Whole lines of `str`s: UTF-8 throughout.
    String::from_utf8(out).map_err(|e| WriteError::Output(std::io::Error::other(e)))
}

/// What writing one part of a program ([`crate::interp::PartReader`])
/// leaves to the next: the state of the written program that the writer
/// follows. [`WriterCarry::new`] is the start of a program.
#[derive(Clone, Debug, PartialEq)]
pub struct WriterCarry {
    /// The part is the program's first (it gets the headers).
    first: bool,
    /// The motion mode and path control the written program has in force.
    motion: MotionMode,
    path: Option<String>,
    /// The input's path control in force ([`blend::before_runs`]).
    path_in_force: Option<PathControl>,
    /// The line a window's cut put in at the end of the part before
    /// ([`Program::window_cut`]), held back where that part's run was
    /// kept as written: it is written before this part's text where the
    /// run going on is rewritten here, and dropped where it is kept too
    /// (the program's own line then goes on from the line before the
    /// cut, as the program has it).
    cut_line: Option<String>,
}

impl Default for WriterCarry {
    fn default() -> Self {
        WriterCarry::new()
    }
}

impl WriterCarry {
    /// Before the first line of a program.
    pub fn new() -> WriterCarry {
        WriterCarry {
            first: true,
            motion: MotionMode::None,
            path: None,
            path_in_force: None,
            cut_line: None,
        }
    }

    /// The line held back at the end of the part written last
    /// ([`WriterCarry::cut_line`]), with its ending.
    pub fn cut_line(&self) -> Option<&str> {
        self.cut_line.as_deref()
    }
}

/// [`write_gcode_with`] of a part of a program (or a whole one), whose
/// whole has `facts`, from the state `carry` leaves it in, which it then
/// holds for the next part. The parts written one after the other make the
/// text [`write_gcode_with`] makes of the whole program.
///
/// The text goes to `out` as it is made, a megabyte or so at a time
/// ([`crate::text_out`]): a long rendered run is never held whole. Returns
/// the lines written (as `str::lines` counts them).
pub fn write_part(
    program: &Program,
    smoothed: &[RunOutput],
    opts: &GcodeWriteOptions,
    facts: &ProgramFacts,
    carry: &mut WriterCarry,
    text_out: &mut dyn TextOut,
) -> Result<usize, WriteError> {
    let runs = program.run_spans();
    if smoothed.len() != runs.len() {
        return Err(WriteError::RunCount {
            expected: runs.len(),
            got: smoothed.len(),
        });
    }
    if !(opts.chord_mm.is_finite() && opts.chord_mm > 0.0) {
        return Err(WriteError::BadChord(opts.chord_mm));
    }
    let lines = program.lines();
    let eol = facts.eol;
    // The lines the output keeps are most of it for a comment-heavy
    // program: reserved once, the text is not copied as it grows.
    let kept: usize = lines.iter().map(|l| l.text.len() + l.ending.len()).sum();
    let mut out = String::with_capacity(kept.min(2 * SPILL_BYTES) + 256);
    let mut spill = Spill::new(text_out);
    // An expanded program says so first (after a leading `%`, which must
    // stay the first line).
    let leading_percent =
        carry.first && matches!(lines.first(), Some(l) if l.text.trim_start().starts_with('%'));
    if carry.first && program.expanded() && !leading_percent {
        out.push_str(EXPANDED_HEADER);
        out.push_str(eol);
    }
    let mut header_pending = opts.header && carry.first;
    if header_pending && !leading_percent {
        out.push_str("(smoothed by fairpath)");
        out.push_str(eol);
        header_pending = false;
    }
    let mut style = facts.style;
    style.decimal_point |= opts.decimal_point;
    let (path_before, path_after) = blend::before_runs_from(program, carry.path_in_force.take());
    // Modal state as the written program leaves it.
    let mut written_motion = carry.motion;
    let mut written_path: Option<String> = carry.path.take();
    // The cut line held back by the part before: written where the run
    // going on is rewritten.
    if let Some(cut) = carry.cut_line.take() {
        let kept = matches!(smoothed.first(), Some(RunOutput::Original));
        if program.window_continued() && !kept {
            out.push_str(&cut);
        }
    }
    // This part's cut line, held back where its run is kept.
    let hold_last = program.window_cut() && matches!(smoothed.last(), Some(RunOutput::Original));
    let mut held = None;
    // The last line of a kept window that ends a run cut into windows,
    // after which the program's own path control is written back.
    let mut restore_after = None;
    let mut i = 0;
    let mut run_idx = 0;
    while i < lines.len() {
        let line = &lines[i];
        let smoothed_run = match smoothed.get(run_idx) {
            Some(RunOutput::Original) if runs[run_idx].first_line == line.number => {
                // Copied line by line below; a window of a run that is
                // cut into windows under our blending command keeps it
                // in force (`kept_window_blending`).
                let run = &runs[run_idx];
                match kept_window_blending(program, run_idx, opts, &path_before) {
                    Some(WindowBlending::Begin) => {
                        let scale = run.units.mm_per_unit();
                        if let Some(pc) = run::g64_command(opts, scale, style) {
                            run::put_path_control(&mut out, eol, &mut written_path, &pc);
                        }
                    }
                    Some(WindowBlending::End) => restore_after = Some(run.last_line),
                    None => {}
                }
                run_idx += 1;
                None
            }
            Some(o) if runs[run_idx].first_line == line.number => Some(o),
            _ => None,
        };
        if let Some(output) = smoothed_run {
            let run = &runs[run_idx];
            let mut w = RunWriter::new(program, run, opts, eol, &mut out, &mut spill)?;
            w.style = style;
            w.path_before = path_before[run_idx].clone();
            w.path = written_path.take();
            match output {
                RunOutput::Pieces(p) => w.write(p, &[])?,
                RunOutput::Rendered(p, v) => w.write(p, v)?,
                RunOutput::Parts(source) => w.write_parts(&mut *source.borrow_mut())?,
                RunOutput::Original => unreachable!("copied line by line"),
            }
            if let Some(m) = w.motion {
                written_motion = m;
            }
            written_path = w.path;
            written_motion =
                restore_motion_before_block_delete(program, run, written_motion, eol, &mut out);
            // The last line of the span may be the last line of the file.
            let last = program.line(run.last_line);
            i = run.last_line + 1 - program.first_number();
            if last.ending.is_empty() && i == lines.len() && out.ends_with(eol) {
                out.truncate(out.len() - eol.len());
            }
            run_idx += 1;
            continue;
        }
        if line.interpreted && line.uses_modal_motion && written_motion != line.motion_before {
            if let Some(g) = line.motion_before.gword() {
                // Insert the motion word the line relies on.
                let col = line.insert_column - 1;
                let byte = line
                    .text
                    .char_indices()
                    .nth(col)
                    .map_or(line.text.len(), |(b, _)| b);
                out.push_str(&line.text[..byte]);
                out.push_str(&g);
                out.push(' ');
                out.push_str(&line.text[byte..]);
                out.push_str(line.ending);
                written_motion = line.motion_before;
                i += 1;
                continue;
            }
        }
        if line.interpreted && line.sets_motion {
            written_motion = line.motion_after;
        }
        if blend::sets_path_control(line) {
            written_path = line.path_control_after.clone();
        }
        spill.spill(&mut out).map_err(WriteError::Output)?;
        if hold_last && i + 1 == lines.len() {
            held = Some(format!("{}{}", line.text, line.ending));
            i += 1;
            continue;
        }
        out.push_str(&line.text);
        out.push_str(line.ending);
        if restore_after == Some(line.number) {
            restore_after = None;
            if let Some(orig) = &line.path_control_after {
                if written_path.as_ref() != Some(orig) && line.ending.is_empty() {
                    out.push_str(eol);
                }
                run::put_path_control(&mut out, eol, &mut written_path, orig);
            }
        }
        if i == 0 && leading_percent && program.expanded() {
            out.push_str(EXPANDED_HEADER);
            out.push_str(if line.ending.is_empty() { "" } else { eol });
        }
        if header_pending {
            out.push_str("(smoothed by fairpath)");
            out.push_str(if line.ending.is_empty() { "" } else { eol });
            header_pending = false;
        }
        i += 1;
    }
    *carry = WriterCarry {
        first: false,
        motion: written_motion,
        path: written_path,
        path_in_force: path_after,
        cut_line: held,
    };
    spill.finish(&mut out).map_err(WriteError::Output)
}

/// Where a kept window of a run cut into windows stands in our blending
/// command ([`kept_window_blending`]).
enum WindowBlending {
    /// The run's first window: the command goes before it.
    Begin,
    /// The run's last window: the program's own path control is written
    /// back after it.
    End,
}

/// For run `k` of `program`, kept as the program wrote it: where it is a
/// window of a run cut into windows ([`Program::window_cut`]) around which
/// the writer writes its blending command ([`run::tightens_blending`]),
/// whether it is the run's first window or its last.
///
/// Why: the command goes before the run's first window and the program's
/// own after its last, whichever windows are rewritten. A window written
/// between a kept one and a rewritten one would put a path-control line
/// inside the run, which ends it there (`Cereal.ngc`, `auto`, windows of
/// one line: 51 runs read back where the program has 50). A kept window
/// under our command is the program's own path blended within the share,
/// which is closer to it than the program's own blending; the planned
/// times do not depend on the blending command.
fn kept_window_blending(
    program: &Program,
    k: usize,
    opts: &GcodeWriteOptions,
    path_before: &[Option<PathControl>],
) -> Option<WindowBlending> {
    let goes_on = program.window_cut() && k + 1 == program.run_spans().len();
    let continued = program.window_continued() && k == 0;
    if !run::tightens_blending(opts, path_before[k].as_ref()) {
        return None;
    }
    match (continued, goes_on) {
        (false, true) => Some(WindowBlending::Begin),
        (true, false) => Some(WindowBlending::End),
        _ => None,
    }
}

/// After a written run whose motion mode differs from the program's, a
/// `/` line coming before the next motion word would see one mode or the
/// other depending on the block-delete switch (a motion word inserted into
/// it runs only with the switch off): the program's mode is restored on a
/// line of its own right after the run. Returns the written mode.
fn restore_motion_before_block_delete(
    program: &Program,
    run: &RunSpan,
    written: MotionMode,
    eol: &str,
    out: &mut String,
) -> MotionMode {
    let lines = program.lines();
    // Index of the line after the run.
    let after = run.last_line + 1 - program.first_number();
    let Some(next) = lines.get(after) else {
        return written;
    };
    let wanted = next.motion_before;
    let deleted = |l: &crate::program::ProgramLine| l.text.trim_start().starts_with('/');
    // Up to the next motion word that runs either way.
    let slash_first = lines[after..]
        .iter()
        .take_while(|l| !l.sets_motion || deleted(l))
        .any(|l| l.interpreted && deleted(l));
    // Only a straight mode: a bare G5.2 would open a block, a bare G81 run
    // a cycle.
    let straight = matches!(wanted, MotionMode::Linear | MotionMode::Rapid);
    match wanted.gword() {
        Some(g) if written != wanted && slash_first && straight => {
            out.push_str(&g);
            out.push_str(eol);
            wanted
        }
        _ => written,
    }
}
