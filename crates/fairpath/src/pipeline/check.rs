//! The check of a written program read back: its runs paired with the
//! original's and verified against the tolerance the written path may use
//! (`ToleranceBudget::written`), run end points kept.

use super::verify_runs;
use crate::geom::Curve;
use crate::path::{Piece, Run};
use crate::verify::VerifyOptions;
use alloc::vec::Vec;

/// Groups feed pieces (from JSON) into the original runs by the input lines
/// they name.
pub fn group_by_source(original: &[Run], pieces: &[Piece]) -> Vec<Run> {
    original
        .iter()
        .map(|run| {
            let lo = run.pieces.first().map(|p| p.source_lines.0).unwrap_or(0);
            let hi = run.pieces.last().map(|p| p.source_lines.1).unwrap_or(0);
            Run::new(
                pieces
                    .iter()
                    .filter(|p| !p.rapid && p.source_lines.0 >= lo && p.source_lines.1 <= hi)
                    .cloned()
                    .collect(),
            )
        })
        .collect()
}

fn is_zero_length(run: &Run) -> bool {
    run.pieces
        .iter()
        .all(|p| matches!(&p.curve, Curve::Line(l) if l.p0 == l.p1))
}

/// The runs of a candidate do not pair with the original's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the smoothed program has {candidate} runs of feed moves where the original has {original}"
)]
pub struct RunCountMismatch {
    /// Runs of the original that move.
    pub original: usize,
    /// Runs of the candidate that move.
    pub candidate: usize,
}

/// The verdict on the written output.
#[derive(Clone, Debug, PartialEq)]
pub struct WrittenCheck {
    pub within: bool,
    pub max_deviation: f64,
    pub endpoint_failures: usize,
    pub runs_checked: usize,
    /// The runs (index in the original's `runs()`) that failed; `None`
    /// when the failure is not tied to runs.
    pub failed_runs: Vec<Option<usize>>,
}

/// The runs of `candidate` that stand for each run of `original`, in
/// order, as `(original index, candidate index)`: runs of zero length on
/// either side are skipped. An error when the counts differ.
pub fn pair_runs(
    original: &[Run],
    candidate: &[Run],
) -> Result<Vec<(usize, usize)>, RunCountMismatch> {
    let o: Vec<usize> = (0..original.len())
        .filter(|&i| !is_zero_length(&original[i]))
        .collect();
    let c: Vec<usize> = (0..candidate.len())
        .filter(|&i| !candidate[i].pieces.is_empty() && !is_zero_length(&candidate[i]))
        .collect();
    if o.len() != c.len() {
        return Err(RunCountMismatch {
            original: o.len(),
            candidate: c.len(),
        });
    }
    Ok(o.into_iter().zip(c).collect())
}

/// Pairs runs ([`pair_runs`]) and verifies each pair.
pub fn compare_runs(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
) -> Result<WrittenCheck, RunCountMismatch> {
    compare_runs_within(original, candidate, tolerance, 0.0)
}

/// Run end points count as equal within this share of the tolerance: the
/// rounding of the input's own reading (1,000 G91 moves of 0.0005 in sum
/// to 12.700000000000152 mm in f64; the written `X0.5` reads as 12.7:
/// `straight_segments.ngc`), far below any machine's resolution.
pub const ENDPOINT_ROUNDING_SHARE: f64 = 1e-9;

/// [`compare_runs`], with run end points that may differ by up to
/// `endpoint_slack` mm (0: equal up to [`ENDPOINT_ROUNDING_SHARE`] of the
/// tolerance).
pub fn compare_runs_within(
    original: &[Run],
    candidate: &[Run],
    tolerance: f64,
    endpoint_slack: f64,
) -> Result<WrittenCheck, RunCountMismatch> {
    let pairs_idx = pair_runs(original, candidate)?;
    let mut out = WrittenCheck {
        within: true,
        max_deviation: 0.0,
        endpoint_failures: 0,
        runs_checked: 0,
        failed_runs: Vec::new(),
    };
    let pairs: Vec<(&[Piece], &[Piece])> = pairs_idx
        .iter()
        .map(|&(a, b)| {
            (
                original[a].pieces.as_slice(),
                candidate[b].pieces.as_slice(),
            )
        })
        .collect();
    for (k, rep) in verify_runs(&pairs, &VerifyOptions::new(tolerance))
        .into_iter()
        .enumerate()
    {
        out.max_deviation = out.max_deviation.max(rep.deviation_bound);
        let slack = endpoint_slack + ENDPOINT_ROUNDING_SHARE * tolerance;
        let moved = rep.start_gap > slack || rep.end_gap > slack;
        if moved {
            out.endpoint_failures += 1;
        }
        let within = rep.deviation_bound <= tolerance && !moved;
        if !within {
            out.within = false;
            out.failed_runs.push(Some(pairs_idx[k].0));
        }
        out.runs_checked += 1;
    }
    Ok(out)
}
