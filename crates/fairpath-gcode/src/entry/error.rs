//! Why a program was not smoothed and written.

use super::Report;
use crate::emit::EmitError;
use crate::pipeline::PlanError;
use crate::GcodeError;
use fairpath::pipeline::PipelineError;

/// Why a program was not smoothed and written.
#[derive(Debug, thiserror::Error)]
pub enum SmoothProgramError {
    /// Nothing but blanks.
    #[error("empty program")]
    EmptyProgram,
    #[error(transparent)]
    Read(#[from] GcodeError),
    /// The method failed, or its curves did not verify
    /// ([`PipelineError::NotVerified`]).
    #[error(transparent)]
    Curves(#[from] PipelineError),
    /// Planning the input, the curves or the written text.
    #[error(transparent)]
    Plan(#[from] PlanError),
    #[error(transparent)]
    Emit(#[from] EmitError),
    /// The written text, read back, leaves the tolerance or moves a run
    /// end point: it is not an output. The report holds the evidence.
    #[error(
        "the output leaves the tolerance ({deviation:.6} mm > {tolerance} mm) or moves a run \
         endpoint"
    )]
    OutputNotVerified {
        /// The bound of the written path's deviation (mm).
        deviation: f64,
        /// What it may deviate (mm,
        /// [`ToleranceBudget::written`](fairpath::budget::ToleranceBudget::written)).
        tolerance: f64,
        report: Box<Report>,
    },
}
