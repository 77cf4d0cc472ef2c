//! The errors of the pipeline's steps: options that cannot be used, and
//! programs that cannot be planned.

use crate::{GcodeError, JsonError};
use fairpath::budget::BudgetError;
use fairpath::choose;
use fairpath::feed::limits::LimitError;
use fairpath::feed::program::ProgramPlanError;

/// Options that cannot be used; each names the option and its value.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OptionsError {
    #[error("tolerance must be a number of mm from 1e-6 to 1000, got {0}")]
    Tolerance(f64),
    /// The output share (the command line's `--chord`).
    #[error(
        "output share must be a positive number of mm, at most half the tolerance ({half} mm); \
         got {value}"
    )]
    OutputShare { value: f64, half: f64 },
    /// The shares do not make a budget.
    #[error("tolerance {tolerance} mm")]
    Budget {
        tolerance: f64,
        #[source]
        source: BudgetError,
    },
    /// What is left for smoothing after `auto`'s sampling of arcs.
    #[error(
        "tolerance {tolerance} mm leaves {left:e} mm for smoothing after the output share \
         ({output} mm) and arc sampling; at least 1e-6 mm is needed"
    )]
    NothingLeft {
        tolerance: f64,
        output: f64,
        left: f64,
    },
    #[error("unknown method {0:?}; known: {known}", known = choose::METHODS.join(", "))]
    UnknownMethod(String),
    #[error("step share must be a positive number or inf; got {0}")]
    StepShare(f64),
    #[error("machine")]
    Machine(#[source] LimitError),
    #[error(
        "run windows must hold at least one line and cut at a positive length; got {0} lines, \
         {1} mm"
    )]
    RunWindows(usize, f64),
}

/// Why a program's time could not be planned.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error("planning {what}")]
    Plan {
        /// `the input`, `the curves`, `the written program`.
        what: &'static str,
        #[source]
        source: ProgramPlanError,
    },
    #[error("the written program does not read back")]
    ReadWritten(#[source] GcodeError),
    #[error("the written program does not read back")]
    ReadWrittenJson(#[source] JsonError),
    /// A run cut into windows ([`crate::interp::RunWindows`]) whose plan,
    /// made a window at a time, did not stitch: it must be planned whole,
    /// which the job in windows cannot (it no longer holds the run). The
    /// job is then done again without windows.
    #[error("{what}: a run cut into windows must be planned whole")]
    Unstitched { what: &'static str },
}
