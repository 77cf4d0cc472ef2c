//! Method `bspline-corner`: corner transitions by a symmetric five-point
//! cubic B-spline inside the tolerance band (Guo, Yan, Wang 2023, "Toolpath
//! Smoothing Based on Controlled NURBS Interpolation", J. Eng. Res. Rep.
//! 25(12), sections 3.1 to 3.5; seed 000).
//!
//! At a corner `Q1` between segments towards `Q0` and `Q2` (unit directions
//! `a`, `b` from the corner, half corner angle `theta`), the control points
//! are `P0 = Q1 + 2L a`, `P1 = Q1 + L a`, `P2 = Q1`, `P3 = Q1 + L b`,
//! `P4 = Q1 + 2L b`, knots `{0,0,0,0,0.5,1,1,1,1}` (section 3.1). Closed forms
//! (derived here from the knot vector; the paper computes `e` by evaluation):
//!
//! * `C(0.5) = (P1 + 2 P2 + P3) / 4`, so the paper's error (eq. 7)
//!   `e = |P2 C(0.5)| = (L/2) cos(theta)` ([`corner_error`]);
//! * the band corner lies at `epsilon = delta / sin(theta)` from `Q1`
//!   (section 3.3), and the largest distance of the curve from the two
//!   segments is at `C(0.5)`: `e sin(theta) = L sin(2 theta) / 4`
//!   ([`corner_deviation`]), so `e <= epsilon` is exactly "within delta";
//! * the curvature peaks at `C(0.5)`: `kappa = 4 cos(theta) / (3 L sin^2(theta))`
//!   ([`corner_peak_curvature`]); at both ends the curvature is zero
//!   (`P0 P1 P2` collinear), so every joint with the segments is G2.
//!
//! Scaling the control polygon by `alpha` about `Q1` scales `e` by `alpha`
//! (section 3.3). The paper aims at `e* = delta / 2`
//! ([`ErrorTarget::HalfBand`]); [`ErrorTarget::FullBand`] uses the band
//! fully (`e* = epsilon`, deviation exactly `delta`), which gives longer
//! transitions and, since `kappa ~ 1/L`, lower peak curvature: it is the
//! default.
//!
//! Routines 1 to 3 (section 3.5) are run along each chain of segments:
//! the first corner starts from `Q0`, every later one from
//! `S = P4 + lambda (Q_next - P4)` of the previous transition (overlap
//! avoidance, section 3.4, eq. 8); the initial `L` is half the shorter of
//! the available incoming length `|S Q1|` and the outgoing segment (the three
//! cases of section 3.2: the longer side is cut to the shorter one's length).
//! Where the paper halves `L` when `P4` would reach the next vertex
//! (section 3.4, "set alpha = 1/2"), this implementation applies the same rule
//! whenever `P4` would pass the middle of the next segment, so that the next
//! corner is never starved; the last corner may use its whole outgoing
//! segment. Gaps the paper leaves, and what is done here:
//!
//! * zero-length moves are dropped; vertices where the path runs straight on
//!   are merged (see `chains.rs`);
//! * a full reversal (half-angle below [`BsplineCornerOptions::min_half_angle`])
//!   is kept as a corner and reported;
//! * arcs of the input stay arcs: chains of lines are smoothed between them,
//!   and the joints next to arcs keep the continuity they had;
//! * a closed run (ending where it starts) keeps its start and end exactly,
//!   so its closing corner, where the tool starts and stops anyway, is not
//!   blended (see the README: blending it needs a lead-in and lead-out that
//!   the paper does not define).
//!
//! The walk along a chain (line pieces, transitions, kept corners) is the
//! corner engine's (`corner_engine.rs`, shared with `ctm` and `lotm`); this
//! file gives it the transition above (`UniformPlan`) and its rules.

use super::chains::{smooth_by_chains, LineChain};
use super::corner_engine::{self, Band, Corner, CornerPlan, CornerRules, Reach, Room, Undirected};
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::{Nurbs, Vec3};
use crate::math;
use crate::path::Run;
use crate::smooth::{require, OptionError};

/// Which approximation error the transitions aim at when they must shrink.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum ErrorTarget {
    /// The paper's `e* = delta / 2` (section 3.3).
    HalfBand,
    /// `e* = epsilon = delta / sin(theta)`: the deviation reaches the whole
    /// tolerance, the transition is as long as the band allows.
    FullBand,
}

pub use crate::budget::BAND_USE;

/// Options of [`BsplineCorner`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct BsplineCornerOptions {
    pub target: ErrorTarget,
    /// Overlap-avoidance ratio `lambda` in `[0, 1)` (paper eq. 8): the share
    /// of the room left on a segment that is kept straight between two
    /// transitions.
    pub lambda: f64,
    /// Corners whose half-angle `theta` (radians) is below this are
    /// reversals and kept.
    pub min_half_angle: f64,
    /// What to do at the joints next to arcs that are not G2: keep them
    /// (the seed's method, the default) or blend them G2
    /// ([`super::ArcJoints`]).
    pub arc_joints: super::ArcJoints,
}

impl BsplineCornerOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        self.validate_for("bspline-corner")
    }

    /// [`Self::validate`], naming `method` (whose options these are part of).
    pub fn validate_for(&self, method: &'static str) -> Result<(), OptionError> {
        let l = self.lambda;
        require(
            (0.0..1.0).contains(&l),
            method,
            "lambda",
            l,
            "must be in [0, 1)",
        )?;
        let a = self.min_half_angle;
        require(
            (0.0..0.5).contains(&a),
            method,
            "min_half_angle",
            a,
            "must be in [0, 0.5) rad",
        )
    }
}

