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

use super::chains::{smooth_by_chains, CleanTolerances, CornerReason, KeptCorner, LineChain};
use super::{check_tolerance, SmoothError, SmoothedRun, Smoother};
use crate::geom::{classify_joint, Continuity, JointTolerances};
use crate::geom::{point_segment_distance, Arc, Curve, Line, ParamCurve, Vec3};
use crate::math;
use crate::path::{Piece, Run};
use crate::smooth::{require, OptionError};
use alloc::vec::Vec;
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

/// Most samples of one arc; an arc needing more is rejected.
const MAX_SAMPLES: f64 = 1e6;

/// Steps of the golden-section search for a free arc's bulge.
const BULGE_ITERATIONS: usize = 16;

/// A best-bulge arc is looked for only where the three-point arc's
/// estimate ([`Fitter::bulge_error`]) is within this many fit tolerances:
/// choosing the bulge gains less than a factor of two on it (0.14 against
/// 0.25 of the depth of a corner between two segments), so further out
/// the search would be wasted.
const BULGE_GATE: f64 = 2.5;

/// Segments searched either side of the one at a sample's angle.
const WINDOW: usize = 2;

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

/// `x <= limit`, false for NaN: every check rejects what it cannot
/// compare.
fn within(x: f64, limit: f64) -> bool {
    x <= limit
}

/// The unit XY direction of `v`, if it has one.
fn xy_dir(v: Vec3) -> Option<Vec3> {
    Vec3::new(v.x, v.y, 0.0).normalized(0.0)
}

/// The direction in which `c` ends.
fn end_tangent(c: &Curve) -> Vec3 {
    match c {
        Curve::Line(l) => l.p1 - l.p0,
        c => c.deriv1(c.domain().1),
    }
}

/// Reports the joints inside `pieces[first..]` that are not G2 as kept
/// corners (the joint into them is `smooth_by_chains`' to report): this
/// method blends nothing, so a joint between blocks keeps whatever
/// continuity the fit gave it, and every one that is not G2 is reported,
/// as the other methods report the corners they leave (`none` reports its
/// joints with it too).
pub(crate) fn report_corners(
    pieces: &[Piece],
    first: usize,
    jt: &JointTolerances,
    kept: &mut Vec<KeptCorner>,
) {
    for k in first + 1..pieces.len() {
        let (a, b) = (&pieces[k - 1], &pieces[k]);
        if classify_joint(&a.curve, &b.curve, jt) != Continuity::G2 {
            let ta = end_tangent(&a.curve);
            let tb = b.curve.deriv1(b.curve.domain().0);
            let reason = if ta.angle_to(tb) >= PI - 2.0 * jt.angle {
                CornerReason::Reversal
            } else {
                CornerReason::NoRoom
            };
            kept.push(KeptCorner {
                at: b.start(),
                source_line: a.source_lines.1,
                reason,
            });
        }
    }
}

/// The thresholds of one fit, in mm.
struct Limits {
    /// Fit tolerance.
    tol: f64,
    /// Chord deviation allowed to samples of an arc.
    sample: f64,
    max_radius: f64,
    min_chord: f64,
    /// Below this, points coincide (the cleaning's zero length).
    coincident: f64,
}

/// The fitter over one chain's vertices.
struct Fitter<'a> {
    pts: &'a [Vec3],
    /// Cumulative length at each vertex.
    cum: Vec<f64>,
    lim: Limits,
    /// Scratch: the vertices' angles along the arc being checked, as a
    /// running maximum.
    angles: Vec<f64>,
}

