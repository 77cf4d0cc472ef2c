//! Smoothing methods behind one trait (the methods only: choosing among
//! them is [`crate::choose`], checking them [`crate::verify`]).
//!
//! A [`Smoother`] turns one [`Run`] of feed moves into pieces that stay
//! within a tolerance of it, start and end exactly where it does, and join
//! with G2 continuity wherever it can; corners it cannot blend are kept and
//! reported. [`crate::verify`] checks all of that without trusting the
//! smoother.

mod absorb;
mod arc_candidates;
mod arc_chain;
mod arc_check;
mod arc_fit;
mod arc_joints;
mod bezier_corner;
mod bspline_corner;
mod bspline_fit;
mod chains;
mod corner_engine;
mod fair;
mod fair_measures;
mod fair_options;
mod fit_chain;
mod fit_fairing;
mod fit_fill;
mod fit_search;
mod fit_sections;
mod kept_joints;
mod lotm;
mod none;
mod options;
mod outer_guide;
mod run_memo;
mod unfaired;

pub use arc_fit::{
    ArcFit, ArcFitOptions, ARC_FIT_LOOKAHEAD, ARC_FIT_SHARE, ARC_MAX_RADIUS_PER_TOL,
    ARC_MAX_SPLIT_DEPTH, ARC_MAX_SWEEP, ARC_MIN_CHORD_PER_TOL, ARC_MIN_RADIUS_MM, ARC_SAMPLE_SHARE,
};
pub use arc_joints::{blend_arc_joints, ArcJoints};
pub use bezier_corner::{
    bezier_corner_beziers, bezier_corner_curve, bezier_corner_deviation, bezier_corner_error,
    bezier_corner_peak_curvature, bezier_corner_points, bezier_length_for_deviation, Ctm,
    CtmOptions, MIN_COEFFICIENT,
};
pub use bspline_corner::{
    corner_deviation, corner_error, corner_peak_curvature, edge_for_deviation, transition_curve,
    BsplineCorner, BsplineCornerOptions, ErrorTarget, BAND_USE, TRANSITION_KNOTS,
};
pub use bspline_fit::{
    fit_polyline, fit_polyline_faired, fit_polyline_weighted, BsplineFit, BsplineFitOptions,
    SectionFit, FAIRNESS_RAISE, FAIRNESS_RAISES,
};
pub use chains::{CornerReason, KeptCorner};
pub(crate) use corner_engine::Reach;
pub use fair::{Fair, FairAlternatives};
pub use fair_measures::{
    run_peak_curvature, run_turning, sampled_demand, sampled_demands, shallow_corner_sections,
    TURNING_ACCURACY,
};
pub use fair_options::{FairOptions, LineFit, OtherCurves, Straighten, MOST_FIXED_POINTS};
pub use fit_sections::{
    dense_sections, through_corners_sections, SectionOptions, THROUGH_MAX_TURN,
};
pub use lotm::{
    curvature_variation_energy, lotm_coefficient, lotm_coefficient_fit, optimal_coefficient,
    split_shared_segment, Lotm, LotmOptions, LOTM_COEFFICIENT_FIT, LOTM_MIN_COEFFICIENT,
};
pub use none::{NoSmoothing, NONE_GAP_SHARE};
pub(crate) use options::require;
pub use options::OptionError;
pub use outer_guide::{outer_guide, OuterGuide};
pub use run_memo::RunMemo;
pub use unfaired::{Unfaired, UnfairedReason};

use crate::budget::ToleranceBudget;
use crate::path::{Piece, Run};
use alloc::vec::Vec;

/// What a smoother produced for one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SmoothedRun {
    /// The new pieces, continuous, from the run's start to its end.
    pub pieces: Vec<Piece>,
    /// Corners left as corners, with the reason.
    pub kept_corners: Vec<KeptCorner>,
    /// Zero-length moves that were dropped.
    pub dropped_zero_length: usize,
    /// Vertices where the path runs straight on, merged into one line.
    pub merged_collinear: usize,
    /// Moves far inside the tolerance absorbed into their neighbours
    /// (jogs, `absorb.rs`).
    pub absorbed_jogs: usize,
    /// Corners replaced by a transition curve.
    pub transitions: usize,
    /// The candidate `auto` kept for each section of this run, in order
    /// (empty from the other methods): e.g. `"bspline-fit"`,
    /// `"bspline-fit, through corners"`, `"lotm"`.
    pub chosen: Vec<&'static str>,
    /// Curves of the run left as written although the method smooths
    /// their kind, with the reason (method `fair`: curves the thesis'
    /// fairing cannot take).
    pub unfaired: Vec<Unfaired>,
}

