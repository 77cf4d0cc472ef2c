//! LinuxCNC's splines as LinuxCNC computes them: the knot vector of a G5.2
//! block, its NURBS evaluation, and the biarcs its canon layer feeds.
//!
//! Source: LinuxCNC master (commit 5c41560eb),
//! `src/emc/rs274ngc/nurbs_additional_functions.cc`
//! (`nurbs_G5_knot_vector_creator`, `nurbs_G5_Nmix`, `nurbs_G5_Rden`,
//! `nurbs_G5_point`, `nurbs_G5_tangent`; written by M. Leto, 2009) and
//! `src/emc/task/emccanon.cc` (`NURBS_G5_FEED`, the static `biarc` and `arc`,
//! `ARC_FEED`'s angle wrap). LinuxCNC 2.9 (every 2.9.x tag and Debian's
//! 2.9.0~pre1) has the same arithmetic under other names (`NURBS_FEED`,
//! `knot_vector_creator`, `Nmix`, ...) with two differences noted below.
//!
//! ## What LinuxCNC runs for G5, G5.1, G5.2/G5.3
//! The interpreter collects control points in the plane's coordinates
//! ([`Plane::to_plane`]), program units, the current position first, and
//! calls `NURBS_G5_FEED(points, order)`: order 4 for G5 (a cubic Bezier),
//! 3 for G5.1 (a quadratic Bezier), the block's `L` (at least 3) for G5.2.
//! The canon layer then
//! 1. builds the clamped uniform knot vector with integer knots
//!    ([`g5_2_knots`]): `order` zeros, `1, 2, ..., n - order + 1`, `order`
//!    times `n - order + 2` (`n + 1` points), so `u` runs over
//!    `[0, umax]`, `umax = n - order + 2`;
//! 2. samples `div = 4 (n + 1)` parameters `u_i = umax i / div`, with the
//!    point from the Cox-de Boor recursion written with closed intervals at
//!    order 1 (a parameter on a knot counts in both spans; the rational sum
//!    divides it out) and the unit tangent from a central difference of
//!    step [`DU`] clamped to `[0, umax]`;
//! 3. joins each pair of consecutive samples by a biarc (`biarc`, radius
//!    ratio 1; Bolton's construction: the two arcs meet at
//!    `p2 = (p1 beta + p3 alpha) / (alpha + beta)`, `p1 = p0 + alpha t0`,
//!    `p3 = p4 - beta t4`, `beta` the larger root of
//!    `a beta^2 + b beta + c = 0`, `a = 2 (t0.t4 - 1)`,
//!    `b = 2 (p0 - p4).(t0 + t4)`, `c = |p0 - p4|^2`);
//! 4. feeds each arc by `arc`: `ARC_FEED` to the arc's end about the centre
//!    on the start tangent's normal, counter-clockwise when the signed
//!    radius `-(|chord|^2) / (2 chord x tangent)` is negative, or a straight
//!    feed when `|2 chord x tangent|` is at most [`ARC_DEN_MIN`].
//!
//! Degenerate cases, replicated: `biarc` feeds nothing when the discriminant
//! is negative or both roots are positive; it feeds one straight line to
//! `p4` when a root is infinite or `beta > 1 / CART_FUZZ` (master only:
//! LinuxCNC 2.9 computes on with the infinite or huge `beta`, which gives NaN
//! or a numerically straight pair); that straight feed takes `p4`'s two
//! coordinates as X and Y whatever the plane (a LinuxCNC bug in G18/G19,
//! replicated: the tool leaves the plane's axes there). Moves with a NaN end
//! (`beta = 0` from coincident samples gives `0/0`) are dropped, and
//! zero-length straight moves too (LinuxCNC's motion planner discards them).
//! `ARC_FEED` makes a full turn when the arc's angle is at most
//! [`ARC_FEED_MIN_ANGLE`]. With `G64 Q` above 0 LinuxCNC's naive-CAM
//! detector may further replace XY arcs by lines; that is not modelled.
//!
//! Everything here is computed in program units, as LinuxCNC does (its
//! thresholds are in program units); [`g5_2_motion`] converts the result
//! to mm curves.