impl Fitter<'_> {
    /// Whether the line `P_i P_j` stays within the fit tolerance of the
    /// polyline and passes its vertices in order (module docs).
    fn line_fits(&self, i: usize, j: usize) -> bool {
        if j == i + 1 {
            return true;
        }
        let (a, b) = (self.pts[i], self.pts[j]);
        let d = b - a;
        let l2 = d.norm_sq();
        let l = math::sqrt(l2);
        if !(l > self.lim.coincident && l.is_finite()) {
            return false;
        }
        let slack = self.lim.tol / l;
        let mut smax: f64 = 0.0;
        for &q in &self.pts[i + 1..j] {
            let w = q - a;
            let s = w.dot(d) / l2;
            if !(s >= smax - slack && s <= 1.0 + slack) {
                return false;
            }
            smax = smax.max(s);
            if !within((w - d * s).norm(), self.lim.tol) {
                return false;
            }
        }
        true
    }

    /// The helical arc from `P_i` to `P_j` about the XY centre `center`,
    /// clockwise or not, if it is one that may be written.
    fn arc(&self, i: usize, j: usize, center: Vec3, clockwise: bool) -> Option<Arc> {
        let (p, q) = (self.pts[i], self.pts[j]);
        if !within(
            self.lim.min_chord,
            Vec3::new(q.x - p.x, q.y - p.y, 0.0).norm(),
        ) {
            return None;
        }
        let arc =
            Arc::from_center(p, q, center, Vec3::Z, clockwise, 1, self.lim.coincident).ok()?;
        let (rmin, rmax) = (arc.r0.min(arc.r1), arc.r0.max(arc.r1));
        let ok = rmin >= ARC_MIN_RADIUS_MM
            && rmax <= self.lim.max_radius
            && arc.sweep > 0.0
            && arc.sweep <= ARC_MAX_SWEEP
            && arc.rise.is_finite()
            && arc.center.is_finite();
        ok.then_some(arc)
    }

    /// The arc from `P_i` leaving along the unit XY direction `t`, through
    /// `P_j` (module docs).
    fn tangent_arc(&self, i: usize, j: usize, t: Vec3) -> Option<Arc> {
        let (p, q) = (self.pts[i], self.pts[j]);
        let d = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let n = Vec3::new(-t.y, t.x, 0.0);
        let dn = d.dot(n);
        let rho = d.norm_sq() / (2.0 * dn);
        if !(rho.is_finite() && math::abs(rho) <= self.lim.max_radius) {
            return None;
        }
        self.arc(i, j, p + n * rho, rho < 0.0)
    }

    /// The arc through `P_i`, the vertex halfway along `i..j` by length,
    /// and `P_j`.
    fn three_point_arc(&self, i: usize, j: usize) -> Option<Arc> {
        let half = 0.5 * (self.cum[i] + self.cum[j]);
        let m = (i + self.cum[i..=j].partition_point(|&c| c < half)).clamp(i + 1, j - 1);
        let (p, pm, q) = (self.pts[i], self.pts[m], self.pts[j]);
        let b = Vec3::new(pm.x - p.x, pm.y - p.y, 0.0);
        let c = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let dd = 2.0 * (b.x * c.y - b.y * c.x);
        let (bb, cc) = (b.norm_sq(), c.norm_sq());
        let ux = (c.y * bb - b.y * cc) / dd;
        let uy = (b.x * cc - c.x * bb) / dd;
        if !(ux.is_finite() && uy.is_finite()) {
            return None;
        }
        self.arc(i, j, p + Vec3::new(ux, uy, 0.0), dd < 0.0)
    }

    /// The XY circle through `P_i` and `P_j` of bulge `b` (the tangent of a
    /// quarter of the signed sweep, positive counter-clockwise): its centre
    /// and whether it runs clockwise. The centre lies on the chord's
    /// perpendicular bisector, `(c / 4) (1 / b - b)` to the left of the
    /// chord of length `c`.
    fn bulge_center(&self, i: usize, j: usize, b: f64) -> Option<(Vec3, bool)> {
        let (p, q) = (self.pts[i], self.pts[j]);
        let d = Vec3::new(q.x - p.x, q.y - p.y, 0.0);
        let c = d.norm();
        let n = Vec3::new(-d.y, d.x, 0.0) / c;
        let s = 0.25 * c * (1.0 / b - b);
        let center = p + d * 0.5 + n * s;
        (center.is_finite() && b != 0.0).then_some((center, b < 0.0))
    }

    /// The largest XY radial distance of the vertices and segment
    /// midpoints of `i..j` from the circle of bulge `b` through `P_i` and
    /// `P_j` (a cheap estimate of the fit, used to choose `b`).
    fn bulge_error(&self, i: usize, j: usize, b: f64) -> f64 {
        let Some((center, _)) = self.bulge_center(i, j, b) else {
            return f64::INFINITY;
        };
        let radial = |q: Vec3| {
            let (dx, dy) = (q.x - center.x, q.y - center.y);
            math::sqrt(dx * dx + dy * dy)
        };
        let r = radial(self.pts[i]);
        let mut e: f64 = 0.0;
        for k in i..j {
            let (a, bq) = (self.pts[k], self.pts[k + 1]);
            e = e
                .max(math::abs(radial(bq) - r))
                .max(math::abs(radial(a.lerp(bq, 0.5)) - r));
        }
        e
    }

    /// An arc from `P_i` to `P_j` not bound to the vertices between: the
    /// bulge that minimises [`Fitter::bulge_error`], by golden-section
    /// search between half and 1.25 times the bulge of the three-point arc
    /// `arc3` (an arc through a corner of the polyline fits best somewhat
    /// flatter than through the corner).
    fn bulge_arc(&self, i: usize, j: usize, arc3: &Arc) -> Option<Arc> {
        let b0 = math::tan(0.25 * arc3.sweep) * if arc3.normal.z < 0.0 { -1.0 } else { 1.0 };
        if !within(self.bulge_error(i, j, b0), BULGE_GATE * self.lim.tol) {
            return None;
        }
        let (mut lo, mut hi) = (0.5 * b0, 1.25 * b0);
        let g = 0.5 * (math::sqrt(5.0) - 1.0);
        let mut x1 = hi - g * (hi - lo);
        let mut x2 = lo + g * (hi - lo);
        let (mut f1, mut f2) = (self.bulge_error(i, j, x1), self.bulge_error(i, j, x2));
        for _ in 0..BULGE_ITERATIONS {
            if f1 < f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = self.bulge_error(i, j, x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = self.bulge_error(i, j, x2);
            }
        }
        let (b, e) = if f1 < f2 { (x1, f1) } else { (x2, f2) };
        if !within(e, self.lim.tol) {
            return None;
        }
        let (center, cw) = self.bulge_center(i, j, b)?;
        self.arc(i, j, center, cw)
    }

    /// A free arc over `i..j` that fits: the three-point arc, else the arc
    /// of the best bulge.
    fn free_arc(&mut self, i: usize, j: usize) -> Option<Arc> {
        let arc3 = self.three_point_arc(i, j)?;
        if self.arc_fits(&arc3, i, j) {
            return Some(arc3);
        }
        let arc = self.bulge_arc(i, j, &arc3)?;
        self.arc_fits(&arc, i, j).then_some(arc)
    }

    /// Whether `arc` (from `P_i` to `P_j`) is within the fit tolerance of
    /// the polyline `P_i..P_j` and passes its vertices in order (module
    /// docs).
    fn arc_fits(&mut self, arc: &Arc, i: usize, j: usize) -> bool {
        let tol = self.lim.tol;
        let rmin = arc.r0.min(arc.r1);
        let rmax = arc.r0.max(arc.r1);
        let sweep = arc.sweep;
        let (c, u) = (arc.center, arc.u);
        let v = arc.normal.cross(u);
        let slack = (tol / rmin).min(0.25 * PI);
        // 1. In order, and every vertex near the arc.
        self.angles.clear();
        self.angles.push(0.0);
        let mut prev = 0.0;
        let mut angle = 0.0;
        let mut top: f64 = 0.0;
        for k in i + 1..=j {
            let w = self.pts[k] - c;
            let a = math::atan2(w.dot(v), w.dot(u));
            let mut da = a - prev;
            if da > PI {
                da -= 2.0 * PI;
            } else if da <= -PI {
                da += 2.0 * PI;
            }
            prev = a;
            angle += da;
            if !(angle >= top - slack && angle >= -slack && angle <= sweep + slack) {
                return false;
            }
            top = top.max(angle);
            self.angles.push(top);
            if k < j {
                let t = (angle / sweep).clamp(0.0, 1.0);
                if !within(arc.eval(t).dist(self.pts[k]), tol) {
                    return false;
                }
            }
        }
        if !within(math::abs(angle - sweep), slack) {
            return false;
        }
        // 2. Everywhere, by sampled chords.
        let m2 = rmax * sweep * sweep + 2.0 * math::abs(arc.r1 - arc.r0) * sweep;
        let n = if m2 > 0.0 {
            math::ceil(math::sqrt(m2 / (8.0 * self.lim.sample)))
        } else {
            1.0
        };
        if !(n.is_finite() && n <= MAX_SAMPLES) {
            return false;
        }
        let n = (n as usize).max(1);
        // The uniform samples merged with the vertices' angles, so that
        // most spans lie along one segment, where the convexity bound is
        // tight.
        let last = self.angles.len() - 1;
        let (mut s, mut kv) = (1, 1);
        let (mut ta, mut pa, mut ka) = (0.0, arc.p0, 0);
        while s <= n {
            let tu = s as f64 / n as f64;
            let tv = if kv < last {
                self.angles[kv] / sweep
            } else {
                f64::INFINITY
            };
            let tb = if tv < tu {
                kv += 1;
                tv
            } else {
                s += 1;
                tu
            };
            if tb <= ta {
                continue;
            }
            let pb = arc.eval(tb);
            let kb = self.vertex_at(ka, tb * sweep);
            if !self.span_fits(arc, i, j, (ta, tb), (pa, pb), (ka, kb), m2, 0) {
                return false;
            }
            (ta, pa, ka) = (tb, pb, kb);
        }
        true
    }

    /// The last vertex (offset from `i`), from `from` on, whose running
    /// angle is at most `angle`.
    fn vertex_at(&self, from: usize, angle: f64) -> usize {
        let mut k = from;
        while k + 1 < self.angles.len() && self.angles[k + 1] <= angle {
            k += 1;
        }
        k
    }

    /// Whether the arc between parameters `t.0` and `t.1` (points `p`,
    /// vertices at their angles `k`, offsets from `i`) is within the fit
    /// tolerance of the polyline `P_i..P_j`.
    #[allow(clippy::too_many_arguments)]
    fn span_fits(
        &self,
        arc: &Arc,
        i: usize,
        j: usize,
        t: (f64, f64),
        p: (Vec3, Vec3),
        k: (usize, usize),
        m2: f64,
        depth: u32,
    ) -> bool {
        let h = m2 * (t.1 - t.0) * (t.1 - t.0) / 8.0;
        let lo = i + k.0.saturating_sub(WINDOW);
        let hi = (i + k.1 + WINDOW).min(j - 1);
        let (mut best, mut near_a, mut near_b) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        for s in lo..=hi {
            let (a, b) = (self.pts[s], self.pts[s + 1]);
            let (da, db) = (
                point_segment_distance(p.0, a, b),
                point_segment_distance(p.1, a, b),
            );
            best = best.min(da.max(db));
            near_a = near_a.min(da);
            near_b = near_b.min(db);
        }
        if best + h <= self.lim.tol {
            return true;
        }
        // An end already too far (from the segments near it) fails however
        // finely the span is cut.
        if depth >= ARC_MAX_SPLIT_DEPTH || !within(near_a.max(near_b), self.lim.tol) {
            return false;
        }
        let tm = 0.5 * (t.0 + t.1);
        let pm = arc.eval(tm);
        let km = self.vertex_at(k.0, tm * arc.sweep).min(k.1);
        self.span_fits(arc, i, j, (t.0, tm), (p.0, pm), (k.0, km), m2, depth + 1)
            && self.span_fits(arc, i, j, (tm, t.1), (pm, p.1), (km, k.1), m2, depth + 1)
    }
}

