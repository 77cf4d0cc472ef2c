//! The library's entry point: every run of a program smoothed by one
//! method within the smoothing share of a [`ToleranceBudget`], and the
//! curves verified independently ([`crate::verify`]) against that share
//! before anything is returned. A run whose curves fail is an error naming
//! the run's first input line ([`PipelineError::NotVerified`], which holds
//! the evidence), never a result.
//!
//! Reading a program, writing it in a controller's format and checking the
//! written text read back against the original are `fairpath-gcode`'s
//! (`fairpath_gcode::smooth_program`).
//!
//! ```
//! use fairpath::budget::ToleranceBudget;
//! use fairpath::geom::{Curve, Line, Vec3};
//! use fairpath::path::{Piece, Run};
//!
//! // Two moves with a corner between them (input lines 2 and 3).
//! let line = |a: Vec3, b: Vec3, n: usize| Piece {
//!     curve: Curve::Line(Line::new(a, b)),
//!     rapid: false,
//!     source_lines: (n, n),
//!     feed: Some(1200.0),
//! };
//! let (a, b, c) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, 0.0, 0.0), Vec3::new(10.0, 10.0, 0.0));
//! let run = Run::new(vec![line(a, b, 2), line(b, c, 3)]);
//!
//! let budget = ToleranceBudget::new(0.05, None, 0.0)?;
//! let method = fairpath::choose::by_name("bspline-corner").unwrap();
//! let result = fairpath::pipeline::smooth_runs(vec![run], method.as_ref(), &budget)?;
//! let run = &result.runs[0];
//! assert!(run.report.within(budget.smoothing()));
//! assert_eq!(run.report.joint_counts()[3], 2); // G2 joints of the corner transition
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

mod parallel;

pub use parallel::{par_map, verify_runs, verify_runs_measuring, VERIFY_CHUNK};

use crate::budget::ToleranceBudget;
use crate::path::{Piece, Run};
use crate::smooth::{SmoothError, SmoothedRun, Smoother};
use crate::verify::{RunReport, VerifyOptions};
use alloc::boxed::Box;
use alloc::vec::Vec;

/// One run before and after.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub original: Run,
    pub smoothed: SmoothedRun,
    /// The verifier's report on `smoothed` against `original` at the
    /// smoothing share.
    pub report: RunReport,
}

/// Every run of a program, smoothed and verified, in order.
#[derive(Clone, Debug, Default)]
pub struct SmoothResult {
    pub runs: Vec<RunResult>,
}

/// A step of [`smooth_runs_observed`], reported when it is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Every run smoothed.
    Smoothed,
    /// Every run's curves verified.
    Verified,
}

/// Why the runs could not be smoothed.
#[derive(Clone, Debug, thiserror::Error)]
pub enum PipelineError {
    /// The method failed on a run.
    #[error("smoothing the run starting at line {line}")]
    Smooth {
        /// The run's first input line.
        line: usize,
        #[source]
        source: SmoothError,
    },
    /// The curves of a run (the first that failed) leave the smoothing
    /// share or move a run end point: a method's fault, nothing made of
    /// them can be trusted. `result` holds every run and its report.
    #[error(
        "the smoothed curves of the run starting at line {line} leave the smoothing share of the \
         tolerance ({deviation:.6} mm > {share} mm) or move a run endpoint"
    )]
    NotVerified {
        /// The run's first input line.
        line: usize,
        /// The verifier's bound of the run's deviation (mm).
        deviation: f64,
        /// The smoothing share (mm).
        share: f64,
        result: Box<SmoothResult>,
    },
}

/// The first input line of `run` (0 for an empty run).
pub fn first_line(run: &Run) -> usize {
    run.pieces.first().map_or(0, |p| p.source_lines.0)
}

/// Smooths every run with `method` within `budget.smoothing()` and
/// verifies the curves against that share (on all cores with `std`).
/// Errors: the method's, or [`PipelineError::NotVerified`] for the first
/// run whose curves leave the share or move an end point.
pub fn smooth_runs(
    runs: Vec<Run>,
    method: &dyn Smoother,
    budget: &ToleranceBudget,
) -> Result<SmoothResult, PipelineError> {
    smooth_runs_observed(runs, method, budget, &mut |_| {})
}

/// [`smooth_runs`], calling `observe` after each [`Stage`] (to time them).
pub fn smooth_runs_observed(
    runs: Vec<Run>,
    method: &dyn Smoother,
    budget: &ToleranceBudget,
    observe: &mut dyn FnMut(Stage),
) -> Result<SmoothResult, PipelineError> {
    smooth_windows_observed(runs, (false, false), method, budget, observe)
}

/// [`smooth_runs_observed`] of the runs of a part of a program whose first
/// run may start, and whose last may end, at a cut of a longer run
/// (`cut`: the first run's start, the last run's end): those runs are
/// smoothed as windows ([`Smoother::smooth_window`]).
pub fn smooth_windows_observed(
    runs: Vec<Run>,
    cut: (bool, bool),
    method: &dyn Smoother,
    budget: &ToleranceBudget,
    observe: &mut dyn FnMut(Stage),
) -> Result<SmoothResult, PipelineError> {
    let share = budget.smoothing();
    let n = runs.len();
    let cut_of = |i: usize| (i == 0 && cut.0, i + 1 == n && cut.1);
    // Runs are independent: smoothed on all cores (with `std`), results in
    // order, so the output and the first error reported do not depend on
    // the number of threads.
    let smoothed_runs = par_map(n, |i| match cut_of(i) {
        (false, false) => method.smooth_run(&runs[i], share),
        c => method.smooth_window(&runs[i], share, c),
    })
    .into_iter()
    .zip(&runs)
    .map(|(smoothed, run)| {
        smoothed.map_err(|source| PipelineError::Smooth {
            line: first_line(run),
            source,
        })
    })
    .collect::<Result<Vec<_>, _>>()?;
    observe(Stage::Smoothed);
    let pairs: Vec<(&[Piece], &[Piece])> = runs
        .iter()
        .zip(&smoothed_runs)
        .map(|(r, s)| (r.pieces.as_slice(), s.pieces.as_slice()))
        .collect();
    let reports = verify_runs(&pairs, &VerifyOptions::new(share));
    let result = SmoothResult {
        runs: runs
            .into_iter()
            .zip(smoothed_runs)
            .zip(reports)
            .map(|((original, smoothed), report)| RunResult {
                original,
                smoothed,
                report,
            })
            .collect(),
    };
    observe(Stage::Verified);
    // Curves that leave their share are a smoother's fault: nothing
    // written from them can be trusted.
    if let Some(bad) = result.runs.iter().find(|r| !r.report.within(share)) {
        return Err(PipelineError::NotVerified {
            line: first_line(&bad.original),
            deviation: bad.report.deviation_bound,
            share,
            result: Box::new(result),
        });
    }
    Ok(result)
}
