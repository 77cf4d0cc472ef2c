//! The options of method `fair` ([`super::Fair`]), checked once at the
//! front door.

use super::bspline_fit::BsplineFitOptions;
use super::{require, OptionError};
use crate::budget::{BAND_USE, FAIR_FIT_SHARE};
use crate::geom::tube_fair::{
    EndRule, PeakPass, TubeFairError, TubeMeasure, DEFAULT_MAX_ITERATIONS, THESIS_ACCURACY,
    THESIS_PRECISION,
};

/// Most control points of a cubic (three spans) that the fairing cannot
/// move once it keeps the first and last three where the curve joins its
/// neighbours G2: the spans LinuxCNC's G5.2 blocks are read as, one piece
/// each (`fairpath_gcode`), are such curves, and only sampled
/// ([`OtherCurves::Sampled`]) can they be faired.
pub const MOST_FIXED_POINTS: usize = 6;

/// Options of [`Fair`](super::Fair).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct FairOptions {
    /// The fit of runs of lines (`bspline-fit`'s options; its `band_use`
    /// is scaled by `fit_share`).
    pub fit: BsplineFitOptions,
    /// Share of the band the fits of runs of lines may use, in (0, 1); the
    /// fairing of the fitted curves gets the rest.
    pub fit_share: f64,
    /// Share of the tolerance (or of what the fit leaves) the tube's
    /// radius is, in (0, 0.998]: the rest covers the cleaning of the run
    /// and the verifier's accuracy.
    pub band_use: f64,
    /// Samples per knot interval of the thesis' allowance (its precision).
    pub precision: usize,
    /// Share of the radius within which the curve touches the tube (its
    /// accuracy).
    pub accuracy: f64,
    /// Most iterations per curve.
    pub max_iterations: usize,
    /// What the run's ends do.
    pub ends: EndRule,
    /// Put back moves that raise the peak curvature locally (the thesis'
    /// U-to-V failure).
    pub peak_guard: bool,
    /// After the thesis' iterations, lower the highest curvature peaks
    /// with the room left in the tube (ours: the thesis' iterations stop
    /// where the curve first touches the tube and carry the top of a wide
    /// bend along unchanged; `geom::tube_fair::peak`). By default the
    /// default machine's speed caps ([`PeakPass::DEFAULT_MACHINE`]), which
    /// the verified pipeline and `auto` replace by the job's machine's
    /// (`choose::fair_on`: its speed caps, or the curvature where it caps
    /// curves by their normal acceleration alone, the thesis' model).
    pub peak_pass: PeakPass,
    /// How the tube is measured in the straightening and the peak pass:
    /// at equal parameters (the thesis' difference spline, the default),
    /// or to the original path, its points matched by projection (ours,
    /// `geom::tube_fair::slide`: the project's tolerance, looser).
    pub tube: TubeMeasure,
    /// Whether, after the thesis' iterations, the turning is minimised
    /// inside the tube (ours, `geom::tube_fair::straighten`): see
    /// [`Straighten`].
    pub straighten: Straighten,
    /// Whether the peak pass works up to each curve's programmed feed
    /// only (the default: where the program asks for less speed than the
    /// shape allows, lowering the shape's demand buys nothing,
    /// [`PeakPass::at_feed`]), or up to its own `max_feed` whatever the
    /// program's feeds: where every move is run at the machine's maximum
    /// feed (`--override-feed`; the verified pipeline and `auto` set it
    /// from their objective, `choose::fair_on`), the programmed feeds are
    /// not what the machine runs.
    pub programmed_feeds: bool,
    /// How runs of lines are fitted before they are faired.
    pub lines: LineFit,
    /// What becomes of the curves the thesis' fairing cannot take.
    pub other_curves: OtherCurves,
}

/// Whether [`Fair`](super::Fair) straightens its curves
/// (`geom::tube_fair::straighten`: the turning minimised inside the tube,
/// after the thesis' iterations and before the peak pass).
///
/// Why not always: it plans the thesis' square of rippled corners faster
/// than the peak pass alone, but on a smooth design curve the curvature
/// it lowers between the peaks steepens the ramps, which a jerk-limited
/// planner pays for: forced on over the thesis' cases and LinuxCNC's G6.2
/// examples, 28 programs planned faster and 43 slower, at several times
/// the computing time (docs/tuning.md, "Straightening and the sliding
/// tube"). So by default the planner judges it, run by run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum Straighten {
    /// Never.
    Off,
    /// Always, in the tube as `FairOptions::tube` measures it.
    On,
    /// The default. Where a planner judges the method (`fair` as the
    /// pipeline builds it, `choose::JudgedFair`), each run that holds a
    /// B-spline of the program (the thesis' input) is also smoothed with
    /// the straightening in the sliding tube, and the smoothing that plans
    /// faster on the user's machine is kept; runs of lines and arcs alone
    /// are not (their fits were not measured to gain, and the work would
    /// grow with every fitted run), nor is anything without a planner (the
    /// method alone). `auto` offers the straightened smoothing as a
    /// candidate of its own on the same runs (`choose::FAIR_STRAIGHTENED`),
    /// so it stays no slower than `fair`.
    #[default]
    Judged,
}