use super::Plane;
use crate::geom::{Arc, ArcError, Curve, Line, Nurbs, ParamCurve, Vec3};
use crate::math;
use alloc::vec::Vec;
use core::f64::consts::PI;

/// `nurbs_G5_tangent`'s central-difference step, in knot units.
pub const DU: f64 = 1e-5;
/// `arc`'s `small`: below this `|2 chord x tangent|` (program units) an arc
/// of the biarc is fed as a straight line.
pub const ARC_DEN_MIN: f64 = 0.000001;
/// posemath's `CART_FUZZ`: `biarc` feeds a straight line when
/// `beta > 1 / CART_FUZZ`.
pub const CART_FUZZ: f64 = 1.0e-8;
/// `ARC_FEED`'s `min_arc_angle` (radians): an arc whose angle from start to
/// end is at most this becomes a full turn.
pub const ARC_FEED_MIN_ANGLE: f64 = 1e-12;
/// Parameter samples per control point (`div = 4 * points`).
pub const SAMPLES_PER_POINT: usize = 4;
/// Units in the last place of the largest coordinate within which the end
/// of the last move, as LinuxCNC evaluates it, counts as the last control
/// point (`(x w) / w` and the basis sums round).
const END_ULPS: f64 = 64.0;

/// Why a G5.2 definition is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum G5Error {
    #[error("order {0} is below 2")]
    BadOrder(usize),
    #[error("{points} control points, fewer than the order {order}")]
    TooFewPoints { points: usize, order: usize },
    #[error("weights must be positive and finite, one per control point")]
    BadWeights,
    #[error("a coordinate is not finite")]
    NotFinite,
    #[error("millimetres per program unit must be positive and finite")]
    BadScale,
    #[error("order {0} is above the highest degree fairpath evaluates plus one")]
    OrderTooHigh(usize),
}

/// LinuxCNC's G5.2 knot vector (`nurbs_G5_knot_vector_creator(n, k)` with
/// `n = n_points - 1`, `k = order`): `order` zeros, then
/// `1, 2, ..., n_points - order`, then `order` times `n_points - order + 1`.
/// `n_points + order` knots.
pub fn g5_2_knots(n_points: usize, order: usize) -> Result<Vec<f64>, G5Error> {
    Ok(int_knots(n_points, order)?
        .into_iter()
        .map(|k| k as f64)
        .collect())
}

fn int_knots(n_points: usize, order: usize) -> Result<Vec<u64>, G5Error> {
    if order < 2 {
        return Err(G5Error::BadOrder(order));
    }
    if n_points < order {
        return Err(G5Error::TooFewPoints {
            points: n_points,
            order,
        });
    }
    let (n, k) = (n_points as u64 - 1, order as u64);
    Ok((0..=n + k)
        .map(|i| {
            if i < k {
                0
            } else if i <= n {
                i - k + 1
            } else {
                n + 2 - k
            }
        })
        .collect())
}

/// The exact curve of a G5.2 block: the NURBS of degree `order - 1` with
/// LinuxCNC's knot vector ([`g5_2_knots`]) through `points` (any units;
/// the first is the position before the block) and `weights` (the `P`
/// words; `None` in the result when all are equal).
pub fn g5_2_curve(points: &[Vec3], weights: &[f64], order: usize) -> Result<Nurbs, G5Error> {
    check(points.len(), weights, order)?;
    if order > Nurbs::MAX_DEGREE + 1 {
        return Err(G5Error::OrderTooHigh(order));
    }
    if points.iter().any(|p| !p.is_finite()) {
        return Err(G5Error::NotFinite);
    }
    let knots = g5_2_knots(points.len(), order)?;
    let weights = if weights.iter().all(|&w| w == weights[0]) {
        None
    } else {
        Some(weights.to_vec())
    };
    Nurbs::new(order - 1, knots, points.to_vec(), weights).map_err(|_| G5Error::NotFinite)
}

