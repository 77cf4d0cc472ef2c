//! Where a long run is cut into windows ([`RunWindows`]): at the middle of
//! one of its lines, so that a program of one long run (a raster) is read,
//! smoothed, written and checked a window at a time by
//! [`super::PartReader`], and its memory grows with a window, not with the
//! run.
//!
//! The cut is a line the reader puts in before the cut line: `G1` to the
//! cut line's midpoint, each coordinate the exact decimal midpoint of the
//! texts the program wrote for the line's two ends (one decimal more than
//! they have: the midpoint of two decimals of `d` places is a decimal of at
//! most `d + 1`). The midpoint therefore lies on the programmed line (up to
//! the reading of a decimal as f64, as every programmed point), the
//! original path is the same set of points, and the cut line, read after
//! it, goes on from the midpoint to its own end in absolute distance mode.
//! One window's run ends at the midpoint and the next one's starts there.
//!
//! Only a plain line is cut: in a run, absolute (G90), G1 at a feed per
//! minute, without cutter compensation or an open spline block, and whose
//! words are its N number, `G1` and X, Y, Z as plain numbers (comments
//! stay on it); the program has no `/` lines (whose look-ahead the writer
//! does after a run).

use super::State;
use crate::lexer::{scan_line, ItemKind};
use crate::program::{MotionMode, Move, MoveKind, ProgramLine};
use fairpath::geom::Vec3;

/// How long runs are cut into windows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunWindows {
    /// Lines a window holds before a cut is looked for.
    pub lines: usize,
    /// Shortest line cut (mm): the smoothing either side of the cut keeps
    /// the cut line straight (a fit ends along it), which costs nothing on
    /// a long line and slows a curve traced by short ones (a circle of
    /// 10,000 segments in windows of 300 lines planned 4.5 s written by
    /// `bspline-fit`, against 1.4 s whole). A run without such a line is
    /// not cut.
    pub min_cut_mm: f64,
}

impl RunWindows {
    /// Windows of 2,048 lines cut at lines of 1 mm or more (`auto`'s
    /// shortest section cut, [`fairpath::choose::SECTION_LINES`]). On the
    /// one-run raster `surface-raster-large.ngc` (3.7 MB) that holds the
    /// job under 20 times the input with every method, for about a tenth
    /// more time than the run whole with `bspline-corner` and `auto`
    /// (docs/performance.md, "Long runs cut into windows").
    pub const DEFAULT: RunWindows = RunWindows {
        lines: 2048,
        min_cut_mm: 1.0,
    };
}

/// The line that cuts the run before `text` (line `number`), read after
/// `prev` (whose last move is `prev_move`) in the state `st`, if `text`
/// is a plain line at least `min_mm` long (see the module docs).
pub(super) fn cut_before(
    st: &State,
    prev: &ProgramLine,
    prev_move: &Move,
    text: &str,
    number: usize,
    min_mm: f64,
) -> Option<String> {
    let in_run = prev.interpreted
        && !prev.breaks_run
        && !prev.in_block
        && prev_move.kind == MoveKind::Linear
        && prev_move.pinned.is_none()
        && !prev_move.piece.rapid;
    let plain_state = !st.ended
        && !st.incremental
        && !st.comp
        && st.motion == MotionMode::Linear
        && st.feed_mode == super::FeedMode::PerMinute
        && !st.spline.is_open();
    if !in_run || !plain_state {
        return None;
    }
    let src = scan_line(text, number).ok()?;
    if src.block_delete || src.percent || src.program_number || src.oword.is_some() {
        return None;
    }
    let mut ends: [Option<&str>; 3] = [None; 3];
    let mut seen_n = false;
    let mut seen_g = false;
    for item in &src.items {
        let ItemKind::Word {
            letter, literal, ..
        } = &item.kind
        else {
            return None;
        };
        let literal = literal.as_deref()?;
        match letter {
            'N' if !seen_n => seen_n = true,
            'G' if !seen_g && decimal(literal).is_some_and(|d| d == (1, 0)) => seen_g = true,
            'X' | 'Y' | 'Z' => {
                let a = (*letter as usize) - ('X' as usize);
                if ends[a].is_some() {
                    return None;
                }
                ends[a] = Some(literal);
            }
            _ => return None,
        }
    }
    let mm = st.units.mm_per_unit();
    let mut end = st.pos;
    let mut words = String::from("G1");
    for a in 0..3 {
        let Some(b) = ends[a] else { continue };
        let from = st.axis_text[a].as_deref()?;
        let mid = decimal_midpoint(from, b)?;
        let v = decimal(b)?;
        set(&mut end, a, v.0 as f64 / 10f64.powi(v.1 as i32) * mm);
        words.push(' ');
        words.push(['X', 'Y', 'Z'][a]);
        words.push_str(&mid);
    }
    let length = st.pos.dist(end);
    (words.len() > 2 && length > 0.0 && length >= min_mm).then_some(words)
}

