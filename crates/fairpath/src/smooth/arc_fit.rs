//! Method `arc-fit`: the program's own feed moves refitted with as few
//! blocks as the tolerance allows, the longest arcs (helical in XY when Z
//! changes) and lines that stay within it, as ArcWelder does for 3D
//! printers (<https://github.com/FormerLurker/ArcWelderLib>).
//!
//! **Why.** LinuxCNC's S-curve planner (master, `tp.c`:
//! `tpComputeOptimalVelocity` -> `findSCurveVPeak`) caps the speed at the
//! end of every block at the rest-to-rest jerk-limited peak speed over that
//! block, about `(L sqrt(J) / 2)^(2/3)` for a block of length `L`. A program
//! of few long blocks runs faster there than one of many short ones, however
//! smooth; the other methods write thousands of short arcs. This method
//! writes the fewest blocks it finds.
//!
//! **The fit** (greedy, per chain of lines after the cleaning of
//! `chains.rs`; input arcs and curves are blocks already, kept as they are,
//! and end a chain). From the current vertex `P_i` three kinds of block are
//! tried, each over the longest stretch of vertices `i..j` it fits
//! (expanding `j = i + 1, 2, 4, ...` until a fit fails, then bisecting
//! between the last success and the first failure; at most
//! [`ArcFitOptions::max_lookahead`] segments, and never past a change of
//! the programmed feed):
//!
//! * a **line** `P_i P_j` (one segment always fits; several when every
//!   vertex between is within the fit tolerance of the chord, so nearly
//!   straight stretches become lines, not arcs of huge radius);
//! * a **tangent arc**: the circle in XY through `P_i` tangent to where the
//!   previous block ended and through `P_j` (unique: centre `P_i + n rho`,
//!   `rho = |d|^2 / (2 d.n)` for the chord `d` and the left normal `n` of
//!   the tangent), Z linear in the angle (a helix);
//! * a **free arc**: the circle through `P_i`, the vertex halfway along the
//!   stretch by length, and `P_j`.
//!
//! The kind that reaches furthest is written; on ties the tangent arc
//! (tangent continuity: LinuxCNC blends a tangent joint without slowing),
//! unless the line is tangent too, then the line, then the free arc. Nothing is blended: every joint between
//! blocks that is not G2 (a corner, or the curvature step between tangent
//! blocks) is reported as a kept corner, [`CornerReason::Reversal`] where
//! the path turns back, [`CornerReason::NoRoom`] otherwise (no one block
//! fits across it).
//!
//! **The check** (sound: an accepted arc is within the fit tolerance of the
//! polyline `P_i..P_j` everywhere). The fit tolerance is
//! [`ARC_FIT_SHARE`] (0.9) of the method's tolerance; the rest covers the
//! cleaning (zero-length moves move vertices by at most a thousandth of the
//! tolerance) and the rounding of the written centres. For an arc `C(t)`,
//! `t` in `[0, 1]` (the [`Arc`] that is written, its own formula):
//!
//! 1. *In order.* Every vertex's angle about the centre, unwrapped from
//!    `P_i`, advances along the arc (it may fall back by no more than the
//!    angle of the tolerance, `tol / r`), stays within `[0, sweep]` up to
//!    that slack, and `P_j` ends at the arc's sweep after the same number
//!    of turns: the arc cannot skip a loop of the path. Every vertex is
//!    within the fit tolerance of the arc's point at its angle (not needed
//!    for the guarantee, which is one-sided, but an arc that cuts a spike
//!    of the path off is not what the program meant).
//! 2. *Everywhere.* `|C''(t)| <= M = r_max sweep^2 + 2 |r1 - r0| sweep`
//!    (the rise is linear in `t`), so the arc between two parameters `t_a`,
//!    `t_b` is within `h = M (t_b - t_a)^2 / 8` of the chord between its
//!    points there (the interpolation error of a `C^2` curve by its chord).
//!    The arc is sampled at a step with `h <=` [`ARC_SAMPLE_SHARE`] of the
//!    fit tolerance, and at the vertices' angles (so that most spans run
//!    along one segment). The distance to one segment `s` is convex along a
//!    chord `A B`, so every point of the chord is within
//!    `max(dist(A, s), dist(B, s))` of `s`; over the segments near the
//!    samples' angles (any segment gives an upper bound) the smallest such
//!    value plus `h` bounds the distance of the arc between `A` and `B` to
//!    the polyline. Where that bound exceeds the fit tolerance the span is
//!    halved (at most [`ARC_MAX_SPLIT_DEPTH`] times, the bound with the smaller
//!    `h`), else the arc is rejected: rejection is always safe.
//!
//! A line `P_i P_j` is checked exactly: every vertex's projection on the
//! chord lies in `[0, 1]` and advances (up to the tolerance), and its
//! distance from the chord is within the fit tolerance. The projections of
//! the segments cover `[0, 1]` (they run continuously from 0 to 1), and
//! along a segment the offset from the chord is linear, so every point of
//! the chord is within the larger offset of some segment's ends.
//!
//! **Limits.** Arcs of radius below [`ARC_MIN_RADIUS_MM`] (twice LinuxCNC's
//! 0.00127 mm) or above [`ARC_MAX_RADIUS_PER_TOL`] times the tolerance
//! (numerically a line; the line candidate covers such stretches), sweeps
//! above [`ARC_MAX_SWEEP`] (a full circle is split in two blocks, so
//! rounding never turns a block into a full circle) and arcs whose ends are
//! closer in XY than [`ARC_MIN_CHORD_PER_TOL`] times the tolerance are not
//! written. Arcs lie in the XY plane (G17); a path in another plane, or
//! whose Z is not linear in the angle, fails the check and stays lines.
//!
//! **Cost.** Each check is linear in the vertices it covers plus the
//! samples; the search makes `O(log L)` checks for a block over `L`
//! vertices, and the look-ahead is capped, so a run costs about
//! `O(n log L)`.
//!
//! **Files.** This one holds the method, its options and limits; the
//! candidate arcs are in `arc_candidates.rs`, the checks in `arc_check.rs`,
//! the search and the walk along a chain in `arc_chain.rs`, and the
//! reporting of joints as kept corners in `kept_joints.rs`.
//!
//! [`CornerReason::Reversal`]: super::CornerReason::Reversal
//! [`CornerReason::NoRoom`]: super::CornerReason::NoRoom
//! [`Arc`]: crate::geom::Arc