fn check(n_points: usize, weights: &[f64], order: usize) -> Result<(), G5Error> {
    int_knots(n_points, order)?;
    if weights.len() != n_points || weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(G5Error::BadWeights);
    }
    Ok(())
}

/// One canon motion call, in program units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CanonMove {
    /// `STRAIGHT_FEED` to `end` (X, Y, Z).
    Straight { end: Vec3 },
    /// `ARC_FEED` from the current position to `end` about the axis through
    /// `center` (in-plane coordinates, [`Plane::to_plane`]) along the plane
    /// normal, counter-clockwise about it when `ccw`.
    Arc {
        end: Vec3,
        center: [f64; 2],
        ccw: bool,
    },
}

impl CanonMove {
    pub fn end(&self) -> Vec3 {
        match *self {
            CanonMove::Straight { end } | CanonMove::Arc { end, .. } => end,
        }
    }
}

/// LinuxCNC's evaluation of a G5.2 NURBS (`nurbs_G5_point`,
/// `nurbs_G5_tangent`), operation for operation.
struct G5Eval<'a> {
    pts: &'a [[f64; 2]],
    w: &'a [f64],
    k: usize,
    knots: Vec<u64>,
    umax: f64,
}

impl G5Eval<'_> {
    /// `nurbs_G5_Nmix(i, k, u)` for every control point `i`: the recursion
    /// evaluated bottom-up (the same operations on the same values).
    fn basis(&self, u: f64) -> Vec<f64> {
        let kv = &self.knots;
        let mut n: Vec<f64> = (0..kv.len() - 1)
            .map(|i| {
                if u >= kv[i] as f64 && u <= kv[i + 1] as f64 {
                    1.0
                } else {
                    0.0
                }
            })
            .collect();
        for j in 2..=self.k {
            for i in 0..kv.len() - j {
                let d1 = kv[i + j - 1] - kv[i];
                let d2 = kv[i + j] - kv[i + 1];
                n[i] = if d1 == 0 && d2 != 0 {
                    ((kv[i + j] as f64 - u) * n[i + 1]) / d2 as f64
                } else if d2 == 0 && d1 != 0 {
                    ((u - kv[i] as f64) * n[i]) / d1 as f64
                } else if d1 == 0 && d2 == 0 {
                    0.0
                } else {
                    ((u - kv[i] as f64) * n[i]) / d1 as f64
                        + ((kv[i + j] as f64 - u) * n[i + 1]) / d2 as f64
                };
            }
        }
        n.truncate(self.pts.len());
        n
    }

    /// `nurbs_G5_point(u)`.
    fn point(&self, u: f64) -> [f64; 2] {
        let n = self.basis(u);
        let mut rden = 0.0;
        for (ni, wi) in n.iter().zip(self.w) {
            rden += ni * wi;
        }
        let (mut x, mut y) = (0.0, 0.0);
        for ((p, ni), wi) in self.pts.iter().zip(&n).zip(self.w) {
            x += p[0] * ni * wi / rden;
            y += p[1] * ni * wi / rden;
        }
        [x, y]
    }

    /// `nurbs_G5_tangent(u)`.
    fn tangent(&self, u: f64) -> [f64; 2] {
        let lo = u - DU;
        let ulo = if 0.0 < lo { lo } else { 0.0 };
        let hi = u + DU;
        let uhi = if hi < self.umax { hi } else { self.umax };
        let p1 = self.point(ulo);
        let p3 = self.point(uhi);
        unit([(p3[0] - p1[0]) / (uhi - ulo), (p3[1] - p1[1]) / (uhi - ulo)])
    }
}

/// LinuxCNC's point of a G5.2 NURBS at parameter `u` in `[0, umax]`,
/// `umax = points - order + 1` (`nurbs_G5_point`: the closed-interval
/// Cox-de Boor recursion, the rational sum in its order of operations).
pub fn g5_2_point(
    points: &[[f64; 2]],
    weights: &[f64],
    order: usize,
    u: f64,
) -> Result<[f64; 2], G5Error> {
    Ok(G5Eval::new(points, weights, order)?.point(u))
}

