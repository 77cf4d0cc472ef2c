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

// Axis loops index several parallel arrays by axis number.
#![allow(clippy::needless_range_loop)]

use crate::error::WriteError;
use crate::program::{Feed, MotionMode, Program, RunSpan, Units};
use fairpath::geom::{flatten_params, Arc, Curve, ParamCurve, Plane, Vec3};
use fairpath::path::Piece;

mod blend;
mod carry;
mod style;

pub use blend::{before_runs as path_control_before_runs, PathControl};
pub use carry::MAX_COMMENT_CHARS;
pub use style::NumberStyle;

/// How NURBS pieces are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NurbsBlocks {
    /// Fanuc-style G6.2 blocks (3D, orders 2 to 4).
    G6_2Fanuc,
    /// LinuxCNC master's G6.2 blocks (in the plane the curve lies in).
    G6_2Linuxcnc,
    /// LinuxCNC G5.2/G5.3 blocks (in the plane the curve lies in).
    G5_2,
}

/// How arcs are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcWords {
    /// Centre offsets I, J, K (absolute centre after G90.1).
    Ijk,
    /// Radius R (negative for more than half a circle); IJK for arcs of
    /// nearly half a circle, whose centre R leaves ill-defined, and for
    /// full circles.
    R,
}

/// Options of [`write_gcode`].
#[derive(Clone, Debug, PartialEq)]
pub struct GcodeWriteOptions {
    /// Largest distance (mm) between a smoothed curve and what is written
    /// for it, as the written text reads back: G1 chords of curves written
    /// as lines, and the rounding of written coordinates (see
    /// [`write_decimals`]; at most [`ROUNDING_SHARE`] of it for any piece).
    pub chord_mm: f64,
    /// Fewest decimals of coordinates written in mm programs (4: 0.05 um
    /// rounding); more when `chord_mm` needs them ([`write_decimals`]).
    pub decimals_mm: usize,
    /// Fewest decimals of coordinates written in inch programs (5: 0.127
    /// um); more when `chord_mm` needs them.
    pub decimals_inch: usize,
    /// Write a `(smoothed by fairpath)` comment as the first line (after a
    /// leading `%` line).
    pub header: bool,
    /// Write arcs as G2/G3 in this form; `None`: as G1 chords.
    pub arcs: Option<ArcWords>,
    /// Write NURBS pieces as these blocks; `None`: as G1 chords.
    pub nurbs: Option<NurbsBlocks>,
    /// Always write a decimal point in numbers (`X5.`), whatever the input
    /// does: the controller requires it (Fanuc-family controls without
    /// decimal-point input read `X5` as 5 um). Without it the input's own
    /// style decides ([`NumberStyle::of`]: a program that always writes the
    /// point gets it in every number written for it, and leading zeros
    /// follow its habit).
    pub decimal_point: bool,
    /// The share of the tolerance (mm) the controller's blending may spend
    /// (LinuxCNC's `G64 P`). `G64 P<blend> Q0` (in the run's units, P
    /// rounded down) is written before each run that does not already run
    /// under it when [`GcodeWriteOptions::g64_always`] is set, or when the
    /// input's path control in force at the run blends beyond it
    /// ([`PathControl::exceeds`]: a `G64` with a larger P, `G64 P0` or a
    /// bare `G64`; the input used LinuxCNC's syntax, so the output may
    /// too). After the run the input's own path-control command in force
    /// there is written back as the input wrote it (if the input set one:
    /// otherwise ours stays in force). `Q0` turns off LinuxCNC's merging
    /// of short blocks (`G64 P` alone sets Q = P, and arcs and lines within
    /// Q of a line are replaced by it). `None`: path control is left as the
    /// input has it.
    pub g64_blend_mm: Option<f64>,
    /// Write `G64 P<g64_blend_mm> Q0` before every run, even where the
    /// input set no path control or a tighter one (the controller is
    /// LinuxCNC, whose default blends without a tolerance).
    pub g64_always: bool,
    /// Largest distance (mm) rounding may move a written point, whatever
    /// the chord tolerance: the direction and curvature of a short piece
    /// come from its written coordinates, and a rounding error `rho` on a
    /// piece of length `L` tilts it by about `rho / L`. A jerk-limited
    /// controller passing pieces one interpolation period `Ts` long at
    /// jerk `J` needs `rho` of about `J Ts^3 / 4` (5 nm for 20000 mm/s^3 and
    /// 1 ms: 6 decimals in mm; with 4, arcs of a few um written for a tight
    /// corner of butterfly-80 re-read with kinks of 0.05 rad and planned
    /// 2.6 times slower than the curves). `None`: the chord alone decides.
    pub resolution_mm: Option<f64>,
}

