//! Writes a program back as G-code with each run replaced by its smoothed
//! pieces as G1 polylines; everything else is copied byte for byte.

// Axis loops index several parallel arrays by axis number.
#![allow(clippy::needless_range_loop)]

use crate::error::WriteError;
use crate::program::{Feed, MotionMode, Program, RunSpan, Units};
use fairpath::geom::{flatten_params, Curve, ParamCurve, Vec3};
use fairpath::path::Piece;

/// Options of [`write_gcode`].
#[derive(Clone, Debug, PartialEq)]
pub struct GcodeWriteOptions {
    /// Largest distance (mm) between a smoothed curve and the G1 polyline
    /// written for it, as the written text reads back: the chords and the
    /// rounding of their coordinates together (see [`write_decimals`]).
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
}

impl Default for GcodeWriteOptions {
    fn default() -> Self {
        GcodeWriteOptions {
            chord_mm: 0.001,
            decimals_mm: 4,
            decimals_inch: 5,
            header: true,
        }
    }
}

/// Most decimals [`write_decimals`] asks for (the fast formatting handles
/// up to 15).
const MAX_DECIMALS: usize = 12;

/// Share of the chord tolerance that coordinate rounding may take before
/// more decimals are written.
const ROUNDING_SHARE: f64 = 0.1;

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
/// `smooth` refused to write it.
pub fn write_decimals(chord_mm: f64, mm_per_unit: f64, min: usize) -> (usize, f64) {
    let rounding = |d: usize| 0.5 * 3f64.sqrt() * 10f64.powi(-(d as i32)) * mm_per_unit;
    let mut d = min;
    while d < MAX_DECIMALS && rounding(d) > ROUNDING_SHARE * chord_mm {
        d += 1;
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
/// * Lines outside runs are copied unchanged, in place. Lines inside a run's
///   span that hold no move (comments, blank lines, F-only lines, modal words
///   restating the state) are emitted before the first output piece whose
///   `source_lines.1` is greater than their line number.
/// * Each piece is written as `G1` lines: a line as one G1, arcs and NURBS as
///   polylines within `chord_mm` of the curve as they read back (sampled by
///   `flatten_params` within what coordinate rounding leaves of it, with
///   more decimals when the chord is small: [`write_decimals`]). Every
///   output line carries an explicit `G1`.
/// * Coordinates are in the run's units; in G91 (incremental) runs they are
///   written as increments (the program stays position-independent), each
///   increment computed from the position the written text re-reads to, so
///   rounding does not accumulate. Axes whose value does not change are
///   omitted. The run's end point is written with the original text of each
///   coordinate (absolute runs) so that it re-reads exactly.
/// * F is written on the first G1 of a run and whenever the feed changes; if
///   the modal feed after the run would differ from the original's, an
///   `F` line restores it.
/// * A line after a run that relies on the modal motion mode (axis words
///   without G0/G1/G2/G3) gets the motion word it relied on inserted when the
///   written G1 lines changed that mode.
pub fn write_gcode(
    program: &Program,
    smoothed: &[Vec<Piece>],
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
    let mut out = String::new();
    let mut header_pending = opts.header;
    if header_pending && !matches!(lines.first(), Some(l) if l.text.trim_start().starts_with('%')) {
        out.push_str("(smoothed by fairpath)");
        out.push_str(eol);
        header_pending = false;
    }
    // Motion mode as the written program leaves it.
    let mut written_motion = MotionMode::None;
    let mut i = 0;
    let mut run_idx = 0;
    while i < lines.len() {
        let line = &lines[i];
        if run_idx < runs.len() && runs[run_idx].first_line == line.number {
            let run = &runs[run_idx];
            let wrote_g1 = write_run(program, run, &smoothed[run_idx], opts, eol, &mut out)?;
            if wrote_g1 {
                written_motion = MotionMode::Linear;
            }
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
        out.push_str(&line.text);
        out.push_str(line.ending);
        if header_pending {
            out.push_str("(smoothed by fairpath)");
            out.push_str(if line.ending.is_empty() { "" } else { eol });
            header_pending = false;
        }
        i += 1;
    }
    Ok(out)
}

/// Writes one run; returns whether any G1 line was written.
fn write_run(
    program: &Program,
    run: &RunSpan,
    pieces: &[Piece],
    opts: &GcodeWriteOptions,
    eol: &str,
    out: &mut String,
) -> Result<bool, WriteError> {
    let lines = program.lines();
    let moves = program.moves();
    let scale = run.units.mm_per_unit();
    let min_decimals = match run.units {
        Units::Mm => opts.decimals_mm,
        Units::Inch => opts.decimals_inch,
    };
    let (decimals, rounding) = write_decimals(opts.chord_mm, scale, min_decimals);
    // The chords get what the rounding leaves.
    let chord = opts.chord_mm - rounding;
    if chord.is_nan() || chord <= 0.0 {
        return Err(WriteError::ChordBelowRounding {
            chord_mm: opts.chord_mm,
            decimals,
            rounding_mm: rounding,
        });
    }
    let letters = ['X', 'Y', 'Z'];
    // Original feeds and their text, to write F as the program did.
    let mut feed_texts: Vec<Feed> = Vec::new();
    feed_texts.extend(run.feed_before.iter().cloned());
    for l in &lines[run.first_line - 1..run.last_line] {
        feed_texts.extend(l.feed_after.iter().cloned());
    }
    let feed_text = |mm_per_min: f64| -> String {
        feed_texts
            .iter()
            .find(|f| f.mm_per_min == mm_per_min && f.units == run.units)
            .map_or_else(|| fmt_fixed(mm_per_min / scale, 4), |f| f.text.clone())
    };
    // Interior lines without moves, emitted in place.
    let interior: Vec<usize> = (run.first_line..=run.last_line)
        .filter(|&n| lines[n - 1].moves.is_empty())
        .collect();
    let mut next_interior = 0;
    let first_move = &moves[run.moves.start];
    let last_move = &moves[run.moves.end - 1];
    let orig_end = last_move.piece.end();
    // Position as the written program re-reads it (mm).
    let mut cur = first_move.piece.start();
    // Modal feed of the written program (equal to the original's before
    // the run).
    let mut cur_feed: Option<f64> = run.feed_before.as_ref().map(|f| f.mm_per_min);
    let mut first_g1 = true;
    let mut wrote = false;
    let n_pieces = pieces.len();
    for (pi, piece) in pieces.iter().enumerate() {
        while next_interior < interior.len() && piece.source_lines.1 > interior[next_interior] {
            let l = &lines[interior[next_interior] - 1];
            out.push_str(&l.text);
            out.push_str(l.ending);
            if l.words.iter().any(|w| w.letter == 'F') {
                cur_feed = l.feed_after.as_ref().map(|f| f.mm_per_min);
            }
            next_interior += 1;
        }
        let pts = piece_points(&piece.curve, chord);
        let n_pts = pts.len();
        for (k, p) in pts.into_iter().enumerate() {
            if !p.is_finite() {
                return Err(WriteError::NotFinite);
            }
            let is_run_end = pi + 1 == n_pieces && k + 1 == n_pts;
            let mut words = String::new();
            let mut next = cur;
            for a in 0..3 {
                let target = axis(p, a);
                let now = axis(cur, a);
                let text = if run.incremental {
                    let t = fmt_fixed((target - now) / scale, decimals);
                    if t == "0" {
                        continue;
                    }
                    t
                } else {
                    let orig = if is_run_end && p.dist(orig_end) <= SAME_POINT_MM {
                        last_move.end_text[a].clone()
                    } else {
                        None
                    };
                    match orig {
                        Some(t) => {
                            let v: f64 = t.parse().unwrap_or(f64::NAN) * scale;
                            if v == now {
                                continue;
                            }
                            t
                        }
                        None => {
                            let t = fmt_fixed(target / scale, decimals);
                            if t == fmt_fixed(now / scale, decimals) {
                                continue;
                            }
                            t
                        }
                    }
                };
                let v: f64 = text.parse().unwrap_or(f64::NAN) * scale;
                let new = if run.incremental { now + v } else { v };
                match a {
                    0 => next.x = new,
                    1 => next.y = new,
                    _ => next.z = new,
                }
                words.push(' ');
                words.push(letters[a]);
                words.push_str(&text);
            }
            if words.is_empty() {
                continue;
            }
            cur = next;
            out.push_str("G1");
            out.push_str(&words);
            if let Some(f) = piece.feed {
                if first_g1 || cur_feed != Some(f) {
                    out.push_str(" F");
                    out.push_str(&feed_text(f));
                    cur_feed = Some(f);
                }
            }
            first_g1 = false;
            wrote = true;
            out.push_str(eol);
        }
    }
    for &n in &interior[next_interior..] {
        let l = &lines[n - 1];
        out.push_str(&l.text);
        out.push_str(l.ending);
        if l.words.iter().any(|w| w.letter == 'F') {
            cur_feed = l.feed_after.as_ref().map(|f| f.mm_per_min);
        }
    }
    // Restore the modal feed the original leaves after the run.
    if let Some(f) = &run.feed_after {
        if cur_feed != Some(f.mm_per_min) {
            out.push('F');
            out.push_str(&if f.units == run.units {
                f.text.clone()
            } else {
                fmt_fixed(f.mm_per_min / scale, 4)
            });
            out.push_str(eol);
        }
    }
    Ok(wrote)
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