use super::arc_chain::fit_chain;
use super::chains::smooth_by_chains;
use super::kept_joints::report_corners;
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::JointTolerances;
use crate::path::Run;
use crate::smooth::{require, OptionError};
use core::f64::consts::PI;

pub use crate::budget::{ARC_FIT_SHARE, ARC_SAMPLE_SHARE};

/// Most segments one block covers (keeps the fit linear-ish in the run).
pub const ARC_FIT_LOOKAHEAD: usize = 2000;

/// Smallest radius of a written arc (mm): twice LinuxCNC's limit of
/// 0.00127 mm (`RADIUS_TOLERANCE_INCH`, interp_internal.hh), as the CLI's
/// `MIN_ARC_RADIUS_MM`.
pub const ARC_MIN_RADIUS_MM: f64 = 0.00254;

/// Largest radius of a written arc, in units of the tolerance (5e5 mm at
/// 0.05 mm): beyond it the arc is a line for any block the look-ahead
/// allows, and its centre is far enough out for f64 to lose micrometres.
pub const ARC_MAX_RADIUS_PER_TOL: f64 = 1e7;

/// Largest sweep of one arc (350 degrees): closer to a full turn, the
/// rounding of written ends could make a full circle of it.
pub const ARC_MAX_SWEEP: f64 = 2.0 * PI - PI / 18.0;

/// Shortest XY chord of an arc, in units of the tolerance: arcs whose ends
/// (nearly) coincide in XY are full circles in G-code.
pub const ARC_MIN_CHORD_PER_TOL: f64 = 1e-2;

/// Most times one sampled span of an arc is halved before the arc is
/// rejected.
pub const ARC_MAX_SPLIT_DEPTH: u32 = 8;

/// Options of [`ArcFit`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct ArcFitOptions {
    /// Share of the tolerance the fit uses, in `(0, 1]`
    /// (default [`ARC_FIT_SHARE`]).
    pub fit_share: f64,
    /// Most segments one block covers, at least 2
    /// (default [`ARC_FIT_LOOKAHEAD`]).
    pub max_lookahead: usize,
    /// Try arcs tangent to the previous block (default `true`).
    pub tangent: bool,
}

impl ArcFitOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        let m = "arc-fit";
        let s = self.fit_share;
        require(s > 0.0 && s <= 1.0, m, "fit_share", s, "must be in (0, 1]")?;
        let n = self.max_lookahead;
        require(n >= 2, m, "max_lookahead", n, "must be at least 2")
    }
}

impl Default for ArcFitOptions {
    fn default() -> Self {
        ArcFitOptions {
            fit_share: ARC_FIT_SHARE,
            max_lookahead: ARC_FIT_LOOKAHEAD,
            tangent: true,
        }
    }
}

/// The `arc-fit` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArcFit {
    pub options: ArcFitOptions,
}

impl Smoother for ArcFit {
    fn name(&self) -> &'static str {
        "arc-fit"
    }

    fn writes_for_block_capped_planner(&self) -> bool {
        true
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        check_tolerance(tolerance)?;
        let o = self.options;
        o.validate()?;
        let joints = JointTolerances::from_tolerance(tolerance);
        smooth_by_chains(run, tolerance, |chain, out| {
            let first = out.pieces.len();
            fit_chain(chain, tolerance, &o, out);
            report_corners(&out.pieces, first, &joints, &mut out.kept_corners);
        })
    }
}