impl Default for GcodeWriteOptions {
    fn default() -> Self {
        GcodeWriteOptions {
            chord_mm: 0.001,
            decimals_mm: 4,
            decimals_inch: 5,
            header: true,
            arcs: None,
            nurbs: None,
            decimal_point: false,
            g64_blend_mm: None,
            g64_always: false,
            resolution_mm: None,
        }
    }
}

/// Most decimals [`write_decimals`] asks for (the fast formatting handles
/// up to 15).
const MAX_DECIMALS: usize = 12;

/// Share of the chord tolerance that the rounding of written coordinates
/// may take (more decimals are written until it fits): what it leaves is
/// for the chords, arcs or spline blocks themselves.
pub const ROUNDING_SHARE: f64 = 0.1;

/// How far rounding can move a written arc, in units of the rounding `rho`
/// of one point: start and end by `rho` each, the centre by `rho`, so the
/// radius by up to `2 rho` at either end and the angle by `2 rho / r` (a
/// chord of `2 rho` seen from the centre), so `rho + 2 rho + 2 rho`.
pub const ARC_ROUNDING_FACTOR: f64 = 5.0;

/// Decimals to write coordinates with in units of `mm_per_unit` mm, at
/// least `min`, and the largest distance (mm) rounding then moves a point:
/// each axis by at most half a unit of the last decimal, so
/// `sqrt(3) / 2 * 10^-decimals * mm_per_unit`. Decimals are added until that
/// is at most [`ROUNDING_SHARE`] of `chord_mm` (or [`MAX_DECIMALS`] are
/// reached); the curves are then sampled within `chord_mm` less the
/// rounding, so that the polyline as it reads back stays within
/// `chord_mm` of them (a segment between two moved points lies within the
/// larger move of the segment between the exact ones). Without this, 4
/// decimals (up to 0.087 um of rounding) on top of a chord error of 0.1 um
/// took LinuxCNC's `Cereal.ngc` smoothed at 0.001 mm to 0.001012 mm, and
/// `smooth` refused to write it. Writers of arcs pass `chord_mm /`
/// [`ARC_ROUNDING_FACTOR`].
pub fn write_decimals(chord_mm: f64, mm_per_unit: f64, min: usize) -> (usize, f64) {
    let rounding = |d: usize| 0.5 * 3f64.sqrt() * 10f64.powi(-(d as i32)) * mm_per_unit;
    let mut d = min;
    while d < MAX_DECIMALS && rounding(d) > ROUNDING_SHARE * chord_mm {
        d += 1;
    }
    (d, rounding(d))
}