/// LinuxCNC's unit tangent of a G5.2 NURBS at `u` (`nurbs_G5_tangent`: a
/// central difference of step [`DU`] clamped to `[0, umax]`, normalised).
pub fn g5_2_tangent(
    points: &[[f64; 2]],
    weights: &[f64],
    order: usize,
    u: f64,
) -> Result<[f64; 2], G5Error> {
    Ok(G5Eval::new(points, weights, order)?.tangent(u))
}

impl<'a> G5Eval<'a> {
    fn new(pts: &'a [[f64; 2]], w: &'a [f64], k: usize) -> Result<G5Eval<'a>, G5Error> {
        check(pts.len(), w, k)?;
        Ok(G5Eval {
            pts,
            w,
            k,
            knots: int_knots(pts.len(), k)?,
            umax: (pts.len() + 1 - k) as f64,
        })
    }
}

/// emccanon's `unit`: divides by `hypot` unless it is 0.
fn unit(v: [f64; 2]) -> [f64; 2] {
    let h = math::hypot(v[0], v[1]);
    if h != 0.0 {
        [v[0] / h, v[1] / h]
    } else {
        v
    }
}

/// The canon layer's state while it feeds one block.
struct Feeder {
    plane: Plane,
    /// Position after the moves fed so far (`canon.endPoint`), program units.
    cur: Vec3,
    out: Vec<CanonMove>,
}

impl Feeder {
    fn feed(&mut self, m: CanonMove) {
        self.cur = m.end();
        self.out.push(m);
    }

    /// emccanon's `arc(x0, y0, x1, y1, dx, dy)`.
    fn arc(&mut self, p0: [f64; 2], p1: [f64; 2], d: [f64; 2]) {
        let small = ARC_DEN_MIN;
        let x = p1[0] - p0[0];
        let y = p1[1] - p0[1];
        let den = 2.0 * (y * d[0] - x * d[1]);
        let off = self.plane.off_plane(self.cur);
        let end = self.plane.from_plane(p1, off);
        if math::abs(den) > small {
            let r = -(x * x + y * y) / den;
            let i = d[1] * r;
            let j = -d[0] * r;
            let center = [p0[0] + i, p0[1] + j];
            self.feed(CanonMove::Arc {
                end,
                center,
                ccw: r < 0.0,
            });
        } else {
            self.feed(CanonMove::Straight { end });
        }
    }

    /// emccanon's `biarc(p0, ts, p4, te, r = 1)`; false when it feeds
    /// nothing.
    fn biarc(&mut self, p0: [f64; 2], ts: [f64; 2], p4: [f64; 2], te: [f64; 2]) -> bool {
        let r = 1.0;
        let [tsx, tsy] = unit(ts);
        let [tex, tey] = unit(te);
        let vx = p0[0] - p4[0];
        let vy = p0[1] - p4[1];
        let c = vx * vx + vy * vy;
        let b = 2.0 * (vx * (r * tsx + tex) + vy * (r * tsy + tey));
        let a = 2.0 * r * (tsx * tex + tsy * tey - 1.0);
        let discr = b * b - 4.0 * a * c;
        if discr < 0.0 {
            return false;
        }
        let disq = math::sqrt(discr);
        let beta1 = (-b - disq) / 2.0 / a;
        let beta2 = (-b + disq) / 2.0 / a;
        if beta1 > 0.0 && beta2 > 0.0 {
            return false;
        }
        // std::max(beta1, beta2)
        let beta = if beta1 < beta2 { beta2 } else { beta1 };
        if beta1 == f64::INFINITY || beta2 == f64::INFINITY || beta > 1.0 / CART_FUZZ {
            // STRAIGHT_FEED(p4x, p4y, p.z): X and Y whatever the plane.
            let end = Vec3::new(p4[0], p4[1], self.cur.z);
            self.feed(CanonMove::Straight { end });
        } else {
            let alpha = beta * r;
            let ab = alpha + beta;
            let p1 = [p0[0] + alpha * tsx, p0[1] + alpha * tsy];
            let p3 = [p4[0] - beta * tex, p4[1] - beta * tey];
            let p2 = [
                (p1[0] * beta + p3[0] * alpha) / ab,
                (p1[1] * beta + p3[1] * alpha) / ab,
            ];
            let tm = unit([p3[0] - p2[0], p3[1] - p2[1]]);
            self.arc(p0, p2, [tsx, tsy]);
            self.arc(p2, p4, tm);
        }
        true
    }
}