/// The largest `j` in `lo..=hi` for which `fits(j)` holds, found by
/// expanding `j - lo = 0, 1, 2, 4, ...` until a failure, then bisecting
/// (fits need not be monotone in `j`; every `j` returned did fit).
fn longest(lo: usize, hi: usize, mut fits: impl FnMut(usize) -> bool) -> Option<usize> {
    if lo > hi || !fits(lo) {
        return None;
    }
    let mut good = lo;
    let mut bad;
    let mut step = 1;
    loop {
        let j = lo + step;
        if j >= hi {
            if good < hi && fits(hi) {
                return Some(hi);
            }
            bad = hi;
            break;
        }
        if fits(j) {
            good = j;
            step *= 2;
        } else {
            bad = j;
            break;
        }
    }
    while bad - good > 1 {
        let mid = good + (bad - good) / 2;
        if fits(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(good)
}

/// Fits one chain of lines with the fewest blocks (module docs).
fn fit_chain(chain: &LineChain, tolerance: f64, o: &ArcFitOptions, out: &mut SmoothedRun) {
    let tangent_angle = JointTolerances::from_tolerance(tolerance).angle;
    let pts = &chain.pts;
    let n = chain.segments();
    if n == 0 {
        return;
    }
    let tol = tolerance * o.fit_share;
    let mut cum = Vec::with_capacity(n + 1);
    let mut acc = 0.0;
    cum.push(0.0);
    for w in pts.windows(2) {
        acc += w[0].dist(w[1]);
        cum.push(acc);
    }
    // The last vertex each segment's feed reaches.
    let mut feed_end = alloc::vec![n; n];
    for k in (0..n.saturating_sub(1)).rev() {
        feed_end[k] = if chain.feed[k] == chain.feed[k + 1] {
            feed_end[k + 1]
        } else {
            k + 1
        };
    }
    let mut f = Fitter {
        pts,
        cum,
        lim: Limits {
            tol,
            sample: tol * ARC_SAMPLE_SHARE,
            max_radius: tolerance * ARC_MAX_RADIUS_PER_TOL,
            min_chord: tolerance * ARC_MIN_CHORD_PER_TOL,
            coincident: CleanTolerances::from_tolerance(tolerance).min_segment,
        },
        angles: Vec::new(),
    };
    let mut tangent = out
        .pieces
        .last()
        .filter(|p| p.end() == pts[0])
        .and_then(|p| xy_dir(end_tangent(&p.curve)));
    let mut i = 0;
    while i < n {
        let hi = feed_end[i].min(i + o.max_lookahead);
        let line_j = longest(i + 1, hi, |j| f.line_fits(i, j)).unwrap_or(i + 1);
        let mut best: (usize, Option<Arc>) = (line_j, None);
        if line_j < hi {
            let free_j = longest(i + 2, hi, |j| f.free_arc(i, j).is_some());
            if let Some(j) = free_j.filter(|&j| j > best.0) {
                best = (j, f.free_arc(i, j));
            }
        }
        if let (true, Some(t)) = (o.tangent, tangent) {
            // The tangent arc wins ties, but not against a line that is
            // tangent itself.
            let line_tangent = best.1.is_none()
                && xy_dir(pts[line_j] - pts[i]).is_some_and(|d| d.angle_to(t) <= tangent_angle);
            let floor = if line_tangent { best.0 + 1 } else { best.0 };
            if floor <= hi {
                let tan_j = longest(i + 2, hi, |j| {
                    f.tangent_arc(i, j, t).is_some_and(|a| f.arc_fits(&a, i, j))
                });
                if let Some(j) = tan_j.filter(|&j| j >= floor) {
                    best = (j, f.tangent_arc(i, j, t));
                }
            }
        }
        let (j, arc) = best;
        let curve = match arc {
            Some(a) => {
                out.transitions += j - i - 1;
                Curve::Arc(a)
            }
            None => {
                out.merged_collinear += j - i - 1;
                Curve::Line(Line::new(pts[i], pts[j]))
            }
        };
        tangent = xy_dir(end_tangent(&curve));
        out.pieces.push(Piece {
            curve,
            rapid: false,
            source_lines: (chain.lines[i].0, chain.lines[j - 1].1),
            feed: chain.feed[i],
        });
        i = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn longest_finds_the_end_of_a_monotone_predicate() {
        for end in 3..40 {
            assert_eq!(longest(3, 39, |j| j <= end), Some(end));
        }
        assert_eq!(longest(3, 39, |_| false), None);
        assert_eq!(longest(3, 3, |_| true), Some(3));
        assert_eq!(longest(4, 3, |_| true), None);
    }

    #[test]
    fn tangent_arc_leaves_along_the_tangent() {
        let pts = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let mut f = Fitter {
            pts: &pts,
            cum: alloc::vec![0.0, 1.0, 2.0],
            lim: Limits {
                tol: 0.01,
                sample: 0.0005,
                max_radius: 1e5,
                min_chord: 1e-4,
                coincident: 1e-5,
            },
            angles: Vec::new(),
        };
        let a = f.tangent_arc(0, 2, Vec3::X).unwrap();
        assert!((a.r0 - 1.0).abs() < 1e-12 && (a.sweep - PI).abs() < 1e-12);
        let t = a.deriv1(0.0);
        assert!(t.y.abs() < 1e-12 && t.x > 0.0);
        let b = f.three_point_arc(0, 2).unwrap();
        assert!((b.center - Vec3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
        let (c, cw) = f.bulge_center(0, 2, 1.0).unwrap();
        assert!((c - b.center).norm() < 1e-12 && !cw);
        // The two segments are chords of 90 degrees: 0.29 mm off the arc.
        assert!(f.free_arc(0, 2).is_none());
        f.lim.tol = 0.3;
        f.lim.sample = 0.015;
        assert!(f.free_arc(0, 2).is_some());
    }
}