/// Decimals of coordinates written in units of `mm_per_unit` mm (at least
/// `min`) under `opts`, and the distance (mm) rounding then moves a point:
/// [`write_decimals`] of the chord (divided by [`ARC_ROUNDING_FACTOR`]
/// when arcs are written), more when [`GcodeWriteOptions::resolution_mm`]
/// asks for them.
pub fn output_decimals(opts: &GcodeWriteOptions, mm_per_unit: f64, min: usize) -> (usize, f64) {
    let factor = if opts.arcs.is_some() {
        ARC_ROUNDING_FACTOR
    } else {
        1.0
    };
    let (d, _) = write_decimals(opts.chord_mm / factor, mm_per_unit, min);
    let rounding = |d: usize| 0.5 * 3f64.sqrt() * 10f64.powi(-(d as i32)) * mm_per_unit;
    let mut d = d;
    if let Some(r) = opts.resolution_mm {
        while d < MAX_DECIMALS && rounding(d) > r {
            d += 1;
        }
    }
    (d, rounding(d))
}

/// Distance (mm) within which a smoothed run end counts as the original
/// run end, so that the original coordinate text is written for it.
const SAME_POINT_MM: f64 = 1e-9;

/// Formats `v` with `decimals` decimals, trailing zeros and a trailing point
/// removed, and no negative zero. Values are rounded to the nearest unit of
/// the last decimal through integer arithmetic (std's exact float formatting
/// is the slowest part of writing large programs otherwise).
pub(crate) fn fmt_fixed(v: f64, decimals: usize) -> String {
    let scale = 10f64.powi(decimals as i32);
    let scaled = (v * scale).round();
    if decimals > 15 || !scaled.is_finite() || scaled.abs() >= 9.0e15 {
        return fmt_fixed_slow(v, decimals);
    }
    let n = scaled as i64;
    let neg = n < 0;
    let mut digits = n.unsigned_abs();
    let mut frac = [0u8; 16];
    let mut nf = 0;
    // Fraction digits, dropping trailing zeros.
    let mut significant = false;
    for _ in 0..decimals {
        let d = (digits % 10) as u8;
        digits /= 10;
        if d != 0 || significant {
            significant = true;
            frac[nf] = b'0' + d;
            nf += 1;
        }
    }
    let mut s = String::with_capacity(24);
    if neg && (digits != 0 || nf != 0) {
        s.push('-');
    }
    s.push_str(itoa_u64(digits).as_str());
    if nf > 0 {
        s.push('.');
        for i in (0..nf).rev() {
            s.push(frac[i] as char);
        }
    }
    s
}

fn itoa_u64(v: u64) -> String {
    v.to_string()
}