/// The canon calls LinuxCNC's `NURBS_G5_FEED` makes for a G5/G5.1/G5.2
/// spline: `points` are the control points in the plane's coordinates,
/// program units, the first being the position before the block; `start`
/// is that position in X, Y, Z (program units: it gives the off-plane
/// coordinate); `weights` one per point; `order` as LinuxCNC uses it (4
/// for G5, 3 for G5.1, the block's for G5.2). Calls with a non-finite end
/// are left out (see the module docs).
pub fn nurbs_g5_feed(
    start: Vec3,
    points: &[[f64; 2]],
    weights: &[f64],
    order: usize,
    plane: Plane,
) -> Result<Vec<CanonMove>, G5Error> {
    check(points.len(), weights, order)?;
    if !start.is_finite() || points.iter().flatten().any(|c| !c.is_finite()) {
        return Err(G5Error::NotFinite);
    }
    let ev = G5Eval::new(points, weights, order)?;
    let umax = ev.umax;
    let div = points.len() * SAMPLES_PER_POINT;
    let mut f = Feeder {
        plane,
        cur: start,
        out: Vec::with_capacity(2 * div),
    };
    let mut p0 = ev.point(0.0);
    let mut t0 = ev.tangent(0.0);
    for i in 1..=div {
        let u = umax * i as f64 / div as f64;
        let p1 = ev.point(u);
        let t1 = ev.tangent(u);
        // When biarc feeds nothing, the next one starts from p1 all the same.
        let _fed = f.biarc(p0, t0, p1, t1);
        p0 = p1;
        t0 = t1;
        // A NaN end leaves LinuxCNC's position undefined: keep the last
        // finite one (the move is dropped below).
        if !f.cur.is_finite() {
            f.cur = f
                .out
                .iter()
                .rev()
                .map(|m| m.end())
                .find(|e| e.is_finite())
                .unwrap_or(start);
        }
    }
    f.out.retain(|m| match *m {
        CanonMove::Straight { end } => end.is_finite(),
        CanonMove::Arc { end, center, .. } => {
            end.is_finite() && center[0].is_finite() && center[1].is_finite()
        }
    });
    Ok(f.out)
}

