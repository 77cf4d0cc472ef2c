//! Splitting a run into chains of straight segments (where corner methods
//! work) and the pieces between them (arcs, curves), after dropping
//! zero-length moves and merging vertices where the path runs straight on
//! (the corner engine then absorbs jogs, `absorb.rs`).

use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{point_segment_distance, Curve, Vec3};
use crate::path::{Piece, Run};
use crate::smooth::{SmoothError, SmoothedRun};
use alloc::vec::Vec;

/// A corner left as a corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeptCorner {
    /// Position of the corner, mm.
    pub at: Vec3,
    /// Input line of the move that ends at the corner.
    pub source_line: usize,
    pub reason: CornerReason,
}

/// Why a corner was kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerReason {
    /// The path reverses on itself: no curve can turn there inside the band.
    Reversal,
    /// A neighbouring transition used all the room on a segment.
    NoRoom,
    /// A joint next to an arc or curve of the input, which keeps the
    /// continuity it had (arcs stay arcs in this method).
    ArcJoint,
    /// A corner of a narrow U-turn (a step-over between passes, two
    /// sharp corners a few millimetres apart), kept by `auto` where the
    /// run plans faster so (`choose::u_turn_cuts`): at the step-over's
    /// scale the path turns back, and inside the band a G2 path through
    /// each corner crawls.
    UTurn,
}

impl CornerReason {
    /// Every reason, in the order reports list them.
    pub const ALL: [CornerReason; 4] = [
        CornerReason::Reversal,
        CornerReason::UTurn,
        CornerReason::NoRoom,
        CornerReason::ArcJoint,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            CornerReason::Reversal => "reversal",
            CornerReason::NoRoom => "no room",
            CornerReason::ArcJoint => "next to an arc",
            CornerReason::UTurn => "at a U-turn",
        }
    }
}

/// Consecutive straight segments `pts[i] -> pts[i+1]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LineChain {
    pub pts: Vec<Vec3>,
    /// Input lines of segment `i` (first, last: several after merging).
    pub lines: Vec<(usize, usize)>,
    pub feed: Vec<Option<f64>>,
    /// How far segment `i` may lie from the moves it replaces after jogs
    /// were absorbed into it (mm, `absorb.rs`): empty when nothing was
    /// absorbed, else one per segment. A method builds what it builds on
    /// segment `i` within its band less this.
    pub absorbed: Vec<f64>,
}

impl LineChain {
    pub fn segments(&self) -> usize {
        self.pts.len().saturating_sub(1)
    }

    /// What absorbing jogs spent on segment `i` (mm).
    pub fn absorbed_at(&self, i: usize) -> f64 {
        self.absorbed.get(i).copied().unwrap_or(0.0)
    }

    /// What absorbing jogs spent on the segments `range` (mm, the largest).
    pub fn absorbed_max(&self, range: core::ops::Range<usize>) -> f64 {
        range.map(|i| self.absorbed_at(i)).fold(0.0, f64::max)
    }
}

/// A run cut into line chains and other pieces, in order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Element {
    Chain(LineChain),
    Other(Piece),
}

/// Thresholds for cleaning a run, in mm.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CleanTolerances {
    /// Moves no longer than this are zero-length: their end vertex is
    /// dropped (moving the path by at most this much); consecutive pieces
    /// must meet within it.
    pub min_segment: f64,
    /// A vertex whose removal moves the path by no more than this is a
    /// straight-on vertex and merged away.
    pub collinear: f64,
}

impl CleanTolerances {
    /// Zero-length below a thousandth of the tolerance (50 nm at 0.05 mm:
    /// below the resolution of any G-code, so only rounding artefacts such
    /// as `Y14.828427124746183` followed by `Y14.828427` fall under it);
    /// straight-on within a millionth of it. Smoothers keep this much of
    /// the band in reserve.
    pub fn from_tolerance(tol: f64) -> Self {
        CleanTolerances {
            min_segment: tol * crate::budget::CLEAN_SHARE,
            collinear: tol * crate::budget::COLLINEAR_SHARE,
        }
    }
}

/// What absorbing jogs may spend on one segment (mm) for a method whose
/// band is `band` mm: [`crate::budget::ABSORB_SHARE`] of the tolerance,
/// and never more than half the band (a method's options can narrow its
/// band below the default).
pub(crate) fn absorb_limit(tolerance: f64, band: f64) -> f64 {
    (crate::budget::ABSORB_SHARE * tolerance).min(0.5 * band)
}

/// What cleaning a run did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Cleaned {
    /// Zero-length moves dropped.
    pub dropped: usize,
    /// Straight-on vertices merged.
    pub merged: usize,
}