fn fmt_fixed_slow(v: f64, decimals: usize) -> String {
    let mut s = format!("{:.*}", decimals, v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

fn axis(p: Vec3, a: usize) -> f64 {
    match a {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    }
}

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

/// What [`write_gcode_with`] writes for one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunOutput<'a> {
    /// These pieces, as [`write_gcode`] writes them.
    Pieces(&'a [Piece]),
    /// The run's own lines, as they are (a motion word inserted where a
    /// line relies on a modal motion that the written program changed).
    Original,
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
    let eol = lines
        .iter()
        .map(|l| l.ending)
        .find(|e| !e.is_empty())
        .unwrap_or("\n");
    // The lines the output keeps are most of it for a comment-heavy
    // program: reserved once, the text is not copied as it grows.
    let kept: usize = lines.iter().map(|l| l.text.len() + l.ending.len()).sum();
    let mut out = String::with_capacity(kept + 256);
    // An expanded program says so first (after a leading `%`, which must
    // stay the first line).
    let leading_percent = matches!(lines.first(), Some(l) if l.text.trim_start().starts_with('%'));
    if program.expanded() && !leading_percent {
        out.push_str(EXPANDED_HEADER);
        out.push_str(eol);
    }
    let mut header_pending = opts.header;
    if header_pending && !leading_percent {
        out.push_str("(smoothed by fairpath)");
        out.push_str(eol);
        header_pending = false;
    }
    let mut style = NumberStyle::of(program);
    style.decimal_point |= opts.decimal_point;
    let path_before = blend::before_runs(program);
    // Modal state as the written program leaves it.
    let mut written_motion = MotionMode::None;
    let mut written_path: Option<String> = None;
    let mut i = 0;
    let mut run_idx = 0;
    while i < lines.len() {
        let line = &lines[i];
        let smoothed_run = match smoothed.get(run_idx) {
            Some(RunOutput::Pieces(p)) if runs[run_idx].first_line == line.number => Some(*p),
            Some(RunOutput::Original) if runs[run_idx].first_line == line.number => {
                // Copied line by line below.
                run_idx += 1;
                None
            }
            _ => None,
        };
        if let Some(pieces) = smoothed_run {
            let run = &runs[run_idx];
            let mut w = RunWriter::new(program, run, opts, eol, &mut out)?;
            w.style = style;
            w.path_before = path_before[run_idx].clone();
            w.path = written_path.take();
            w.write(pieces)?;
            if let Some(m) = w.motion {
                written_motion = m;
            }
            written_path = w.path;
            written_motion =
                restore_motion_before_block_delete(program, run, written_motion, eol, &mut out);
            // The last line of the span may be the last line of the file.
            let last = &lines[run.last_line - 1];
            if last.ending.is_empty() && run.last_line == lines.len() && out.ends_with(eol) {
                out.truncate(out.len() - eol.len());
            }
            i = run.last_line;
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
            written_motion = program
                .lines()
                .get(i + 1)
                .map_or(written_motion, |n| n.motion_before);
        }
        if blend::sets_path_control(line) {
            written_path = line.path_control_after.clone();
        }
        out.push_str(&line.text);
        out.push_str(line.ending);
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
    Ok(out)
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
    let Some(next) = lines.get(run.last_line) else {
        return written;
    };
    let wanted = next.motion_before;
    let deleted = |l: &crate::program::ProgramLine| l.text.trim_start().starts_with('/');
    // Up to the next motion word that runs either way.
    let slash_first = lines[run.last_line..]
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

/// The state of writing one run.
struct RunWriter<'a> {
    program: &'a Program,
    run: &'a RunSpan,
    opts: &'a GcodeWriteOptions,
    eol: &'static str,
    out: &'a mut String,
    /// Units of the run: mm per unit, decimals, and the chord the G1
    /// chords of curves get (what rounding leaves of `chord_mm`).
    scale: f64,
    decimals: usize,
    chord: f64,
    /// Original feeds and their text, to write F as the program did.
    feed_texts: Vec<Feed>,
    /// Position as the written program re-reads it (mm).
    cur: Vec3,
    /// Modal feed of the written program (mm/min).
    cur_feed: Option<f64>,
    /// Plane as the written program leaves it.
    plane: Plane,
    /// Motion mode of the last move written, if any.
    motion: Option<MotionMode>,
    /// Path-control command in force in the written program.
    path: Option<String>,
    /// The input's path control in force before the run.
    path_before: Option<PathControl>,
    /// How numbers are written.
    style: NumberStyle,
    /// The N word the next block written starts with.
    pending_n: Option<String>,
    /// N words of replaced lines the next block merges (text, value).
    merged_n: Vec<(String, f64)>,
    first_move: bool,
    /// Arc centres relative to the start (G91.1) in this run.
    arc_incremental: bool,
}

impl<'a> RunWriter<'a> {
    fn new(
        program: &'a Program,
        run: &'a RunSpan,
        opts: &'a GcodeWriteOptions,
        eol: &'static str,
        out: &'a mut String,
    ) -> Result<RunWriter<'a>, WriteError> {
        let lines = program.lines();
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
        for l in &lines[run.first_line - 1..run.last_line] {
            feed_texts.extend(l.feed_after.iter().cloned());
        }
        let before = run.first_line.checked_sub(2).map(|k| &lines[k]);
        let first_move = &program.moves()[run.moves.start];
        Ok(RunWriter {
            program,
            run,
            opts,
            eol,
            out,
            scale,
            decimals,
            chord,
            feed_texts,
            cur: first_move.piece.start(),
            cur_feed: run.feed_before.as_ref().map(|f| f.mm_per_min),
            plane: before.map_or(Plane::Xy, |l| l.plane_after),
            motion: None,
            path: None,
            path_before: None,
            style: NumberStyle::default(),
            pending_n: None,
            merged_n: Vec::new(),
            first_move: true,
            arc_incremental: before.is_none_or(|l| l.arc_incremental_after),
        })
    }

    /// The blending command of [`GcodeWriteOptions::g64_blend_mm`] in the
    /// run's units: P with enough decimals to be within 1% of the asked
    /// blend (rounded down).
    /// `None` when the blend is not positive (LinuxCNC reads `P0` as no
    /// tolerance at all).
    fn g64(&self) -> Option<String> {
        let b = self.opts.g64_blend_mm? / self.scale;
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
                self.style.apply(fmt_fixed(p, d)),
                self.style.apply("0".into())
            )
        })
    }

    /// Whether our blending command goes before this run: always when
    /// asked, or when the input's path control in force blends beyond the
    /// share ([`PathControl::exceeds`]).
    fn tightens_blending(&self) -> bool {
        let Some(blend) = self.opts.g64_blend_mm else {
            return false;
        };
        self.opts.g64_always || self.path_before.as_ref().is_some_and(|p| p.exceeds(blend))
    }

    /// A number in the run's units.
    fn num(&self, v_mm: f64) -> String {
        self.style
            .apply(fmt_fixed(v_mm / self.scale, self.decimals))
    }

    fn feed_text(&self, mm_per_min: f64) -> String {
        self.feed_texts
            .iter()
            .find(|f| f.mm_per_min == mm_per_min && f.units == self.run.units)
            .map_or_else(
                || self.style.apply(fmt_fixed(mm_per_min / self.scale, 4)),
                |f| f.text.to_string(),
            )
    }

    fn push_line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push_str(self.eol);
    }

    /// Writes the run's pieces with the span's lines without moves in
    /// place.
    fn write(&mut self, pieces: &[Piece]) -> Result<(), WriteError> {
        let run = self.run;
        if self.tightens_blending() {
            if let Some(pc) = self.g64() {
                if self.path.as_ref() != Some(&pc) {
                    self.push_line(&pc);
                    self.path = Some(pc);
                }
            }
        }
        // The next line of the span to handle.
        let mut next_line = run.first_line;
        let n_pieces = pieces.len();
        for (pi, piece) in pieces.iter().enumerate() {
            self.reach(&mut next_line, piece.source_lines.1);
            self.write_merged_n("the next block");
            let last = pi + 1 == n_pieces;
            match &piece.curve {
                Curve::Line(l) => self.write_g1(l.p1, last, piece.feed)?,
                Curve::Arc(a) if self.opts.arcs.is_some() => self.write_arc(a, last, piece.feed)?,
                Curve::Nurbs(n) if self.opts.nurbs.is_some() => {
                    self.write_nurbs(n, last, piece.feed)?
                }
                c => {
                    let pts = piece_points(c, self.chord);
                    let n = pts.len();
                    for (k, p) in pts.into_iter().enumerate() {
                        self.write_g1(p, last && k + 1 == n, piece.feed)?;
                    }
                }
            }
        }
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
    /// `end` reaches (see [`write_gcode`]): lines without moves before
    /// `end` are copied, replaced lines up to `end` give their comments (a
    /// line) and N words (the next block's, or merged into it).
    fn reach(&mut self, next: &mut usize, end: usize) {
        let lines = self.program.lines();
        while *next <= self.run.last_line {
            let l = &lines[*next - 1];
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
    fn write_merged_n(&mut self, what: &str) {
        if self.merged_n.is_empty() {
            return;
        }
        let ns = std::mem::take(&mut self.merged_n);
        for c in carry::merged_n_comments(&ns, what) {
            self.push_line(&c);
        }
    }

    /// The pending N word and a space, for the start of the next block.
    fn take_n(&mut self) -> String {
        self.pending_n
            .take()
            .map_or_else(String::new, |n| format!("{n} "))
    }

    fn copy_interior(&mut self, n: usize) {
        let l = &self.program.lines()[n - 1];
        self.out.push_str(&l.text);
        self.out.push_str(l.ending);
        if l.words.iter().any(|w| w.letter == 'F') {
            self.cur_feed = l.feed_after.as_ref().map(|f| f.mm_per_min);
        }
        if l.interpreted {
            self.plane = l.plane_after;
        }
    }

    /// After the run: the feed, plane and path control the original has
    /// in force there.
    fn restore_state(&mut self) {
        let lines = self.program.lines();
        let last = &lines[self.run.last_line - 1];
        if let Some(f) = &self.run.feed_after {
            if self.cur_feed != Some(f.mm_per_min) {
                let text = if f.units == self.run.units {
                    f.text.to_string()
                } else {
                    self.style.apply(fmt_fixed(f.mm_per_min / self.scale, 4))
                };
                self.push_line(&format!("F{text}"));
            }
        }
        if self.plane != last.plane_after {
            self.push_line(last.plane_after.gword());
            self.plane = last.plane_after;
        }
        if self.opts.g64_blend_mm.is_some() {
            if let Some(orig) = &last.path_control_after {
                if self.path.as_ref() != Some(orig) {
                    let orig = orig.clone();
                    self.push_line(&orig);
                    self.path = Some(orig);
                }
            }
        }
    }

    /// The coordinate words that take the written position to `target`
    /// (the original text of the run's end point when `run_end` and it is
    /// that point), and the position they re-read to.
    fn coord_words(&self, target: Vec3, run_end: bool) -> (String, Vec3) {
        let moves = self.program.moves();
        let last_move = &moves[self.run.moves.end - 1];
        let orig_end = last_move.piece.end();
        let letters = ['X', 'Y', 'Z'];
        let mut words = String::new();
        let mut next = self.cur;
        for a in 0..3 {
            let tv = axis(target, a);
            let now = axis(self.cur, a);
            let text = if self.run.incremental {
                let t = fmt_fixed((tv - now) / self.scale, self.decimals);
                if t == "0" {
                    continue;
                }
                t
            } else {
                let orig = if run_end && target.dist(orig_end) <= SAME_POINT_MM {
                    last_move.end_text[a].clone()
                } else {
                    None
                };
                match orig {
                    Some(t) => {
                        let v: f64 = t.parse().unwrap_or(f64::NAN) * self.scale;
                        if v == now {
                            continue;
                        }
                        t
                    }
                    None => {
                        let t = fmt_fixed(tv / self.scale, self.decimals);
                        if t == fmt_fixed(now / self.scale, self.decimals) {
                            continue;
                        }
                        t
                    }
                }
            };
            let v: f64 = text.parse().unwrap_or(f64::NAN) * self.scale;
            let new = if self.run.incremental { now + v } else { v };
            match a {
                0 => next.x = new,
                1 => next.y = new,
                _ => next.z = new,
            }
            words.push(' ');
            words.push(letters[a]);
            words.push_str(&self.style.apply(text));
        }
        (words, next)
    }

    /// The F word for a move at `feed`, if one is due.
    fn feed_word(&mut self, feed: Option<f64>) -> String {
        match feed {
            Some(f) if self.first_move || self.cur_feed != Some(f) => {
                self.cur_feed = Some(f);
                format!(" F{}", self.feed_text(f))
            }
            _ => String::new(),
        }
    }

    fn write_g1(&mut self, p: Vec3, run_end: bool, feed: Option<f64>) -> Result<(), WriteError> {
        if !p.is_finite() {
            return Err(WriteError::NotFinite);
        }
        let (words, next) = self.coord_words(p, run_end);
        if words.is_empty() {
            return Ok(());
        }
        self.cur = next;
        let f = self.feed_word(feed);
        self.first_move = false;
        self.motion = Some(MotionMode::Linear);
        let line = format!("{}G1{words}{f}", self.take_n());
        self.push_line(&line);
        Ok(())
    }

    /// A NURBS piece as a spline block ([`crate::write_spline`]); at the
    /// run's end a G1 to the program's own end text follows when the block's
    /// rounded last point is not it (run ends are kept exactly).
    fn write_nurbs(
        &mut self,
        n: &fairpath::geom::Nurbs,
        run_end: bool,
        feed: Option<f64>,
    ) -> Result<(), WriteError> {
        use crate::write_spline::{g5_2_blocks, g6_2_block, G6Dialect, SplineWriteOptions};
        let kind = self.opts.nurbs.expect("called with NURBS blocks on");
        let feed_text = match feed {
            Some(f) if self.first_move || self.cur_feed != Some(f) => {
                self.cur_feed = Some(f);
                Some(self.feed_text(f))
            }
            _ => None,
        };
        let so = SplineWriteOptions {
            mm_per_unit: self.scale,
            decimals: self.decimals,
            decimal_point: self.style.decimal_point,
            line_ending: self.eol,
            incremental: self.run.incremental,
            feed: feed_text,
        };
        let plane = || {
            Plane::of_points(
                &n.points,
                0.5 * 10f64.powi(-(self.decimals as i32)) * self.scale,
            )
            .ok_or_else(|| WriteError::SplineCurve("the curve is in no principal plane".into()))
        };
        let text = match kind {
            NurbsBlocks::G6_2Fanuc => g6_2_block(n, G6Dialect::Fanuc, &so)?,
            NurbsBlocks::G6_2Linuxcnc => {
                let plane = plane()?;
                self.select_plane(plane);
                g6_2_block(n, G6Dialect::Linuxcnc { plane, method: 1 }, &so)?
            }
            NurbsBlocks::G5_2 => {
                let plane = plane()?;
                self.select_plane(plane);
                g5_2_blocks(n, plane, &so)?
            }
        };
        let n_word = self.take_n();
        self.out.push_str(&n_word);
        self.out.push_str(&text);
        // Where the written text leaves the tool: the rounded last point.
        let end = n.points[n.points.len() - 1];
        let mut cur = end;
        for a in 0..3 {
            let t = fmt_fixed(axis(end, a) / self.scale, self.decimals);
            let v = t.parse::<f64>().unwrap_or(f64::NAN) * self.scale;
            match a {
                0 => cur.x = v,
                1 => cur.y = v,
                _ => cur.z = v,
            }
        }
        self.cur = cur;
        self.first_move = false;
        self.motion = Some(match kind {
            NurbsBlocks::G6_2Fanuc => MotionMode::NurbsG6,
            NurbsBlocks::G6_2Linuxcnc => MotionMode::Linear,
            NurbsBlocks::G5_2 => MotionMode::Nurbs,
        });
        if run_end {
            // Only the axes whose written text differs get a word.
            self.write_g1(n.end(), true, None)?;
        }
        Ok(())
    }

    /// A plane line when `plane` is not the written one.
    fn select_plane(&mut self, plane: Plane) {
        if plane != self.plane {
            self.push_line(plane.gword());
            self.plane = plane;
        }
    }

    fn write_arc(&mut self, a: &Arc, run_end: bool, feed: Option<f64>) -> Result<(), WriteError> {
        if !(a.p1.is_finite() && a.center.is_finite()) {
            return Err(WriteError::NotFinite);
        }
        let Some(plane) = Plane::of_normal(a.normal) else {
            // Not in a principal plane: chords.
            let pts = piece_points(&Curve::Arc(*a), self.chord);
            let n = pts.len();
            for (k, p) in pts.into_iter().enumerate() {
                self.write_g1(p, run_end && k + 1 == n, feed)?;
            }
            return Ok(());
        };
        let (words, next) = self.coord_words(a.p1, run_end);
        let full_turn = a.sweep >= 2.0 * std::f64::consts::PI * (1.0 - 1e-12);
        let (s, e) = (plane.local(self.cur), plane.local(next));
        if !full_turn && s[0] == e[0] && s[1] == e[1] {
            // The rounded ends coincide in the plane: a G2/G3 would be a
            // full circle. The arc is shorter than the rounding: a line.
            return self.write_g1(a.p1, run_end, feed);
        }
        let ccw = a.normal == plane.normal();
        // A plane change on a line of its own: on the move's line it would
        // make the move a state change, which readers keep out of runs.
        self.select_plane(plane);
        let mut line = self.take_n();
        line.push_str(if ccw { "G3" } else { "G2" });
        line.push_str(&words);
        let r = 0.5 * (a.r0 + a.r1);
        let half = std::f64::consts::PI;
        let use_r = self.opts.arcs == Some(ArcWords::R)
            && !full_turn
            && ((a.sweep - half).abs() > 0.1 * half);
        if use_r {
            let signed = if a.sweep > half { -r } else { r };
            line.push_str(" R");
            line.push_str(&self.num(signed));
        } else {
            let letters = ['I', 'J', 'K'];
            let (ia, ib, _) = plane.axes();
            for ax in [ia, ib] {
                let c = axis(a.center, ax);
                let v = if self.arc_incremental {
                    c - axis(self.cur, ax)
                } else {
                    c
                };
                line.push(' ');
                line.push(letters[ax]);
                line.push_str(&self.num(v));
            }
        }
        let turns = ((a.sweep / (2.0 * half)) * (1.0 - 1e-12)).floor() as u64 + 1;
        if turns > 1 {
            line.push_str(&format!(" P{turns}"));
        }
        self.cur = next;
        let f = self.feed_word(feed);
        line.push_str(&f);
        self.first_move = false;
        self.motion = Some(if ccw {
            MotionMode::ArcCcw
        } else {
            MotionMode::ArcCw
        });
        self.push_line(&line);
        Ok(())
    }
}

/// The points after the start of a curve at which G1 lines end.
fn piece_points(c: &Curve, chord: f64) -> Vec<Vec3> {
    match c {
        Curve::Line(l) => vec![l.p1],
        _ => {
            let ts = flatten_params(c, chord);
            let n = ts.len();
            ts.into_iter()
                .enumerate()
                .skip(1)
                .map(|(i, t)| if i + 1 == n { c.end() } else { c.eval(t) })
                .collect()
        }
    }
}

#[cfg(test)]
mod fmt_tests {
    use super::{fmt_fixed, fmt_fixed_slow};

    #[test]
    fn fast_formatting_matches_std_within_half_a_unit() {
        for &v in &[
            0.0,
            -0.0,
            1.5,
            -1.25,
            0.00004,
            -0.00004,
            12.34565,
            99999.0,
            -3.0e-5,
            1.0e9,
            0.1 + 0.2,
        ] {
            for d in [3usize, 4, 5] {
                let a: f64 = fmt_fixed(v, d).parse().unwrap();
                let b: f64 = fmt_fixed_slow(v, d).parse().unwrap();
                assert!(
                    (a - b).abs() <= 10f64.powi(-(d as i32)) * 1.0001,
                    "{v} {d}: {a} {b}"
                );
                assert!((a - v).abs() <= 0.5 * 10f64.powi(-(d as i32)) * 1.0001);
            }
        }
        assert_eq!(fmt_fixed(-0.00001, 4), "0");
        assert_eq!(fmt_fixed(2.5, 4), "2.5");
        assert_eq!(fmt_fixed(-12.0, 4), "-12");
        assert_eq!(fmt_fixed(0.05, 4), "0.05");
    }
}