/// What LinuxCNC runs for a G5/G5.1/G5.2 spline, as curves in mm:
/// [`nurbs_g5_feed`] on `points` (program units, in-plane, the first being
/// the position before the block) and `weights`, from `start` (mm: the
/// first curve starts there exactly), converted with `mm_per_unit`.
/// `ARC_FEED`s become [`Arc`]s from the previous end (spiral when LinuxCNC's
/// start is not on the circle through the end, as its motion planner runs
/// them; a line when the start or end is on the centre), `STRAIGHT_FEED`s
/// [`Line`]s; zero-length lines are dropped. Consecutive curves join
/// exactly. The last curve ends exactly at the last control point when
/// LinuxCNC's evaluation gets there within rounding; otherwise (only when
/// its last biarc degenerates) a straight line to the last control point is
/// added, where LinuxCNC's interpreter continues from.
pub fn g5_2_motion(
    start: Vec3,
    points: &[[f64; 2]],
    weights: &[f64],
    order: usize,
    plane: Plane,
    mm_per_unit: f64,
) -> Result<Vec<Curve>, G5Error> {
    if !(mm_per_unit.is_finite() && mm_per_unit > 0.0) {
        return Err(G5Error::BadScale);
    }
    if points.is_empty() {
        return Err(G5Error::TooFewPoints { points: 0, order });
    }
    let start_prog = plane.from_plane(points[0], plane.off_plane(start) / mm_per_unit);
    let calls = nurbs_g5_feed(start_prog, points, weights, order, plane)?;
    // Program units to mm; coordinates unchanged from the start keep its
    // exact mm value.
    let sp = start_prog.to_array();
    let sm = start.to_array();
    let to_mm = |p: Vec3| {
        let mut c = p.to_array();
        for a in 0..3 {
            c[a] = if c[a] == sp[a] {
                sm[a]
            } else {
                c[a] * mm_per_unit
            };
        }
        Vec3::from_array(c)
    };
    let last = points[points.len() - 1];
    let end_mm = to_mm(plane.from_plane(last, sp[plane.axes().2]));
    let scale = points
        .iter()
        .flatten()
        .fold(0.0f64, |m, c| m.max(math::abs(*c)))
        * mm_per_unit;
    let end_tol = END_ULPS * f64::EPSILON * scale;
    let mut out: Vec<Curve> = Vec::with_capacity(calls.len() + 1);
    let mut cur = start;
    let n_calls = calls.len();
    for (i, call) in calls.into_iter().enumerate() {
        let mut end = to_mm(call.end());
        if i + 1 == n_calls && end.dist(end_mm) <= end_tol {
            end = end_mm;
        }
        let curve = match call {
            CanonMove::Straight { .. } => {
                if end == cur {
                    continue;
                }
                Curve::Line(Line::new(cur, end))
            }
            CanonMove::Arc { center, ccw, .. } => {
                let c = plane.from_plane(
                    [center[0] * mm_per_unit, center[1] * mm_per_unit],
                    plane.off_plane(end),
                );
                match Arc::from_center(cur, end, c, plane.normal(), !ccw, 1, 0.0) {
                    Ok(mut arc) => {
                        if arc.sweep <= ARC_FEED_MIN_ANGLE {
                            arc.sweep += 2.0 * PI;
                        }
                        Curve::from(arc)
                    }
                    Err(ArcError::ZeroRadius) => {
                        if end == cur {
                            continue;
                        }
                        Curve::Line(Line::new(cur, end))
                    }
                    Err(ArcError::NotFinite) => continue,
                }
            }
        };
        cur = curve.end();
        out.push(curve);
    }
    if cur != end_mm {
        out.push(Curve::Line(Line::new(cur, end_mm)));
    }
    Ok(out)
}

/// Convenience: the in-plane program-unit coordinates of mm points (for
/// [`g5_2_motion`] on a curve that is about to be written).
pub fn plane_coords(points: &[Vec3], plane: Plane, mm_per_unit: f64) -> Vec<[f64; 2]> {
    points
        .iter()
        .map(|p| {
            let c = plane.to_plane(*p);
            [c[0] / mm_per_unit, c[1] / mm_per_unit]
        })
        .collect()
}

/// Largest distance of a normalised knot from LinuxCNC's, in units of its
/// knot spacing, for a curve's own knot vector to count as LinuxCNC's.
pub const G5_2_KNOT_MATCH: f64 = 1e-9;

/// Whether `n`'s knot vector is LinuxCNC's G5.2 one ([`g5_2_knots`]) up to
/// an affine map, within [`G5_2_KNOT_MATCH`].
pub fn has_g5_2_knots(n: &Nurbs) -> bool {
    let order = n.degree + 1;
    let Ok(lc) = g5_2_knots(n.points.len(), order) else {
        return false;
    };
    if lc.len() != n.knots.len() {
        return false;
    }
    let (a, b) = (n.knots[0], n.knots[n.knots.len() - 1]);
    let umax = lc[lc.len() - 1];
    let scale = umax / (b - a);
    scale.is_finite()
        && n.knots
            .iter()
            .zip(&lc)
            .all(|(k, l)| crate::math::abs((k - a) * scale - l) <= G5_2_KNOT_MATCH)
}