impl Default for BsplineCornerOptions {
    fn default() -> Self {
        BsplineCornerOptions {
            target: ErrorTarget::FullBand,
            lambda: 0.0,
            min_half_angle: 1e-6,
            arc_joints: super::ArcJoints::Kept,
        }
    }
}

/// The `bspline-corner` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BsplineCorner {
    pub options: BsplineCornerOptions,
}

/// Paper eq. 7 in closed form: `e = |P2 C(0.5)| = (L/2) cos(theta)` for
/// control-polygon edge `L` and half corner angle `theta`.
pub fn corner_error(l: f64, theta: f64) -> f64 {
    0.5 * l * math::cos(theta)
}

/// Largest distance of the transition from its two segments:
/// `e sin(theta) = L sin(2 theta) / 4`, reached at `C(0.5)`.
pub fn corner_deviation(l: f64, theta: f64) -> f64 {
    0.25 * l * math::sin(2.0 * theta)
}

/// Peak curvature of the transition, at `C(0.5)`:
/// `4 cos(theta) / (3 L sin^2(theta))`.
pub fn corner_peak_curvature(l: f64, theta: f64) -> f64 {
    let s = math::sin(theta);
    4.0 * math::cos(theta) / (3.0 * l * s * s)
}

/// The largest edge `L` whose transition deviates at most `delta` from the
/// segments: `L = 4 delta / sin(2 theta)`.
pub fn edge_for_deviation(delta: f64, theta: f64) -> f64 {
    4.0 * delta / math::sin(2.0 * theta)
}

/// The knot vector of every transition.
pub const TRANSITION_KNOTS: [f64; 9] = [0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];

/// The transition curve from its five control points.
pub fn transition_curve(p: [Vec3; 5]) -> Nurbs {
    Nurbs {
        degree: 3,
        knots: TRANSITION_KNOTS.to_vec(),
        points: p.to_vec(),
        weights: None,
    }
}

impl Smoother for BsplineCorner {
    fn name(&self) -> &'static str {
        "bspline-corner"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_reaching(run, tolerance, None)
    }
}

impl BsplineCorner {
    /// [`Smoother::smooth_run`] with every transition's apex held to
    /// `reach` instead of the band's own ([`Band::new`]).
    pub(crate) fn smooth_run_reaching(
        &self,
        run: &Run,
        tolerance: f64,
        reach: Option<Reach>,
    ) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        let o = &self.options;
        o.validate()?;
        let band = Band::new(tolerance, tolerance * BAND_USE);
        let band = reach.map_or(band, |r| band.with_reach(r));
        let mut out = smooth_by_chains(run, tolerance, |chain, out| {
            self.smooth_chain(chain, band, out)
        })?;
        o.arc_joints.apply(&mut out, tolerance);
        Ok(out)
    }

    /// Smooths one chain of segments (its end vertices kept exactly) in
    /// `band`; `bspline-fit` calls it for the sparse parts between fitted
    /// sections.
    pub(crate) fn smooth_chain(&self, chain: &LineChain, band: Band, out: &mut SmoothedRun) {
        let o = &self.options;
        // Routines 1 to 3 plan each corner from the room the previous
        // transition left (section 3.4), under the paper's one reversal
        // threshold (module docs).
        let rules = CornerRules {
            min_half_angle: o.min_half_angle,
            keep_exact_reversal: false,
            room: Room::LeftByPrevious { lambda: o.lambda },
            undirected: Undirected::Skip,
        };
        corner_engine::smooth_chain(chain, band, &rules, &mut UniformPlan(o), out);
    }
}

/// The transitions of `bspline-corner` for the corner engine: the uniform
/// five-point polygon of edge `L` (reach `2L`), sized by sections 3.2 to
/// 3.4 from the room the walk reports.
struct UniformPlan<'a>(&'a BsplineCornerOptions);

impl CornerPlan for UniformPlan<'_> {
    fn reach(&mut self, c: &Corner) -> f64 {
        let o = self.0;
        let (theta, len_in, len_out) = (c.theta, c.room_in, c.len_out);
        // Section 3.2: the longer side is cut to the shorter's length;
        // the polygon spans 2L on each side.
        let mut l = 0.5 * len_in.min(len_out);
        // Section 3.3: scale the polygon when the error leaves the band.
        let e = corner_error(l, theta);
        let eps = c.delta / math::sin(theta);
        if e > eps {
            let e_star = match o.target {
                ErrorTarget::HalfBand => 0.5 * c.delta,
                ErrorTarget::FullBand => eps,
            };
            l *= e_star / e;
        }
        // Section 3.4: leave room for the next corner.
        if !c.last && 2.0 * l > 0.5 * len_out {
            l = 0.25 * len_out;
        }
        2.0 * l
    }

    fn ends(&self, c: &Corner, reach: f64) -> (Vec3, Vec3) {
        (c.at + c.a * reach, c.at + c.out * (reach / c.len_out))
    }

    /// `P1` and `P3` halfway along the edges from the placed ends, so the
    /// polygon stays the paper's (collinear `P0 P1 P2`: G2 joints).
    fn control_points(&self, c: &Corner, _reach: f64, p0: Vec3, p4: Vec3) -> [Vec3; 5] {
        let p1 = p0.lerp(c.at, 0.5);
        let p3 = c.at.lerp(p4, 0.5);
        [p0, p1, c.at, p3, p4]
    }
}
