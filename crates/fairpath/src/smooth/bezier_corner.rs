//! Bezier corner transitions with a proportional coefficient (seed 001:
//! "A locally optimal transition method ...", Proc. IMechE Part B,
//! DOI 10.1177/0954405417697351, section "Preliminary", eqs. 2-5, after
//! Zhao, Zhu, Ding 2013, "A real-time look-ahead interpolation methodology
//! with curvature-continuous B-spline transition scheme for CNC machining of
//! short line segments", Int. J. Mach. Tools Manuf. 65), and the baseline
//! method `ctm` built on them. The optimised method `lotm` is in `lotm.rs`.
//!
//! At a corner `Q` between segments towards the previous and next vertices
//! (unit directions `a`, `b` from the corner, half corner angle `theta`, so
//! the seed's corner angle is `2 theta`), the transition of *transition
//! length* `l` and proportional coefficient `c > 0` has, with
//! `d = l / (1 + c)`, the five B-spline control points
//! `P0 = Q + l a`, `P1 = Q + d a`, `P2 = Q`, `P3 = Q + d b`, `P4 = Q + l b`
//! and knots `{0,0,0,0,0.5,1,1,1,1}` ([`bezier_corner_points`]). Inserting the
//! knot 0.5 twice gives the seed's two symmetric cubic Bezier curves
//! (eq. 2; [`bezier_corner_beziers`]): `P0, P1, Q + (d/2) a, M` and
//! `M, Q + (d/2) b, P3, P4` with the joint `M = Q + d (a + b) / 4`. The
//! curve uses `l` of each segment; `c = 1` is the uniform five-point spline
//! of `bspline-corner` (seed 000) with edge `L = d`.
//!
//! Closed forms (derived here for the left Bezier curve `B(t)` with `d = 1`,
//! writing `B' = 3 (u a + v b)`, `u = -c (1-t)^2 - t (1-t) - t^2/4`,
//! `v = t^2/4`; the seed's eqs. 4 and 5 were lost in extraction):
//!
//! * `|B' x B''| = (9/2) t (c (1-t) + t/2) sin(2 theta)`, so the curvature is
//!   `kappa(t) = t (c (1-t) + t/2) sin(2 theta) / (6 d (u^2 + v^2 + 2 u v
//!   cos(2 theta))^(3/2))`: zero at `t = 0` (the joints with the segments are
//!   G2) and, at the joint `M` (`t = 1`), `4 cos(theta) / (3 d sin^2(theta))`.
//!   The speed has a stationary point at `M` and `kappa' (1) ~ 2 (1 - c)`, so
//!   for `c <= 1` the curvature rises towards `M`; for every `c` in
//!   `[`[`MIN_COEFFICIENT`]`, 1]` at every angle, and for the coefficients
//!   `lotm` uses, `M` is where it peaks (checked on a dense grid of angles
//!   and coefficients by the tests; below about 0.056 a second peak appears
//!   near the ends at obtuse corners), so the peak curvature is
//!   `kappa_max = 4 (1 + c) cos(theta) / (3 l sin^2(theta))`
//!   ([`bezier_corner_peak_curvature`]).
//! * `P0`, `P1` and `Q + (d/2) a` lie on the incoming segment, so only `M`
//!   moves the curve off it: the distance to that segment's line is
//!   `t^3 |M x a| = t^3 d sin(2 theta) / 4`, monotone along the left half,
//!   and at `M` both segments are at that distance. The largest distance of
//!   the transition from its two segments is therefore
//!   `d sin(2 theta) / 4 = l sin(2 theta) / (4 (1 + c))`, independent of the
//!   shape once `d` is fixed ([`bezier_corner_deviation`]); the seed's
//!   approximation error (distance from the corner to the curve) is
//!   `|M - Q| = d cos(theta) / 2` ([`bezier_corner_error`]).
//!
//! Method `ctm` (the seed's conventional transition method, Zhao et al.):
//! `c` fixed ([`CtmOptions::c`]), `d` from the error bound
//! `d = 4 delta / sin(2 theta)`, then `l = (1 + c) d` limited to half of
//! every segment shared with a neighbouring transition, so transitions never
//! overlap. Gaps in the seed, and what is done here:
//!
//! * *The error measure.* The seed bounds the distance from the corner to the
//!   curve; the project's tolerance bounds the distance from the path, so the
//!   transitions use the band fully: deviation `delta = tolerance *`
//!   [`BAND_USE`], as `bspline-corner` does with its default full band.
//! * *The value of `c` in CTM* is not given in the seed: the default is
//!   `c = 1`, the uniform spline (control points at `d` and `2d`), the largest
//!   `c` whose curvature peaks at the joint `M`; any `c` in
//!   `[`[`MIN_COEFFICIENT`]`, 1]` may be set.
//! * *End segments.* A segment with a transition at one end only (the first
//!   and last segments of a chain of lines, and segments next to a kept
//!   corner) is given whole to that transition in both methods: nothing else
//!   competes for it.
//! * *Degenerate corners* are handled as in `bspline-corner` (see
//!   `chains.rs`): zero-length moves are dropped, straight-on vertices
//!   merged, reversals (half-angle below `min_half_angle`, or exactly 0 even
//!   when that is 0) and corners next
//!   to a segment no longer than the zero-length threshold are kept and
//!   reported, arcs stay arcs and their joints keep their continuity, and a
//!   closed run keeps its seam.
//! * *Rounding at shared segments.* When two transitions leave less than the
//!   zero-length threshold of a segment between them, the second starts
//!   exactly where the first ends: its `P0` moves along the segment by at
//!   most that much, which leaves `d`, the deviation and G2 unchanged.
//!
//! The walk along a chain is the corner engine's (`corner_engine.rs`,
//! shared with `bspline-corner`); [`smooth_run_by_corners`] gives it the
//! planned lengths of `ctm` or `lotm` and their rules.