/// The G5.2 blocks that say `nurbs` exactly: the curve itself when its knot
/// vector is LinuxCNC's ([`has_g5_2_knots`]), else its Bezier spans
/// (LinuxCNC fixes the knots from the number of points, so only these two
/// forms are exact), degree 1 raised to 2 (G5.2's lowest order is 3).
pub fn g5_2_blocks_of(nurbs: &Nurbs) -> Vec<Nurbs> {
    if nurbs.degree >= 2 && has_g5_2_knots(nurbs) {
        return alloc::vec![nurbs.clone()];
    }
    let spans = nurbs.bezier_spans();
    if nurbs.degree == 1 {
        spans.iter().map(elevate_linear).collect()
    } else {
        spans
    }
}

/// A degree-1 Bezier span raised to degree 2 (the same line).
fn elevate_linear(span: &Nurbs) -> Nurbs {
    let (p0, p1) = (span.points[0], span.points[1]);
    let w = span
        .weights
        .clone()
        .unwrap_or_else(|| alloc::vec![1.0, 1.0]);
    let wm = 0.5 * (w[0] + w[1]);
    let mid = (p0 * w[0] + p1 * w[1]) / (w[0] + w[1]);
    let (t0, t1) = (span.knots[0], span.knots[span.knots.len() - 1]);
    Nurbs {
        degree: 2,
        knots: alloc::vec![t0, t0, t0, t1, t1, t1],
        points: alloc::vec![p0, mid, p1],
        weights: span.weights.as_ref().map(|_| alloc::vec![w[0], wm, w[1]]),
    }
}

