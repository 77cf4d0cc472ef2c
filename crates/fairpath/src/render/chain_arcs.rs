//! Consecutive short pieces as one staircase of arcs, a cell per corner.
//!
//! Why: a run smoothed corner by corner (`bspline-corner`, `ctm`, `lotm`)
//! is lines and transitions; each transition's curvature rises from none
//! to its peak and falls back, so the exact curves carry a bump of
//! curvature at every input vertex, and arcs that follow each bump
//! ([`super::even_arcs`], [`super::arcs`]) need a dozen arcs per corner on
//! a densely sampled surface (`surface-raster-large.ngc`; measurements:
//! docs/tuning.md, `render::chain_arcs`). Within the chord share the
//! written path need not follow the bumps: an arc per corner, whose curvature is the turn of
//! the corner over the stretch from the middle of the line before it to
//! the middle of the line after it (the discrete curvature of the
//! input's vertices), stays near the curves where the corners turn little
//! over short lines, and its steps from arc to arc are the change of that
//! curvature from vertex to vertex, small on a smooth surface, where the
//! bumps of the curves step by their whole peak.
//!
//! Method: the chain's pieces are sampled (the chord's samples of each
//! curve and [`PIECE_SAMPLES`] uniform ones) in the principal plane of
//! [`super::arcs::arc_plane`]; the cells run between the middles of the
//! chain's lines and the joints of two curves (a cell shorter than a
//! block at the planned speed joins the next). Cell `i`, of in-plane
//! length `h_i`, takes the chain's mean curvature over it,
//! `(theta(b_{i+1}) - theta(b_i)) / h_i`; the means are smoothed
//! ([`SMOOTH_PASSES`] passes of `[1 2 1]`, weighted by length so that
//! the turn is kept), because a short cell's turn carries the noise of
//! the input's vertices. At each end of the chain the first cells become
//! a ramp from the chain's own curvature there (a line's none) to the
//! next cell's mean, in steps the planned speed passes, that turns the
//! path as much as the cells it replaces (a linear ramp plus a half-sine
//! bump). The arcs' points drift from the chain's by what the staircase
//! misses in each cell, so the curvatures take the correction of least
//! `sum h_i dk_i^2` (the curvature change's square integrated along the
//! path, so that it is one smooth function of the length whatever the
//! cells' lengths; Gauss-Newton, as [`super::even_arcs`] does for one
//! curve) that puts
//! the arcs' points on the chain's every [`CHECK_CELLS`] cells and at its
//! end, and the end direction on the chain's: one correction for the whole
//! chain, which the ramps' arcs take less of the nearer they are to the
//! chain's end, and with no point held in the ramps or near them, so that
//! they stay graded. The arcs are written only
//! where they pass what the renderer's other arcs pass: the chord share
//! both ways (every sample near an arc, every arc's points near the
//! samples' polyline), curvature steps, at the chain's ends against its
//! curves and between arcs, that the speed planned for the curves passes
//! (`step_share J Ts / v^2` each side), and no arc whose own curvature
//! caps the speed below the curves' plan over it. A chain that does not pass
//! is halved, down to [`MIN_CHAIN`] pieces; the pieces of no chain are
//! rendered one by one.
//!
//! A chain holds lines and NURBS of one feed, at most
//! [`super::CHAIN_PIECES`] of them, and never crosses a
//! multiple of it in the run's piece numbers. A curve joins a chain only
//! if one arc over it can stay near it: its turn times its length within
//! [`CELL_BULGE`] chord shares. Input arcs stay arcs (they break chains).

use super::arcs::{arc_plane, points_near_polyline, MAX_SWEEP, MIN_IN_PLANE};
use super::even_arcs::walk;
use super::lines::FINE_CHORD;
use super::speed::PlannedSpeed;
use super::{RenderOptions, CHAIN_PIECES};
use crate::budget::DEVIATION_USE;
use crate::feed::limits::{speed_cap, PathPoint};
use crate::geom::biarc::{arc_from_tangent, in_plane_direction, piece_distance_bound};
use crate::geom::{
    curvature_vector_from, flatten_params_between, BezierSpline, Curve, ParamCurve, Vec3,
};
use crate::math;
use crate::path::Piece;
use alloc::vec::Vec;