/// Splits `run` into elements. Returns the elements and what was cleaned.
pub(crate) fn split_run(
    run: &Run,
    clean: CleanTolerances,
) -> Result<(Vec<Element>, Cleaned), SmoothError> {
    let mut out: Vec<Element> = Vec::new();
    let mut cleaned = Cleaned::default();
    let mut prev_end: Option<Vec3> = None;
    let mut chain = LineChain::default();
    // First input line of zero-length moves at the start of the run, not yet
    // named by any piece.
    let mut pending_first: Option<usize> = None;
    let finish = |chain: &mut LineChain,
                  out: &mut Vec<Element>,
                  cleaned: &mut Cleaned,
                  end: Option<Vec3>| {
        if chain.segments() > 0 {
            // A dropped tail leaves the chain short of the true end: move
            // the last vertex there (by at most `min_segment`).
            if let Some(e) = end {
                *chain.pts.last_mut().unwrap() = e;
            }
            cleaned.merged += merge_collinear(chain, clean.collinear);
            out.push(Element::Chain(core::mem::take(chain)));
        } else {
            *chain = LineChain::default();
        }
    };
    for piece in &run.pieces {
        let s = piece.start();
        let e = piece.end();
        if !s.is_finite() || !e.is_finite() {
            return Err(SmoothError::NotFinite {
                line: piece.source_lines.0,
            });
        }
        if let Some(pe) = prev_end {
            if pe.dist(s) > clean.min_segment {
                return Err(SmoothError::Discontinuous {
                    line: piece.source_lines.0,
                });
            }
        }
        match &piece.curve {
            Curve::Line(l) => {
                if chain.pts.is_empty() {
                    chain.pts.push(prev_end.unwrap_or(l.p0));
                }
                let last = *chain.pts.last().unwrap();
                if last.dist(l.p1) <= clean.min_segment {
                    cleaned.dropped += 1;
                    // The dropped move's line is named by a neighbour.
                    if let Some(lines) = chain.lines.last_mut() {
                        lines.1 = piece.source_lines.1;
                    } else if let Some(Element::Other(p)) = out.last_mut() {
                        p.source_lines.1 = p.source_lines.1.max(piece.source_lines.1);
                    } else {
                        pending_first = Some(pending_first.unwrap_or(piece.source_lines.0));
                    }
                } else {
                    let mut lines = piece.source_lines;
                    if let Some(first) = pending_first.take() {
                        lines.0 = lines.0.min(first);
                    }
                    chain.pts.push(l.p1);
                    chain.lines.push(lines);
                    chain.feed.push(piece.feed);
                }
            }
            _ => {
                finish(&mut chain, &mut out, &mut cleaned, prev_end);
                let mut p = piece.clone();
                if let Some(first) = pending_first.take() {
                    p.source_lines.0 = p.source_lines.0.min(first);
                }
                out.push(Element::Other(p));
            }
        }
        prev_end = Some(e);
    }
    if chain.segments() == 0 && !chain.pts.is_empty() && out.is_empty() {
        // Nothing but zero-length moves: keep one segment so the run still
        // goes from its start to its end.
        if let (Some(first), Some(last)) = (run.pieces.first(), run.pieces.last()) {
            if first.start() != last.end() {
                chain.pts.push(last.end());
                chain
                    .lines
                    .push((first.source_lines.0, last.source_lines.1));
                chain.feed.push(last.feed);
            }
        }
    }
    finish(&mut chain, &mut out, &mut cleaned, prev_end);
    Ok((out, cleaned))
}

