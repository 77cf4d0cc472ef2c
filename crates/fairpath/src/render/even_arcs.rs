//! A whole curve as arcs whose curvatures step evenly: the curve's own
//! `dk/ds` as a staircase.
//!
//! Why: the biarcs of [`super::arcs`] match the curve's point and tangent
//! at both ends of every biarc, which fixes the step between its two arcs
//! near two thirds of the curve's change of curvature over it and leaves a
//! third for the steps to its neighbours. On a corner transition, where
//! the curvature changes as fast as the jerk allows, the larger steps cap
//! the machine's speed below the curve's (`surface-raster.ngc`;
//! measurements: docs/tuning.md, `render::even_arcs`; `docs/output.md`).
//! Here the arcs match
//! the curve's point and tangent at its two ends only: arc `i`, of
//! in-plane length `h_i`, takes the curve's mean curvature over its
//! stretch, `m_i = (theta(s_i + h_i) - theta(s_i)) / h_i` (`theta` the
//! in-plane direction at in-plane arc length `s`), so that each step is
//! the curve's change between two neighbouring arcs' middles. The means
//! already turn the path by the curve's turn; the end point misses the
//! curve's by the small error of the staircase, which the least-norm
//! correction of the curvatures removes (Gauss-Newton on the end point and
//! direction; the change of the end point with `k_i` taken as a turn of the
//! path after arc `i` about its middle, `h_i R90 (p_end - p_mid_i)`). The
//! correction is nearly linear along the arcs, so it changes the steps
//! alike and they stay even.
//!
//! Each arc is as long as the curve's change of curvature over it allows
//! at the planned speed (`|dk/ds| h <= 2 step_share J Ts / v^2`, with a
//! margin for the correction), but not shorter than one block of travel
//! ([`RenderOptions::min_block_periods`]): there the steps are what one
//! block's change asks, as the biarcs' there, but even. Each arc's mean
//! curvature is the turn of the curve's own tangent between the arc's ends
//! over its length, so the staircase is as fine as the arcs wherever they
//! are shorter than the samples. Where the curve leaves its plane,
//! Gauss-Newton does not converge, or the arcs leave the chord share or
//! step from the curve's ends more than the speed passes, this gives up;
//! [`super::arcs`] keeps its biarcs there, and where their slowest joint
//! passes as fast or they are as few.

use super::arcs::{arc_plane, MAX_SWEEP, MIN_IN_PLANE};
use super::lines::FINE_CHORD;
use super::speed::PlannedSpeed;
use super::RenderOptions;
use crate::budget::DEVIATION_USE;
use crate::geom::biarc::{arc_from_tangent, in_plane_direction, piece_distance_bound};
use crate::geom::{curvature_vector_from, flatten_params_between, Curve, ParamCurve, Vec3};
use crate::math;
use alloc::vec::Vec;

/// Fewest arcs: the correction of the end point spreads over them.
const MIN_ARCS: usize = 4;

/// Most arcs for one curve (beyond, the biarcs adapt better).
const MAX_ARCS: usize = 2048;

/// Share of the spacing the steps allow that is used: the correction of
/// the end point changes the steps a little.
const EVEN_MARGIN: f64 = 0.9;

/// Samples uniform in the curve's parameter, besides the chord error's.
const UNIFORM_SAMPLES: usize = 128;

/// Gauss-Newton iterations at most.
const MAX_ITERATIONS: usize = 8;

/// Below this `|x|`, [`sinc`] takes the series `1 - x^2 / 6`, whose error
/// `x^4 / 120` (below 1e-18) is under f64's rounding of 1: the quotient
/// `sin(x) / x` would lose digits there and is 0/0 at 0.
const SINC_SERIES_BELOW: f64 = 1e-4;

/// `sin(x) / x`, 1 at 0.
fn sinc(x: f64) -> f64 {
    if math::abs(x) < SINC_SERIES_BELOW {
        1.0 - x * x / 6.0
    } else {
        math::sin(x) / x
    }
}