impl SmoothedRun {
    /// `next` appended: its pieces after these (the caller sees that they
    /// meet), its reports and counts added to these.
    pub fn append(&mut self, next: &SmoothedRun) {
        self.pieces.extend_from_slice(&next.pieces);
        self.kept_corners.extend_from_slice(&next.kept_corners);
        self.dropped_zero_length += next.dropped_zero_length;
        self.merged_collinear += next.merged_collinear;
        self.absorbed_jogs += next.absorbed_jogs;
        self.transitions += next.transitions;
        self.chosen.extend_from_slice(&next.chosen);
        self.unfaired.extend_from_slice(&next.unfaired);
    }
}

/// Why smoothing could not be done.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SmoothError {
    /// The tolerance is not a positive finite number of mm.
    #[error("tolerance must be a positive number of mm, got {0}")]
    BadTolerance(f64),
    /// Consecutive pieces of the run do not meet.
    #[error("run is not continuous at input line {line}")]
    Discontinuous { line: usize },
    /// A coordinate is NaN or infinite.
    #[error("non-finite coordinate at input line {line}")]
    NotFinite { line: usize },
    /// A method option is out of range.
    #[error("{0}")]
    BadOption(#[from] OptionError),
    /// `auto` found no candidate it could use.
    #[error("auto: no candidate")]
    NoCandidate,
}

/// A smoothing method. `Sync`, so that the verified pipeline can smooth
/// independent runs on several threads.
pub trait Smoother: Sync {
    /// The name used on the command line (`bspline-corner`, ...).
    fn name(&self) -> &'static str;
    /// Smooths one run so that every point of the result lies within
    /// `tolerance` mm (3D Euclidean) of the run, with the run's endpoints
    /// kept exactly.
    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError>;
    /// [`Smoother::smooth_run`] with the smoothing share of `budget`
    /// ([`ToleranceBudget::smoothing`]): what the verified pipeline calls.
    fn smooth_within(
        &self,
        run: &Run,
        budget: &ToleranceBudget,
    ) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run(run, budget.smoothing())
    }
    /// [`Smoother::smooth_run`] of a window of a longer run: `cut` says
    /// which of its ends (start, end) cut the longer run at the middle of
    /// a line, where the run goes on straight. A method that can keeps the
    /// cut line straight there and chooses as it would for the whole run;
    /// by default the window is smoothed as a run of its own (its ends
    /// kept exactly, as a cut needs).
    fn smooth_window(
        &self,
        run: &Run,
        tolerance: f64,
        cut: (bool, bool),
    ) -> Result<SmoothedRun, SmoothError> {
        let _ = cut;
        self.smooth_run(run, tolerance)
    }
    /// Whether the method writes for a planner that caps the speed at the
    /// end of every block (LinuxCNC master's S-curve planner): its output
    /// is then judged by that model (`feed::plan::Corners::BlockCapped`)
    /// rather than by a blending controller's.
    fn writes_for_block_capped_planner(&self) -> bool {
        false
    }
    /// Whether the method keeps every run as it is (`none`): its output is
    /// the program's own text, which no writer's command may change.
    fn keeps_every_run(&self) -> bool {
        false
    }
}

/// Rejects tolerances that are not positive and finite, or absurdly small
/// or large: below 1 nm (beneath any machine's resolution and f64 rounding on
/// metre-sized parts) or above 1 m.
pub fn check_tolerance(tolerance: f64) -> Result<(), SmoothError> {
    if tolerance.is_finite() && (1e-6..=1000.0).contains(&tolerance) {
        Ok(())
    } else {
        Err(SmoothError::BadTolerance(tolerance))
    }
}