use super::bspline_corner::{transition_curve, BAND_USE};
use super::chains::smooth_by_chains;
use super::corner_engine::{
    self, Band, ChainCorners, Corner, CornerPlan, CornerRules, Reach, Room, Undirected,
};
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::{Nurbs, Vec3};
use crate::math;
use crate::path::Run;
use crate::smooth::{require, OptionError};
use alloc::vec::Vec;

/// Smallest proportional coefficient [`Ctm`] accepts. Below about 0.056 the
/// curvature of the transition can peak near its ends instead of at its
/// joint (obtuse corners), and the closed forms above no longer give the
/// peak. (`lotm` goes lower only at sharp corners, where the end peak
/// appears at far smaller `c`.)
pub const MIN_COEFFICIENT: f64 = 0.06;

/// The five control points of the transition at `corner` with unit
/// directions `a`, `b` towards the previous and next vertices, transition
/// length `l` and proportional coefficient `c` (module docs).
pub fn bezier_corner_points(corner: Vec3, a: Vec3, b: Vec3, l: f64, c: f64) -> [Vec3; 5] {
    let d = l / (1.0 + c);
    [
        corner + a * l,
        corner + a * d,
        corner,
        corner + b * d,
        corner + b * l,
    ]
}

/// The transition as the seed's two cubic Bezier curves (control polygons),
/// from its five B-spline control points: knot 0.5 inserted twice.
pub fn bezier_corner_beziers(p: [Vec3; 5]) -> [[Vec3; 4]; 2] {
    let m = (p[1] + p[2] * 2.0 + p[3]) * 0.25;
    [
        [p[0], p[1], p[1].lerp(p[2], 0.5), m],
        [m, p[2].lerp(p[3], 0.5), p[3], p[4]],
    ]
}

/// The transition curve at `corner` (see [`bezier_corner_points`]).
pub fn bezier_corner_curve(corner: Vec3, a: Vec3, b: Vec3, l: f64, c: f64) -> Nurbs {
    transition_curve(bezier_corner_points(corner, a, b, l, c))
}

/// Largest distance of the transition from its two segments:
/// `l sin(2 theta) / (4 (1 + c))`, at the joint `M` (module docs).
pub fn bezier_corner_deviation(l: f64, c: f64, theta: f64) -> f64 {
    l * math::sin(2.0 * theta) / (4.0 * (1.0 + c))
}

/// The seed's approximation error, the distance from the corner to the
/// curve: `|M - Q| = l cos(theta) / (2 (1 + c))`.
pub fn bezier_corner_error(l: f64, c: f64, theta: f64) -> f64 {
    0.5 * l * math::cos(theta) / (1.0 + c)
}

/// Peak curvature of the transition, at its joint `M`, for `c` in
/// `[MIN_COEFFICIENT, 1]`: `4 (1 + c) cos(theta) / (3 l sin^2(theta))`.
pub fn bezier_corner_peak_curvature(l: f64, c: f64, theta: f64) -> f64 {
    let s = math::sin(theta);
    4.0 * (1.0 + c) * math::cos(theta) / (3.0 * l * s * s)
}

/// The longest transition whose deviation is at most `delta`:
/// `l = 4 (1 + c) delta / sin(2 theta)`.
pub fn bezier_length_for_deviation(delta: f64, c: f64, theta: f64) -> f64 {
    4.0 * (1.0 + c) * delta / math::sin(2.0 * theta)
}

/// Options of [`Ctm`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct CtmOptions {
    /// Proportional coefficient `c` in `[MIN_COEFFICIENT, 1]`.
    pub c: f64,
    /// Corners whose half-angle `theta` (radians) is below this are
    /// reversals and kept.
    pub min_half_angle: f64,
    /// What to do at the joints next to arcs that are not G2: keep them
    /// (the seed's method, the default) or blend them G2
    /// ([`super::ArcJoints`]).
    pub arc_joints: super::ArcJoints,
}

impl Default for CtmOptions {
    fn default() -> Self {
        CtmOptions {
            c: 1.0,
            min_half_angle: 1e-6,
            arc_joints: super::ArcJoints::Kept,
        }
    }
}

/// The `ctm` method (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ctm {
    pub options: CtmOptions,
}