/// Uniform samples per curve of the chain, besides the chord error's.
const PIECE_SAMPLES: usize = 8;

/// A curve joins a chain where its turn (rad) times its length is at most
/// this many chord shares: an arc of the curve's mean curvature over it
/// bulges from it by about an eighth of that product.
const CELL_BULGE: f64 = 4.0;

/// Gauss-Newton iterations at most.
const MAX_ITERATIONS: usize = 12;

/// Arcs between two points held to the chain's.
const CHECK_CELLS: usize = 8;

/// Passes of the `[1 2 1]` smoothing of the cells' curvatures.
const SMOOTH_PASSES: usize = 2;

/// Most cells a ramp at an end of the chain replaces.
const RAMP_CELLS: usize = 8;

/// Most arcs of a ramp at an end of the chain.
const MAX_RAMP: usize = 64;

/// Share of the steps allowed that a ramp takes (the correction of the
/// chain's points changes them a little).
const EVEN_MARGIN: f64 = 0.8;

/// Accuracy of the points and the end direction the correction holds, in
/// chord shares (far below what the chord share and the written decimals
/// resolve).
const GN_ACCURACY: f64 = 1e-5;

/// A piece's curve as it is sampled: polynomial splines by their Bezier
/// spans (the same curve, sampled at a fraction of the cost).
enum View<'a> {
    Spans(BezierSpline),
    Curve(&'a Curve),
}

impl View<'_> {
    fn of(c: &Curve) -> View<'_> {
        match super::bezier_spline_of(c) {
            Some(s) => View::Spans(s),
            None => View::Curve(c),
        }
    }
    fn curve(&self) -> &dyn ParamCurve {
        match self {
            View::Spans(s) => s,
            View::Curve(c) => *c,
        }
    }
}

/// Whether `p` may be in a chain (a line, or a curve an arc can stay
/// near over its length).
fn chainable(p: &Piece, chord: f64) -> bool {
    if p.rapid {
        return false;
    }
    match &p.curve {
        Curve::Line(_) => true,
        Curve::Nurbs(_) => {
            let c = &p.curve;
            let (t0, t1) = c.domain();
            let turn = match (c.unit_tangent(t0), c.unit_tangent(t1)) {
                (Some(a), Some(b)) => a.angle_to(b),
                _ => return false,
            };
            let len = (c.end() - c.start()).norm();
            turn * len <= CELL_BULGE * chord
        }
        Curve::Arc(_) => false,
    }
}

/// The end (exclusive) of the chain that starts at piece `from`, before
/// `end`: `from` itself where no chain of two curves or more starts there.
pub(crate) fn chain_end(pieces: &[Piece], from: usize, end: usize, chord: f64) -> usize {
    let limit = ((from / CHAIN_PIECES + 1) * CHAIN_PIECES).min(end);
    let Some(first) = pieces.get(from) else {
        return from;
    };
    if !chainable(first, chord) {
        return from;
    }
    let mut j = from + 1;
    while j < limit && pieces[j].feed == first.feed && chainable(&pieces[j], chord) {
        j += 1;
    }
    let curves = pieces[from..j]
        .iter()
        .filter(|p| !matches!(p.curve, Curve::Line(_)))
        .count();
    if curves >= 2 {
        j
    } else {
        from
    }
}

/// A chain written as arcs: the pieces it replaces, its arcs, the speed
/// planned over each and the input lines each replaces.
pub(crate) struct Chained {
    pub(crate) range: core::ops::Range<usize>,
    pub(crate) arcs: Vec<Curve>,
    pub(crate) speeds: Vec<f64>,
    pub(crate) lines: Vec<(usize, usize)>,
}

/// Fewest pieces a chain is halved to when its arcs do not pass.
const MIN_CHAIN: usize = 6;