/// What LinuxCNC runs for `nurbs` written as G5.2 blocks in `plane`
/// ([`g5_2_blocks_of`], in mm, unrounded): each block's [`g5_2_motion`],
/// from the curve's start to its end.
pub fn g5_2_motion_of(nurbs: &Nurbs, plane: Plane) -> Result<Vec<Curve>, G5Error> {
    let mut out = Vec::new();
    for b in g5_2_blocks_of(nurbs) {
        let pts = plane_coords(&b.points, plane, 1.0);
        let w = b
            .weights
            .clone()
            .unwrap_or_else(|| alloc::vec![1.0; b.points.len()]);
        let start = out.last().map_or(b.points[0], |c: &Curve| c.end());
        out.extend(g5_2_motion(start, &pts, &w, b.degree + 1, plane, 1.0)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knot_vector_as_linuxcnc() {
        assert_eq!(
            g5_2_knots(5, 3).unwrap(),
            vec![0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            g5_2_knots(4, 4).unwrap(),
            vec![0., 0., 0., 0., 1., 1., 1., 1.]
        );
        assert!(g5_2_knots(2, 3).is_err());
        assert!(g5_2_knots(3, 1).is_err());
    }

    #[test]
    fn linuxcnc_evaluation_is_the_nurbs() {
        let pts: Vec<[f64; 2]> = vec![[0.0, 0.0], [0.0, 1.0], [2.0, 2.0], [2.0, 0.0], [0.5, -1.0]];
        let w = [1.0, 2.0, 0.5, 1.0, 3.0];
        for order in 3..=5 {
            let ev = G5Eval::new(&pts, &w, order).unwrap();
            let p3: Vec<Vec3> = pts.iter().map(|p| Vec3::new(p[0], p[1], 0.0)).collect();
            let exact = g5_2_curve(&p3, &w, order).unwrap();
            for i in 0..=40 {
                let u = ev.umax * i as f64 / 40.0;
                let a = ev.point(u);
                let b = exact.eval(u);
                assert!((a[0] - b.x).abs() < 1e-12 && (a[1] - b.y).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn motion_joins_and_follows_the_curve() {
        let pts: Vec<[f64; 2]> = vec![[0.0, 0.0], [0.0, 10.0], [20.0, 20.0], [20.0, 0.0]];
        let w = [1.0; 4];
        for plane in [Plane::Xy, Plane::Zx, Plane::Yz] {
            let start = plane.from_plane(pts[0], 5.0);
            let m = g5_2_motion(start, &pts, &w, 3, plane, 1.0).unwrap();
            assert_eq!(m[0].start(), start);
            for pair in m.windows(2) {
                assert_eq!(pair[0].end(), pair[1].start());
            }
            assert_eq!(m.last().unwrap().end(), plane.from_plane(pts[3], 5.0));
            let p3: Vec<Vec3> = pts.iter().map(|p| plane.from_plane(*p, 5.0)).collect();
            let exact = g5_2_curve(&p3, &w, 3).unwrap();
            for c in &m {
                for i in 0..=8 {
                    let p = c.eval(i as f64 / 8.0);
                    let d = (0..=2000)
                        .map(|j| exact.eval(2.0 * j as f64 / 2000.0).dist(p))
                        .fold(f64::INFINITY, f64::min);
                    assert!(d < 0.05, "{plane:?}: {d}");
                }
            }
        }
    }

    /// Reference canon calls from LinuxCNC master's own `NURBS_G5_FEED`,
    /// `biarc` and `arc` (emccanon.cc and nurbs_additional_functions.cc
    /// compiled with stubs printing each call; glibc's hypot): the 1st, 5th
    /// and last of the 32 ARC_FEEDs of a quadratic over the unit square's
    /// corners, bit for bit.
    #[test]
    fn arcs_bit_for_bit_as_linuxcnc() {
        let pts = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        let calls = nurbs_g5_feed(Vec3::ZERO, &pts, &[1.0; 4], 3, Plane::Xy).unwrap();
        assert_eq!(calls.len(), 32);
        let arc = |i: usize| match calls[i] {
            CanonMove::Arc { end, center, ccw } => (
                [end.x.to_bits(), end.y.to_bits()],
                [center[0].to_bits(), center[1].to_bits()],
                ccw,
            ),
            _ => panic!("not an arc"),
        };
        let want = [
            (
                0,
                [0x3f5dc5cca9cad96e, 0x3fbe04e231ba571d],
                [0x400e4799e3a64b3d, 0xbee3d81d5e190d8c],
            ),
            (
                4,
                [0x3fa89c969e095a53, 0x3fe0c5294cbae5e6],
                [0x3ffa8320d0c84a85, 0x3fc55129944a850c],
            ),
            (
                31,
                [1.0f64.to_bits(), 0],
                [0xc0064799e3a10f7d, 0xbee3d81d7a17c000],
            ),
        ];
        for (i, end, center) in want {
            let (e, c, ccw) = arc(i);
            #[cfg(feature = "std")]
            assert_eq!((e, c), (end, center), "call {i}");
            #[cfg(not(feature = "std"))]
            let _ = (e, c, end, center);
            assert!(!ccw);
        }
    }

    /// LinuxCNC master's straight-feed fallback in `biarc` writes the
    /// plane's two coordinates to X and Y: in G19 a straight G5.2 moves X.
    #[test]
    fn straight_fallback_keeps_linuxcncs_plane_bug() {
        let pts = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
        let start = Vec3::new(5.0, 0.0, 0.0);
        let calls = nurbs_g5_feed(start, &pts, &[1.0; 4], 3, Plane::Yz).unwrap();
        assert_eq!(
            calls[0],
            CanonMove::Straight {
                end: Vec3::new(0.2421875, 0.0, 0.0)
            }
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        let pts = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]];
        let o = Vec3::ZERO;
        assert!(nurbs_g5_feed(o, &pts, &[1.0, -1.0, 1.0], 3, Plane::Xy).is_err());
        assert!(nurbs_g5_feed(o, &pts, &[1.0; 2], 3, Plane::Xy).is_err());
        assert!(nurbs_g5_feed(o, &pts, &[1.0; 3], 4, Plane::Xy).is_err());
        assert!(nurbs_g5_feed(o, &[[f64::NAN, 0.0]; 3], &[1.0; 3], 3, Plane::Xy).is_err());
        assert!(g5_2_motion(o, &pts, &[1.0; 3], 3, Plane::Xy, 0.0).is_err());
        // Coincident control points: no NaN, no panic.
        let same = [[1.0, 1.0]; 4];
        let m = g5_2_motion(
            Vec3::new(1.0, 1.0, 0.0),
            &same,
            &[1.0; 4],
            3,
            Plane::Xy,
            1.0,
        );
        assert!(m.unwrap().iter().all(|c| c.end().is_finite()));
    }
}