/// What [`Fair`](super::Fair) does with the curves the thesis' fairing cannot take
/// (arcs), cannot move (at most [`MOST_FIXED_POINTS`] control points), or
/// takes beyond the thesis (rational, degree 4 and above).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum OtherCurves {
    /// Sampled as chords within [`FAIR_SAMPLE_SHARE`](crate::budget::FAIR_SAMPLE_SHARE) of the tolerance,
    /// fitted and faired as lines, where that lowers the demand of
    /// [`FairOptions::peak_pass`]'s speed caps there, at its peak and in all
    /// ([`sampled_demands`](super::sampled_demands));
    /// kept as written otherwise (see the module documentation).
    #[default]
    Sampled,
    /// Kept as written, and reported (rational and high-degree B-splines
    /// too: not faired).
    Kept,
}

/// How [`Fair`](super::Fair) fits a run of lines before the thesis' fairing (the
/// thesis starts from a CAM spline; a G1 program has none).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum LineFit {
    /// `bspline-fit`'s sections ([`BsplineFitOptions::sections`]): dense
    /// vertices fitted, sparse corners blended by transitions, which the
    /// fairing leaves as they are. Best where the tube is narrow beside
    /// the corners.
    Sections,
    /// Every vertex that turns no more than `bspline-fit`'s sections allow
    /// ([`SectionOptions::max_turn`](super::SectionOptions::max_turn)) fitted, however long its segments
    /// ([`shallow_corner_sections`](super::shallow_corner_sections)), so the fairing has one curve across
    /// the shallow corners to straighten: a line with two points 0.2 mm
    /// off (the thesis' case 5, as G1: its vertices are sparse only by
    /// their 31 mm segments) becomes straight in a 0.25 mm tube, where
    /// transitions at its corners use 0.025 mm of it. Sharper corners keep
    /// their transitions: fits of a quarter of the band through them fail
    /// and are split again and again (through every corner up to 143
    /// degrees, `makerblock_tinycnc.gcode` took many times as long;
    /// measurements: docs/tuning.md, `LineFit::ThroughShallowCorners`).
    ThroughShallowCorners,
    /// Both, keeping `ThroughShallowCorners` where it has the lower sampled
    /// peak curvature ([`run_peak_curvature`](super::run_peak_curvature)) and no more turning
    /// ([`run_turning`](super::run_turning)), `Sections` otherwise: the speed a curve allows
    /// falls with its curvature (`v <= sqrt(A / k)`), and which fit gives
    /// the lower one depends on the tube (on the noisy line at 0.25 mm the
    /// sections give 0.11 1/mm against 0). A geometric proxy, not a plan
    /// (the method knows no machine): on `LHchips4.ngc` at 0.05 mm the
    /// pick plans slightly slower than the sections alone (measurements:
    /// docs/tuning.md, `LineFit::Fairer`).
    #[default]
    Fairer,
}

impl Default for FairOptions {
    fn default() -> Self {
        FairOptions {
            fit: BsplineFitOptions {
                fairness_raises: 0,
                relax: None,
                ..BsplineFitOptions::default()
            },
            fit_share: FAIR_FIT_SHARE,
            band_use: BAND_USE,
            precision: THESIS_PRECISION,
            accuracy: THESIS_ACCURACY,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            ends: EndRule::Pinned,
            peak_guard: true,
            peak_pass: PeakPass::DEFAULT_MACHINE,
            tube: TubeMeasure::EqualParameter,
            straighten: Straighten::Judged,
            programmed_feeds: true,
            lines: LineFit::Fairer,
            other_curves: OtherCurves::Sampled,
        }
    }
}

impl FairOptions {
    /// These options with the straightening forced on, in the sliding tube
    /// (what [`Straighten::Judged`] weighs against them).
    pub fn straightened(self) -> Self {
        FairOptions {
            straighten: Straighten::On,
            tube: TubeMeasure::Sliding,
            ..self
        }
    }

    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let m = "fair";
        self.fit.validate().map_err(|e| OptionError {
            method: m,
            option: "fit",
            value: alloc::format!("{}: {}", e.option, e.value),
            expected: e.expected,
        })?;
        let f = self.fit_share;
        require(f > 0.0 && f < 1.0, m, "fit_share", f, "must be in (0, 1)")?;
        let b = self.band_use;
        require(
            b > 0.0 && b <= BAND_USE,
            m,
            "band_use",
            b,
            "must be in (0, 0.998]",
        )?;
        match self.tube(1.0, false, false).validate() {
            Ok(()) => Ok(()),
            Err(TubeFairError::BadOption {
                option,
                value,
                expected,
            }) => Err(OptionError {
                method: m,
                option,
                value,
                expected,
            }),
            Err(_) => Ok(()),
        }
    }
}