/// In-plane points where each of arcs of lengths `h` and curvatures `k`
/// from `p` at angle `theta` starts, and where the last ends, and the
/// direction there.
pub(super) fn walk(p: [f64; 2], theta: f64, h: &[f64], k: &[f64]) -> (Vec<[f64; 2]>, f64) {
    let mut pts = Vec::with_capacity(k.len() + 1);
    let (mut x, mut y, mut a) = (p[0], p[1], theta);
    pts.push([x, y]);
    for (&ki, &hi) in k.iter().zip(h) {
        let half = 0.5 * ki * hi;
        let chord = hi * sinc(half);
        x += chord * math::cos(a + half);
        y += chord * math::sin(a + half);
        a += ki * hi;
        pts.push([x, y]);
    }
    (pts, a)
}

/// Arcs for curve `c` (piece `piece` of the run) whose curvatures step
/// evenly (module docs), from `c.start()` to `c.end()` exactly and
/// tangent to the curve there, within [`DEVIATION_USE`] of the chord share
/// of the curve (the curve sampled at a tenth of the share, both ways);
/// `None` where the curve does not lend itself (then biarcs).
pub(crate) fn even_arcs<C: ParamCurve + ?Sized>(
    c: &C,
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    straight: f64,
    planar: f64,
) -> Option<(Vec<Curve>, Vec<f64>)> {
    let (t0, t1) = c.domain();
    // The chord error's samples, and uniform ones: where the curve is
    // nearly straight the former are far apart and would hide how fast
    // its curvature starts to change.
    let mut ts = flatten_params_between(c, t0, t1, FINE_CHORD * opts.chord);
    ts.extend((1..UNIFORM_SAMPLES).map(|i| t0 + (t1 - t0) * i as f64 / UNIFORM_SAMPLES as f64));
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    // And where the machine is slow, samples as close as the arcs will be
    // there (one block of travel): the arcs' lengths follow the curve's
    // `dk/ds` measured between samples, which over wider intervals misses
    // how sharply it peaks at a corner.
    let ts = densify_where_slow(c, ts, piece, speed, opts);
    let n = ts.len();
    if n < 3 {
        return None;
    }
    // Each sample's point, unit tangent and curvature vector from one
    // evaluation of the curve.
    let mut pts: Vec<Vec3> = Vec::with_capacity(n);
    let mut frames: Vec<(Vec3, Vec3)> = Vec::with_capacity(n);
    for &t in &ts {
        let (p, d1, d2) = c.eval_derivs12(t);
        pts.push(p);
        frames.push((d1.normalized(0.0)?, curvature_vector_from(d1, d2)));
    }
    let plane = arc_plane(&pts, &frames, planar)?;
    // In-plane directions, unwrapped, and in-plane arc length.
    let mut theta = Vec::with_capacity(n);
    let mut s = Vec::with_capacity(n);
    let mut prev: Option<[f64; 2]> = None;
    for (j, (t, _)) in frames.iter().enumerate() {
        let d = in_plane_direction(plane, *t, MIN_IN_PLANE)?;
        let a = match prev {
            None => math::atan2(d[1], d[0]),
            Some(p) => {
                theta[j - 1] + math::atan2(p[0] * d[1] - p[1] * d[0], p[0] * d[0] + p[1] * d[1])
            }
        };
        theta.push(a);
        prev = Some(d);
        let l = plane.local(pts[j]);
        s.push(if j == 0 {
            0.0
        } else {
            let q = plane.local(pts[j - 1]);
            s[j - 1] + math::sqrt((l[0] - q[0]) * (l[0] - q[0]) + (l[1] - q[1]) * (l[1] - q[1]))
        });
    }
    let total = s[n - 1];
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    // The spacing each sample asks for: the largest whose change of the
    // curve's curvature the planned speed passes, but not below one block
    // of travel (there the arcs step by what one block's change asks, as
    // biarcs there, but evenly).
    let m = &opts.limits;
    let mut want = alloc::vec![total; n];
    let mut floor = alloc::vec![false; n];
    // The curvature of each sampled stretch (its turn over its length) at
    // its middle, and its change between neighbouring stretches.
    let seg: Vec<(f64, f64)> = (0..n - 1)
        .map(|i| {
            let ds = s[i + 1] - s[i];
            let k = if ds > 0.0 {
                (theta[i + 1] - theta[i]) / ds
            } else {
                0.0
            };
            (k, 0.5 * (s[i] + s[i + 1]))
        })
        .collect();
    let slope = |i: usize| {
        // Between stretches i - 1 and i (1 <= i < n - 1).
        let ((ka, sa), (kb, sb)) = (seg[i - 1], seg[i]);
        if sb > sa {
            math::abs(kb - ka) / (sb - sa)
        } else {
            0.0
        }
    };
    for j in 0..n {
        let v = speed.at(piece, ts[j]);
        let dkds = if n < 3 {
            0.0
        } else {
            let i = j.clamp(1, n - 2);
            let mut d = slope(i);
            if i + 1 < n - 1 {
                d = d.max(slope(i + 1));
            }
            d
        };
        let need = if v > 0.0 && dkds > 0.0 && dkds.is_finite() {
            EVEN_MARGIN * 2.0 * opts.step_share * m.jerk * m.period / (v * v * dkds)
        } else {
            total
        };
        let block = opts.block_length(v).max(opts.min_arc_length);
        floor[j] = need < block;
        want[j] = need.max(block).min(total);
    }
    // Arc lengths, marching along the curve: each the least any sample it
    // covers wants.
    let mut h: Vec<f64> = Vec::new();
    let mut at_floor: Vec<bool> = Vec::new();
    let mut x = 0.0;
    let mut j = 0;
    while x < total && h.len() <= MAX_ARCS {
        while j + 1 < n && s[j + 1] <= x {
            j += 1;
        }
        let mut len = want[j];
        let mut fl = floor[j];
        let mut i = j;
        while i + 1 < n && s[i + 1] < x + len {
            i += 1;
            if want[i] < len {
                len = want[i].max(s[i] - x);
                fl = floor[i];
            }
        }
        let len = len.min(total - x);
        h.push(len);
        at_floor.push(fl);
        x += len;
    }
    if h.len() > MAX_ARCS {
        return None;
    }
    // A last arc much shorter than the one before joins it.
    if h.len() >= 2 && h[h.len() - 1] < 0.5 * h[h.len() - 2] {
        let last = h.pop().unwrap_or(0.0);
        at_floor.pop();
        let k = h.len() - 1;
        h[k] += last;
    }
    // The first and last arcs in a third and two thirds: each end arc then
    // steps from the curve's curvature by a sixth of an inner step's
    // change, as a biarc's first arc does, so that a joint with the piece
    // before or after, which may be a line micrometres long (where the
    // planner passes a step at `(J l / dk)^(1/3)`), steps little.
    let last = h.len() - 1;
    let (a, b) = (h[last] / 3.0, h[last] - h[last] / 3.0);
    h[last] = b;
    h.push(a);
    at_floor.push(at_floor[last]);
    let (a, b) = (h[0] / 3.0, h[0] - h[0] / 3.0);
    h[0] = b;
    h.insert(0, a);
    at_floor.insert(0, at_floor[0]);
    if h.len() < MIN_ARCS {
        h = alloc::vec![total / MIN_ARCS as f64; MIN_ARCS];
        at_floor = alloc::vec![true; MIN_ARCS];
    }
    let count = h.len();
    if h.iter().any(|&v| v < opts.min_arc_length) {
        return None;
    }
    // The samples `j - 1` and `j` around in-plane arc length `x`, and where
    // `x` lies between them (0 to 1 inside).
    let bracket = |x: f64| {
        let j = s.partition_point(|&v| v <= x).clamp(1, n - 1);
        let (sa, sb) = (s[j - 1], s[j]);
        (j, if sb > sa { (x - sa) / (sb - sa) } else { 0.0 })
    };
    // The curve's parameter there (linear between samples: parameter and
    // arc length are smooth functions of each other).
    let param_of = |(j, f): (usize, f64)| ts[j - 1] + (ts[j] - ts[j - 1]) * f.clamp(0.0, 1.0);
    let param_at = |x: f64| param_of(bracket(x));
    // The curve's direction at in-plane arc length `x`: its tangent there,
    // unwrapped next to the samples' directions interpolated. (The
    // interpolation alone takes the curvature as constant between samples,
    // a staircase as coarse as they are: where arcs are shorter than the
    // samples' spacing, as on a corner's curvature ramp, every third or
    // fourth arc stepped by the change over a whole sample interval.)
    let theta_at = |x: f64| {
        let (j, f) = bracket(x);
        let near = theta[j - 1] + (theta[j] - theta[j - 1]) * f;
        let exact = c
            .unit_tangent(param_of((j, f)))
            .and_then(|u| in_plane_direction(plane, u, MIN_IN_PLANE));
        match exact {
            Some(d) => {
                let (cn, sn) = (math::cos(near), math::sin(near));
                near + math::atan2(cn * d[1] - sn * d[0], cn * d[0] + sn * d[1])
            }
            None => near,
        }
    };
    let mut bounds = Vec::with_capacity(count + 1);
    bounds.push(0.0);
    for &hi in &h {
        bounds.push(bounds[bounds.len() - 1] + hi);
    }
    bounds[count] = total;
    let mut k: Vec<f64> = (0..count)
        .map(|i| (theta_at(bounds[i + 1]) - theta_at(bounds[i])) / h[i])
        .collect();
    let (l0, l1) = (plane.local(c.start()), plane.local(c.end()));
    let start = [l0[0], l0[1]];
    let (theta0, theta1) = (theta[0], theta[n - 1]);
    let accuracy = 1e-6 * opts.chord;
    let mut converged = false;
    for _ in 0..MAX_ITERATIONS {
        let (p, a) = walk(start, theta0, &h, &k);
        let end = p[count];
        let scale = total / count as f64;
        let r = [end[0] - l1[0], end[1] - l1[1], (a - theta1) * scale];
        if r.iter().all(|v| math::abs(*v) <= accuracy) {
            converged = true;
            break;
        }
        // Jacobian rows (x, y, h theta) against each k_i.
        let col = |i: usize| {
            let mid = [0.5 * (p[i][0] + p[i + 1][0]), 0.5 * (p[i][1] + p[i + 1][1])];
            let (dx, dy) = (end[0] - mid[0], end[1] - mid[1]);
            [-h[i] * dy, h[i] * dx, h[i] * scale]
        };
        let mut jjt = [[0.0f64; 3]; 3];
        for i in 0..count {
            let cl = col(i);
            for (a, row) in jjt.iter_mut().enumerate() {
                for (b, v) in row.iter_mut().enumerate() {
                    *v += cl[a] * cl[b];
                }
            }
        }
        let y = solve3(jjt, [-r[0], -r[1], -r[2]])?;
        for (i, ki) in k.iter_mut().enumerate() {
            let cl = col(i);
            *ki += cl[0] * y[0] + cl[1] * y[1] + cl[2] * y[2];
        }
        if !k.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    if !converged {
        return None;
    }
    let (p, _) = walk(start, theta0, &h, &k);
    let rise = |i: usize| l0[2] + (l1[2] - l0[2]) * bounds[i] / total;
    let mut out: Vec<Curve> = Vec::with_capacity(count);
    let mut at = c.start();
    let mut dir = in_plane_direction(plane, frames[0].0, MIN_IN_PLANE)?;
    for i in 0..count {
        let to = if i + 1 == count {
            c.end()
        } else {
            plane.point([p[i + 1][0], p[i + 1][1], rise(i + 1)])
        };
        let a = arc_from_tangent(plane, at, dir, to, straight)?;
        if let Curve::Arc(arc) = &a {
            if arc.r0.min(arc.r1) < opts.min_radius
                || arc.sweep > MAX_SWEEP
                || arc.approx_length() < opts.min_arc_length
            {
                return None;
            }
        }
        let angle = theta0 + k[..=i].iter().zip(&h).map(|(a, b)| a * b).sum::<f64>();
        dir = [math::cos(angle), math::sin(angle)];
        at = to;
        out.push(a);
    }
    if !checks_pass(c, &out, &pts, piece, speed, opts, &at_floor) {
        return None;
    }
    // The speed planned over each arc (the curve's parameters at its
    // ends, from the in-plane arc length).
    let speeds = (0..count)
        .map(|i| speed.max_over(piece, param_at(bounds[i]), param_at(bounds[i + 1])))
        .collect();
    Some((out, speeds))
}

/// Most samples [`densify_where_slow`] adds to one curve.
const MAX_DENSE_SAMPLES: usize = 16 * MAX_ARCS;

/// `ts` (increasing parameters of `c`) with samples added between
/// neighbours farther apart than two blocks of travel at the slower of
/// their planned speeds ([`RenderOptions::block_length`]) whose curvatures
/// differ by more than the step that speed passes
/// ([`RenderOptions::step_room`]): evenly in the parameter, about one block
/// apart, or one per half of that step where fewer. At most
/// [`MAX_DENSE_SAMPLES`] are added (none where more would be needed: a
/// curve that long and slow is left to the biarcs' halving).
fn densify_where_slow<C: ParamCurve + ?Sized>(
    c: &C,
    ts: Vec<f64>,
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Vec<f64> {
    let at: Vec<(Vec3, Vec3)> = ts
        .iter()
        .map(|&t| {
            let (p, d1, d2) = c.eval_derivs12(t);
            (p, curvature_vector_from(d1, d2))
        })
        .collect();
    let extra: Vec<usize> = ts
        .windows(2)
        .zip(at.windows(2))
        .map(|(t, a)| {
            let v = speed.at(piece, t[0]).min(speed.at(piece, t[1]));
            let block = opts.block_length(v).max(opts.min_arc_length);
            let d = a[0].0.dist(a[1].0);
            // The change of the curvature (its size, and through zero
            // where it turns to the other side), not of the vector, which
            // also turns with the tangent along a circle.
            let (k0, k1) = (a[0].1.norm(), a[1].1.norm());
            let dk = if a[0].1.dot(a[1].1) < 0.0 {
                k0 + k1
            } else {
                math::abs(k1 - k0)
            };
            let step = opts.step_room(v);
            if d > 2.0 * block && dk > step {
                let by_length = math::ceil(d / block) - 1.0;
                let by_step = math::ceil(2.0 * dk / step);
                by_length.min(by_step).min(MAX_DENSE_SAMPLES as f64) as usize
            } else {
                0
            }
        })
        .collect();
    let added: usize = extra.iter().sum();
    if added == 0 || added > MAX_DENSE_SAMPLES {
        return ts;
    }
    let mut out = Vec::with_capacity(ts.len() + added);
    for (i, w) in ts.windows(2).enumerate() {
        out.push(w[0]);
        let m = extra[i];
        for k in 1..=m {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / (m + 1) as f64);
        }
    }
    out.push(ts[ts.len() - 1]);
    out
}

/// The least ratio, over the joints of `arcs` (speeds `v` over each) and
/// their ends against a neighbour stepping as far again from the curve's
/// curvature vectors `ends`, of the speed the planner lets a joint pass
/// (`min(sqrt(J Ts / dk), cbrt(J l / dk))`, `l` the shorter neighbour;
/// `crate::feed::junction::step_cap`) to the speed planned there: below 1
/// the arcs slow the machine.
pub(crate) fn joint_speed_ratio(
    arcs: &[Curve],
    v: &[f64],
    ends: (Vec3, Vec3),
    opts: &RenderOptions,
    accuracy: f64,
) -> f64 {
    let m = &opts.limits;
    let ratio = |dk: f64, l: f64, v: f64| {
        if v > 0.0 {
            crate::feed::junction::step_cap(m, dk, l) / v
        } else {
            f64::INFINITY
        }
    };
    let n = arcs.len();
    if n == 0 {
        return f64::INFINITY;
    }
    let len: Vec<f64> = arcs.iter().map(|a| a.length(accuracy)).collect();
    let mut worst = ratio(
        2.0 * (arcs[0].curvature_vector(0.0) - ends.0).norm(),
        len[0],
        v[0],
    )
    .min(ratio(
        2.0 * (arcs[n - 1].curvature_vector(1.0) - ends.1).norm(),
        len[n - 1],
        v[n - 1],
    ));
    for i in 0..n - 1 {
        let dk = (arcs[i + 1].curvature_vector(0.0) - arcs[i].curvature_vector(1.0)).norm();
        worst = worst.min(ratio(dk, len[i].min(len[i + 1]), v[i].max(v[i + 1])));
    }
    worst
}

/// Whether `arcs` are within the chord share of the curve (its samples
/// `pts`) both ways, step from the curve's curvature at its ends by no
/// more than the planned speed passes, and leave the curve's end tangent
/// by no kink the speed does not pass. The steps between the arcs are not
/// held to the planned speed here: where the curve's `dk/ds` peaks
/// between its samples some step exceeds it, as some step of the biarcs
/// does, and [`joint_speed_ratio`] judges the two renderings by their
/// slowest joint (`super::arcs`).
fn checks_pass<C: ParamCurve + ?Sized>(
    c: &C,
    arcs: &[Curve],
    pts: &[Vec3],
    piece: usize,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
    at_floor: &[bool],
) -> bool {
    let step = |v: f64| opts.step_room(v);
    let (t0, t1) = c.domain();
    let (va, vb) = (speed.at(piece, t0), speed.at(piece, t1));
    let n = arcs.len();
    let first = &arcs[0];
    let last = &arcs[arcs.len() - 1];
    if (!at_floor[0] && (first.curvature_vector(0.0) - c.curvature_vector(t0)).norm() > step(va))
        || (!at_floor[n - 1]
            && (last.curvature_vector(1.0) - c.curvature_vector(t1)).norm() > step(vb))
    {
        return false;
    }
    // The end tangent: a kink of angle `a` costs about `2 a / L`.
    let len = last.length(opts.chord * 1e-3);
    let kink = last
        .unit_tangent(1.0)
        .zip(c.unit_tangent(t1))
        .map_or(f64::INFINITY, |(a, b)| a.angle_to(b));
    if !at_floor[n - 1] && 2.0 * kink > step(vb) * len {
        return false;
    }
    // Deviation, both ways: every curve sample near some arc, every arc's
    // points near the curve's polyline (searches move forward from the
    // last hit).
    let lim = DEVIATION_USE * opts.chord;
    let mut hint = 0;
    for &q in &pts[1..pts.len() - 1] {
        let near = |i: usize| piece_distance_bound(&arcs[i], q).is_some_and(|d| d <= lim);
        match (hint..arcs.len()).chain(0..hint).find(|&i| near(i)) {
            Some(i) => hint = i,
            None => return false,
        }
    }
    super::arcs::points_near_polyline(arcs, pts, lim)
}

/// The solution of the 3x3 system `m x = b` (Cramer's rule); `None` when
/// it is singular.
pub(super) fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    if !(d.is_finite() && d != 0.0) {
        return None;
    }
    let mut x = [0.0; 3];
    for (j, xj) in x.iter_mut().enumerate() {
        let mut a = m;
        for i in 0..3 {
            a[i][j] = b[i];
        }
        *xj = det(a) / d;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::limits::MachineLimits;
    use crate::feed::plan::{plan_run, PlanOptions};
    use crate::geom::Nurbs;
    use crate::path::Piece;
    use crate::render::CurveForm;

    fn opts() -> RenderOptions {
        RenderOptions {
            form: CurveForm::Arcs,
            chord: 0.0045,
            limits: MachineLimits::thesis(),
            min_block_periods: 1.02,
            min_radius: 0.00254,
            step_share: crate::render::arcs::STEP_SHARE,
            min_arc_length: 4e-6,
        }
    }

    /// A cubic whose curvature rises from 0 (its first three control
    /// points are collinear), as a corner transition's half does.
    fn ramp() -> Curve {
        let p = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        Curve::from(
            Nurbs::new(
                3,
                alloc::vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                alloc::vec![p(0.0, 0.0), p(0.4, 0.0), p(0.8, 0.0), p(1.2, 0.15)],
                None,
            )
            .unwrap(),
        )
    }

    /// The curvature steps between consecutive arcs.
    fn steps(arcs: &[Curve]) -> Vec<f64> {
        arcs.windows(2)
            .map(|w| (w[1].curvature_vector(0.0) - w[0].curvature_vector(1.0)).norm())
            .collect()
    }

    /// A right-angle corner between 11 mm straights, rounded by a cubic
    /// B-spline whose legs at the corner are 1 mm: a long curve whose
    /// curvature rises and falls sharply where the machine is slow.
    fn corner() -> Curve {
        let p = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        Curve::from(
            Nurbs::new(
                3,
                alloc::vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0],
                alloc::vec![
                    p(0.0, 0.0),
                    p(6.0, 0.0),
                    p(11.0, 0.0),
                    p(12.0, 0.0),
                    p(12.0, 1.0),
                    p(12.0, 6.0),
                    p(12.0, 12.0)
                ],
                None,
            )
            .unwrap(),
        )
    }

    /// `c` as a run of one piece, its plan at the thesis' machine (every
    /// feed at the maximum, at rest at both ends) and the planned speed
    /// along it.
    fn planned(c: &Curve) -> (Piece, PlanOptions, crate::feed::plan::RunPlan, PlannedSpeed) {
        let piece = Piece {
            curve: c.clone(),
            rapid: false,
            source_lines: (1, 1),
            feed: None,
        };
        let po = PlanOptions {
            limits: MachineLimits::thesis(),
            override_feed: true,
            window: None,
            ends: Default::default(),
        };
        let plan = plan_run(core::slice::from_ref(&piece), &po).unwrap();
        let speed = PlannedSpeed::new(1, &plan, 1e-3);
        (piece, po, plan, speed)
    }

    /// [`even_arcs`] of `c` at [`opts`], and the speed over each arc.
    fn even(c: &Curve, speed: &PlannedSpeed) -> Option<(Vec<Curve>, Vec<f64>)> {
        let o = opts();
        even_arcs(
            c,
            0,
            speed,
            &o,
            super::super::arcs::STRAIGHT_CURVATURE_CHORD / o.chord,
            o.chord * 1e-3,
        )
    }

    #[test]
    fn a_rising_curvature_gets_even_steps_and_the_curves_ends() {
        let c = ramp();
        let (_, _, _, speed) = planned(&c);
        let o = opts();
        let (arcs, _) = even(&c, &speed).unwrap();
        assert!(arcs.len() >= MIN_ARCS);
        assert_eq!(arcs[0].start(), c.start());
        assert_eq!(arcs[arcs.len() - 1].end(), c.end());
        for w in arcs.windows(2) {
            assert_eq!(w[0].end(), w[1].start());
            let (a, b) = (
                w[0].unit_tangent(1.0).unwrap(),
                w[1].unit_tangent(0.0).unwrap(),
            );
            assert!(a.angle_to(b) < 1e-9, "tangent-continuous");
        }
        let t = arcs[arcs.len() - 1].unit_tangent(1.0).unwrap();
        assert!(t.angle_to(c.unit_tangent(1.0).unwrap()) < 1e-6);
        // Every sample of the curve within the chord share of the arcs.
        for i in 0..=200 {
            let q = c.eval(i as f64 / 200.0);
            let d = arcs
                .iter()
                .filter_map(|a| piece_distance_bound(a, q))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= o.chord, "{d} mm off at {i}");
        }
        // Even: inside (the end arcs are split in a third and two thirds,
        // so the steps next to them are smaller), no step is more than 1.5
        // times its neighbour's, where a biarc's are about twice.
        let st = steps(&arcs);
        assert!(st.len() >= 4, "{st:?}");
        for w in st[1..st.len() - 1].windows(2) {
            let (a, b) = (w[0].max(w[1]), w[0].min(w[1]));
            assert!(a <= 1.5 * b.max(1e-12), "uneven steps {st:?}");
        }
    }

    /// Samples are added only where the machine is slow and the curvature
    /// changes between neighbours by more than the step it passes there:
    /// none on a line nor on a circle at any speed, some at a slow corner,
    /// each inside the interval it splits.
    #[test]
    fn samples_are_added_only_where_slow_and_bending_faster() {
        let p = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let line = Curve::Line(crate::geom::Line::new(p(0.0, 0.0), p(20.0, 0.0)));
        let circle = Curve::from(
            crate::geom::Arc::from_center(
                p(0.5, 0.0),
                p(-0.5, 0.0),
                p(0.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                false,
                1,
                1e-9,
            )
            .unwrap(),
        );
        let o = opts();
        for (name, c, want_more) in [
            ("corner", &corner(), true),
            ("line", &line, false),
            ("circle", &circle, false),
        ] {
            let (_, _, _, speed) = planned(c);
            let (t0, t1) = c.domain();
            let ts: Vec<f64> = (0..=64).map(|i| t0 + (t1 - t0) * i as f64 / 64.0).collect();
            let dense = densify_where_slow(c, ts.clone(), 0, &speed, &o);
            assert!(dense.windows(2).all(|w| w[0] < w[1]), "{name}: increasing");
            assert!(
                ts.iter().all(|t| dense.contains(t)),
                "{name}: keeps its samples"
            );
            assert_eq!(
                dense.len() > ts.len(),
                want_more,
                "{name}: {} -> {}",
                ts.len(),
                dense.len()
            );
        }
    }

    /// Regression (`r008_pocket.ngc`, a pocket of seed 9711 of
    /// `scripts/random-programs.py`, its rounded corners fitted through
    /// with the straights either side): a long curve turning a sharp
    /// corner, where the machine is slow and the arcs are as short as a
    /// block, shorter than the spacing of the curve's samples. The arcs'
    /// curvatures were the samples' directions interpolated, a staircase as
    /// coarse as the samples: every third or fourth step took the change of
    /// a whole sample interval, and the arcs' lengths followed the
    /// curve's `dk/ds` measured over intervals far wider than the arcs.
    #[test]
    fn regression_r008_pocket_arcs_shorter_than_the_samples_step_evenly() {
        // The slowest joint passed at 0.68 of the planned speed with the
        // samples' directions interpolated, 0.85 with the curve's tangent
        // at the arcs' ends, 0.98 with samples a block apart where it is
        // slow; the biarcs, which were written, planned 1.4% slower than
        // the curve.
        let c = corner();
        let (piece, po, plan, speed) = planned(&c);
        let o = opts();
        let (arcs, v) = even(&c, &speed).unwrap();
        let ends = (c.curvature_vector(0.0), c.curvature_vector(1.0));
        // (`render_run` writes whichever of the even arcs and the biarcs
        // passes its slowest joint faster.)
        let r = joint_speed_ratio(&arcs, &v, ends, &o, 1e-9);
        assert!(r > 0.95, "joints pass at {r} of the planned speed");
        let written = crate::render::render_run(core::slice::from_ref(&piece), &speed, &o).unwrap();
        let t = plan_run(&written.pieces, &po).unwrap().time;
        assert!(
            t <= 1.002 * plan.time,
            "written {t} s against the curve's {} s",
            plan.time
        );
    }
}