/// A transition planned at one vertex: coefficient `c` and length `l`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Planned {
    pub c: f64,
    pub l: f64,
}

/// Rejects a reversal threshold outside `[0, 0.5)` rad.
pub(crate) fn check_min_half_angle(
    method: &'static str,
    min_half_angle: f64,
) -> Result<(), OptionError> {
    require(
        (0.0..0.5).contains(&min_half_angle),
        method,
        "min_half_angle",
        min_half_angle,
        "must be in [0, 0.5) rad",
    )
}

impl CtmOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), OptionError> {
        require(
            (MIN_COEFFICIENT..=1.0).contains(&self.c),
            "ctm",
            "c",
            self.c,
            "must be in [0.06, 1]",
        )?;
        check_min_half_angle("ctm", self.min_half_angle)
    }
}

impl Smoother for Ctm {
    fn name(&self) -> &'static str {
        "ctm"
    }

    fn smooth_run(&self, run: &Run, tolerance: f64) -> Result<SmoothedRun, SmoothError> {
        self.smooth_run_reaching(run, tolerance, None)
    }
}

impl Ctm {
    /// [`Smoother::smooth_run`] with every transition's apex held to
    /// `reach` instead of the band's own.
    pub(crate) fn smooth_run_reaching(
        &self,
        run: &Run,
        tolerance: f64,
        reach: Option<Reach>,
    ) -> Result<SmoothedRun, SmoothError> {
        let o = self.options;
        o.validate()?;
        let mut out = smooth_run_by_corners(run, tolerance, o.min_half_angle, reach, &|cc| {
            ctm_plan(cc, o.c)
        })?;
        o.arc_joints.apply(&mut out, tolerance);
        Ok(out)
    }
}

/// CTM lengths: `l = (1 + c) 4 delta / sin(2 theta)`, at most half of a
/// shared segment and all of an unshared one.
pub(crate) fn ctm_plan(cc: &ChainCorners, c: f64) -> Vec<Planned> {
    let n = cc.seg_len.len();
    let room = |j: usize| {
        if cc.shared(j) {
            0.5 * cc.seg_len[j]
        } else {
            cc.seg_len[j]
        }
    };
    (0..=n)
        .map(|k| {
            if !cc.blend[k] {
                return Planned::default();
            }
            let l = bezier_length_for_deviation(cc.delta[k], c, cc.theta[k])
                .min(room(k - 1))
                .min(room(k));
            Planned { c, l }
        })
        .collect()
}

/// The driver shared by `ctm` and `lotm`: cleans the run, plans every chain
/// of lines with `plan`, and emits lines and transitions through the corner
/// engine, every apex held to `reach` (the band's own when `None`).
pub(crate) fn smooth_run_by_corners(
    run: &Run,
    tolerance: f64,
    min_half_angle: f64,
    reach: Option<Reach>,
    plan: &dyn Fn(&ChainCorners) -> Vec<Planned>,
) -> Result<SmoothedRun, SmoothError> {
    check_tolerance(tolerance)?;
    let band = Band::new(tolerance, tolerance * BAND_USE);
    let band = reach.map_or(band, |r| band.with_reach(r));
    // Lengths planned per chain on whole segments; exact reversals kept
    // (module docs, "Degenerate corners").
    let rules = CornerRules {
        min_half_angle,
        keep_exact_reversal: true,
        room: Room::WholeSegment,
        undirected: Undirected::LineTo,
    };
    smooth_by_chains(run, tolerance, |chain, out| {
        let mut lengths = ChainPlan {
            plan,
            planned: Vec::new(),
        };
        corner_engine::smooth_chain(chain, band, &rules, &mut lengths, out)
    })
}

/// The transitions of `ctm` and `lotm` for the corner engine: a length and
/// coefficient per vertex from `plan`, the control points of
/// [`bezier_corner_points`].
struct ChainPlan<'a> {
    plan: &'a dyn Fn(&ChainCorners) -> Vec<Planned>,
    planned: Vec<Planned>,
}

impl CornerPlan for ChainPlan<'_> {
    fn plan_chain(&mut self, corners: &ChainCorners) {
        self.planned = (self.plan)(corners);
    }

    fn reach(&mut self, c: &Corner) -> f64 {
        self.planned[c.k].l
    }

    fn ends(&self, c: &Corner, reach: f64) -> (Vec3, Vec3) {
        let [p0, _, _, _, p4] = bezier_corner_points(c.at, c.a, c.b, reach, self.planned[c.k].c);
        (p0, p4)
    }

    /// `P1` and `P3` stay where `d` puts them when the ends move: by at
    /// most the zero-length threshold along their segments (module docs,
    /// "Rounding at shared segments"), or onto the neighbouring vertex
    /// when the whole segment is used.
    fn control_points(&self, c: &Corner, reach: f64, p0: Vec3, p4: Vec3) -> [Vec3; 5] {
        let [_, p1, p2, p3, _] = bezier_corner_points(c.at, c.a, c.b, reach, self.planned[c.k].c);
        [p0, p1, p2, p3, p4]
    }
}