/// The chains of arcs that pass within the chain `range`, in order: the
/// whole, or, where it does not pass, each half, down to [`MIN_CHAIN`]
/// pieces (the pieces of no chain are rendered one by one).
pub(crate) fn cover(
    pieces: &[Piece],
    range: core::ops::Range<usize>,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Vec<Chained> {
    let mut out = Vec::new();
    let mut todo = alloc::vec![range];
    while let Some(r) = todo.pop() {
        let curves = pieces[r.clone()]
            .iter()
            .filter(|p| !matches!(p.curve, Curve::Line(_)))
            .count();
        if curves < 2 {
            continue;
        }
        match chain_arcs(pieces, r.clone(), speed, opts) {
            Some((arcs, speeds, lines)) => out.push(Chained {
                range: r,
                arcs,
                speeds,
                lines,
            }),
            None if r.len() >= 2 * MIN_CHAIN => {
                let mid = r.start + r.len() / 2;
                todo.push(mid..r.end);
                todo.push(r.start..mid);
            }
            None => {}
        }
    }
    out
}

/// One sample of a chain.
struct Sample {
    piece: usize,
    t: f64,
    p: Vec3,
    tangent: Vec3,
    kvec: Vec3,
}

/// Arcs for the chain `pieces[range]` (module docs), from its start to
/// its end exactly and tangent to it there, each within [`DEVIATION_USE`]
/// of the chord share of the chain, with the planned speed over each and
/// the input lines each replaces; `None` where they do not pass.
#[allow(clippy::type_complexity)]
pub(crate) fn chain_arcs(
    pieces: &[Piece],
    range: core::ops::Range<usize>,
    speed: &PlannedSpeed,
    opts: &RenderOptions,
) -> Option<(Vec<Curve>, Vec<f64>, Vec<(usize, usize)>)> {
    let chord = opts.chord;
    let straight = super::arcs::STRAIGHT_CURVATURE_CHORD / chord;
    let planar = chord * 1e-3;
    // Samples, and where each line's middle and each joint of two curves
    // fall among them (the cells' boundaries).
    let mut samples: Vec<Sample> = Vec::new();
    let mut cuts: Vec<usize> = alloc::vec![0];
    let last_piece = range.end - 1;
    for i in range.clone() {
        let view = View::of(&pieces[i].curve);
        let c = view.curve();
        let (t0, t1) = c.domain();
        let is_line = matches!(pieces[i].curve, Curve::Line(_));
        let ts: Vec<f64> = if is_line {
            alloc::vec![t0, 0.5 * (t0 + t1), t1]
        } else {
            let mut ts = flatten_params_between(c, t0, t1, FINE_CHORD * chord);
            ts.extend((1..PIECE_SAMPLES).map(|k| t0 + (t1 - t0) * k as f64 / PIECE_SAMPLES as f64));
            ts.sort_by(f64::total_cmp);
            ts.dedup();
            ts
        };
        let prev_curve = i > range.start && !matches!(pieces[i - 1].curve, Curve::Line(_));
        if !is_line && prev_curve {
            cuts.push(samples.len() - 1);
        }
        for (k, &t) in ts.iter().enumerate() {
            if k == 0 && i > range.start {
                continue;
            }
            let (p, d1, d2) = c.eval_derivs12(t);
            samples.push(Sample {
                piece: i,
                t,
                p,
                tangent: d1.normalized(0.0)?,
                kvec: curvature_vector_from(d1, d2),
            });
            if is_line && k == 1 && i > range.start && i < last_piece {
                cuts.push(samples.len() - 1);
            }
        }
    }
    let n = samples.len();
    if n < 3 {
        return None;
    }
    cuts.push(n - 1);
    cuts.dedup();
    // The chain's ends exactly as its pieces have them (a spline's Bezier
    // spans evaluate its ends to within rounding only).
    samples[0].p = pieces[range.start].curve.start();
    samples[n - 1].p = pieces[last_piece].curve.end();
    let pts: Vec<Vec3> = samples.iter().map(|s| s.p).collect();
    let frames: Vec<(Vec3, Vec3)> = samples.iter().map(|s| (s.tangent, s.kvec)).collect();
    let plane = arc_plane(&pts, &frames, planar)?;
    let mut theta: Vec<f64> = Vec::with_capacity(n);
    let mut s: Vec<f64> = Vec::with_capacity(n);
    let mut prev: Option<[f64; 2]> = None;
    for j in 0..n {
        let d = in_plane_direction(plane, samples[j].tangent, MIN_IN_PLANE)?;
        theta.push(match prev {
            None => math::atan2(d[1], d[0]),
            Some(p) => {
                theta[j - 1] + math::atan2(p[0] * d[1] - p[1] * d[0], p[0] * d[0] + p[1] * d[1])
            }
        });
        prev = Some(d);
        let l = plane.local(pts[j]);
        s.push(if j == 0 {
            0.0
        } else {
            let q = plane.local(pts[j - 1]);
            s[j - 1] + math::hypot(l[0] - q[0], l[1] - q[1])
        });
    }
    let total = s[n - 1];
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    // Cells no shorter than one block at the planned speed, nor than the
    // shortest arc: a short one joins the cell after it (the last, the one
    // before).
    let v_at = |j: usize| speed.at(samples[j].piece, samples[j].t);
    let mut bounds: Vec<usize> = alloc::vec![cuts[0]];
    for &c in &cuts[1..] {
        let a = *bounds.last()?;
        let len = s[c] - s[a];
        let v = v_at(a).max(v_at(c));
        if len >= opts.block_length(v).max(opts.min_arc_length) || c == n - 1 {
            bounds.push(c);
        }
    }
    if bounds.len() >= 3 {
        let m = bounds.len();
        let len = s[bounds[m - 1]] - s[bounds[m - 2]];
        let v = v_at(bounds[m - 2]).max(v_at(bounds[m - 1]));
        if len < opts.block_length(v).max(opts.min_arc_length) {
            bounds.remove(m - 2);
        }
    }
    // Boundaries as in-plane arc lengths; the end cells split at a third
    // (the third outside).
    let b: Vec<f64> = bounds.iter().map(|&j| s[j]).collect();
    if b.len() < 2 {
        return None;
    }
    let locate = |x: f64| {
        let j = s.partition_point(|&v| v <= x).clamp(1, n - 1);
        let (sa, sb) = (s[j - 1], s[j]);
        let f = if sb > sa {
            ((x - sa) / (sb - sa)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (j, f)
    };
    let theta_at = |x: f64| {
        let (j, f) = locate(x);
        theta[j - 1] + (theta[j] - theta[j - 1]) * f
    };
    let point_at = |x: f64| {
        let (j, f) = locate(x);
        let (a, c) = (plane.local(pts[j - 1]), plane.local(pts[j]));
        [a[0] + (c[0] - a[0]) * f, a[1] + (c[1] - a[1]) * f]
    };
    let step = |v: f64| opts.step_room(v);
    // Cells (lengths, curvatures): the chain's mean curvature over each.
    let mut h: Vec<f64> = b.windows(2).map(|w| w[1] - w[0]).collect();
    let mut k: Vec<f64> = b
        .windows(2)
        .map(|w| (theta_at(w[1]) - theta_at(w[0])) / (w[1] - w[0]))
        .collect();
    // The chain's own in-plane curvature at sample `j`, signed as the
    // turns: what the ends are checked against.
    let signed_k = |j: usize| {
        let (t, kv) = (
            plane.local(samples[j].tangent),
            plane.local(samples[j].kvec),
        );
        let tn = math::hypot(t[0], t[1]);
        if tn > 0.0 {
            (t[0] * kv[1] - t[1] * kv[0]) / tn
        } else {
            0.0
        }
    };
    // The means of neighbouring cells differ by the noise of the input's
    // vertices (a turn's error over a short cell is a large error of
    // curvature, where the path moves little): smoothed a few passes,
    // weighted by the cells' lengths so that the turn is kept, the steps
    // are the path's and the points move by about `dk h^2 / 8`, which the
    // correction then holds (the deviation is checked below).
    for _ in 0..SMOOTH_PASSES {
        let turn: Vec<f64> = k.iter().zip(&h).map(|(a, b)| a * b).collect();
        let cells = k.len();
        if cells < 3 {
            break;
        }
        let mut next = k.clone();
        for i in 1..cells - 1 {
            next[i] =
                (turn[i - 1] + 2.0 * turn[i] + turn[i + 1]) / (h[i - 1] + 2.0 * h[i] + h[i + 1]);
        }
        k = next;
    }
    // The fastest the curves are planned over samples `j0..=j1`.
    let v_over = |j0: usize, j1: usize| (j0..=j1).map(v_at).fold(0.0f64, f64::max);
    // The end cells ramp from the chain's own curvature at its ends to
    // the cells' means, in steps the planned speed passes; how much of
    // the correction of the chain's points each arc takes: the ramps' arcs
    // less the nearer the chain's end (the end arcs none), so that the
    // ramps stay graded.
    let mut weight: Vec<f64> = alloc::vec![1.0; h.len()];
    let reach = RAMP_CELLS.min(bounds.len() - 1);
    let v_head = v_over(0, bounds[reach]);
    let v_tail = v_over(bounds[bounds.len() - 1 - reach], n - 1);
    let block = |v: f64| opts.block_length(v).max(opts.min_arc_length);
    let head = ramp_start(
        (&mut h, &mut k, &mut weight),
        signed_k(0),
        EVEN_MARGIN * step(v_head),
        block(v_head),
    );
    h.reverse();
    k.reverse();
    weight.reverse();
    let tail = ramp_start(
        (&mut h, &mut k, &mut weight),
        signed_k(n - 1),
        EVEN_MARGIN * step(v_tail),
        block(v_tail),
    );
    h.reverse();
    k.reverse();
    weight.reverse();
    let count = h.len();
    if h.iter().any(|&x| x <= 0.0 || x < opts.min_arc_length) {
        return None;
    }
    let mut b: Vec<f64> = Vec::with_capacity(count + 1);
    b.push(0.0);
    for &x in &h {
        b.push(b[b.len() - 1] + x);
    }
    b[count] = total;
    let l0 = plane.local(pts[0]);
    let l1 = plane.local(pts[n - 1]);
    let (theta0, theta1) = (theta[0], theta[n - 1]);
    let accuracy = GN_ACCURACY * chord;
    // The least-norm correction of the curvatures (each arc's share
    // `weight`; the norm `sum h_i dk_i^2 / weight_i`: each arc's change
    // is `weight_i` times the same smooth function of the length, where
    // the plain `sum dk_i^2` gave the longer cells more, a step at each
    // change of cell length: docs/tuning.md, `render::chain_arcs`) that
    // puts the arcs' points at every CHECK_CELLS-th
    // boundary, and the end, on the chain's, and the end direction on
    // the chain's. One correction for the whole chain: corrections of
    // separate stretches would step where they meet.
    // (None in the ramps, whose arcs take little of the correction, nor
    // within CHECK_CELLS of them: there a few arcs would take it all.)
    let first_check = head + CHECK_CELLS;
    let last_check = count.saturating_sub(tail + CHECK_CELLS);
    let mut checks: Vec<usize> = (first_check..=last_check).step_by(CHECK_CELLS).collect();
    checks.push(count);
    let targets: Vec<[f64; 2]> = checks
        .iter()
        .map(|&i| {
            if i == count {
                [l1[0], l1[1]]
            } else {
                point_at(b[i])
            }
        })
        .collect();
    let rows = 2 * checks.len() + 1;
    let scale = total / count as f64;
    let start = [l0[0], l0[1]];
    let mut converged = false;
    let mut jjt = alloc::vec![0.0f64; rows * rows];
    for _ in 0..MAX_ITERATIONS {
        let (p, a) = walk(start, theta0, &h, &k);
        let mut r: Vec<f64> = Vec::with_capacity(rows);
        for (c, &i) in checks.iter().enumerate() {
            r.push(targets[c][0] - p[i][0]);
            r.push(targets[c][1] - p[i][1]);
        }
        r.push((theta1 - a) * scale);
        if r.iter().all(|v| math::abs(*v) <= accuracy) {
            converged = true;
            break;
        }
        // Column of the Jacobian for k_i: the turn of the path after arc
        // i about its middle `m_i` moves each later checked point `P`,
        // by `h_i (-(P - m_i)_y, (P - m_i)_x)`, and the end direction by
        // `h_i` (times `scale`). With the norm's weights `weight_i / h_i`,
        // `J W J^T` is made of sums over the arcs before each checked
        // point of `weight_i h_i` times 1, `m`, and `m m^T` (prefix sums,
        // about the chain's start so that they keep their digits): O(arcs
        // + checks^2) where the columns one by one were O(arcs checks^2).
        let o = p[0];
        let mid = |i: usize| {
            [
                0.5 * (p[i][0] + p[i + 1][0]) - o[0],
                0.5 * (p[i][1] + p[i + 1][1]) - o[1],
            ]
        };
        let nc = checks.len();
        // [1, m_x, m_y, m_x^2, m_x m_y, m_y^2], summed over the arcs
        // before each checked point.
        let mut sums = [0.0f64; 6];
        let mut before: Vec<[f64; 6]> = Vec::with_capacity(nc);
        for i in 0..count {
            while before.len() < nc && checks[before.len()] <= i {
                before.push(sums);
            }
            let wi = weight[i] * h[i];
            if wi == 0.0 {
                continue;
            }
            let m = mid(i);
            sums[0] += wi;
            sums[1] += wi * m[0];
            sums[2] += wi * m[1];
            sums[3] += wi * m[0] * m[0];
            sums[4] += wi * m[0] * m[1];
            sums[5] += wi * m[1] * m[1];
        }
        while before.len() < nc {
            before.push(sums);
        }
        let at = |c: usize| [p[checks[c]][0] - o[0], p[checks[c]][1] - o[1]];
        jjt.iter_mut().for_each(|v| *v = 0.0);
        for c1 in 0..nc {
            let p1 = at(c1);
            for c2 in c1..nc {
                let p2 = at(c2);
                let sm = &before[c1];
                // sum w h^2 (P1 - m)_u (P2 - m)_v for u, v in x, y.
                let xx = p1[0] * p2[0] * sm[0] - p1[0] * sm[1] - p2[0] * sm[1] + sm[3];
                let xy = p1[0] * p2[1] * sm[0] - p1[0] * sm[2] - p2[1] * sm[1] + sm[4];
                let yx = p1[1] * p2[0] * sm[0] - p1[1] * sm[1] - p2[0] * sm[2] + sm[4];
                let yy = p1[1] * p2[1] * sm[0] - p1[1] * sm[2] - p2[1] * sm[2] + sm[5];
                let (r1, r2) = (2 * c1, 2 * c2);
                let block = [
                    (r1, r2, yy),
                    (r1, r2 + 1, -yx),
                    (r1 + 1, r2, -xy),
                    (r1 + 1, r2 + 1, xx),
                ];
                for (x, y, v) in block {
                    jjt[x * rows + y] = v;
                    jjt[y * rows + x] = v;
                }
            }
            let sm = &before[c1];
            let (ey, ex) = (
                -scale * (p1[1] * sm[0] - sm[2]),
                scale * (p1[0] * sm[0] - sm[1]),
            );
            let last = rows - 1;
            jjt[2 * c1 * rows + last] = ey;
            jjt[last * rows + 2 * c1] = ey;
            jjt[(2 * c1 + 1) * rows + last] = ex;
            jjt[last * rows + 2 * c1 + 1] = ex;
        }
        jjt[rows * rows - 1] = scale * scale * sums[0];
        let y = solve(&mut jjt, r, rows)?;
        // Each arc's change: `weight_i` times the sum, over the checked
        // points after it, of `-(P - m_i)_y y_P,x + (P - m_i)_x y_P,y`,
        // plus `scale` times the direction's (suffix sums over the checks).
        let (mut t0, mut ty, mut tx) = (0.0f64, 0.0f64, 0.0f64);
        let mut c = nc;
        for i in (0..count).rev() {
            while c > 0 && checks[c - 1] > i {
                c -= 1;
                let pc = at(c);
                t0 += -pc[1] * y[2 * c] + pc[0] * y[2 * c + 1];
                ty += y[2 * c];
                tx += y[2 * c + 1];
            }
            if weight[i] == 0.0 {
                continue;
            }
            let m = mid(i);
            let d = t0 + m[1] * ty - m[0] * tx + scale * y[rows - 1];
            k[i] += weight[i] * d;
        }
        if !k.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    if !converged {
        return None;
    }
    let (p, _) = walk(start, theta0, &h, &k);
    let rise = |x: f64| l0[2] + (l1[2] - l0[2]) * x / total;
    let mut out: Vec<Curve> = Vec::with_capacity(count);
    let mut at = pts[0];
    let mut dir = in_plane_direction(plane, samples[0].tangent, MIN_IN_PLANE)?;
    let mut angle = theta0;
    for i in 0..count {
        let to = if i + 1 == count {
            pts[n - 1]
        } else {
            plane.point([p[i + 1][0], p[i + 1][1], rise(b[i + 1])])
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
        angle += k[i] * h[i];
        dir = [math::cos(angle), math::sin(angle)];
        at = to;
        out.push(a);
    }
    // Speeds over each arc (the samples it spans), and the lines it
    // replaces.
    let mut speeds = Vec::with_capacity(count);
    let mut lines = Vec::with_capacity(count);
    for i in 0..count {
        let (ja, _) = locate(b[i]);
        let (jb, _) = locate(b[i + 1]);
        let (ja, jb) = (ja - 1, jb.min(n - 1));
        let mut v = 0.0f64;
        let (mut lo, mut hi) = (usize::MAX, 0);
        for smp in &samples[ja..=jb] {
            v = v.max(speed.at(smp.piece, smp.t));
            let sl = pieces[smp.piece].source_lines;
            lo = lo.min(sl.0);
            hi = hi.max(sl.1);
        }
        speeds.push(v);
        lines.push((lo, hi));
    }
    if !passes(&out, &speeds, &samples, &pts, opts) {
        return None;
    }
    Some((out, speeds, lines))
}

/// Replaces the first cells of `(h, k, weight)` (lengths, curvatures,
/// shares of the correction) by a ramp of equal sub-cells, no shorter
/// than `block`, from curvature `from` to the mean of the cell after them
/// in steps of at most `room`, that turns the path as much as the cells
/// it replaces: a linear ramp plus a half-sine bump that puts back the
/// turn the ramp misses (the correction of the chain's points would else
/// put it into a few arcs). Over as few cells as give it room (at most
/// [`RAMP_CELLS`]), in as few sub-cells as keep the steps (at most
/// [`MAX_RAMP`]); where none do, the most sub-cells of the most cells.
/// Returns the ramp's sub-cells.
fn ramp_start(
    (h, k, w): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>),
    from: f64,
    room: f64,
    block: f64,
) -> usize {
    let cells = h.len();
    if cells < 2 || room.is_nan() || room <= 0.0 {
        return 0;
    }
    // The ramp over the first `c` cells in `r` sub-cells, and its largest
    // step (against `from`, inside, and into the cell after it).
    let ramp = |c: usize, r: usize| -> (f64, Vec<f64>, f64) {
        let len: f64 = h[..c].iter().sum();
        let turn: f64 = h[..c].iter().zip(&k[..c]).map(|(a, b)| a * b).sum();
        let target = k[c];
        let sub = len / r as f64;
        let lin: Vec<f64> = (0..r)
            .map(|i| from + (target - from) * (i + 1) as f64 / (r + 1) as f64)
            .collect();
        let bump: Vec<f64> = (0..r)
            .map(|i| math::sin(core::f64::consts::PI * (i as f64 + 0.5) / r as f64))
            .collect();
        let (lin_turn, bump_turn) = (
            lin.iter().sum::<f64>() * sub,
            bump.iter().sum::<f64>() * sub,
        );
        let amp = if bump_turn > 0.0 {
            (turn - lin_turn) / bump_turn
        } else {
            0.0
        };
        let ks: Vec<f64> = lin.iter().zip(&bump).map(|(a, b)| a + amp * b).collect();
        let mut worst = math::abs(ks[0] - from).max(math::abs(target - ks[r - 1]));
        for p in ks.windows(2) {
            worst = worst.max(math::abs(p[1] - p[0]));
        }
        (sub, ks, worst)
    };
    let most_cells = RAMP_CELLS.min(cells - 1);
    let mut chosen = None;
    'cells: for c in 1..=most_cells {
        let len: f64 = h[..c].iter().sum();
        for r in 1..=MAX_RAMP {
            if len / (r as f64) < block {
                break;
            }
            let (sub, ks, worst) = ramp(c, r);
            if worst <= room {
                chosen = Some((c, sub, ks));
                break 'cells;
            }
        }
    }
    let (c, sub, ks) = match chosen {
        Some(x) => x,
        None => {
            let len: f64 = h[..most_cells].iter().sum();
            let r = if block > 0.0 {
                math::floor(len / block)
            } else {
                1.0
            };
            let (sub, ks, _) = ramp(most_cells, (r as usize).clamp(1, MAX_RAMP));
            (most_cells, sub, ks)
        }
    };
    let r = ks.len();
    h.splice(0..c, core::iter::repeat_n(sub, r));
    k.splice(0..c, ks);
    w.splice(0..c, (0..r).map(|i| i as f64 / r as f64));
    r
}

/// Whether `arcs` (planned speeds `v` over each) pass: curvature steps at
/// the chain's ends against its curves and between arcs that the planned
/// speed passes, and the chord share both ways against the samples.
fn passes(
    arcs: &[Curve],
    v: &[f64],
    samples: &[Sample],
    pts: &[Vec3],
    opts: &RenderOptions,
) -> bool {
    let m = &opts.limits;
    let step = |v: f64| opts.step_room(v);
    let n = arcs.len();
    // Each arc's own speed caps (its curvature's, at both ends and the
    // middle) at least the speed planned for the curves over it: a mean
    // curvature above the curves' where they are fast would slow the
    // machine there.
    for (a, &va) in arcs.iter().zip(v) {
        for t in [0.0, 0.5, 1.0] {
            let Some(tangent) = a.unit_tangent(t) else {
                return false;
            };
            let p = PathPoint {
                tangent,
                curvature: a.curvature_vector(t),
                dkappa_ds: 0.0,
            };
            if speed_cap(m, f64::INFINITY, &p).0 < va {
                return false;
            }
        }
    }
    let (first, last) = (&samples[0], &samples[samples.len() - 1]);
    if (arcs[0].curvature_vector(0.0) - first.kvec).norm() > step(v[0])
        || (arcs[n - 1].curvature_vector(1.0) - last.kvec).norm() > step(v[n - 1])
    {
        return false;
    }
    for i in 0..n - 1 {
        let dk = (arcs[i + 1].curvature_vector(0.0) - arcs[i].curvature_vector(1.0)).norm();
        if dk > 2.0 * step(v[i].max(v[i + 1])) {
            return false;
        }
    }
    let kink = arcs[n - 1]
        .unit_tangent(1.0)
        .map_or(f64::INFINITY, |a| a.angle_to(last.tangent));
    let len = arcs[n - 1].length(opts.chord * 1e-3);
    if 2.0 * kink > step(v[n - 1]) * len {
        return false;
    }
    let lim = DEVIATION_USE * opts.chord;
    let mut hint = 0;
    for &q in &pts[1..pts.len() - 1] {
        let near = |i: usize| piece_distance_bound(&arcs[i], q).is_some_and(|d| d <= lim);
        match (hint..arcs.len()).chain(0..hint).find(|&i| near(i)) {
            Some(i) => hint = i,
            None => return false,
        }
    }
    points_near_polyline(arcs, pts, lim)
}

/// `m x = rhs` for the `n` by `n` symmetric positive semidefinite `m`
/// (row-major; overwritten), by Gaussian elimination with partial
/// pivoting; `None` where it is singular.
fn solve(m: &mut [f64], mut rhs: Vec<f64>, n: usize) -> Option<Vec<f64>> {
    let scale = m.iter().fold(0.0f64, |a, v| a.max(math::abs(*v)));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for c in 0..n {
        let piv =
            (c..n).max_by(|&a, &b| math::abs(m[a * n + c]).total_cmp(&math::abs(m[b * n + c])))?;
        if math::abs(m[piv * n + c]) <= f64::EPSILON * scale {
            return None;
        }
        if piv != c {
            for j in 0..n {
                m.swap(c * n + j, piv * n + j);
            }
            rhs.swap(c, piv);
        }
        for r in c + 1..n {
            let f = m[r * n + c] / m[c * n + c];
            if f != 0.0 {
                for j in c..n {
                    m[r * n + j] -= f * m[c * n + j];
                }
                rhs[r] -= f * rhs[c];
            }
        }
    }
    let mut x = alloc::vec![0.0; n];
    for r in (0..n).rev() {
        let mut acc = rhs[r];
        for j in r + 1..n {
            acc -= m[r * n + j] * x[j];
        }
        x[r] = acc / m[r * n + r];
    }
    Some(x)
}
