//! Writing one run: its pieces in order, the lines of its span without
//! moves in place, the N numbers and comments of the lines it replaces,
//! and after it the feed, plane and path control the program has there.

use super::blend::PathControl;
use super::carry;
use super::numbers::{fmt_fixed, output_decimals, MAX_DECIMALS};
use super::style::NumberStyle;
use super::GcodeWriteOptions;
use crate::error::WriteError;
use crate::program::{Feed, MotionMode, Program, RunSpan, Units};
use crate::text_out::Spiller;
use fairpath::geom::{Curve, Plane, Vec3};
use fairpath::path::Piece;

/// The blending command of [`GcodeWriteOptions::g64_blend_mm`] in units
/// of `scale` mm, in `style`: P with enough decimals to be within 1% of the
/// asked blend (rounded down). `None` when the blend is not positive
/// (LinuxCNC reads `P0` as no tolerance at all).
pub(super) fn g64_command(
    opts: &GcodeWriteOptions,
    scale: f64,
    style: NumberStyle,
) -> Option<String> {
    let b = opts.g64_blend_mm? / scale;
    if !(b.is_finite() && b > 0.0) {
        return None;
    }
    let mut d = 4;
    while d < MAX_DECIMALS && 10f64.powi(-(d as i32)) > 0.01 * b {
        d += 1;
    }
    let p = (b * 10f64.powi(d as i32)).floor() / 10f64.powi(d as i32);
    (p > 0.0).then(|| {
        format!(
            "G64 P{} Q{}",
            style.apply(fmt_fixed(p, d)),
            style.apply("0".into())
        )
    })
}

/// Whether our blending command goes before a run where the input's path
/// control in force is `path_before`: always when asked
/// ([`GcodeWriteOptions::g64_always`]), or when that control blends beyond
/// the share ([`PathControl::exceeds`]).
pub(super) fn tightens_blending(
    opts: &GcodeWriteOptions,
    path_before: Option<&PathControl>,
) -> bool {
    let Some(blend) = opts.g64_blend_mm else {
        return false;
    };
    opts.g64_always || path_before.is_some_and(|p| p.exceeds(blend))
}

/// Writes the path-control command `pc` as a line of `out` unless it is
/// the one `in_force` in the written program, which it then is.
pub(super) fn put_path_control(
    out: &mut String,
    eol: &str,
    in_force: &mut Option<String>,
    pc: &str,
) {
    if in_force.as_deref() != Some(pc) {
        out.push_str(pc);
        out.push_str(eol);
        *in_force = Some(pc.to_string());
    }
}

/// The state of writing one run.
pub(super) struct RunWriter<'a> {
    pub(super) program: &'a Program,
    pub(super) run: &'a RunSpan,
    pub(super) opts: &'a GcodeWriteOptions,
    pub(super) eol: &'static str,
    pub(super) out: &'a mut String,
    /// Where `out`'s complete lines go as the run is written.
    spill: &'a mut dyn Spiller,
    /// Units of the run: mm per unit, decimals, and the chord the G1
    /// chords of curves get (what rounding leaves of `chord_mm`).
    pub(super) scale: f64,
    pub(super) decimals: usize,
    pub(super) chord: f64,
    /// Original feeds and their text, to write F as the program did.
    pub(super) feed_texts: Vec<Feed>,
    /// Position as the written program re-reads it (mm).
    pub(super) cur: Vec3,
    /// Modal feed of the written program (mm/min).
    pub(super) cur_feed: Option<f64>,
    /// Plane as the written program leaves it.
    pub(super) plane: Plane,
    /// Motion mode of the last move written, if any.
    pub(super) motion: Option<MotionMode>,
    /// Path-control command in force in the written program.
    pub(super) path: Option<String>,
    /// The input's path control in force before the run.
    pub(super) path_before: Option<PathControl>,
    /// How numbers are written.
    pub(super) style: NumberStyle,
    /// The N word the next block written starts with.
    pub(super) pending_n: Option<String>,
    /// N words of replaced lines the next block merges (text, value).
    pub(super) merged_n: Vec<(String, f64)>,
    pub(super) first_move: bool,
    /// Arc centres relative to the start (G91.1) in this run.
    pub(super) arc_incremental: bool,
    /// The planned speed (mm/s) of the piece being written, if known.
    pub(super) speed: Option<f64>,
    /// The most decimals a move of the run has been written with so far.
    pub(super) finest: usize,
    /// The fewest decimals the end of the piece being written gets: those
    /// the next piece needs at its start ([`RunWriter::start_decimals`]).
    pub(super) end_decimals: usize,
}