fn set(p: &mut Vec3, axis: usize, v: f64) {
    match axis {
        0 => p.x = v,
        1 => p.y = v,
        _ => p.z = v,
    }
}

/// Digits a decimal may have: its mantissa and the midpoint's fit an i128.
const MAX_DIGITS: usize = 30;

/// A plain decimal (`-12.5`, `+.25`, `3`, `3.`): its mantissa and its
/// places, `value = mantissa / 10^places`; `None` for anything else.
fn decimal(text: &str) -> Option<(i128, u32)> {
    let (neg, body) = match text.as_bytes().first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    };
    let (int, frac) = body.split_once('.').unwrap_or((body, ""));
    let digits = int.len() + frac.len();
    if digits == 0 || digits > MAX_DIGITS {
        return None;
    }
    let mut m: i128 = 0;
    for c in int.bytes().chain(frac.bytes()) {
        if !c.is_ascii_digit() {
            return None;
        }
        m = m * 10 + i128::from(c - b'0');
    }
    Some((if neg { -m } else { m }, frac.len() as u32))
}

/// The midpoint of two plain decimals as a decimal, exactly: with the
/// places of the longer, or one more where the sum is odd; always with a
/// decimal point and a digit either side of it (`2.7175`, `0.5`, `3.0`).
fn decimal_midpoint(a: &str, b: &str) -> Option<String> {
    let ((ma, pa), (mb, pb)) = (decimal(a)?, decimal(b)?);
    let places = pa.max(pb);
    let sum = ma * 10i128.pow(places - pa) + mb * 10i128.pow(places - pb);
    let (mut m, mut places) = if sum % 2 == 0 {
        (sum / 2, places)
    } else {
        (sum * 5, places + 1)
    };
    if places == 0 {
        (m, places) = (m * 10, 1);
    }
    let digits = m.unsigned_abs().to_string();
    let places = places as usize;
    let padded = format!("{digits:0>width$}", width = places + 1);
    let (int, frac) = padded.split_at(padded.len() - places);
    let sign = if m < 0 { "-" } else { "" };
    Some(format!("{sign}{int}.{frac}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(text: &str) -> f64 {
        text.parse().unwrap()
    }

    #[test]
    fn decimal_midpoints_are_exact() {
        let cases = [
            ("2.274", "3.161", "2.7175"),
            ("0", "1", "0.5"),
            ("1", "3", "2.0"),
            ("-0.0005", "0.0005", "0.0000"),
            ("-1.5", "-2.25", "-1.875"),
            ("+.25", ".5", "0.375"),
            ("3.", "4", "3.5"),
            ("-0.001", "0", "-0.0005"),
            ("10", "-10.2", "-0.1"),
        ];
        for (a, b, want) in cases {
            assert_eq!(decimal_midpoint(a, b).as_deref(), Some(want), "{a} {b}");
            assert_eq!(decimal_midpoint(b, a).as_deref(), Some(want), "{b} {a}");
        }
        for bad in ["", "-", ".", "1e3", "1.2.3", "x", "#1", "1-"] {
            assert_eq!(decimal_midpoint(bad, "1"), None, "{bad:?}");
        }
    }

    fn text_of(m: i64, places: u32) -> String {
        let s = m.unsigned_abs().to_string();
        let s = format!("{s:0>w$}", w = places as usize + 1);
        let (i, f) = s.split_at(s.len() - places as usize);
        format!("{}{i}.{f}", if m < 0 { "-" } else { "" })
    }

    proptest::proptest! {
        /// The midpoint of random decimals, read as f64, is the f64
        /// midpoint within the rounding of a reading.
        #[test]
        fn random_midpoints_read_as_the_midpoint(
            ma in -10_000_000_000i64..10_000_000_000,
            mb in -10_000_000_000i64..10_000_000_000,
            pa in 0u32..7,
            pb in 0u32..7,
        ) {
            let (a, b) = (text_of(ma, pa), text_of(mb, pb));
            let mid = decimal_midpoint(&a, &b).unwrap();
            let want = 0.5 * (value(&a) + value(&b));
            let scale = value(&a).abs().max(value(&b).abs()).max(1.0);
            proptest::prop_assert!(
                (value(&mid) - want).abs() <= 4.0 * f64::EPSILON * scale,
                "{} {} -> {}", a, b, mid
            );
        }
    }
}