/// Removes vertices where the chain runs straight on: every removed vertex
/// lies within `tol` of the merged segment, the direction does not
/// reverse, and the feed is the same on both sides (a vertex where the
/// programmed feed changes stays, so that each feed keeps its stretch of
/// path: merging it once made `X2.001 F10` slow a whole line down in
/// `linuxcnc/diagnostic/feed-tracking-test.ngc`). Returns the number
/// removed.
///
/// A merged segment lies within `tol` of the segments it replaces (every
/// removed vertex is within `tol` of it), so its [`LineChain::absorbed`]
/// bound is theirs (the largest) plus `tol`.
pub(crate) fn merge_collinear(chain: &mut LineChain, tol: f64) -> usize {
    let n = chain.pts.len();
    if n < 3 {
        return 0;
    }
    let mut pts = Vec::with_capacity(n);
    let mut lines = Vec::with_capacity(n - 1);
    let mut feed = Vec::with_capacity(n - 1);
    pts.push(chain.pts[0]);
    let mut span_start = 0; // index in chain.pts of the last kept vertex
    let mut cur_lines = chain.lines[0];
    let mut cur_feed = chain.feed[0];
    let mut absorbed = Vec::new();
    let mut cur_abs = chain.absorbed_at(0);
    for k in 1..n - 1 {
        let a = chain.pts[span_start];
        let b = chain.pts[k + 1];
        let d_in = chain.pts[k] - chain.pts[k - 1];
        let d_out = chain.pts[k + 1] - chain.pts[k];
        let straight = chain.feed[k] == chain.feed[k - 1]
            && d_in.dot(d_out) > 0.0
            && (b - a).dot(d_out) > 0.0
            && (span_start + 1..=k).all(|j| point_segment_distance(chain.pts[j], a, b) <= tol);
        if straight {
            cur_lines.1 = chain.lines[k].1;
            cur_abs = cur_abs.max(chain.absorbed_at(k)) + tol;
        } else {
            pts.push(chain.pts[k]);
            lines.push(cur_lines);
            feed.push(cur_feed);
            absorbed.push(cur_abs);
            span_start = k;
            cur_lines = chain.lines[k];
            cur_feed = chain.feed[k];
            cur_abs = chain.absorbed_at(k);
        }
    }
    pts.push(chain.pts[n - 1]);
    lines.push(cur_lines);
    feed.push(cur_feed);
    absorbed.push(cur_abs);
    let removed = n - pts.len();
    chain.pts = pts;
    chain.lines = lines;
    chain.feed = feed;
    if !chain.absorbed.is_empty() {
        chain.absorbed = absorbed;
    }
    removed
}

/// The lower of two optional feeds (a transition between two moves runs at
/// the slower one's feed).
pub(crate) fn min_feed(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    }
}

/// The driver every chain-based method shares: cleans `run` (see
/// [`split_run`]), smooths each chain of lines with `smooth_chain`, keeps
/// arcs and curves as they are, and reports each joint next to them that
/// is not G2 as a kept corner ([`CornerReason::ArcJoint`]).
pub(crate) fn smooth_by_chains(
    run: &Run,
    tolerance: f64,
    mut smooth_chain: impl FnMut(&LineChain, &mut SmoothedRun),
) -> Result<SmoothedRun, SmoothError> {
    let clean = CleanTolerances::from_tolerance(tolerance);
    let (elements, cleaned) = split_run(run, clean)?;
    let mut out = SmoothedRun {
        dropped_zero_length: cleaned.dropped,
        merged_collinear: cleaned.merged,
        ..SmoothedRun::default()
    };
    let joints = JointTolerances::from_tolerance(tolerance);
    for (i, el) in elements.iter().enumerate() {
        let first_of_element = out.pieces.len();
        match el {
            Element::Chain(chain) => smooth_chain(chain, &mut out),
            Element::Other(p) => {
                let mut p = p.clone();
                p.rapid = false;
                out.pieces.push(p);
            }
        }
        // A joint between an arc and anything else stays as it was;
        // report it when that is not G2.
        if i > 0 && first_of_element > 0 && first_of_element < out.pieces.len() {
            let (a, b) = (
                &out.pieces[first_of_element - 1],
                &out.pieces[first_of_element],
            );
            if classify_joint(&a.curve, &b.curve, &joints) != Continuity::G2 {
                out.kept_corners.push(KeptCorner {
                    at: b.start(),
                    source_line: a.source_lines.1,
                    reason: CornerReason::ArcJoint,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    fn x(v: f64) -> Vec3 {
        Vec3::new(v, 0.0, 0.0)
    }

    /// Regression (`linuxcnc/diagnostic/feed-tracking-test.ngc`): a
    /// straight-on vertex where the feed changes is kept; one where it does
    /// not is merged.
    #[test]
    fn merge_collinear_keeps_feed_changes() {
        let mut c = LineChain {
            pts: vec![x(0.0), x(1.0), x(2.0), x(3.0)],
            lines: vec![(1, 1), (2, 2), (3, 3)],
            feed: vec![Some(1000.0), Some(10.0), Some(10.0)],
            absorbed: vec![],
        };
        assert_eq!(merge_collinear(&mut c, 1e-9), 1);
        assert_eq!(c.pts, vec![x(0.0), x(1.0), x(3.0)]);
        assert_eq!(c.lines, vec![(1, 1), (2, 3)]);
        assert_eq!(c.feed, vec![Some(1000.0), Some(10.0)]);
        let mut same = LineChain {
            pts: vec![x(0.0), x(1.0), x(2.0)],
            lines: vec![(1, 1), (2, 2)],
            feed: vec![Some(10.0), Some(10.0)],
            absorbed: vec![],
        };
        assert_eq!(merge_collinear(&mut same, 1e-9), 1);
        assert_eq!(same.feed, vec![Some(10.0)]);
    }
}