impl<'a> RunWriter<'a> {
    pub(super) fn new(
        program: &'a Program,
        run: &'a RunSpan,
        opts: &'a GcodeWriteOptions,
        eol: &'static str,
        out: &'a mut String,
        spill: &'a mut dyn Spiller,
    ) -> Result<RunWriter<'a>, WriteError> {
        let scale = run.units.mm_per_unit();
        let min_decimals = match run.units {
            Units::Mm => opts.decimals_mm,
            Units::Inch => opts.decimals_inch,
        };
        let (decimals, rounding) = output_decimals(opts, scale, min_decimals);
        // The chords get what the rounding leaves.
        let chord = opts.chord_mm - rounding;
        if chord.is_nan() || chord <= 0.0 {
            return Err(WriteError::ChordBelowRounding {
                chord_mm: opts.chord_mm,
                decimals,
                rounding_mm: rounding,
            });
        }
        let mut feed_texts: Vec<Feed> = Vec::new();
        feed_texts.extend(run.feed_before.iter().cloned());
        for l in program.lines_between(run.first_line, run.last_line) {
            feed_texts.extend(l.feed_after.iter().cloned());
        }
        let (plane, arc_incremental) = program.arc_modes_before(run.first_line);
        let first_move = &program.moves()[run.moves.start];
        Ok(RunWriter {
            program,
            run,
            opts,
            eol,
            out,
            spill,
            scale,
            decimals,
            chord,
            feed_texts,
            cur: first_move.piece.start(),
            cur_feed: run.feed_before.as_ref().map(|f| f.mm_per_min),
            plane,
            motion: None,
            path: None,
            path_before: None,
            style: NumberStyle::default(),
            pending_n: None,
            merged_n: Vec::new(),
            first_move: true,
            arc_incremental,
            speed: None,
            finest: decimals,
            end_decimals: 0,
        })
    }

    /// The blending command of [`GcodeWriteOptions::g64_blend_mm`] in the
    /// run's units ([`g64_command`]).
    pub(super) fn g64(&self) -> Option<String> {
        g64_command(self.opts, self.scale, self.style)
    }

    /// Whether our blending command goes before this run
    /// ([`tightens_blending`]).
    pub(super) fn tightens_blending(&self) -> bool {
        tightens_blending(self.opts, self.path_before.as_ref())
    }

    pub(super) fn push_line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push_str(self.eol);
    }

    /// Writes the run's pieces with the span's lines without moves in
    /// place; `speeds`, one per piece or none, say how fast each is passed
    /// ([`RunOutput::Rendered`](super::RunOutput::Rendered)).
    pub(super) fn write(&mut self, pieces: &[Piece], speeds: &[f64]) -> Result<(), WriteError> {
        let run = self.run;
        self.begin();
        // The next line of the span to handle.
        let mut next_line = run.first_line;
        let n_pieces = pieces.len();
        for (pi, piece) in pieces.iter().enumerate() {
            let last = pi + 1 == n_pieces;
            let next = pieces.get(pi + 1).map(|p| (p, speeds.get(pi + 1).copied()));
            self.end_decimals = next.map_or(0, |(p, v)| self.start_decimals(p, v));
            self.piece(&mut next_line, piece, speeds.get(pi).copied(), last)?;
        }
        self.finish(next_line)
    }

    /// [`RunWriter::write`] of the pieces `source` gives part after part
    /// ([`RenderedParts`](super::RenderedParts)): the same text.
    pub(super) fn write_parts(
        &mut self,
        source: &mut dyn super::RenderedParts,
    ) -> Result<(), WriteError> {
        self.begin();
        let mut next_line = self.run.first_line;
        // One piece held back: whether it is the run's last is known only
        // once the next part comes.
        let mut held: Option<(Piece, Option<f64>)> = None;
        while let Some((pieces, speeds)) = source.next_part() {
            let with_speeds = speeds.len() == pieces.len();
            let mut speeds = speeds.into_iter();
            for piece in pieces {
                let speed = if with_speeds { speeds.next() } else { None };
                self.end_decimals = self.start_decimals(&piece, speed);
                if let Some((p, v)) = held.replace((piece, speed)) {
                    self.piece(&mut next_line, &p, v, false)?;
                }
            }
        }
        self.end_decimals = 0;
        if let Some((p, v)) = held {
            self.piece(&mut next_line, &p, v, true)?;
        }
        self.finish(next_line)
    }

    /// What goes before the run's first block: our blending command where
    /// it tightens the program's.
    fn begin(&mut self) {
        if self.tightens_blending() {
            if let Some(pc) = self.g64() {
                put_path_control(self.out, self.eol, &mut self.path, &pc);
            }
        }
    }

    /// One piece of the run (`last`: the run's last), after the span's
    /// lines it reaches, with its planned `speed` if known.
    fn piece(
        &mut self,
        next_line: &mut usize,
        piece: &Piece,
        speed: Option<f64>,
        last: bool,
    ) -> Result<(), WriteError> {
        self.spill.spill(self.out).map_err(WriteError::Output)?;
        self.reach(next_line, piece.source_lines.1);
        self.write_merged_n("the next block");
        self.speed = speed;
        match &piece.curve {
            Curve::Line(l) => self.write_g1(l.p1, last, piece.feed),
            Curve::Arc(a) if self.opts.arcs.is_some() => self.write_arc(a, last, piece.feed),
            Curve::Nurbs(n) if self.opts.nurbs.is_some() => self.write_nurbs(n, last, piece.feed),
            c => self.write_chords(c, last, piece.feed),
        }
    }

    /// After the run's last block: the span's lines left, the N words
    /// pending, and the state the program has after the run.
    fn finish(&mut self, mut next_line: usize) -> Result<(), WriteError> {
        let run = self.run;
        self.reach(&mut next_line, run.last_line + 1);
        if let Some(n) = self.pending_n.take() {
            let value = n[1..].parse().unwrap_or(f64::NAN);
            self.merged_n.insert(0, (n, value));
        }
        self.write_merged_n("the blocks above");
        self.restore_state();
        Ok(())
    }

    /// Handles the span's lines from `next` on that a piece ending on line
    /// `end` reaches (see [`write_gcode`](super::write_gcode)): lines without moves before
    /// `end` are copied, replaced lines up to `end` give their comments (a
    /// line) and N words (the next block's, or merged into it).
    pub(super) fn reach(&mut self, next: &mut usize, end: usize) {
        let program = self.program;
        while *next <= self.run.last_line {
            let l = program.line(*next);
            // Lines of a multi-line spline block carry part of its move:
            // they are replaced with it.
            let replaced = !l.moves.is_empty() || l.in_block;
            if !(*next < end || (replaced && *next == end)) {
                break;
            }
            if replaced {
                let comments = carry::comments_of(&l.text);
                if !comments.is_empty() {
                    let text = comments.join(" ");
                    self.push_line(&text);
                }
                if let Some(n) = carry::n_word(&l.words) {
                    if self.pending_n.is_none() && self.merged_n.is_empty() {
                        self.pending_n = Some(n);
                    } else {
                        let value = l
                            .words
                            .iter()
                            .find(|w| w.letter == 'N')
                            .map_or(f64::NAN, |w| w.value);
                        self.merged_n.push((n, value));
                    }
                }
            } else {
                self.copy_interior(*next);
            }
            *next += 1;
        }
    }

    /// The comment lines naming the merged N words, if any.
    pub(super) fn write_merged_n(&mut self, what: &str) {
        if self.merged_n.is_empty() {
            return;
        }
        let ns = std::mem::take(&mut self.merged_n);
        for c in carry::merged_n_comments(&ns, what) {
            self.push_line(&c);
        }
    }

    /// The pending N word and a space, for the start of the next block.
    pub(super) fn take_n(&mut self) -> String {
        self.pending_n
            .take()
            .map_or_else(String::new, |n| format!("{n} "))
    }

    pub(super) fn copy_interior(&mut self, n: usize) {
        let l = self.program.line(n);
        self.out.push_str(&l.text);
        self.out.push_str(l.ending);
        if l.words.iter().any(|w| w.letter == 'F') {
            self.cur_feed = l.feed_after.as_ref().map(|f| f.mm_per_min);
        }
        if l.interpreted {
            // Only a line with a plane word changes the written plane: a
            // comment between the moves leaves the plane the written arcs
            // selected (the program's own plane there is not in force in
            // the written text).
            if l.words
                .iter()
                .any(|w| w.letter == 'G' && [17.0, 18.0, 19.0].contains(&w.value))
            {
                self.plane = l.plane_after;
            }
            // A bare motion word (`G3` alone) between the run's moves sets
            // the mode the lines after the run see if no move follows it.
            if l.sets_motion {
                self.motion = Some(l.motion_after);
            }
        }
    }

    /// After the run: the feed, plane and path control the original has
    /// in force there.
    pub(super) fn restore_state(&mut self) {
        let last = self.program.line(self.run.last_line);
        if let Some(f) = &self.run.feed_after {
            if self.cur_feed != Some(f.mm_per_min) {
                let text = if f.units == self.run.units {
                    f.text.to_string()
                } else {
                    self.feed_number(f.mm_per_min)
                };
                self.push_line(&format!("F{text}"));
            }
        }
        if self.plane != last.plane_after {
            self.push_line(last.plane_after.gword());
            self.plane = last.plane_after;
        }
        // A run that goes on into the next part (a window's cut) keeps our
        // blending command: a path-control line would end the run there.
        let goes_on = self.program.window_cut()
            && self.program.lines().last().map(|l| l.number) == Some(self.run.last_line);
        if self.opts.g64_blend_mm.is_some() && !goes_on {
            if let Some(orig) = &last.path_control_after {
                put_path_control(self.out, self.eol, &mut self.path, orig);
            }
        }
    }
}
